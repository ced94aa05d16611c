"""Results of substates, their justifications, and the goal dependency set.

A preference made by an instantiation in a substate (level ``L``) whose
identifier belongs to a higher level is a **result**; so is every preference
of the same firing on an identifier that a result links into the higher
level (those identifiers are *promoted* to that level).

A result is not supported by the instantiation that made it (that goes away
with the substate) but by a **justification** (:class:`Justification`, an
instantiation without a production), built as Soar builds one:

* **Grounds** -- backtrace from the instantiation's matched WMEs through the
  instantiations that made the local WMEs it tested (and through theirs, and
  so on); every matched WME whose identifier belongs to a higher level is a
  ground.  A substate's ``^item`` WME backtraces to the acceptable preference
  ``(S ^operator O +)`` behind it (in Soar, ``^item`` is made by an
  architectural instantiation that tests that preference).
* **Negated conditions** -- every negated condition and conjunctive negation
  of the instantiations backtraced through (including those a deeper
  justification holds), instantiated with that instantiation's bindings, is
  kept when it is *connected to the grounds*: a negated condition when its
  identifier is one of the identifiers the grounds mention (as identifier or
  value); a conjunctive negation when all of its conditions become connected
  (its positive conditions connect the variables they bind).  Negations that
  test substate-local structure are dropped (Soar's "local negations"): they
  do not retract the result.

The justification's match goal is the lowest state among its grounds' ids;
it is **o-supported** when it tests that state's selected operator (then the
result persists), otherwise **i-supported**: it is retracted, as an ordinary instantiation at
that level, when one of its grounds leaves working memory or one of its
negated conditions comes to have a match (:meth:`ResultMaker.check_negations`,
called by :meth:`adapt.engine.kernel.Kernel.commit`).  Operator-slot
preferences that are results (``(<ss> ^operator <o> >)``, ``<o1> > <o2>``,
``=`` ...) are held by the justification the same way and leave the slot when
it retracts; o-supported ones stay in the slot whatever happens to their basis
(until their goal is removed), as in Soar.

**Goal dependency set.** When an o-supported instantiation in a substate makes
local structure, the superstate WMEs behind it (backtraced the same way, but
stopping at local o-supported WMEs; negated conditions play no part, as in
Soar) join the substate's GDS; when one of them leaves working memory, the
substate is removed (and the decision cycle regenerates it if the impasse
still holds).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Final

from adapt.engine.conditions import Bindings, exists
from adapt.engine.events import Event
from adapt.engine.instantiation import Instantiation
from adapt.engine.production import (
    Condition,
    ConditionElement,
    ConjunctiveNegation,
    PreferenceKind,
    Variable,
    equality_variable,
)
from adapt.engine.reorder import join_order
from adapt.engine.support import MadePreference
from adapt.engine.symbols import Identifier, level_of
from adapt.engine.vocabulary import Support
from adapt.engine.wme import WME

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.goals import Goal
    from adapt.engine.kernel import Kernel

__all__ = ["ResultMaker", "Justification"]

_ACCEPTABLE: Final = PreferenceKind.ACCEPTABLE


#: A negated condition (or conjunctive negation) of a justification, with the
#: bindings of the instantiation it came from.
Negation = tuple[ConditionElement, Bindings]


class Justification(Instantiation):
    """The instantiation-like support of results: grounds plus negated conditions.

    ``wmes`` are the grounds (positive conditions, instantiated: the WMEs);
    ``negations`` the negated conditions and conjunctive negations kept, each
    with the bindings of the substate instantiation it came from.  The
    justification holds while every ground is in working memory and no
    negation has a match.
    """

    __slots__ = ("negations",)

    def __init__(self, goal: Goal, support: Support, wmes: tuple[WME, ...],
                 negations: tuple[Negation, ...]) -> None:
        super().__init__(None, None, goal, support, wmes)
        self.negations = negations

    def __repr__(self) -> str:
        tags = [w.timetag for w in self.wmes]
        return (f"Justification({self.support.value}, level {self.goal.level}, {tags}, "
                f"{len(self.negations)} negated)")


class ResultMaker:
    """Finds results, builds their justifications, keeps the GDS up to date."""

    __slots__ = ("kernel", "grounds_index", "negated_index", "ncc_justs")

    def __init__(self, kernel: Kernel) -> None:
        self.kernel = kernel
        #: timetag -> i-supported justifications that test that WME
        self.grounds_index: dict[int, list[Instantiation]] = {}
        #: identifier -> justifications with a negated condition on it
        self.negated_index: dict[object, list[Justification]] = {}
        #: justifications with a conjunctive negation (checked on every change)
        self.ncc_justs: list[Justification] = []

    def level(self, ident: object) -> int:
        """The goal level an identifier belongs to (0 when unknown)."""
        return level_of(ident)

    def split(self, inst: Instantiation,
              prefs: list[MadePreference]) -> set[MadePreference] | None:
        """The preferences of ``inst`` that are results (``None`` when none)."""
        level = inst.goal.level
        results: set[MadePreference] = set()
        linked: set[Identifier] = set()
        changed = True
        while changed:
            changed = False
            for p in prefs:
                if p in results:
                    continue
                ident = p[1]
                if level_of(ident) < level or ident in linked:
                    results.add(p)
                    changed = True
                    value = p[3]
                    if type(value) is Identifier and value.level >= level \
                            and value not in linked:
                        linked.add(value)
        if not results:
            return None
        return results

    def make(self, inst: Instantiation, results: list[MadePreference]) -> None:
        """Assert the results of ``inst`` with a justification's support."""
        k = self.kernel
        negated: list[Negation] = []
        grounds = self.backtrace(inst, stop_at_o=False, negated=negated)
        if not grounds and self._surely_ungrounded(inst):
            self._ungrounded(inst, results)
            return
        target = min((self.level(p[1]) for p in results), default=inst.goal.level - 1)
        just = self._justification(grounds, negated, target)
        goal = just.goal
        # bottom up, as Soar's chunker does: a justification whose match goal
        # is below the results' level makes them results of its own, and the
        # justification for those -- one level up, backtracing through the
        # first one's local grounds -- is the one that holds them (so a result
        # two levels up that depends on the top state's selected operator is
        # o-supported there)
        while goal.level > target:
            negated = []
            higher = self.backtrace(just, stop_at_o=False, negated=negated)
            if not higher:
                break
            just = self._justification(higher, negated, target)
            goal = just.goal
        grounds = list(just.wmes)
        negations = just.negations
        support = just.support
        for p in results:
            self._promote(p, target)
        k.events.emit(Event.RESULT, (inst, just, results))
        if inst.support is Support.O:
            # Soar keeps the firing's own o-supported preferences too (the
            # justification holds clones of them) until the substate goes: the
            # result outlives a justification that retracts meanwhile
            self._keep_own(inst, results)
        k.preferences.assert_preferences(just, results, support is Support.O)
        if just.slot_prefs and support is Support.O:
            # o-supported operator-slot preferences stay, as in Soar, until
            # their goal goes
            goal.instantiations[id(just)] = just
        if support is Support.O:
            # an o-supported justification keeps its results, but its match
            # (grounds, negations) is watched: when it goes, its retraction is
            # work of its goal for one elaboration cycle, as in Soar
            self._watch(just, grounds, negations)
        elif just.i_wmes or just.slot_prefs:
            goal.instantiations[id(just)] = just
            self._watch(just, grounds, negations)

    def _watch(self, just: Justification, grounds: list[WME],
               negations: tuple[Negation, ...]) -> None:
        """Retract ``just`` when a ground leaves or a negation comes to match."""
        index = self.grounds_index
        for w in grounds:
            index.setdefault(w.timetag, []).append(just)
        for element, bindings in negations:
            if isinstance(element, Condition):
                self.negated_index.setdefault(bindings[element.id], []).append(just)
            elif just not in self.ncc_justs:
                self.ncc_justs.append(just)
        if negations and self._violated(just):
            # a negation already has a match (the instantiation behind it
            # is waiting to retract): the justification does not hold
            self.kernel.schedule_retraction(just)

    def _justification(self, grounds: list[WME], negated: list[Negation],
                       target: int) -> Justification:
        """The justification over ``grounds``: its match goal is the lowest state
        among its WMEs' identifiers; it is o-supported when it tests that
        state's selected operator."""
        k = self.kernel
        goal: Goal | None = None
        for w in grounds:
            g = k.goals.get(w.id)
            if g is not None and (goal is None or g.level > goal.level):
                goal = g
        if goal is None:
            goal = _goal_at(k, target)
        support = Support.I
        for w in grounds:
            if w.id is goal.id and w.attr == "operator" and not w.acceptable:
                support = Support.O
                break
        return Justification(goal, support, tuple(grounds), _connected(grounds, negated))

    def _surely_ungrounded(self, inst: Instantiation) -> bool:
        """Whether a complete backtrace of ``inst`` meets no superstate WME.

        Called only when :meth:`backtrace` found no grounds.  This backtrace
        also follows a selected operator ``(S ^operator O)`` to the
        instantiations behind its acceptable preference, as Soar does.  It
        answers ``False`` -- not sure -- when it meets a local WME that is not
        architectural and whose creator is no longer known (an instantiation
        that has retracted): Soar would still backtrace through it, and the
        result is then kept with an empty justification, as before.
        """
        k = self.kernel
        level = inst.goal.level
        seen: set[int] = {id(inst)}
        stack = [inst]
        while stack:
            current = stack.pop()
            for w in current.wmes:
                if level_of(w.id) < level:
                    return False
                g = k.goals.get(w.id)
                attr = w.attr
                if g is not None:
                    if attr == "item":  # stands for the superstate's (S ^operator O +)
                        return False
                    if attr == "operator" and not w.acceptable:
                        creators = list(k.preferences.isup.get((w.id, attr, w.value, True), ()))
                        if not creators:
                            return False
                    else:
                        key = w.key
                        if key in g.arch:
                            continue
                        creators = list(k.preferences.isup.get(key, ()))
                else:
                    key = w.key
                    creators = list(k.preferences.isup.get(key, ()))
                o = k.preferences.osup.get(w.key)
                if o is not None:
                    creators.append(o)
                if not creators:
                    return False
                for c in creators:
                    if id(c) not in seen:
                        seen.add(id(c))
                        stack.append(c)
        return True

    def _ungrounded(self, inst: Instantiation, results: list[MadePreference]) -> None:
        """Results whose justification would have no grounds stay the firing's own.

        Soar builds no justification then ("no conditions"): the results keep
        the preferences of the substate instantiation, with its support, and
        go with the substate.  An i-supported one retracts with the
        instantiation; an o-supported one persists until the substate is
        removed (:attr:`Goal.ungrounded`, emptied by
        :meth:`adapt.engine.kernel.Kernel.remove_goal`).
        """
        k = self.kernel
        target = min(self.level(p[1]) for p in results)
        for p in results:
            self._promote(p, target)
        k.events.emit(Event.RESULT, (inst, None, results))
        self._keep_own(inst, results)

    def _keep_own(self, inst: Instantiation, results: list[MadePreference]) -> None:
        """Assert ``results`` held by the substate instantiation that made them,
        with its support; o-supported ones are removed with its goal."""
        k = self.kernel
        goal = inst.goal
        o_supported = inst.support is Support.O
        k.preferences.assert_preferences(inst, results, o_supported)
        if o_supported:
            goals = k.goals
            goal.ungrounded.extend(
                ((p[1], p[2], p[3], False), inst) for p in results
                if p[0] is _ACCEPTABLE and not (p[2] == "operator" and p[1] in goals))
        if inst.i_wmes or inst.slot_prefs:
            goal.instantiations[inst.key if inst.key is not None else id(inst)] = inst

    def check_negations(self, added: list[WME], removed: list[WME]) -> None:
        """Retract the justifications whose negated conditions now have a match.

        Called after every working-memory commit.  A plain negated condition
        can only come to match through an added WME on its identifier; a
        conjunctive negation is re-evaluated after any change.
        """
        index = self.negated_index
        if index and added:
            hit: list[Justification] = []
            for w in added:
                justs = index.get(w[0])
                if justs:
                    live = [j for j in justs if not (j.retracted or j.unmatched)]
                    if len(live) != len(justs):
                        if live:
                            index[w[0]] = live
                        else:
                            del index[w[0]]
                    for j in live:
                        if j not in hit:
                            hit.append(j)
            for j in hit:
                if self._violated(j):
                    self.kernel.schedule_retraction(j)
        if self.ncc_justs and (added or removed):
            live = [j for j in self.ncc_justs if not (j.retracted or j.unmatched)]
            self.ncc_justs = live
            for j in live:
                if self._violated(j):
                    self.kernel.schedule_retraction(j)

    def _violated(self, just: Justification) -> bool:
        """Whether one of the justification's negations has a match now."""
        wm = self.kernel.wm
        for element, bindings in just.negations:
            if exists(element, wm, bindings, join_order):
                return True
        return False

    def note_o_local(self, inst: Instantiation) -> None:
        """An o-supported instantiation made local structure: extend its goal's GDS."""
        goal = inst.goal
        if goal.level == 0:
            return
        k = self.kernel
        for w in self.backtrace(inst, stop_at_o=True):
            if w.timetag not in goal.gds:
                goal.gds.add(w.timetag)
                k.gds_index.setdefault(w.timetag, set()).add(goal)

    def backtrace(self, inst: Instantiation, *, stop_at_o: bool,
                  negated: list[Negation] | None = None) -> list[WME]:
        """The WMEs above ``inst``'s level that its match depends on.

        When ``negated`` is given, the negated conditions and conjunctive
        negations of every instantiation backtraced through are appended to
        it, each with that instantiation's bindings.
        """
        k = self.kernel
        level = inst.goal.level
        grounds: dict[int, WME] = {}
        seen: set[int] = {id(inst)}
        stack = [inst]
        while stack:
            current = stack.pop()
            if negated is not None:
                _negations_of(current, negated)
            traces = current.traces
            for i, w in enumerate(current.wmes):
                if level_of(w.id) < level:
                    grounds[w.timetag] = w
                    continue
                if traces is not None:
                    traced = traces[i]
                    if traced is not None and w.attr != "item":
                        if stop_at_o and traced.support is Support.O:
                            continue
                        if id(traced) not in seen:
                            seen.add(id(traced))
                            stack.append(traced)
                        continue
                key = w.key
                if w.attr == "item" and w.id in k.goals:
                    sub = k.goals[w.id]
                    if sub.superstate is not None:
                        acc = k.wm.get(sub.superstate.id, "operator", w.value, True)
                        if acc is not None:
                            grounds[acc.timetag] = acc
                    continue
                creators: list[Instantiation] = list(k.preferences.isup.get(key, ()))
                o = k.preferences.osup.get(key)
                if o is not None:
                    if stop_at_o:
                        continue
                    creators.append(o)
                for c in creators:
                    if id(c) not in seen:
                        seen.add(id(c))
                        stack.append(c)
        return sorted(grounds.values(), key=lambda w: w.timetag)

    def _promote(self, p: MadePreference, level: int) -> None:
        """Move an identifier a result links upwards (and its structure) to ``level``."""
        value = p[3]
        if type(value) is not Identifier:
            return
        k = self.kernel
        stack = [value]
        while stack:
            ident = stack.pop()
            if ident.level <= level:
                continue
            ident.level = level
            for w in k.wm.of(ident):
                if type(w.value) is Identifier:
                    stack.append(w.value)


def _goal_at(k: Kernel, level: int) -> Goal:
    goal = k.top
    while goal.lower is not None and goal.level < level:
        goal = goal.lower
    return goal


def _negations_of(inst: Instantiation, out: list[Negation]) -> None:
    """Append the negated conditions of ``inst`` with its bindings."""
    if isinstance(inst, Justification):
        out.extend(inst.negations)
        return
    rule = inst.rule
    if rule is None:
        return
    production = rule.production
    elements = [c for c in production.conditions
                if isinstance(c, ConjunctiveNegation) or c.negated]
    if not elements:
        return
    bindings = inst.bindings
    if bindings is None:
        bindings = production.bindings(inst.wmes)
    for element in elements:
        out.append((element, bindings))


def _connected(grounds: list[WME], negated: list[Negation]) -> tuple[Negation, ...]:
    """The negations connected to the grounds (Soar keeps only those).

    The grounds mark the identifiers they mention (identifier and value
    fields).  A negated condition is connected when its identifier is marked;
    a conjunctive negation when all of its conditions become connected, its
    positive conditions marking the identifiers and variables they bind.
    """
    marked: set[object] = set()
    for w in grounds:
        marked.add(w.id)
        if type(w.value) is Identifier:
            marked.add(w.value)
    out: list[Negation] = []
    seen: set[tuple[int, int]] = set()
    for element, bindings in negated:
        key = (id(element), id(bindings))
        if key in seen:
            continue
        seen.add(key)
        if _in_tc(element, bindings, marked):
            out.append((element, bindings))
    return tuple(out)


def _term_marked(term: object, bindings: Bindings, marked: set[object]) -> bool:
    if isinstance(term, Variable):
        if term in bindings:
            return bindings[term] in marked
        return term in marked
    return term in marked


def _in_tc(element: ConditionElement, bindings: Bindings, marked: set[object]) -> bool:
    if isinstance(element, Condition):
        return _term_marked(element.id, bindings, marked)
    local = set(marked)
    pending = list(element.conditions)
    changed = True
    while pending and changed:
        changed = False
        for c in list(pending):
            if not _in_tc(c, bindings, local):
                continue
            pending.remove(c)
            changed = True
            if isinstance(c, Condition) and not c.negated:
                for test in (c.id, c.value):
                    var = test if isinstance(test, Variable) else equality_variable(test)
                    if var is None:
                        continue
                    local.add(bindings[var] if var in bindings else var)
    return not pending
