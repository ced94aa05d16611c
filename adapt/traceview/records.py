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

__all__ = ["RecordError", "check_record", "check_header", "MAX_GOAL_LEVEL", "MAX_NESTING",
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


def _is_int(v: Any) -> bool:
    return type(v) is int


def _is_ident(v: Any) -> bool:
    return type(v) is dict and type(v.get("id")) is str


def _is_symbol(v: Any) -> bool:
    t = type(v)
    return t is str or t is int or t is float or (t is dict and type(v.get("id")) is str)


def _is_wme(w: Any) -> bool:
    return (type(w) is list and len(w) == 5 and type(w[0]) is int and _is_symbol(w[1])
            and _is_symbol(w[2]) and _is_symbol(w[3]) and type(w[4]) is bool)


def _wmes(record: dict[str, Any], key: str, where: str) -> None:
    wmes = record.get(key)
    if wmes is None:
        return
    if type(wmes) is not list:
        raise _bad(where, wmes, f"a list of WMEs {_WME[6:]}")
    for i, w in enumerate(wmes):
        if not _is_wme(w):
            raise _bad(f"{where}[{i}]", w, _WME)


def _ints(value: Any, where: str) -> None:
    if value is None:
        return
    if type(value) is not list:
        raise _bad(where, value, "a list of timetags (integers)")
    for i, t in enumerate(value):
        if type(t) is not int:
            raise _bad(f"{where}[{i}]", t, "a timetag (an integer)")


def _strings(value: Any, where: str) -> None:
    if value is None:
        return
    if type(value) is not list or not all(type(s) is str for s in value):
        raise _bad(where, value, "a list of strings")


def _level(value: Any, where: str, optional: bool = False) -> None:
    if value is None and optional:
        return
    if type(value) is not int or not 0 <= value <= MAX_GOAL_LEVEL:
        raise _bad(where, value, f"a goal level, an integer from 0 to {MAX_GOAL_LEVEL:,}")


def _d(record: dict[str, Any], lowest: int) -> None:
    d = record.get("d")
    if type(d) is not int or d < lowest:
        raise _bad('"d"', d, f"a decision count, an integer >= {lowest}")


def _number(value: Any, where: str) -> None:
    if value is not None and (type(value) not in (int, float) or value < 0):
        raise _bad(where, value, "a number >= 0")


def _string(value: Any, where: str) -> None:
    if value is not None and type(value) is not str:
        raise _bad(where, value, "a string")


def _instantiations(value: Any, where: str) -> None:
    if value is None:
        return
    if type(value) is not list:
        raise _bad(where, value, "a list of firings {\"rule\", \"level\", ...}")
    for i, f in enumerate(value):
        here = f"{where}[{i}]"
        if type(f) is not dict:
            raise _bad(here, f, 'a firing {"rule": ..., "level": ...}')
        if type(f.get("rule")) is not str:
            raise _bad(f'{here}."rule"', f.get("rule"), "a rule name (a string)")
        _level(f.get("level"), f'{here}."level"', optional=True)
        support = f.get("support")
        if support is not None and support not in ("o", "i", "none"):
            raise _bad(f'{here}."support"', support, '"o", "i" or "none"')
        bindings = f.get("bindings")
        if bindings is not None:
            if type(bindings) is not dict:
                raise _bad(f'{here}."bindings"', bindings, "an object of variables and symbols")
            for var, val in bindings.items():
                if not _is_symbol(val):
                    raise _bad(f'{here}."bindings".{var!r}', val, _SYMBOL)
        _ints(f.get("wmes"), f'{here}."wmes"')
        _ints(f.get("adds"), f'{here}."adds"')


def _phase(record: dict[str, Any]) -> None:
    _d(record, 0)
    if record.get("phase") not in PHASES:
        raise _bad('"phase"', record.get("phase"), "one of " + ", ".join(sorted(PHASES)))
    _wmes(record, "adds", '"adds"')
    _ints(record.get("removes"), '"removes"')
    _instantiations(record.get("firings"), '"firings"')
    _instantiations(record.get("retractions"), '"retractions"')
    _string(record.get("writes"), '"writes"')
    _strings(record.get("messages"), '"messages"')
    _number(record.get("time_s"), '"time_s"')


def _operator(value: Any, where: str) -> None:
    if value is None:
        return
    if type(value) is not dict:
        raise _bad(where, value, 'null or an operator {"id": {"id": "O1"}, "name": ...}')
    if not _is_ident(value.get("id")):
        raise _bad(f'{where}."id"', value.get("id"), _IDENT)
    if value.get("name") is not None and not _is_symbol(value["name"]):
        raise _bad(f'{where}."name"', value["name"], _SYMBOL)


def _decision(record: dict[str, Any]) -> None:
    _d(record, 1)
    _level(record.get("level"), '"level"', optional=True)  # null when nothing was decided
    _operator(record.get("selected"), '"selected"')
    impasse = record.get("impasse")
    if impasse is not None:
        if type(impasse) is not dict:
            raise _bad('"impasse"', impasse, 'null or {"type", "attribute", "state", ...}')
        if impasse.get("type") not in IMPASSE_TYPES:
            raise _bad('"impasse"."type"', impasse.get("type"),
                       "one of " + ", ".join(sorted(IMPASSE_TYPES)))
        if impasse.get("attribute") not in (None, "operator", "state"):
            raise _bad('"impasse"."attribute"', impasse.get("attribute"), '"operator" or "state"')
        if impasse.get("state") is not None and not _is_ident(impasse["state"]):
            raise _bad('"impasse"."state"', impasse["state"], _IDENT)
        items = impasse.get("items")
        if items is not None and (type(items) is not list or not all(_is_symbol(i) for i in items)):
            raise _bad('"impasse"."items"', items, "a list of identifiers")
    candidates = record.get("candidates")
    if candidates is not None:
        if type(candidates) is not list:
            raise _bad('"candidates"', candidates, "a list of candidates")
        for i, c in enumerate(candidates):
            here = f'"candidates"[{i}]'
            if type(c) is not dict:
                raise _bad(here, c, 'a candidate {"id", "name", "preferences"}')
            _operator(c, here)
            prefs = c.get("preferences")
            if prefs is None:
                continue
            if type(prefs) is not list:
                raise _bad(f'{here}."preferences"', prefs, "a list of [kind, referent]")
            for j, p in enumerate(prefs):
                if not (type(p) is list and len(p) == 2 and type(p[0]) is str
                        and (p[1] is None or _is_symbol(p[1]))):
                    raise _bad(f'{here}."preferences"[{j}]', p, "[kind, referent or null]")
    goals = record.get("removed_goals")
    if goals is not None and (type(goals) is not list or not all(_is_ident(g) for g in goals)):
        raise _bad('"removed_goals"', goals, "a list of identifiers")
    _string(record.get("mmd_frame"), '"mmd_frame"')


def _nesting(value: Any, where: str) -> None:
    """Refuse a free-form value nested more than :data:`MAX_NESTING` deep (iteratively)."""
    stack = [(value, 1)]
    while stack:
        item, depth = stack.pop()
        if type(item) is dict:
            children = item.values()
        elif type(item) is list:
            children = item  # type: ignore[assignment]
        else:
            continue
        if depth > MAX_NESTING:
            raise RecordError(f"{where} nests more than {MAX_NESTING} levels deep")
        stack.extend((c, depth + 1) for c in children)


def _schema(record: dict[str, Any]) -> None:
    _d(record, 0)
    _string(record.get("event"), '"event"')
    _string(record.get("schema"), '"schema"')
    _string(record.get("mmd_frame"), '"mmd_frame"')
    _nesting(record.get("data"), '"data"')


_FOOTER_INTS = ("decisions", "production_firings", "wm_size_final")


def _footer(record: dict[str, Any]) -> None:
    for key in _FOOTER_INTS:
        value = record.get(key)
        if (value is not None or key == "decisions") and (type(value) is not int or value < 0):
            raise _bad(f'"{key}"', value, "an integer >= 0")
    if record.get("halted") is not None and type(record["halted"]) is not bool:
        raise _bad('"halted"', record["halted"], "true or false")
    _string(record.get("stop_reason"), '"stop_reason"')
    _string(record.get("error"), '"error"')
    _number(record.get("elapsed_s"), '"elapsed_s"')
    _nesting(record, "the footer")


_CHECKS = {"phase": _phase, "decision": _decision, "schema": _schema, "footer": _footer}

# -- the fast path ------------------------------------------------------------------
# Reading a trace is dominated by phase records.  ``_phase_ok`` answers only
# "does it follow the schema?", with builtins and no messages; when it says no,
# ``_phase`` (above) finds the field and words the error.  Measured on a
# 30,000-decision level-5 trace (bench/traces.py), the check costs about a
# third of the JSON decoding time.

_SCALARS = frozenset({str, int, float})


def _sym_ok(v: Any) -> bool:
    return type(v) in _SCALARS or (type(v) is dict and type(v.get("id")) is str)


def _wme_ok(w: Any) -> bool:
    return (type(w) is list and len(w) == 5 and type(w[0]) is int and type(w[4]) is bool
            and _sym_ok(w[1]) and _sym_ok(w[2]) and _sym_ok(w[3]))


def _int_list_ok(v: Any) -> bool:
    return v is None or (type(v) is list and all(type(t) is int for t in v))


def _inst_ok(f: Any) -> bool:
    if type(f) is not dict or type(f.get("rule")) is not str:
        return False
    level = f.get("level")
    if level is not None and (type(level) is not int or not 0 <= level <= MAX_GOAL_LEVEL):
        return False
    support = f.get("support")
    if support is not None and support not in ("o", "i", "none"):
        return False
    b = f.get("bindings")
    if b is not None and (type(b) is not dict or not all(map(_sym_ok, b.values()))):
        return False
    return _int_list_ok(f.get("wmes")) and _int_list_ok(f.get("adds"))


def _phase_ok(r: dict[str, Any]) -> bool:
    d = r.get("d")
    if type(d) is not int or d < 0 or r.get("phase") not in PHASES:
        return False
    adds = r.get("adds")
    if adds is not None and (type(adds) is not list or not all(map(_wme_ok, adds))):
        return False
    if not _int_list_ok(r.get("removes")):
        return False
    for key in ("firings", "retractions"):
        v = r.get(key)
        if v is not None and (type(v) is not list or not all(map(_inst_ok, v))):
            return False
    w = r.get("writes")
    m = r.get("messages")
    t = r.get("time_s")
    return ((w is None or type(w) is str)
            and (m is None or (type(m) is list and all(type(x) is str for x in m)))
            and (t is None or (type(t) in (int, float) and t >= 0)))


def check_record(record: dict[str, Any]) -> None:
    """Raise :class:`RecordError` unless ``record`` (not the header) follows the schema.

    Records of kinds this version does not know pass unchecked.
    """
    kind = record.get("kind")
    if kind == "phase" and _phase_ok(record):
        return
    check = _CHECKS.get(kind)  # type: ignore[arg-type]
    if check is not None:
        check(record)


def check_header(record: dict[str, Any]) -> None:
    """Raise :class:`RecordError` unless the header's optional fields have their types.

    (``format``, ``version``, ``level`` and ``files`` are checked by the
    reader, which words those errors for a file that is not a trace.)
    """
    for key in ("adapt", "created"):
        _string(record.get(key), f'"{key}"')
    _wmes(record, "wmes", '"wmes"')
    _nesting(record, "the header")
