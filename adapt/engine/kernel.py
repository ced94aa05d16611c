"""The kernel's mechanics: firing, support, retraction, goals and WM phases.

:class:`Kernel` holds one agent's state -- working memory, the matcher,
preference memory, the goal stack -- and the operations the decision cycle
(:mod:`adapt.engine.cycle`) sequences:

* :meth:`Kernel.commit` -- Soar's working-memory phase: apply the buffered WME
  changes, feed the matcher, sort its match-set changes into the goals'
  pending i-assertions, o-assertions and retractions, and remove goals whose
  goal dependency set changed;
* :meth:`Kernel.fire` -- one elaboration cycle at one goal: retract, then fire
  every pending match of one kind in parallel (all right-hand sides are
  evaluated before any preference is asserted; o-rejects go first);
* :meth:`Kernel.select`, :meth:`Kernel.create_impasse`,
  :meth:`Kernel.remove_goal` -- what decisions do.

Preference memory for ordinary attributes is a support count: a WME
``(id ^attr value)`` is in working memory while some live i-supported
instantiation supports it or some o-supported preference holds it
(:attr:`Kernel.isup`, :attr:`Kernel.osup`).  A ``-`` action of an o-supported
instantiation removes every preference for that WME (i-supported ones
included, as Soar's ``process_o_rejects`` does); a ``-`` action of an
i-supported instantiation keeps the WME out of working memory while that
instantiation lasts (:attr:`Kernel.irej`).
Operator slots keep every preference (:class:`adapt.engine.goals.Goal`).
"""

from __future__ import annotations

import random
from typing import Callable

from adapt.engine.functions import FunctionTable
from adapt.engine.goals import Goal, SlotPreference, item_wmes, substate_wmes, top_state_wmes
from adapt.engine.instantiation import (
    SRC_CONST,
    SRC_NEW,
    SRC_WME,
    SUPPORT_I,
    SUPPORT_O,
    Instantiation,
    RuleInfo,
)
from adapt.engine.matcher import Matcher
from adapt.engine.memory import WmeKey, WorkingMemory
from adapt.engine.preferences import Preference
from adapt.engine.production import PreferenceKind, Production
from adapt.engine.results import ResultMaker
from adapt.engine.symbols import Identifier, IdentifierFactory, Symbol, format_symbol, level_of
from adapt.engine.wme import WME

__all__ = ["Kernel", "Listener"]

_ACCEPTABLE = PreferenceKind.ACCEPTABLE
_REJECT = PreferenceKind.REJECT
_REQUIRE = PreferenceKind.REQUIRE

#: Called for trace events: ``listener(kind, payload)``.
Listener = Callable[[str, object], None]


def _raw_changes(matcher: Matcher) -> tuple[dict, dict]:
    """``matcher.take_changes()`` as the kernel files them: ``(added, removed)``
    dicts ``(name, timetag, ...) -> wmes`` (what :meth:`Rete.take_raw` gives
    directly)."""
    added, removed = matcher.take_changes()
    return ({(m.key[0], *m.key[1]): m.wmes for m in added},
            {(m.key[0], *m.key[1]): m.wmes for m in removed})


class Kernel:
    """One agent's state and the mechanics of changing it.

    Parameters
    ----------
    matcher : Matcher
    functions : FunctionTable
    context : RhsContext-like object
        Passed to right-hand-side functions (``write``, ``halt`` ...).
    """

    def __init__(self, matcher: Matcher, functions: FunctionTable, context: object) -> None:
        self.ids = IdentifierFactory()
        self.matcher = matcher
        self.functions = functions
        self.context = context
        self.wm = WorkingMemory(matcher)
        #: the matcher's changes as ``(added, removed)`` dicts ``flat key -> wmes``
        self._take_changes: Callable[[], tuple[dict, dict]] = getattr(
            matcher, "take_raw", None) or (lambda: _raw_changes(matcher))
        self.rules: dict[str, RuleInfo] = {}
        self.goals: dict[Symbol, Goal] = {}
        self.isup: dict[WmeKey, list[Instantiation]] = {}
        self.osup: dict[WmeKey, Instantiation] = {}
        self.irej: dict[WmeKey, list[Instantiation]] = {}
        #: pending match (flat key ``(name, timetag, ...)``) -> its goal
        self.pending_goal: dict[tuple, Goal] = {}
        #: fired match (flat key) -> its instantiation
        self.fired: dict[tuple, Instantiation] = {}
        self.gds_index: dict[int, set[Goal]] = {}
        self.results = ResultMaker(self)
        self.firings = 0
        self.tracer: Listener | None = None
        self.events: list[tuple[str, object]] = []
        #: the matcher may hold match-set changes not yet scheduled
        self._matcher_dirty = True
        s1 = self.ids.new("S")
        io, il, ol = self.ids.new("I"), self.ids.new("I"), self.ids.new("I")
        self.top = Goal(s1, 0, None)
        self.bottom = self.top
        self.goals[s1] = self.top
        self.input_link, self.output_link = il, ol
        self.wm.add_root(s1)
        for t in top_state_wmes(s1, io, il, ol):
            self.wm.add(*t)
            self.top.arch.append((t[0], t[1], t[2], False))

    # -- productions -------------------------------------------------------
    def add_production(self, production: Production) -> None:
        """Add (or replace) a production; its matches become pending."""
        if production.name in self.rules:
            self.matcher.remove_production(production.name)
        self.rules[production.name] = RuleInfo(production)
        self.matcher.add_production(production)
        self._matcher_dirty = True

    # -- working-memory phase ----------------------------------------------
    def commit(self) -> tuple[list[WME], list[WME]]:
        """Apply buffered WME changes and schedule the match-set changes.

        Returns every WME added and removed (goal removals included).
        """
        wm = self.wm
        if not wm.pending and not self._matcher_dirty:
            return [], []
        self._matcher_dirty = False
        all_added: list[WME] | None = None
        all_removed: list[WME] | None = None
        take_changes = self._take_changes
        while True:
            added, removed = wm.commit()
            if all_added is None:
                all_added, all_removed = added, removed
            else:
                all_added.extend(added)
                all_removed.extend(removed)  # type: ignore[union-attr]
            doomed: list[Goal] | None = None
            if removed:
                osup = self.osup
                if osup:
                    for w in removed:
                        osup.pop(w[:4], None)
                gds = self.gds_index
                just = self.results.grounds_index
                if gds or just:  # only with substates
                    for w in removed:
                        tt = w[4]
                        if tt in gds:
                            if doomed is None:
                                doomed = []
                            doomed.extend(gds.pop(tt))
                        if tt in just:
                            for j in just.pop(tt):
                                self._schedule_retraction(j)
            results = self.results
            if results.negated_index or results.ncc_justs:  # justifications' negations
                results.check_negations(added, removed)
            self._schedule(*take_changes())
            if doomed is None:
                break
            live = [g for g in doomed if self.goals.get(g.id) is g]
            if not live:
                break
            top = min(live, key=lambda g: g.level)
            self.emit("gds", top)
            self.remove_goal(top)
        if self.tracer is not None and (all_added or all_removed):
            self.tracer("wm", (all_added, all_removed))
        return all_added, all_removed  # type: ignore[return-value]

    def _schedule(self, added: dict[tuple, tuple], removed: dict[tuple, tuple]) -> None:
        """File the matcher's changes (flat key -> wmes): a new match waits at
        its goal, a vanished one is unscheduled or its instantiation retracts."""
        pending_goal = self.pending_goal
        for key in removed:
            goal = pending_goal.pop(key, None)
            if goal is not None:
                if goal.pending_i.pop(key, None) is None:
                    goal.pending_o.pop(key, None)
                continue
            inst = self.fired.pop(key, None)
            if inst is not None:  # every fired instantiation retracts (o-supported too)
                self._schedule_retraction(inst)
        if not added:
            return
        goals = self.goals
        rules = self.rules
        top = self.top
        only_top = top.lower is None
        for key, wmes in added.items():
            if only_top:
                goal = top
            else:
                goal = None
                for w in wmes:
                    g = goals.get(w[0])
                    if g is not None and (goal is None or g.level > goal.level):
                        goal = g
                if goal is None:
                    goal = top
            info = rules[key[0]]
            support = info.static_support
            if support is None:
                support = info.support_of(wmes, goal.id)
            if support == SUPPORT_O:
                goal.pending_o[key] = wmes
            else:
                goal.pending_i[key] = wmes
            pending_goal[key] = goal

    def _schedule_retraction(self, inst: Instantiation) -> None:
        if inst.retracted:
            return
        goal = inst.goal
        if self.goals.get(goal.id) is goal:
            goal.retractions[inst.key if inst.key is not None else id(inst)] = inst
        else:
            self.retract(inst)

    # -- firing ----------------------------------------------------------------
    def fire(self, goal: Goal, kind: str) -> int:
        """One elaboration cycle at ``goal``: ``kind`` is ``"i"`` (retractions
        and i-assertions) or ``"o"`` (o-assertions).  Returns the number of
        productions fired."""
        if kind == "i":
            retractions = goal.retractions
            if retractions:
                goal.retractions = {}
                tracer = self.tracer
                for inst in retractions.values():
                    if tracer is not None:
                        tracer("retract", inst)
                    self.retract(inst)
            matches = goal.pending_i
            if not matches:
                return 0
            goal.pending_i = {}
        else:
            matches = goal.pending_o
            if not matches:
                return 0
            goal.pending_o = {}
        pending_goal = self.pending_goal
        fired = self.fired
        instantiate = self._instantiate
        rules = self.rules
        if len(matches) == 1:  # the common case: one firing, nothing to order
            ((key, wmes),) = matches.items()
            del pending_goal[key]
            rule = rules[key[0]]
            if kind == "i":
                support = rule.static_support
                if support is None:
                    support = SUPPORT_I
            else:
                support = SUPPORT_O
            inst, prefs = instantiate(key, wmes, rule, goal, support)
            fired[key] = inst
            self.firings += 1
            if prefs:
                if kind != "i":
                    for p in prefs:
                        if p[0] is _REJECT and p[5]:
                            self._o_reject(p)
                self._assert(inst, prefs)
            return 1
        made: list[tuple[Instantiation, list[tuple]]] = []
        for key, wmes in matches.items():
            del pending_goal[key]
            rule = rules[key[0]]
            if kind == "i":
                support = rule.static_support
                if support is None:
                    support = SUPPORT_I
            else:
                support = SUPPORT_O
            pair = instantiate(key, wmes, rule, goal, support)
            fired[key] = pair[0]
            made.append(pair)
        self.firings += len(made)
        # o-rejects first, then everything else (Soar's assert_new_preferences)
        # (every match fired in an IE cycle is i-supported or unsupported)
        if kind != "i":
            for inst, prefs in made:
                for p in prefs:
                    if p[0] is _REJECT and p[5]:
                        self._o_reject(p)
        assert_ = self._assert
        for inst, prefs in made:
            if prefs:
                assert_(inst, prefs)
        return len(made)

    def _instantiate(self, key: tuple, wmes: tuple, rule: RuleInfo, goal: Goal,
                     support: str) -> tuple[Instantiation, list[tuple]]:
        inst = Instantiation(key, rule, goal, support, wmes)
        new: list[Identifier] | None = None
        if rule.new_hints:
            level = goal.level
            ids_new = self.ids.new
            new = [ids_new(hint, level) for hint in rule.new_hints]
        if self.tracer is not None:
            bindings = rule.production.bindings(wmes)
            if new is not None:
                for var, ident in zip(rule.new_variables, new):
                    bindings[var] = ident
            inst.bindings = bindings
            self.tracer("fire", inst)
        prefs: list[tuple] = []
        o_support = support == SUPPORT_O
        value_of = self._rhs_value
        for step in rule.plan:
            if step[0]:
                _, isrc, asrc, vsrc, pref, rsrc = step
                if isrc[0] == SRC_WME:
                    ident = wmes[isrc[1]][isrc[2]]
                else:
                    ident = value_of(isrc, wmes, new)
                tag = asrc[0]
                if tag == SRC_CONST:
                    attr = asrc[1]
                elif tag == SRC_WME:
                    attr = wmes[asrc[1]][asrc[2]]
                else:
                    attr = value_of(asrc, wmes, new)
                tag = vsrc[0]
                if tag == SRC_CONST:
                    value = vsrc[1]
                elif tag == SRC_WME:
                    value = wmes[vsrc[1]][vsrc[2]]
                elif tag == SRC_NEW:
                    value = new[vsrc[1]]  # type: ignore[index]
                else:
                    value = value_of(vsrc, wmes, new)
                if ident is None or attr is None or value is None:
                    continue
                if type(ident) is not Identifier:
                    self.context.error(  # type: ignore[attr-defined]
                        f"RHS makes a preference for a non-identifier ({format_symbol(ident)})")
                    continue
                ref = None if rsrc is None else value_of(rsrc, wmes, new)
                prefs.append((pref, ident, attr, value, ref, o_support))
            else:
                value_of(step[1], wmes, new)
        return inst, prefs

    def _rhs_value(self, src: tuple, wmes: tuple, new: list[Identifier] | None) -> Symbol | None:
        """The value of a compiled RHS value (see :attr:`RuleInfo.plan`)."""
        tag = src[0]
        if tag == SRC_WME:
            return wmes[src[1]][src[2]]
        if tag == SRC_CONST:
            return src[1]
        if tag == SRC_NEW:
            return new[src[1]]  # type: ignore[index]
        args: list[Symbol] = []
        for arg in src[2]:
            tag = arg[0]
            if tag == SRC_WME:
                v = wmes[arg[1]][arg[2]]
            elif tag == SRC_CONST:
                v = arg[1]
            else:
                v = self._rhs_value(arg, wmes, new)
                if v is None:
                    return None
            args.append(v)
        return self.functions.call(src[1], args, self.context)

    def _o_reject(self, p: tuple) -> None:
        _, ident, attr, value, _, _ = p
        if attr == "operator" and ident in self.goals:
            return
        key = (ident, attr, value, False)
        # Soar removes every preference for the value, i-supported ones included
        had = self.osup.pop(key, None) is not None
        if self.isup.pop(key, None) is not None or had:
            self.wm.remove_key(key)

    def _assert(self, inst: Instantiation, prefs: list[tuple]) -> None:
        if not prefs:
            return
        goal = inst.goal
        if goal.level > 0:
            results = self.results.split(inst, prefs)
            if results is not None:
                self._assert_with_results(inst, prefs, results)
                return
        goals = self.goals
        isup, irej, osup = self.isup, self.irej, self.osup
        adds = self.wm.pending_adds
        o_local = False
        for p in prefs:
            kind, ident, attr, value, ref, o = p
            if attr == "operator" and ident in goals:
                self._add_slot_pref(goals[ident], Preference(kind, value, ref), inst)
            elif kind is _ACCEPTABLE:
                key = (ident, attr, value, False)
                if o:
                    osup[key] = inst
                    o_local = True
                else:
                    supporters = isup.get(key)
                    if supporters is None:
                        isup[key] = [inst]
                    else:
                        supporters.append(inst)
                    inst.i_wmes.append(key)
                if key not in irej:
                    adds[key] = None
            elif kind is _REJECT and not o:
                key = (ident, attr, value, False)
                irej.setdefault(key, []).append(inst)
                inst.i_wmes.append(key)
                self.wm.remove_key(key)
        if o_local and goal.level > 0:
            self.results.note_o_local(inst)  # once per firing: it backtraces the whole match
        if inst.i_wmes or inst.slot_prefs:
            goal.instantiations[inst.key if inst.key is not None else id(inst)] = inst

    def _assert_with_results(self, inst: Instantiation, prefs: list[tuple],
                             results: set[tuple]) -> None:
        goal = inst.goal
        goals = self.goals
        for p in prefs:
            kind, ident, attr, value, ref, o = p
            if p in results:
                continue
            if attr == "operator" and ident in goals:
                self._add_slot_pref(goals[ident], Preference(kind, value, ref), inst)
            elif kind is _ACCEPTABLE:
                key = (ident, attr, value, False)
                if o:
                    self.osup[key] = inst
                    self.results.note_o_local(inst)
                else:
                    self.isup.setdefault(key, []).append(inst)
                    inst.i_wmes.append(key)
                if key not in self.irej:
                    self.wm.add(ident, attr, value)
            elif kind is _REJECT and not o:
                key = (ident, attr, value, False)
                self.irej.setdefault(key, []).append(inst)
                inst.i_wmes.append(key)
                self.wm.remove(ident, attr, value)
        if inst.i_wmes or inst.slot_prefs:
            goal.instantiations[inst.key if inst.key is not None else id(inst)] = inst
        if results:
            self.results.make(inst, [p for p in prefs if p in results])

    def _add_slot_pref(self, goal: Goal, pref: Preference, inst: Instantiation) -> None:
        sp = SlotPreference(pref, inst)
        goal.prefs.append(sp)
        goal.changed = True
        inst.slot_prefs.append((goal, sp))
        kind = pref.kind
        if kind is _ACCEPTABLE or kind is _REQUIRE:
            key = (goal.id, "operator", pref.value, True)
            supporters = self.isup.get(key)
            if supporters is None:
                self.isup[key] = [inst]
            else:
                supporters.append(inst)
            self.wm.pending_adds[key] = None

    def retract(self, inst: Instantiation) -> None:
        """Remove everything an instantiation supports with i-support."""
        if inst.retracted:
            return
        inst.retracted = True
        isup, osup, wm = self.isup, self.osup, self.wm
        irej = self.irej
        for key in inst.i_wmes:
            if irej:
                rejecters = irej.get(key)
                if rejecters is not None and inst in rejecters:
                    rejecters.remove(inst)
                    if not rejecters:
                        del irej[key]
                        if key in isup or key in osup:
                            wm.add(*key)
                    continue
            supporters = isup.get(key)
            if supporters is None or inst not in supporters:
                continue
            if len(supporters) == 1:
                del isup[key]
                if key not in osup:
                    wm.remove_key(key)
            else:
                supporters.remove(inst)
        for goal, sp in inst.slot_prefs:
            try:
                goal.prefs.remove(sp)
            except ValueError:
                continue
            goal.changed = True
            kind = sp.preference.kind
            if kind is _ACCEPTABLE or kind is _REQUIRE:
                value = sp.preference.value
                key = (goal.id, "operator", value, True)
                supporters = isup.get(key)
                if supporters is not None:
                    supporters.remove(inst)
                    if not supporters:
                        del isup[key]
                        wm.remove_key(key)
                if kind is _ACCEPTABLE and goal.operator is value and self.goals.get(goal.id) is goal:
                    self.deselect(goal)  # case (a): its acceptable preference retracted
        goal = inst.goal
        if goal.instantiations:
            goal.instantiations.pop(inst.key if inst.key is not None else id(inst), None)

    # -- decisions ---------------------------------------------------------------
    def select(self, goal: Goal, operator: Identifier) -> None:
        """Install ``operator`` as the goal's selected operator."""
        if goal.lower is not None:
            self.remove_goal(goal.lower)
        goal.operator = operator
        goal.changed = False
        self.wm.add(goal.id, "operator", operator)

    def deselect(self, goal: Goal) -> None:
        """Remove the selected operator and every goal below."""
        if goal.operator is not None:
            self.wm.remove(goal.id, "operator", goal.operator)
            goal.operator = None
        if goal.lower is not None:
            self.remove_goal(goal.lower)

    def create_impasse(self, goal: Goal, impasse: str, attribute: str,
                       items: tuple[Symbol, ...], non_numeric: tuple[Symbol, ...]) -> Goal:
        """Create a substate below ``goal`` (removing any existing one)."""
        if goal.lower is not None:
            self.remove_goal(goal.lower)
        ident = self.ids.new("S", goal.level + 1)
        sub = Goal(ident, goal.level + 1, goal)
        sub.impasse, sub.attribute = impasse, attribute
        sub.items, sub.non_numeric = items, non_numeric
        goal.lower = sub
        goal.changed = False
        self.bottom = sub
        self.goals[ident] = sub
        self.wm.add_root(ident)
        for t in substate_wmes(ident, goal.id, impasse, attribute, items, non_numeric):
            self.wm.add(*t)
            sub.arch.append((t[0], t[1], t[2], False))
        return sub

    def update_items(self, goal: Goal, items: tuple[Symbol, ...],
                     non_numeric: tuple[Symbol, ...]) -> None:
        """Replace the ``^item`` set of ``goal``'s substate (same impasse kind)."""
        sub = goal.lower
        assert sub is not None and sub.impasse is not None
        goal.changed = False
        if items == sub.items and non_numeric == sub.non_numeric:
            return
        old = item_wmes(sub.id, sub.impasse, sub.items, sub.non_numeric)
        new = item_wmes(sub.id, sub.impasse, items, non_numeric)
        for t in old:
            if t not in new:
                self.wm.remove(*t)
        for t in new:
            self.wm.add(*t)
        keep = [k for k in sub.arch if k[1] not in ("item", "item-count", "non-numeric",
                                                    "non-numeric-count")]
        sub.arch = keep + [(t[0], t[1], t[2], False) for t in new]
        sub.items, sub.non_numeric = items, non_numeric

    def remove_goal(self, goal: Goal) -> None:
        """Remove ``goal`` and every goal below it, with their local structure."""
        if goal.lower is not None:
            self.remove_goal(goal.lower)
        self.emit("remove-goal", goal)
        level = goal.level
        pending_goal = self.pending_goal
        for key in goal.pending_i:
            pending_goal.pop(key, None)
        for key in goal.pending_o:
            pending_goal.pop(key, None)
        goal.pending_i, goal.pending_o = {}, {}
        for inst in list(goal.retractions.values()) + list(goal.instantiations.values()):
            if inst.key is not None:
                self.fired.pop(inst.key, None)
            self.retract(inst)
        goal.retractions = {}
        for key, inst in goal.ungrounded:  # results without a justification
            if self.osup.get(key) is inst:
                del self.osup[key]
                if key not in self.isup:
                    self.wm.remove(*key)
        for key in [k for k in self.osup if level_of(k[0]) >= level]:
            del self.osup[key]
            if key not in self.isup:
                self.wm.remove(*key)
        if goal.operator is not None:
            self.wm.remove(goal.id, "operator", goal.operator)
            goal.operator = None
        for key in goal.arch:
            self.wm.remove(*key)
        for tt in goal.gds:
            holders = self.gds_index.get(tt)
            if holders is not None:
                holders.discard(goal)
                if not holders:
                    del self.gds_index[tt]
        self.wm.remove_root(goal.id)
        del self.goals[goal.id]
        sup = goal.superstate
        assert sup is not None
        sup.lower = None
        self.bottom = sup

    # -- tracing ---------------------------------------------------------------
    def emit(self, kind: str, payload: object) -> None:
        """Pass an event to the tracer, when one is attached."""
        if self.tracer is not None:
            self.tracer(kind, payload)

    def operator_name(self, operator: Symbol) -> str | None:
        """The operator's ``^name`` as text, or ``None``."""
        names = self.wm.values(operator, "name")
        return format_symbol(names[0]) if names else None

    def new_rng(self, seed: int) -> random.Random:
        """A seeded generator for indifferent selection."""
        return random.Random(seed)
