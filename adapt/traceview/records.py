"""The shape of every trace record, checked as it is read.

:class:`adapt.traceview.reader.Trace` passes each record through
:func:`check_record` before any other module sees it, so the inspectors
(``show``, ``wm``, ``why``, ``stats``, ``diff``, ``html``) may rely on the
types of ``docs/trace-format.schema.json``: a WME is ``[int, symbol, symbol,
symbol, bool]``, ``removes`` holds integers, a firing has a string ``rule``
and a dict of ``bindings``, and so on.  A record that breaks the schema is a
:class:`adapt.errors.TraceError` that names the field and what was expected,
never a crash further on.  Beyond the schema:

* a goal ``level`` is at most :data:`MAX_GOAL_LEVEL`;
* free-form values (a ``schema`` record's ``data``, fields of the header and
  footer that this version does not know) nest at most :data:`MAX_NESTING`
  deep;
* fields this version does not know are otherwise ignored, as are records of
  kinds it does not know (``docs/trace-format.md``: "Readers that do not know
  a record kind skip it").

Examples
--------
>>> check_record({"kind": "phase", "d": 3, "phase": "apply",
...               "adds": [[5, {"id": "S1"}, "count", 3, False]], "removes": [4]})
>>> check_record({"kind": "phase", "d": 3, "phase": "apply", "adds": "oops"})
Traceback (most recent call last):
...
adapt.traceview.records.RecordError: "adds" is 'oops'; expected a list of WMEs [timetag, id, attr, value, acceptable]
>>> check_record({"kind": "decision", "d": 2, "level": 0, "selected": {"id": "O1"},
...               "impasse": None})
Traceback (most recent call last):
...
adapt.traceview.records.RecordError: "selected"."id" is 'O1'; expected an identifier like {"id": "S1"}
"""

from __future__ import annotations

from typing import Any

__all__ = ["RecordError", "check_record", "check_header", "phase_ok", "MAX_GOAL_LEVEL", "MAX_NESTING",
           "PHASES", "IMPASSE_TYPES"]

#: The deepest goal level a trace may name (the engine's default limit is 100).
MAX_GOAL_LEVEL = 10_000
#: How deep free-form JSON values may nest.
MAX_NESTING = 64
#: The phase names.
PHASES = frozenset({"input", "proposal", "decision", "apply", "output"})
#: The impasse types.
IMPASSE_TYPES = frozenset({"tie", "conflict", "constraint-failure", "state no-change",
                           "operator no-change", "no-change"})

_WME = "a WME [timetag, id, attr, value, acceptable]"
_IDENT = 'an identifier like {"id": "S1"}'
_SYMBOL = 'a symbol (an identifier {"id": "S1"}, a string or a number)'


class RecordError(ValueError):
    """A record that breaks the trace schema; the reader adds the file and line."""


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _bad(where: str, value: Any, expected: str) -> RecordError:
    return RecordError(f"{where} is {_show(value)}; expected {expected}")


#: Marks a field that is absent (a field that is present must have its type, even ``null``).
_ABSENT: Any = object()


def _is_ident(v: Any) -> bool:
    return type(v) is dict and type(v.get("id")) is str


def _is_symbol(v: Any) -> bool:
    t = type(v)
    return t is str or t is int or t is float or (t is dict and type(v.get("id")) is str)


def _is_wme(w: Any) -> bool:
    return (type(w) is list and len(w) == 5 and type(w[0]) is int and _is_symbol(w[1])
            and _is_symbol(w[2]) and _is_symbol(w[3]) and type(w[4]) is bool)


def _wmes(value: Any, where: str) -> None:
    if value is _ABSENT:
        return
    if type(value) is not list:
        raise _bad(where, value, "a list of WMEs [timetag, id, attr, value, acceptable]")
    for i, w in enumerate(value):
        if not _is_wme(w):
            raise _bad(f"{where}[{i}]", w, _WME)


def _ints(value: Any, where: str) -> None:
    if value is _ABSENT:
        return
    if type(value) is not list:
        raise _bad(where, value, "a list of timetags (integers)")
    for i, t in enumerate(value):
        if type(t) is not int:
            raise _bad(f"{where}[{i}]", t, "a timetag (an integer)")


def _strings(value: Any, where: str) -> None:
    if value is not _ABSENT and (type(value) is not list or not all(type(s) is str for s in value)):
        raise _bad(where, value, "a list of strings")


def _level(value: Any, where: str, nullable: bool = False) -> None:
    if value is None and nullable:
        return
    if type(value) is not int or not 0 <= value <= MAX_GOAL_LEVEL:
        raise _bad(where, value, f"a goal level, an integer from 0 to {MAX_GOAL_LEVEL:,}")


def _count(value: Any, where: str, lowest: int = 0) -> None:
    if type(value) is not int or value < lowest:
        raise _bad(where, value, f"an integer >= {lowest}")


def _number(value: Any, where: str) -> None:
    if value is not _ABSENT and (type(value) not in (int, float) or value < 0):
        raise _bad(where, value, "a number >= 0")


def _string(value: Any, where: str) -> None:
    if value is not _ABSENT and type(value) is not str:
        raise _bad(where, value, "a string")


def _symbol_or_null(value: Any, where: str) -> None:
    if value is not _ABSENT and value is not None and not _is_symbol(value):
        raise _bad(where, value, _SYMBOL)


def _required(record: dict[str, Any], keys: tuple[str, ...], where: str = "") -> None:
    for key in keys:
        if key not in record:
            raise RecordError(f'{where}"{key}" is missing')


def _instantiations(value: Any, where: str) -> None:
    if value is _ABSENT:
        return
    if type(value) is not list:
        raise _bad(where, value, 'a list of firings {"rule", "level", ...}')
    for i, f in enumerate(value):
        here = f"{where}[{i}]"
        if type(f) is not dict:
            raise _bad(here, f, 'a firing {"rule": ..., "level": ...}')
        if type(f.get("rule")) is not str:
            raise _bad(f'{here}."rule"', f.get("rule"), "a rule name (a string)")
        _level(f.get("level"), f'{here}."level"')
        support = f.get("support", _ABSENT)
        if support is not _ABSENT and support not in ("o", "i", "none"):
            raise _bad(f'{here}."support"', support, '"o", "i" or "none"')
        bindings = f.get("bindings", _ABSENT)
        if bindings is not _ABSENT:
            if type(bindings) is not dict:
                raise _bad(f'{here}."bindings"', bindings, "an object of variables and symbols")
            for var, val in bindings.items():
                if not _is_symbol(val):
                    raise _bad(f'{here}."bindings".{var!r}', val, _SYMBOL)
        _ints(f.get("wmes", _ABSENT), f'{here}."wmes"')
        _ints(f.get("adds", _ABSENT), f'{here}."adds"')


def _phase(record: dict[str, Any]) -> None:
    _count(record.get("d"), '"d"')
    if type(record.get("phase")) is not str or record["phase"] not in PHASES:
        raise _bad('"phase"', record.get("phase"), "one of " + ", ".join(sorted(PHASES)))
    get = record.get
    _wmes(get("adds", _ABSENT), '"adds"')
    _ints(get("removes", _ABSENT), '"removes"')
    _instantiations(get("firings", _ABSENT), '"firings"')
    _instantiations(get("retractions", _ABSENT), '"retractions"')
    _string(get("writes", _ABSENT), '"writes"')
    _strings(get("messages", _ABSENT), '"messages"')
    _number(get("time_s", _ABSENT), '"time_s"')


def _operator(value: Any, where: str) -> None:
    if value is None:
        return
    if type(value) is not dict:
        raise _bad(where, value, 'null or an operator {"id": {"id": "O1"}, "name": ...}')
    if not _is_ident(value.get("id")):
        raise _bad(f'{where}."id"', value.get("id"), _IDENT)
    _symbol_or_null(value.get("name", _ABSENT), f'{where}."name"')  # null: no ^name


def _decision(record: dict[str, Any]) -> None:
    _count(record.get("d"), '"d"', 1)
    _required(record, ("level", "selected", "impasse"))
    _level(record["level"], '"level"', nullable=True)  # null when the phase decided nothing
    _operator(record["selected"], '"selected"')
    impasse = record["impasse"]
    if impasse is not None:
        if type(impasse) is not dict:
            raise _bad('"impasse"', impasse, 'null or {"type", "attribute", "state", ...}')
        _required(impasse, ("type", "attribute", "state"), '"impasse".')
        if type(impasse["type"]) is not str or impasse["type"] not in IMPASSE_TYPES:
            raise _bad('"impasse"."type"', impasse["type"],
                       "one of " + ", ".join(sorted(IMPASSE_TYPES)))
        if impasse["attribute"] not in ("operator", "state"):
            raise _bad('"impasse"."attribute"', impasse["attribute"], '"operator" or "state"')
        if not _is_ident(impasse["state"]):
            raise _bad('"impasse"."state"', impasse["state"], _IDENT)
        items = impasse.get("items", _ABSENT)
        if items is not _ABSENT and (type(items) is not list or not all(map(_is_ident, items))):
            raise _bad('"impasse"."items"', items, "a list of identifiers")
    candidates = record.get("candidates", _ABSENT)
    if candidates is not _ABSENT:
        if type(candidates) is not list:
            raise _bad('"candidates"', candidates, "a list of candidates")
        for i, c in enumerate(candidates):
            here = f'"candidates"[{i}]'
            if type(c) is not dict:
                raise _bad(here, c, 'a candidate {"id", "name", "preferences"}')
            _operator(c, here)
            prefs = c.get("preferences")
            if type(prefs) is not list:
                raise _bad(f'{here}."preferences"', prefs, "a list of [kind, referent]")
            for j, p in enumerate(prefs):
                if not (type(p) is list and len(p) == 2 and type(p[0]) is str
                        and (p[1] is None or _is_symbol(p[1]))):
                    raise _bad(f'{here}."preferences"[{j}]', p, "[kind, referent or null]")
    goals = record.get("removed_goals", _ABSENT)
    if goals is not _ABSENT and (type(goals) is not list or not all(map(_is_ident, goals))):
        raise _bad('"removed_goals"', goals, "a list of identifiers")
    _string(record.get("mmd_frame", _ABSENT), '"mmd_frame"')


def _nesting(value: Any, where: str) -> None:
    """Refuse a free-form value nested more than :data:`MAX_NESTING` deep (iteratively)."""
    stack = [(value, 1)]
    while stack:
        item, depth = stack.pop()
        if type(item) is dict:
            children: Any = item.values()
        elif type(item) is list:
            children = item
        else:
            continue
        if depth > MAX_NESTING:
            raise RecordError(f"{where} nests more than {MAX_NESTING} levels deep")
        stack.extend((c, depth + 1) for c in children)


def _schema(record: dict[str, Any]) -> None:
    _count(record.get("d"), '"d"')
    for key in ("event", "schema"):
        if type(record.get(key)) is not str:
            raise _bad(f'"{key}"', record.get(key), "a string")
    _string(record.get("mmd_frame", _ABSENT), '"mmd_frame"')
    _nesting(record.get("data"), '"data"')


def _footer(record: dict[str, Any]) -> None:
    _count(record.get("decisions"), '"decisions"')
    for key in ("production_firings", "wm_size_final"):
        if key in record:
            _count(record[key], f'"{key}"')
    if "halted" in record and type(record["halted"]) is not bool:
        raise _bad('"halted"', record["halted"], "true or false")
    for key in ("stop_reason", "error"):
        _string(record.get(key, _ABSENT), f'"{key}"')
    _number(record.get("elapsed_s", _ABSENT), '"elapsed_s"')
    _nesting(record, "the footer")


_CHECKS = {"phase": _phase, "decision": _decision, "schema": _schema, "footer": _footer}

# -- the fast path ------------------------------------------------------------------
# Reading a trace is dominated by phase records.  ``_phase_ok`` answers only
# "does it follow the schema?", with builtins and no messages; when it says no,
# ``_phase`` (above) finds the field and words the error.  The two must agree:
# tests/fuzz/test_traces.py checks it on generated records.  Measured with
# bench/traces.py on a 30,000-decision level-5 trace (180,000 records), the
# checks take about as long as decoding the JSON: the reader is 1.6-1.9x
# slower with them than without (medians of 5, a loaded 2-core machine).

_SCALARS = frozenset({str, int, float})
_SYMBOL_TYPES = frozenset({str, int, float, dict})
_INT = frozenset({int})
_STR = frozenset({str})
_LIST = frozenset({list})
_BOOL = frozenset({bool})
_FIVE = frozenset({5})
_SUPPORTS = ("o", "i", "none")

# The checks below look at whole columns at once (``set(map(type, ...))`` runs in C):
# a Python call per value would double the reader's time.


def _symbols_ok(values: Any) -> bool:
    """Whether every value is a symbol (a string, a number or ``{"id": str}``)."""
    types = set(map(type, values))
    if types <= _SCALARS:
        return True
    if not types <= _SYMBOL_TYPES:
        return False
    ids = [v.get("id") for v in values if type(v) is dict]
    return set(map(type, ids)) == _STR


def _wmes_ok(adds: list[Any]) -> bool:
    if set(map(type, adds)) != _LIST or set(map(len, adds)) != _FIVE:
        return False
    timetags, ids, attrs, values, acceptable = zip(*adds)
    return (set(map(type, timetags)) == _INT and set(map(type, acceptable)) == _BOOL
            and _symbols_ok(ids) and _symbols_ok(attrs) and _symbols_ok(values))


def _inst_ok(f: Any) -> bool:
    if type(f) is not dict:
        return False
    get = f.get
    level = get("level")
    if (type(get("rule")) is not str or type(level) is not int
            or not 0 <= level <= MAX_GOAL_LEVEL or get("support", "o") not in _SUPPORTS):
        return False
    b = get("bindings", _ABSENT)
    if b is not _ABSENT and (type(b) is not dict or not _symbols_ok(b.values())):
        return False
    for key in ("wmes", "adds"):
        v = get(key, _ABSENT)
        if v is not _ABSENT and (type(v) is not list or (v and set(map(type, v)) != _INT)):
            return False
    return True


def _phase_ok(r: dict[str, Any]) -> bool:
    get = r.get
    d = get("d")
    phase = get("phase")
    if type(d) is not int or d < 0 or type(phase) is not str or phase not in PHASES:
        return False
    v = get("adds", _ABSENT)
    if v is not _ABSENT and (type(v) is not list or (v and not _wmes_ok(v))):
        return False
    v = get("removes", _ABSENT)
    if v is not _ABSENT and (type(v) is not list or (v and set(map(type, v)) != _INT)):
        return False
    for key in ("firings", "retractions"):
        v = get(key, _ABSENT)
        if v is not _ABSENT and (type(v) is not list or (v and not all(map(_inst_ok, v)))):
            return False
    v = get("messages", _ABSENT)
    if v is not _ABSENT and (type(v) is not list or (v and set(map(type, v)) != _STR)):
        return False
    t = get("time_s", 0)
    return type(get("writes", "")) is str and type(t) in (int, float) and t >= 0


def check_record(record: dict[str, Any], *, fast: bool = True) -> None:
    """Raise :class:`RecordError` unless ``record`` (not the header) follows the schema.

    Records of kinds this version does not know pass unchecked.  ``fast=False``
    skips the fast path (tests compare the two).
    """
    kind = record.get("kind")
    if type(kind) is not str:
        raise _bad('"kind"', kind, "a record kind (a string)")
    if fast and kind == "phase" and _phase_ok(record):
        return
    check = _CHECKS.get(kind)
    if check is not None:
        check(record)


def phase_ok(record: dict[str, Any]) -> bool:
    """The fast path alone: whether a ``phase`` record follows the schema."""
    return _phase_ok(record)


def check_header(record: dict[str, Any]) -> None:
    """Raise :class:`RecordError` unless the header's optional fields have their types.

    (``format``, ``version``, ``level`` and ``files`` are checked by the
    reader, which words those errors for a file that is not a trace.)
    """
    for key in ("adapt", "created"):
        _string(record.get(key, _ABSENT), f'"{key}"')
    _wmes(record.get("wmes", _ABSENT), '"wmes"')
    _nesting(record, "the header")
