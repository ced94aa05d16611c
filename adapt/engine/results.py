"""Results of substates, their justifications, and the goal dependency set.

A preference made by an instantiation in a substate (level ``L``) whose
identifier belongs to a higher level is a **result**; so is every preference
of the same firing on an identifier that a result links into the higher
level (those identifiers are *promoted* to that level).

A result is not supported by the instantiation that made it (that goes away
with the substate) but by a **justification**: the superstate WMEs the
substate's reasoning depended on, found by backtracing from the
instantiation's matched WMEs through the instantiations that made the local
WMEs it tested.  A substate's ``^item`` WME backtraces to the acceptable
preference ``(S ^operator O +)`` behind it.  The justification's match goal is
the lowest state among its WMEs; it is **o-supported** when it tests that
state's selected operator (then the result persists), otherwise
**i-supported**: it is retracted, as an ordinary instantiation at that level,
when any of its WMEs leaves working memory.

**Goal dependency set.** When an o-supported instantiation in a substate makes
local structure, the superstate WMEs behind it (backtraced the same way, but
stopping at local o-supported WMEs) join the substate's GDS; when one of them
leaves working memory, the substate is removed (and the decision cycle
regenerates it if the impasse still holds).

Not modelled: negated conditions in justifications (a result does not retract
when a WME appears that a substate rule tested for absence).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from adapt.engine.instantiation import SUPPORT_I, SUPPORT_O, Instantiation
from adapt.engine.preferences import Preference
from adapt.engine.production import PreferenceKind
from adapt.engine.symbols import Identifier
from adapt.engine.wme import WME

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.goals import Goal
    from adapt.engine.kernel import Kernel

__all__ = ["ResultMaker"]

_ACCEPTABLE = PreferenceKind.ACCEPTABLE


class ResultMaker:
    """Finds results, builds their justifications, keeps the GDS up to date."""

    __slots__ = ("kernel", "grounds_index")

    def __init__(self, kernel: Kernel) -> None:
        self.kernel = kernel
        #: timetag -> i-supported justifications that test that WME
        self.grounds_index: dict[int, list[Instantiation]] = {}

    def level(self, ident: object) -> int:
        """The goal level an identifier belongs to (0 when unknown)."""
        return self.kernel.id_level.get(ident, 0)  # type: ignore[arg-type]

    def split(self, inst: Instantiation, prefs: list[tuple]) -> set[tuple] | None:
        """The preferences of ``inst`` that are results (``None`` when none)."""
        level = inst.goal.level
        id_level = self.kernel.id_level
        results: set[tuple] = set()
        linked: set[Identifier] = set()
        changed = True
        while changed:
            changed = False
            for p in prefs:
                if p in results:
                    continue
                ident = p[1]
                if id_level.get(ident, 0) < level or ident in linked:
                    results.add(p)
                    changed = True
                    value = p[3]
                    if type(value) is Identifier and id_level.get(value, 0) >= level \
                            and value not in linked:
                        linked.add(value)
        if not results:
            return None
        return results

    def make(self, inst: Instantiation, results: list[tuple]) -> None:
        """Assert the results of ``inst`` with a justification's support."""
        k = self.kernel
        grounds = self.backtrace(inst, stop_at_o=False)
        target = min((self.level(p[1]) for p in results), default=inst.goal.level - 1)
        # the justification's match goal: the lowest state among its WMEs' ids
        goal: Goal | None = None
        for w in grounds:
            g = k.goals.get(w.id)
            if g is not None and (goal is None or g.level > goal.level):
                goal = g
        if goal is None:
            goal = _goal_at(k, target)
        support = SUPPORT_I
        for w in grounds:
            if w.id is goal.id and w.attr == "operator" and not w.acceptable:
                support = SUPPORT_O
                break
        just = Instantiation(None, None, goal, support, tuple(grounds))
        for p in results:
            self._promote(p, target)
        k.emit("result", (inst, just, results))
        for p in results:
            kind, ident, attr, value, ref, _ = p
            if attr == "operator" and ident in k.goals:
                k._add_slot_pref(k.goals[ident], Preference(kind, value, ref), just)
                continue
            if kind is not _ACCEPTABLE:
                if kind is PreferenceKind.REJECT and support == SUPPORT_O:
                    k._o_reject(p)
                continue
            key = (ident, attr, value, False)
            if support == SUPPORT_O:
                k.osup[key] = just
            else:
                k.isup.setdefault(key, []).append(just)
                just.i_wmes.append(key)
            k.wm.add(ident, attr, value)
        if just.i_wmes or just.slot_prefs:
            goal.instantiations[id(just)] = just
            index = self.grounds_index
            for w in grounds:
                index.setdefault(w.timetag, []).append(just)

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

    def backtrace(self, inst: Instantiation, *, stop_at_o: bool) -> list[WME]:
        """The WMEs above ``inst``'s level that its match depends on."""
        k = self.kernel
        level = inst.goal.level
        id_level = k.id_level
        grounds: dict[int, WME] = {}
        seen: set[int] = {id(inst)}
        stack = [inst]
        while stack:
            current = stack.pop()
            for w in current.wmes:
                if id_level.get(w.id, 0) < level:
                    grounds[w.timetag] = w
                    continue
                key = w.key
                if w.attr == "item" and w.id in k.goals:
                    sub = k.goals[w.id]
                    if sub.superstate is not None:
                        acc = k.wm.get(sub.superstate.id, "operator", w.value, True)
                        if acc is not None:
                            grounds[acc.timetag] = acc
                    continue
                creators: list[Instantiation] = list(k.isup.get(key, ()))
                o = k.osup.get(key)
                if o is not None:
                    if stop_at_o:
                        continue
                    creators.append(o)
                for c in creators:
                    if id(c) not in seen:
                        seen.add(id(c))
                        stack.append(c)
        return sorted(grounds.values(), key=lambda w: w.timetag)

    def _promote(self, p: tuple, level: int) -> None:
        """Move an identifier a result links upwards (and its structure) to ``level``."""
        value = p[3]
        if type(value) is not Identifier:
            return
        k = self.kernel
        stack = [value]
        while stack:
            ident = stack.pop()
            if k.id_level.get(ident, 0) <= level:
                continue
            k.id_level[ident] = level
            for w in k.wm.of(ident):
                if type(w.value) is Identifier:
                    stack.append(w.value)


def _goal_at(k: Kernel, level: int) -> Goal:
    goal = k.top
    while goal.lower is not None and goal.level < level:
        goal = goal.lower
    return goal

