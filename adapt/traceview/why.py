"""Why a WME is in working memory, and why a rule did not fire.

:func:`explain` finds the phase that added a WME and the instantiation that
made it -- its rule, bindings and the WMEs it matched -- and explains those
WMEs in turn, to a chosen depth.  A firing may list the timetags it added
(``"adds"`` in a firing record, optional); otherwise the maker is found by
instantiating the actions of each firing of that phase with its bindings
(the rules come from the trace header's ``files``).  WMEs that no firing made
are the architecture's: the top state and input in the input phase, the
selected operator and substates in the decision phase.

:func:`why_not` rebuilds working memory at the end of a decision cycle and
checks the rule's conditions against it one at a time
(:func:`adapt.traceview.conditions.first_failure`).

Examples
--------
>>> firing = {"rule": "apply*count", "bindings": {"<s>": {"id": "S1"}, "<c>": 2}}
>>> from adapt.engine.parse import parse_rules
>>> p, = parse_rules('''sp {apply*count (state <s> ^operator.name count ^count <c>)
...   --> (<s> ^count (+ <c> 1) ^count <c> -)}''').productions
>>> made_by(p, firing, (31, {"id": "S1"}, "count", 3, False))
True
>>> made_by(p, firing, (32, {"id": "S2"}, "count", 3, False))
False
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

from adapt.engine.production import (
    ConjunctiveNegation,
    FunctionCall,
    MakeAction,
    PreferenceKind,
    Production,
    Variable,
)
from adapt.engine.symbols import format_symbol
from adapt.engine.wme import WME
from adapt.errors import TraceError
from adapt.traceview.conditions import Failure, condition_text, first_failure, matches
from adapt.traceview.memory import TraceWME, memory_at
from adapt.traceview.reader import Trace, cycle_of
from adapt.traceview.symbols import IdentifierTable, id_name, text_of, wme_text

#: The deepest ``explain`` goes (``adapt trace why --depth``).
MAX_DEPTH = 100

__all__ = ["MAX_DEPTH", "Origin", "made_by", "find_timetag", "explain", "format_origin", "WhyNot", "why_not",
           "format_why_not"]


def _rhs_bind(rhs: object, bindings: dict[str, Any], value: Any) -> bool:
    """Whether ``rhs`` can be ``value``; an unbound variable is bound to it (a new identifier)."""
    if isinstance(rhs, FunctionCall):
        return True  # computed: any value fits
    if isinstance(rhs, Variable):
        if rhs.name in bindings:
            return text_of(bindings[rhs.name]) == text_of(value)
        if id_name(value) is None:
            return False
        bindings[rhs.name] = value
        return True
    return format_symbol(rhs) == text_of(value)  # type: ignore[arg-type]


def _makes(action: MakeAction, bindings: dict[str, Any], wme: TraceWME) -> bool:
    _tt, ident, attr, value, acceptable = wme
    operator = text_of(attr) == "operator"
    if action.preference is not PreferenceKind.ACCEPTABLE or acceptable != operator:
        return False
    return (_rhs_bind(action.id, bindings, ident) and _rhs_bind(action.attr, bindings, attr)
            and _rhs_bind(action.value, bindings, value))


def made_by(production: Production, firing: dict[str, Any], wme: TraceWME,
            phase_adds: list[TraceWME] | None = None) -> bool:
    """Whether an action of ``production``, with the firing's bindings, makes ``wme``.

    When an action makes a new identifier (a variable the conditions do not
    bind), the production's other actions on that identifier must have made
    WMEs among ``phase_adds`` too -- that tells ``propose*a`` from
    ``propose*b`` when both propose an operator in the same phase.
    """
    given = firing.get("bindings") or {}
    for action in production.actions:
        if not isinstance(action, MakeAction):
            continue
        bindings = dict(given)
        if not _makes(action, bindings, wme):
            continue
        new = set(bindings) - set(given)
        if not new or phase_adds is None:
            return True
        others = [a for a in production.actions if isinstance(a, MakeAction) and a is not action
                  and isinstance(a.id, Variable) and a.id.name in new]
        if all(any(_makes(a, dict(bindings), w) for w in phase_adds) for a in others):
            return True
    return False


@dataclass(frozen=True)
class Origin:
    """Where one WME came from.

    Attributes
    ----------
    wme : tuple
        ``(timetag, id, attr, value, acceptable)`` as in the trace.
    cycle : int
        The decision cycle whose phase added it.
    phase : str
        That phase.
    maker : str
        The rule that made it, or what part of the architecture did.
    firing : dict or None
        The firing record of the maker (bindings, matched timetags, support).
    candidates : tuple of str
        When the maker cannot be told apart: the rules that fired in that phase.
    removed : tuple or None
        ``(cycle, phase)`` where it was removed, if it was.
    matched : tuple of Origin
        The origins of the WMEs the firing matched (to the depth asked).
    """

    wme: TraceWME
    cycle: int
    phase: str
    maker: str
    firing: dict[str, Any] | None = None
    candidates: tuple[str, ...] = ()
    removed: tuple[int, str] | None = None
    matched: tuple["Origin", ...] = ()


def find_timetag(trace: Trace, ident: str, attr: str, value: str | None = None,
                 at: int | None = None, acceptable: bool | None = None) -> int:
    """The timetag of the last WME ``(ident ^attr value [+])`` added by the end of cycle ``at``."""
    trace.require_level(4, "finding a WME")
    found: int | None = None
    for _cycle, records in trace.cycles(last=at):
        for record in records:
            for add in record.get("adds") or ():
                if text_of(add[1]) == ident and text_of(add[2]) == attr and (
                    value is None or text_of(add[3]) == value
                ) and (acceptable is None or bool(add[4]) == acceptable):
                    found = add[0]
    if found is None:
        plus = " +" if acceptable else ""
        what = f"({ident} ^{attr}{' ' + value if value is not None else ''}{plus})"
        raise TraceError(f"no WME {what} was added" + (f" by decision {at}" if at is not None else ""))
    return found


def _architecture(phase: str, wme: TraceWME, impasse_states: set[str]) -> str:
    if phase == "input":
        return "input (the architecture or the environment)"
    if phase == "decision":
        if text_of(wme[1]) in impasse_states:
            return "the decision procedure (substate of an impasse)"
        if text_of(wme[2]) == "operator" and not wme[4]:
            return "the decision procedure (operator selection)"
        return "the architecture (decision phase)"
    return f"no firing of the {phase} phase (the architecture)"


def _scan(trace: Trace, wanted: set[int], productions: dict[str, Production] | None) -> dict[int, Origin]:
    # a trace without bindings (the Soar kernel's) cannot re-instantiate firings: a WME a
    # phase's firings added is "one of them", never put on the architecture
    unbound = "firings.bindings" in (trace.header.raw.get("absent") or ())
    found: dict[int, Origin] = {}
    pending_removal: dict[int, Origin] = {}
    for w in trace.initial_wmes():
        if w[0] in wanted:
            origin = Origin((w[0], w[1], w[2], w[3], bool(w[4])), 0, "start",
                            "the architecture (before the first phase)")
            found[w[0]] = pending_removal[w[0]] = origin
    for cycle, records in trace.cycles():
        impasse_states = {text_of(r["impasse"].get("state")) for r in records
                          if r["kind"] == "decision" and r.get("impasse")}
        for record in records:
            if record["kind"] != "phase":
                continue
            phase = str(record.get("phase"))
            for add in record.get("adds") or ():
                if add[0] not in wanted:
                    continue
                wme: TraceWME = (add[0], add[1], add[2], add[3], bool(add[4]))
                firings = record.get("firings") or []
                makers = [f for f in firings if add[0] in (f.get("adds") or ())]
                unknown: list[dict[str, Any]] = []
                if not makers:
                    known = productions or {}
                    adds = [tuple(a) for a in record.get("adds") or ()]
                    makers = [f for f in firings if f.get("rule") in known
                              and made_by(known[f["rule"]], f, wme, adds)]  # type: ignore[arg-type]
                    unknown = [f for f in firings if f.get("rule") not in known]
                if unbound and not makers and firings:
                    unknown = firings
                if len(makers) == 1 and not unknown:
                    origin = Origin(wme, cycle, phase, str(makers[0].get("rule")), makers[0])
                elif makers or unknown:
                    origin = Origin(wme, cycle, phase, "one of the firings of this phase",
                                    candidates=tuple(str(f.get("rule")) for f in makers + unknown))
                else:
                    origin = Origin(wme, cycle, phase, _architecture(phase, wme, impasse_states))
                found[add[0]] = origin
                pending_removal[add[0]] = origin
            # after the adds: a WME can be added and removed in one phase
            for t in record.get("removes") or ():
                if t in pending_removal:
                    origin = pending_removal.pop(t)
                    found[t] = Origin(**{**origin.__dict__, "removed": (cycle, phase)})
        if len(found) == len(wanted) and not pending_removal:
            break
    return found


def explain(trace: Trace, timetag: int, depth: int = 1,
            productions: dict[str, Production] | None = None) -> Origin:
    """The origin of WME ``timetag``, and of the WMEs its maker matched, ``depth`` levels deep.

    Raises
    ------
    adapt.errors.TraceError
        If the trace is below level 4 or no WME has that timetag.
    """
    trace.require_level(4, "explaining a WME")
    if not 0 <= depth <= MAX_DEPTH:
        raise TraceError(f"depth {depth}: expected a depth from 0 to {MAX_DEPTH}")
    levels: list[dict[int, Origin]] = []
    wanted = {timetag}
    for _ in range(depth + 1):
        found = _scan(trace, wanted, productions)
        levels.append(found)
        wanted = {t for o in found.values() if o.firing for t in o.firing.get("wmes") or ()}
        if not wanted:
            break
    if timetag not in levels[0]:
        raise TraceError(f"no WME with timetag {timetag} was added in {trace.path}")

    # One Origin per (timetag, level), shared wherever that WME is matched again:
    # the tree is a DAG whose size grows with the depth, not exponentially.
    built: dict[tuple[int, int], Origin | None] = {}
    for level in range(len(levels) - 1, -1, -1):
        for tt, origin in levels[level].items():
            kids: tuple[Origin, ...] = ()
            firing = origin.firing
            if firing is not None:
                kids = tuple(o for o in (built.get((t, level + 1)) for t in firing.get("wmes") or ())
                             if o is not None)
                if level + 1 < len(levels):
                    firing = {**firing, "explained": True}
            built[(tt, level)] = Origin(**{**origin.__dict__, "matched": kids, "firing": firing})
    result = built[(timetag, 0)]
    assert result is not None
    return result


def format_origin(origin: Origin, indent: str = "") -> str:
    """The text of ``adapt trace why --wme``.

    Each WME is explained once, where it is matched least deep; elsewhere it
    is one line that says at which depth its explanation is, so the answer
    grows with the number of WMEs involved, not exponentially with the depth.
    """
    shallowest: dict[int, int] = {}
    layer, nesting = [origin], 0
    while layer:
        following: list[Origin] = []
        for o in layer:
            if o.wme[0] not in shallowest:
                shallowest[o.wme[0]] = nesting
                following.extend(o.matched)
        layer, nesting = following, nesting + 1
    lines: list[str] = []
    _format(origin, indent, 0, lines, shallowest, set())
    return "\n".join(lines)


def _format(origin: Origin, indent: str, nesting: int, lines: list[str],
            shallowest: dict[int, int], done: set[int]) -> None:
    where = f"decision cycle {origin.cycle} ({origin.phase} phase)"
    head = f"{indent}{wme_text(*origin.wme)}  added in {where} by {origin.maker}"
    tt = origin.wme[0]
    if origin.matched:
        if tt in done or shallowest.get(tt, nesting) != nesting:
            lines.append(f"{head} (explained at depth {shallowest.get(tt, nesting)})")
            return
        done.add(tt)
    pad = indent + "  "
    if origin.firing is not None:
        support = origin.firing.get("support")
        level = origin.firing.get("level")
        head += f" ({support}-support, goal level {level})" if support else ""
    lines.append(head)
    if origin.firing is not None:
        bindings = origin.firing.get("bindings") or {}
        if bindings:
            lines.append(pad + "bindings: " + ", ".join(f"{k}={text_of(v)}" for k, v in bindings.items()
                                                    if not k.startswith("<#")))
    if origin.candidates:
        lines.append(pad + "fired in that phase: " + ", ".join(origin.candidates))
    if origin.removed is not None:
        lines.append(pad + f"removed in decision cycle {origin.removed[0]} ({origin.removed[1]} phase)")
    if origin.matched or (origin.firing is not None and origin.firing.get("explained")):
        lines.append(pad + "matched:")
        for m in origin.matched:
            _format(m, pad + "  ", nesting + 1, lines, shallowest, done)
        known = {m.wme[0] for m in origin.matched}
        missing = [t for t in (origin.firing or {}).get("wmes") or () if t not in known]
        if missing:
            lines.append(pad + "  not in the trace (made before its first record): "
                         + " ".join(str(t) for t in dict.fromkeys(missing)))
    elif origin.firing is not None and origin.firing.get("wmes"):
        lines.append(pad + "matched timetags: " + " ".join(str(t) for t in origin.firing["wmes"]))


@dataclass(frozen=True)
class WhyNot:
    """Why ``rule`` did (not) fire at the end of decision cycle ``at``."""

    rule: str
    at: int
    production: Production
    failure: Failure | None
    instantiations: tuple[dict[str, str], ...]
    fired_in_cycle: int
    last_fired: int | None


def why_not(trace: Trace, rule: str, at: int, productions: dict[str, Production],
            order: Sequence[int] | None = None) -> WhyNot:
    """Check ``rule``'s conditions against working memory at the end of cycle ``at``, in
    ``order``, their evaluation order as the run's matchers loaded the rule files
    (:func:`adapt.engine.joins.join_orders`; by default as a matcher holding only the rule)."""
    if rule not in productions:
        near = [n for n in productions if rule.split("*")[0] in n][:5]
        hint = f" (rules like it: {', '.join(near)})" if near else ""
        raise TraceError(f"no rule named {rule} in the rule files{hint}")
    production = productions[rule]
    wm = memory_at(trace, at)
    table = IdentifierTable()
    wmes = [WME(table.decode(i), table.decode(a), table.decode(v), acc, tt)
            for tt, i, a, v, acc in sorted(wm, key=lambda w: w[0])]
    fired = 0
    last: int | None = None
    substates: set[str] = set()
    for record in trace.records():
        cycle = cycle_of(record)
        if cycle is None or cycle > at:
            break
        if record.get("kind") == "decision" and record.get("impasse"):
            substates.add(text_of(record["impasse"].get("state")))
        for f in record.get("firings") or ():
            if f.get("rule") == rule:
                last = cycle
                fired += cycle == at
    # the states of the goal stack, which (state <s> ...) tests: the top state
    # (^superstate nil, with ^io) and the impasses' substates still present
    ids_with_io = {text_of(i) for _, i, a, _, _ in wm if a == "io"}
    for _, i, a, v, _ in wm:
        name = text_of(i)
        if a == "superstate" and (name in substates or (v == "nil" and name in ids_with_io)):
            table.identifier(name).goal = True
    failure = first_failure(production, wmes, order=order)
    instantiations: tuple[dict[str, str], ...] = ()
    if failure is None:
        instantiations = tuple(
            {v.name: format_symbol(s) for v, s in b.items() if not v.name.startswith("<#")}
            for b in list(matches(production.conditions, wmes, order=order))[:5]
        )
    return WhyNot(rule, at, production, failure, instantiations, fired, last)


def format_why_not(result: WhyNot) -> str:
    """The text of ``adapt trace why --rule``."""
    p = result.production
    where = f" ({p.location})" if p.location else ""
    lines = [f"{result.rule}{where} at the end of decision {result.at}:"]
    if result.fired_in_cycle:
        lines.append(f"  it fired {result.fired_in_cycle} time(s) in decision cycle {result.at}")
    elif result.last_fired is not None:
        lines.append(f"  it last fired in decision cycle {result.last_fired}")
    else:
        lines.append("  it never fired up to here")
    failure = result.failure
    if failure is None:
        lines.append("  all its conditions match now; instantiations:")
        lines.extend("    " + ", ".join(f"{k}={v}" for k, v in b.items()) for b in result.instantiations)
        lines.append("  (an instantiation fires once, when it first matches; it fires again only "
                     "after it retracts)")
        return "\n".join(lines)
    cond = failure.condition
    loc = f"{cond.location}: " if cond.location is not None else ""
    lines.append(f"  condition {failure.index + 1} has no match: {loc}{condition_text(cond)}")
    shown = [", ".join(f"{v.name}={format_symbol(s)}" for v, s in b.items()
                       if not v.name.startswith("<#")) for b in failure.partials if b]
    negated = isinstance(cond, ConjunctiveNegation) or cond.negated
    if failure.waiting:
        lines.append("  relational tests of earlier conditions wait for its variables: "
                     + "; ".join(failure.waiting))
    if negated:
        lines.append("  it is negated, and working memory holds what it excludes:")
        lines.extend(f"    {w!r}" for w in failure.alone)
    elif failure.alone:
        lines.append("  WMEs that match it on their own, but not with the bindings before it:")
        lines.extend(f"    {w!r}" for w in failure.alone)
    else:
        lines.append("  no WME matches it at all")
    if shown:
        lines.append("  bindings from the conditions before it: " + "; ".join(s for s in shown if s))
    return "\n".join(lines)
