"""Preference memory: which instantiations hold each WME, and with what support.

One owner for the bookkeeping between preferences and working memory (the
kernel's firings, the results of substates and their justifications all go
through :meth:`PreferenceMemory.assert_preferences` and
:meth:`PreferenceMemory.retract`):

* an **acceptable** preference ``(id ^attr value +)`` for an ordinary
  attribute keeps the WME in working memory while an i-supported holder of
  it lives (:attr:`PreferenceMemory.isup`, a list of holders per WME) or an
  o-supported one has made it (:attr:`PreferenceMemory.osup`, the last one);
* a **reject** ``-`` of an o-supported holder removes every preference for
  the WME, i-supported ones included (Soar's ``process_o_rejects``): the WME
  goes; a reject of an i-supported holder keeps the WME out of working
  memory while that holder lives (:attr:`PreferenceMemory.irej`);
* a preference on a state's ``^operator`` goes to the goal's operator slot
  (:class:`adapt.engine.goals.SlotPreference`); an acceptable or require
  one also puts the WME ``(S ^operator O +)`` in working memory while a
  holder lives.

A *holder* is an :class:`~adapt.engine.instantiation.Instantiation` (a
production's firing, or a justification); what it holds is recorded on it
(``i_wmes``, ``slot_prefs``) so that :meth:`PreferenceMemory.retract`
undoes exactly that.

The order of working-memory changes
-----------------------------------
The WMEs that preferences add and remove are buffered here and handed to
working memory by :meth:`PreferenceMemory.flush` (at the kernel's commit) in
the order Soar makes them, which decides their timetags and so the order in
which the matcher meets them (``decide_non_context_slots`` and
``do_buffered_acceptable_preference_wme_changes`` in Soar's ``decide.cpp``):
a slot ``(id ^attr)`` is *marked* when a preference for it is asserted or
retracted; the slots are then decided the last marked first (Soar's
``changed_slots`` list grows at its head), each removing its WMEs the newest
first and adding its new ones in candidate order (by each value's most recent
acceptable preference, oldest first); then the ``(S ^operator O +)`` WMEs of
the operator slots whose acceptable or require preferences changed, again the
last marked slot first, in a slot the require preferences first and the
newest preference first.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Final

from adapt.engine.goals import SlotPreference
from adapt.engine.memory import WmeKey, WorkingMemory
from adapt.engine.preferences import Preference, same_symbol
from adapt.engine.production import PreferenceKind
from adapt.engine.symbols import Identifier, Symbol, level_of

if TYPE_CHECKING:  # pragma: no cover
    from adapt.engine.goals import Goal
    from adapt.engine.instantiation import Instantiation

__all__ = ["PreferenceMemory", "MadePreference"]

#: A preference made by a firing: ``(kind, id, attr, value, referent,
#: o_supported)`` -- ``o_supported`` is the support of the firing that made it.
MadePreference = tuple[PreferenceKind, Identifier, Symbol, Symbol, "Symbol | None", bool]

#: added to a require preference's time: its WME comes before the acceptable ones
_REQUIRE_FIRST: Final = 1 << 40
_ACCEPTABLE: Final = PreferenceKind.ACCEPTABLE
_REJECT: Final = PreferenceKind.REJECT
_REQUIRE: Final = PreferenceKind.REQUIRE


def key_is_acceptable(keys: list[WmeKey]) -> bool:
    """Whether the WMEs are acceptable-preference WMEs ``(S ^operator O +)``."""
    return bool(keys) and keys[0][3]


class PreferenceMemory:
    """The support of every WME made by preferences (see the module docstring).

    Parameters
    ----------
    wm : WorkingMemory
        Where supported WMEs are added and unsupported ones removed.
    goals : dict
        The live goals by state identifier (shared with the kernel): a
        preference on ``(S ^operator ...)`` for one of them goes to its slot.
    """

    __slots__ = ("wm", "goals", "isup", "osup", "irej", "changes", "marks", "op_marks",
                 "clock", "made_at")

    def __init__(self, wm: WorkingMemory, goals: dict[Symbol, Goal]) -> None:
        self.wm = wm
        self.goals = goals
        #: WME key -> the i-supported holders of its acceptable preference
        self.isup: dict[WmeKey, list[Instantiation]] = {}
        #: WME key -> the o-supported holder that made it
        self.osup: dict[WmeKey, Instantiation] = {}
        #: WME key -> the i-supported holders of a reject of it
        self.irej: dict[WmeKey, list[Instantiation]] = {}
        #: the buffered WME changes (True: add, False: remove) until :meth:`flush`
        self.changes: dict[WmeKey, bool] = {}
        #: the slots ``(id, attr)`` marked since the last flush, first mark first
        self.marks: dict[tuple[Symbol, Symbol], None] = {}
        #: the operator slots (state ids) whose acceptable or require
        #: preferences changed since the last flush, first mark first
        self.op_marks: dict[Symbol, None] = {}
        #: counts acceptable (and require) preferences as they are asserted
        self.clock = 0
        #: WME key -> when its most recent acceptable preference of this batch
        #: was asserted (require preferences of operators count double: they come first)
        self.made_at: dict[WmeKey, int] = {}

    # -- the buffered changes ---------------------------------------------------
    def _add(self, key: WmeKey) -> None:
        """Request the WME ``key`` (working memory's semantics: a removal
        requested before is overridden)."""
        self.changes[key] = True

    def _remove(self, key: WmeKey) -> None:
        """Request the removal of the WME ``key``; cancels a requested addition
        of a WME that is not in working memory."""
        changes = self.changes
        if changes.get(key) is True and key not in self.wm:
            del changes[key]
        else:
            changes[key] = False

    def flush(self) -> None:
        """Hand the buffered changes to working memory in Soar's order (see the
        module docstring)."""
        changes = self.changes
        if not changes:
            self.marks.clear()
            self.op_marks.clear()
            return
        self.changes = {}
        wm = self.wm
        made_at = self.made_at
        by_slot: dict[tuple[Symbol, Symbol], list[tuple[WmeKey, bool]]] = {}
        for key, add in changes.items():
            slot = (key[0], key[1])
            group = by_slot.get(slot)
            if group is None:
                by_slot[slot] = [(key, add)]
            else:
                group.append((key, add))
        order: dict[tuple[Symbol, Symbol], None] = {}
        for slot in reversed(self.marks):
            if slot in by_slot:
                order[slot] = None
        for ident in reversed(self.op_marks):
            if (ident, "operator") in by_slot:
                order[(ident, "operator")] = None
        if len(order) < len(by_slot):  # changes of slots not marked (none expected)
            for slot in by_slot:
                order[slot] = None
        for slot in order:
            group = by_slot[slot]
            if len(group) > 1:
                removes = [key for key, add in group if not add]
                removes.sort(key=self._timetag_of, reverse=True)
                adds = [key for key, add in group if add]
                if slot[1] == "operator" and key_is_acceptable(adds):
                    adds.sort(key=lambda k: -made_at.get(k, 0))
                else:
                    adds.sort(key=lambda k: made_at.get(k, 0))
                for key in removes:
                    wm.remove_key(key)
                for key in adds:
                    wm.add_key(key)
            else:
                key, add = group[0]
                if add:
                    wm.add_key(key)
                else:
                    wm.remove_key(key)
        self.marks.clear()
        self.op_marks.clear()
        made_at.clear()

    def _timetag_of(self, key: WmeKey) -> int:
        w = self.wm.get(*key)
        return w[4] if w is not None else 0

    # -- asserting -------------------------------------------------------------
    def assert_preferences(self, holder: Instantiation, prefs: list[MadePreference],
                           o_supported: bool, *, o_rejects: bool = True) -> bool:
        """Assert ``prefs`` held by ``holder`` with the given support.

        ``o_rejects`` false: the caller has already applied the o-supported
        rejects (a firing's o-rejects go before every other preference of
        its elaboration cycle).  Returns True when an o-supported acceptable
        preference for an ordinary WME was asserted (the caller may have to
        extend a goal dependency set).
        """
        goals = self.goals
        isup, irej, osup = self.isup, self.irej, self.osup
        changes = self.changes
        marks = self.marks
        made_at = self.made_at
        o_local = False
        for p in prefs:
            kind, ident, attr, value, ref, _ = p
            if attr == "operator" and ident in goals:
                self.add_slot_preference(goals[ident], Preference(kind, value, ref), holder)
            elif kind is _ACCEPTABLE:
                marks[(ident, attr)] = None
                key = (ident, attr, value, False)
                if o_supported:
                    osup[key] = holder
                    o_local = True
                else:
                    supporters = isup.get(key)
                    if supporters is None:
                        isup[key] = [holder]
                    else:
                        supporters.append(holder)
                    holder.i_wmes.append(key)
                self.clock += 1
                made_at[key] = self.clock
                if key not in irej:
                    changes[key] = True
            elif kind is _REJECT:
                marks[(ident, attr)] = None
                if o_supported:
                    if o_rejects:
                        self.o_reject(p)
                else:
                    key = (ident, attr, value, False)
                    irej.setdefault(key, []).append(holder)
                    holder.i_wmes.append(key)
                    self._remove(key)
            else:  # another preference for an ordinary attribute: it marks the slot
                marks[(ident, attr)] = None
        return o_local

    def add_slot_preference(self, goal: Goal, pref: Preference, holder: Instantiation) -> None:
        """Put ``pref`` in ``goal``'s operator slot, held by ``holder``."""
        sp = SlotPreference(pref, holder)
        goal.prefs.append(sp)
        goal.changed = True
        holder.slot_prefs.append((goal, sp))
        kind = pref.kind
        if kind is _ACCEPTABLE or kind is _REQUIRE:
            self.op_marks[goal.id] = None
            key = (goal.id, "operator", pref.value, True)
            supporters = self.isup.get(key)
            if supporters is None:
                self.isup[key] = [holder]
            else:
                supporters.append(holder)
            self.clock += 1
            # the require preferences' WMEs are made first (Soar's slot order)
            made = self.clock + (_REQUIRE_FIRST if kind is _REQUIRE else 0)
            if made > self.made_at.get(key, 0):
                self.made_at[key] = made
            self.changes[key] = True

    def o_reject(self, p: MadePreference) -> list[Goal]:
        """An o-supported reject: remove every preference for the value, and the WME.

        In an operator slot (Soar's ``process_o_rejects``) every preference for
        the operator leaves the slot, whatever instantiation made it, with its
        ``(S ^operator O +)`` WME.  Returns the goals whose selected operator
        that was (Soar deselects it).
        """
        _, ident, attr, value, _, _ = p
        if attr == "operator" and ident in self.goals:
            goal = self.goals[ident]
            kept = [sp for sp in goal.prefs if sp.preference.value is not value]
            if len(kept) == len(goal.prefs):
                return []
            goal.prefs = kept
            goal.changed = True
            self.op_marks[ident] = None
            key = (ident, "operator", value, True)
            if self.isup.pop(key, None) is not None:
                self._remove(key)
            operator = goal.operator
            return [goal] if operator is not None and same_symbol(operator, value) else []
        self.marks[(ident, attr)] = None
        wme_key = (ident, attr, value, False)
        had = self.osup.pop(wme_key, None) is not None
        if self.isup.pop(wme_key, None) is not None or had:
            self._remove(wme_key)
        return []

    # -- retracting ----------------------------------------------------------------
    def retract(self, holder: Instantiation) -> list[Goal]:
        """Remove everything ``holder`` supports with i-support.

        Returns the goals whose *selected* operator just lost an acceptable
        preference of ``holder`` (Soar deselects them at once).
        """
        isup, osup = self.isup, self.osup
        irej = self.irej
        marks = self.marks
        for key in holder.i_wmes:
            marks[(key[0], key[1])] = None
            if irej:
                rejecters = irej.get(key)
                if rejecters is not None and holder in rejecters:
                    rejecters.remove(holder)
                    if not rejecters:
                        del irej[key]
                        if key in isup or key in osup:
                            self._add(key)
                    continue
            supporters = isup.get(key)
            if supporters is None or holder not in supporters:
                continue
            if len(supporters) == 1:
                del isup[key]
                if key not in osup:
                    self._remove(key)
            else:
                supporters.remove(holder)
        deselect: list[Goal] = []
        for goal, sp in holder.slot_prefs:
            try:
                goal.prefs.remove(sp)
            except ValueError:
                continue
            goal.changed = True
            kind = sp.preference.kind
            if kind is _ACCEPTABLE or kind is _REQUIRE:
                self.op_marks[goal.id] = None
                value = sp.preference.value
                key = (goal.id, "operator", value, True)
                supporters = isup.get(key)
                if supporters is not None:
                    supporters.remove(holder)
                    if not supporters:
                        del isup[key]
                        self._remove(key)
                operator = goal.operator
                if kind is _ACCEPTABLE and operator is not None and same_symbol(operator, value):
                    deselect.append(goal)
        return deselect

    def drop_o_supported(self, key: WmeKey, holder: Instantiation | None = None) -> None:
        """Forget the o-supported WME ``key`` (only if ``holder`` made it, when
        given); the WME goes unless something i-supports it."""
        if key not in self.osup or (holder is not None and self.osup[key] is not holder):
            return
        del self.osup[key]
        self.marks[(key[0], key[1])] = None
        if key not in self.isup:
            self._remove(key)

    def drop_levels(self, level: int) -> None:
        """Forget the o-supported WMEs on identifiers of goal level ``level`` or lower
        (a goal at ``level`` is being removed)."""
        for key in [k for k in self.osup if level_of(k[0]) >= level]:
            self.drop_o_supported(key)
