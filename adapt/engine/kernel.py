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

Which WMEs the preferences hold is :class:`adapt.engine.support.PreferenceMemory`'s
(:attr:`Kernel.preferences`); operator slots keep every preference
(:class:`adapt.engine.goals.Goal`).  What happens is announced on the
agent's :class:`~adapt.engine.events.EventBus` (:attr:`Kernel.events`),
payloads built only when someone listens.
"""

from __future__ import annotations

from functools import partial
from typing import Callable, Final

from adapt.engine.events import Event, EventBus
from adapt.engine.functions import FunctionTable, RhsContext
from adapt.engine.goals import Goal, ModuleLinks, item_wmes, substate_wmes, top_state_wmes
from adapt.engine.instantiation import (
    SRC_CONST,
    SRC_NEW,
    SRC_WME,
    CompiledValue,
    Instantiation,
    RuleInfo,
)
from adapt.engine.matcher import FlatKey, MatchChanges, Matcher, RawMatcher
from adapt.engine.memory import WorkingMemory
from adapt.engine.production import PreferenceKind, Production
from adapt.engine.results import ResultMaker
from adapt.engine.support import MadePreference, PreferenceMemory
from adapt.engine.symbols import Float, Identifier, IdentifierFactory, Symbol, format_symbol
from adapt.engine.vocabulary import ImpasseAttribute, ImpasseType, Support
from adapt.engine.wme import WME

__all__ = ["Kernel"]

_REJECT: Final = PreferenceKind.REJECT
_ACCEPTABLE: Final = PreferenceKind.ACCEPTABLE
_BINARY_INDIFFERENT: Final = PreferenceKind.BINARY_INDIFFERENT
_NUMERIC_INDIFFERENT: Final = PreferenceKind.NUMERIC_INDIFFERENT
_O: Final = Support.O
_I: Final = Support.I


def _raw_changes(matcher: Matcher) -> MatchChanges:
    """``matcher.take_changes()`` as the kernel files them: ``(added, removed)``
    dicts ``(name, timetag, ...) -> wmes`` (what :meth:`RawMatcher.take_raw`
    gives directly)."""
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

    def __init__(self, matcher: Matcher | RawMatcher, functions: FunctionTable,
                 context: RhsContext, events: EventBus | None = None) -> None:
        self.ids = IdentifierFactory()
        self.matcher = matcher
        #: the ``multi-attributes`` hints (the matcher's: they order the
        #: conditions of productions added from now on)
        self.multi_attributes = matcher.multi_attributes
        #: the matcher's changes as :data:`~adapt.engine.matcher.MatchChanges`
        self.take_changes: Callable[[], MatchChanges] = (
            matcher.take_raw if isinstance(matcher, RawMatcher) else partial(_raw_changes, matcher))
        self.functions = functions
        self.context = context
        self.events = events if events is not None else EventBus()
        self.wm = WorkingMemory(matcher)
        self.rules: dict[str, RuleInfo] = {}
        self.goals: dict[Symbol, Goal] = {}
        #: the support of every WME made by preferences
        self.preferences = PreferenceMemory(self.wm, self.goals)
        #: pending match (flat key ``(name, timetag, ...)``) -> its goal
        self.pending_goal: dict[FlatKey, Goal] = {}
        #: fired match (flat key) -> its instantiation
        self.fired: dict[FlatKey, Instantiation] = {}
        self.gds_index: dict[int, set[Goal]] = {}
        self.results = ResultMaker(self)
        self.firings = 0
        #: the matcher may hold match-set changes not yet scheduled
        self.matcher_dirty = True
        #: productions were added since the last commit (their matches come
        #: in the order they were added, as in Soar)
        self.productions_added = False
        #: the current matches of the productions that only elaborate an
        #: operator (:attr:`RuleInfo.op_elab_only`), by production
        self.op_elab_matches: dict[str, dict[FlatKey, tuple[WME, ...]]] = {}
        #: the productions flagged ``:interrupt``
        self.interrupt_rules: set[str] = set()
        #: the pending matches of ``:interrupt`` productions: while any is
        #: pending at the end of a phase, the run stops (Soar's match-time
        #: interrupt); the name of the last one
        self.interrupt_matches: dict[FlatKey, str] = {}
        # the live listener lists of the events raised on hot paths
        self._on_fire = self.events.listeners(Event.FIRE)
        self._on_retract = self.events.listeners(Event.RETRACT)
        self._on_wm = self.events.listeners(Event.WM_CHANGES)
        s1 = self.ids.state()
        links = self._module_links(0)
        io, il, ol = self.ids.new("I"), self.ids.new("I"), self.ids.new("I")
        self.top = Goal(s1, 0, None)
        self.bottom = self.top
        self.goals[s1] = self.top
        self.input_link, self.output_link = il, ol
        self.wm.add_root(s1)
        for t in top_state_wmes(s1, io, il, ol, links):
            self.wm.add(*t)
            self.top.arch.append((t[0], t[1], t[2], False))

    # -- productions -------------------------------------------------------
    def add_production(self, production: Production) -> None:
        """Add (or replace) a production; its matches become pending."""
        if production.name in self.rules:
            self.matcher.remove_production(production.name)
        self.rules[production.name] = RuleInfo(production)
        if "interrupt" in production.flags:
            self.interrupt_rules.add(production.name)
        else:
            self.interrupt_rules.discard(production.name)
        self.matcher.add_production(production)
        self.matcher_dirty = True
        self.productions_added = True

    # -- working-memory phase ----------------------------------------------
    def commit(self) -> tuple[list[WME], list[WME]]:
        """Apply buffered WME changes and schedule the match-set changes.

        Returns every WME added and removed (goal removals included).
        """
        wm = self.wm
        preferences = self.preferences
        if preferences.changes or preferences.marks or preferences.op_marks:
            preferences.flush()
        if not wm.pending and not self.matcher_dirty:
            return [], []
        self.matcher_dirty = False
        self.productions_added = False
        all_added: list[WME] | None = None
        all_removed: list[WME] | None = None
        take_changes = self.take_changes
        forget = preferences.osup
        while True:
            if preferences.changes:
                preferences.flush()
            added, removed = wm.commit()
            if all_added is None:
                all_added, all_removed = added, removed
            else:
                all_added.extend(added)
                assert all_removed is not None
                all_removed.extend(removed)
            doomed: list[Goal] | None = None
            if removed:
                if forget:
                    for w in removed:
                        forget.pop(w[:4], None)
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
                                self.schedule_retraction(j)
            results = self.results
            if results.negated_index or results.ncc_justs:  # justifications' negations
                results.check_negations(added, removed)
            added_matches, removed_matches = take_changes()
            self._schedule(added_matches, removed_matches)
            if doomed is None:
                break
            live = [g for g in doomed if self.goals.get(g.id) is g]
            if not live:
                break
            top = min(live, key=lambda g: g.level)
            self.events.emit(Event.GDS, top)
            sup = top.superstate
            if sup is not None and not self._any_slot_changed():
                # Soar marks the superstate's slot changed when nothing else
                # changed, so that the next decision makes the impasse again
                # (Soar's fix of its bug 1011)
                sup.changed = True
            self.remove_goal(top)
        assert all_added is not None and all_removed is not None
        if self._on_wm and (all_added or all_removed):
            self.events.emit(Event.WM_CHANGES, (all_added, all_removed))
        return all_added, all_removed

    def _any_slot_changed(self) -> bool:
        goal: Goal | None = self.top
        while goal is not None:
            if goal.changed:
                return True
            goal = goal.lower
        return False

    def _schedule(self, added: dict[FlatKey, tuple[WME, ...]],
                  removed: dict[FlatKey, tuple[WME, ...]]) -> None:
        """File the matcher's changes (flat key -> wmes): a new match waits at
        its goal (after those waiting already, in the order the matcher found
        them: they fire the other way round), a vanished one is unscheduled or
        its instantiation retracts."""
        pending_goal = self.pending_goal
        interrupts = self.interrupt_rules
        op_elabs = self.op_elab_matches
        for key in removed:
            if op_elabs:
                current = op_elabs.get(key[0])
                if current is not None:
                    current.pop(key, None)
            goal = pending_goal.pop(key, None)
            if goal is not None:
                if interrupts:
                    self.interrupt_matches.pop(key, None)
                if goal.pending_i.pop(key, None) is None:
                    goal.pending_o.pop(key, None)
                continue
            inst = self.fired.pop(key, None)
            if inst is not None:  # every fired instantiation retracts (o-supported too)
                self.schedule_retraction(inst)
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
                support = info.support_of(wmes, goal.id, goals)
            if info.op_elab_only and info.declared is None:
                support = self._op_elab_support(key, wmes)
            if support is _O:
                goal.pending_o[key] = wmes
            else:
                goal.pending_i[key] = wmes
            pending_goal[key] = goal
            if interrupts and key[0] in interrupts:
                self.interrupt_matches[key] = key[0]

    def _op_elab_support(self, key: FlatKey, wmes: tuple[WME, ...]) -> Support:
        """The support of a new match of a production that only elaborates the
        operator it tests: i-support, unless another current match of the
        production tests another selected operator -- then Soar's match-time
        check (``p_node_left_addition``, which compares the new match's
        operator with every match's) files it as an application: o-support."""
        current = self.op_elab_matches.setdefault(key[0], {})
        mine = self._selected_operator(wmes)
        support = _I
        for other in current.values():
            theirs = self._selected_operator(other)
            if theirs is not None and theirs is not mine:
                support = _O
                break
        current[key] = wmes
        return support

    def _selected_operator(self, wmes: tuple[WME, ...]) -> Symbol | None:
        """The selected operator a match tests on its lowest state."""
        goals = self.goals
        lowest: Goal | None = None
        for w in wmes:
            g = goals.get(w[0])
            if g is not None and (lowest is None or g.level > lowest.level):
                lowest = g
        if lowest is None:
            return None
        for w in wmes:
            if w[0] is lowest.id and w[1] == "operator" and not w[3]:
                return w[2]
        return None

    def schedule_retraction(self, inst: Instantiation) -> None:
        """Retract ``inst`` in its goal's next elaboration cycle (at once
        when its goal is gone)."""
        if inst.retracted:
            return
        goal = inst.goal
        if inst.rule is None and inst.support is _O:
            # an o-supported justification: its retraction removes nothing,
            # but Soar still has it to retract at its goal (once)
            if not inst.unmatched and self.goals.get(goal.id) is goal:
                inst.unmatched = True
                goal.retractions[id(inst)] = inst
            return
        if self.goals.get(goal.id) is goal:
            goal.retractions[inst.key if inst.key is not None else id(inst)] = inst
        else:
            self.retract(inst)

    # -- firing ----------------------------------------------------------------
    def fire(self, goal: Goal, kind: Support, below: int = -1) -> int:
        """The firings of one elaboration cycle at ``goal``: ``kind`` is
        ``Support.I`` (i-assertions) or ``Support.O`` (o-assertions).  Returns
        the number of productions fired.  The active goal's retractions are
        :meth:`retract_pending`'s, after the waterfall.

        ``below`` >= 0: ``goal`` is a lower goal in the waterfall of an
        elaboration cycle whose active goal already fired: only the matches
        whose actions change nothing at level ``below`` or higher fire (Soar's
        ``shouldCreateInstantiation``); the others wait.
        """
        if kind is _I:
            pending = goal.pending_i
        else:
            pending = goal.pending_o
        if not pending:
            fired_count = 0
        else:
            if below < 0:
                matches = pending
                if kind is _I:
                    goal.pending_i = {}
                else:
                    goal.pending_o = {}
            else:
                matches = {key: wmes for key, wmes in pending.items()
                           if self.rules[key[0]].changes_below(wmes, below)}
                for key in matches:
                    del pending[key]
            fired_count = self._fire_matches(goal, kind, matches) if matches else 0
        return fired_count

    def retract_pending(self, goal: Goal) -> None:
        """Retract the instantiations waiting to retract at ``goal``."""
        retractions = goal.retractions
        if retractions:
            goal.retractions = {}
            on_retract = self._on_retract
            # the last scheduled first: Soar's retraction lists grow at the head
            for inst in reversed(retractions.values()):
                if inst.unmatched:
                    continue  # an o-supported justification: nothing to retract
                if on_retract:
                    self.events.emit(Event.RETRACT, inst)
                self.retract(inst)

    def _fire_matches(self, goal: Goal, kind: Support,
                      matches: dict[FlatKey, tuple[WME, ...]]) -> int:
        """Instantiate ``matches`` (taken from ``goal``'s pending matches) in
        parallel and assert their preferences."""
        pending_goal = self.pending_goal
        fired = self.fired
        instantiate = self._instantiate
        rules = self.rules
        o_reject = self.preferences.o_reject
        made: list[tuple[Instantiation, list[MadePreference]]] = []
        # Soar takes the newest match first (its match lists grow at the head):
        # instantiations -- their new identifiers and writes -- come in that
        # order; their preferences are asserted oldest match first, each
        # firing's in reverse action order (both lists also grow at the head)
        order = list(matches.items())
        order.reverse()
        for key, wmes in order:
            del pending_goal[key]
            rule = rules[key[0]]
            if kind is _I:
                support = rule.static_support
                if support is None:
                    support = _I
            else:
                support = _O
            pair = instantiate(key, wmes, rule, goal, support)
            fired[key] = pair[0]
            made.append(pair)
        self.firings += len(made)
        made.reverse()
        # o-rejects first, then everything else (Soar's assert_new_preferences)
        # (every match fired in an IE cycle is i-supported or unsupported)
        # An o-reject removes every preference for its value, in any slot
        # (operator slots too), and is not asserted itself -- nor is it a result.
        if kind is _O:
            deselect: list[Goal] = []
            # Soar collects them into a list that grows at its head: they are
            # processed in the order the firings were made, each in action order
            for _, prefs in reversed(made):
                if any(p[0] is _REJECT and p[5] for p in prefs):
                    for p in prefs:
                        if p[0] is _REJECT and p[5]:
                            deselect.extend(o_reject(p))
                    prefs[:] = [p for p in prefs if not (p[0] is _REJECT and p[5])]
            for g in deselect:
                if self.goals.get(g.id) is g:
                    self.deselect(g)
        assert_ = self._assert
        for inst, prefs in made:
            if prefs:
                prefs.reverse()
                assert_(inst, prefs)
        return len(made)

    def _instantiate(self, key: FlatKey, wmes: tuple[WME, ...], rule: RuleInfo, goal: Goal,
                     support: Support) -> tuple[Instantiation, list[MadePreference]]:
        inst = Instantiation(key, rule, goal, support, wmes)
        if goal.level > 0:
            inst.traces = self._traces(wmes, goal.level)
        new: list[Identifier] | None = None
        if rule.new_hints:
            level = goal.level
            ids_new = self.ids.new
            new = [ids_new(hint, level) for hint in rule.new_hints]
        if self._on_fire:
            bindings = rule.production.bindings(wmes)
            if new is not None:
                for var, made_id in zip(rule.new_variables, new):
                    bindings[var] = made_id
            inst.bindings = bindings
            self.events.emit(Event.FIRE, inst)
        prefs: list[MadePreference] = []
        o_support = support is _O
        ident: Symbol | None
        attr: Symbol | None
        value: Symbol | None
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
                    self.context.error(
                        f"RHS makes a preference for a non-identifier ({format_symbol(ident)})")
                    continue
                ref = None
                if rsrc is not None:
                    ref = value_of(rsrc, wmes, new)
                    if pref is _BINARY_INDIFFERENT and (type(ref) is int or type(ref) is Float):
                        # = <x> or = (f ...) that gives a number: numeric indifference
                        # (Soar's add_pref_to_inst decides it when the rule fires)
                        pref = _NUMERIC_INDIFFERENT
                prefs.append((pref, ident, attr, value, ref, o_support))
                if self.context.copied_ids:  # deep-copy: its WMEs are this firing's too
                    self._add_copies(ident.level, prefs, o_support)
            else:
                value_of(step[1], wmes, new)
        return inst, prefs

    def _traces(self, wmes: tuple[WME, ...], level: int) -> tuple[Instantiation | None, ...]:
        """What supports each of a substate match's WMEs of its own level or
        deeper now (the newest holder), for backtracing later."""
        isup = self.preferences.isup
        osup = self.preferences.osup
        out: list[Instantiation | None] = []
        for w in wmes:
            ident = w[0]
            if type(ident) is not Identifier or ident.level < level:
                out.append(None)
                continue
            key = (ident, w[1], w[2], w[3])
            holders = isup.get(key)
            out.append(holders[-1] if holders else osup.get(key))
        return tuple(out)

    def _add_copies(self, level: int, prefs: list[MadePreference], o_support: bool) -> None:
        """Acceptable preferences for the WMEs ``deep-copy`` made, their new
        identifiers at the level of the identifier the copy is attached to
        (Soar's ``add_deep_copy_prefs_to_inst``)."""
        context = self.context
        for made in context.copied_ids:
            made.level = level
        for ident, attr, value in context.copies:
            prefs.append((_ACCEPTABLE, ident, attr, value, None, o_support))
        context.copied_ids.clear()
        context.copies.clear()

    def _rhs_value(self, src: CompiledValue, wmes: tuple[WME, ...],
                   new: list[Identifier] | None) -> Symbol | None:
        """The value of a compiled RHS value (see :attr:`RuleInfo.plan`)."""
        tag = src[0]
        if tag == SRC_WME:
            return wmes[src[1]][src[2]]
        if tag == SRC_CONST:
            return src[1]  # type: ignore[no-any-return]
        if tag == SRC_NEW:
            assert new is not None
            return new[src[1]]
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

    def _assert(self, inst: Instantiation, prefs: list[MadePreference]) -> None:
        """Assert a firing's preferences: its results (in a substate) through
        the result maker, the rest in preference memory, held by ``inst``."""
        goal = inst.goal
        results: set[MadePreference] | None = None
        if goal.level > 0:
            results = self.results.split(inst, prefs)
            if results is not None:
                # the results first, in the firing's order: Soar asserts the
                # justification's preferences before the firing's own
                self.results.make(inst, [p for p in prefs if p in results])
                prefs = [p for p in prefs if p not in results]
        o_local = self.preferences.assert_preferences(inst, prefs, inst.support is _O,
                                                      o_rejects=False)
        if o_local and goal.level > 0:
            self.results.note_o_local(inst)  # once per firing: it backtraces the whole match
        if inst.i_wmes or inst.slot_prefs:
            goal.instantiations[inst.key if inst.key is not None else id(inst)] = inst

    def retract(self, inst: Instantiation) -> None:
        """Remove everything an instantiation supports with i-support."""
        if inst.retracted:
            return
        inst.retracted = True
        for goal in self.preferences.retract(inst):
            if self.goals.get(goal.id) is goal:
                self.deselect(goal)  # case (a): its acceptable preference retracted
        goal = inst.goal
        instantiations = goal.instantiations
        if instantiations:
            key = inst.key if inst.key is not None else id(inst)
            if instantiations.get(key) is inst:  # (a new firing of the same match may hold it)
                del instantiations[key]

    # -- decisions ---------------------------------------------------------------
    def select(self, goal: Goal, operator: Symbol) -> None:
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

    def create_impasse(self, goal: Goal, impasse: ImpasseType, attribute: ImpasseAttribute,
                       items: tuple[Symbol, ...], non_numeric: tuple[Symbol, ...]) -> Goal:
        """Create a substate below ``goal`` (removing any existing one)."""
        if goal.lower is not None:
            self.remove_goal(goal.lower)
        ident = self.ids.state(goal.level + 1)
        links = self._module_links(goal.level + 1)
        sub = Goal(ident, goal.level + 1, goal)
        sub.impasse, sub.attribute = impasse, attribute
        sub.items, sub.non_numeric = items, non_numeric
        goal.lower = sub
        goal.changed = False
        self.bottom = sub
        self.goals[ident] = sub
        self.wm.add_root(ident)
        for t in substate_wmes(ident, goal.id, impasse, attribute, items, non_numeric, links):
            self.wm.add(*t)
            sub.arch.append((t[0], t[1], t[2], False))
        return sub

    def _module_links(self, level: int) -> ModuleLinks:
        """The identifiers of a new state's ``^reward-link``, ``^epmem`` and
        ``^smem`` structures, made in Soar's order (R, E, C, R, L, C, R), so
        that every identifier gets the number it has in Soar."""
        new = self.ids.new
        return ModuleLinks(*(new(letter, level) for letter in "RECRLCR"))

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
        self.events.emit(Event.REMOVE_GOAL, goal)
        goal.id.goal = False
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
        preferences = self.preferences
        for key, inst in goal.ungrounded:  # results without a justification
            preferences.drop_o_supported(key, inst)
        preferences.drop_levels(level)
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

    # -- reading -------------------------------------------------------------
    def operator_name(self, operator: Symbol) -> str | None:
        """The operator's ``^name`` as text, or ``None``."""
        names = self.wm.values(operator, "name")
        return format_symbol(names[0]) if names else None
