"""Goals (states) and their operator slots; the architectural WMEs of states.

Each state in the goal stack is a :class:`Goal`: its identifier, its level
(0 = the top state), its operator slot (the preferences made for ``^operator``
and the selected operator), the impasse that created it, and its pending
match-set changes (i-assertions, o-assertions, retractions), which the
waterfall uses to find the active level.

The WMEs Soar builds for states, in the order it makes them (so they get
Soar's timetags):

* every state: ``^type state ^superstate <sup>|nil``, then the links of
  Soar's memory modules: ``^reward-link R``, ``^epmem E`` with ``(E ^command
  C ^result R ^present-id 1)``, ``^smem L`` with ``(L ^command C ^result
  R)`` (:class:`ModuleLinks`; adapt has no reinforcement learning, episodic
  or semantic memory, so nothing is ever put there, but rules and
  ``print`` see the same states as in Soar);
* the top state then ``^io I1`` and ``(I1 ^input-link I2 ^output-link I3)``;
* a substate then ``^attribute <operator|state> ^impasse <type> ^choices
  <multiple|none> ^quiescence t``, and for tie / conflict /
  constraint-failure one ``^item`` per candidate and ``^item-count``,
  ``^non-numeric`` per non-numeric candidate and ``^non-numeric-count``.

Examples
--------
>>> from adapt.engine.symbols import IdentifierFactory
>>> ids = IdentifierFactory()
>>> s1 = ids.state()
>>> links = ModuleLinks(*(ids.new(letter) for letter in "RECRLCR"))
>>> i1, i2, i3 = ids.new("I"), ids.new("I"), ids.new("I")
>>> [(w[0].name, w[1], str(w[2])) for w in top_state_wmes(s1, i1, i2, i3, links)]
... # doctest: +NORMALIZE_WHITESPACE
[('S1', 'type', 'state'), ('S1', 'superstate', 'nil'), ('S1', 'reward-link', 'R1'),
 ('S1', 'epmem', 'E1'), ('E1', 'command', 'C1'), ('E1', 'result', 'R2'),
 ('E1', 'present-id', '1'), ('S1', 'smem', 'L1'), ('L1', 'command', 'C2'),
 ('L1', 'result', 'R3'), ('S1', 'io', 'I1'), ('I1', 'input-link', 'I2'),
 ('I1', 'output-link', 'I3')]
>>> s2 = ids.state()
>>> links2 = ModuleLinks(*(ids.new(letter) for letter in "RECRLCR"))
>>> for w in substate_wmes(s2, s1, "tie", "operator", (O1 := ids.new("O"), ids.new("O")),
...                        (O1,), links2)[10:]:
...     print(w[1], w[2])
attribute operator
impasse tie
choices multiple
quiescence t
item O1
item O2
item-count 2
non-numeric O1
non-numeric-count 1
"""

from __future__ import annotations

from typing import NamedTuple

from adapt.engine.instantiation import Instantiation
from adapt.engine.matcher import FlatKey
from adapt.engine.memory import WmeKey
from adapt.engine.preferences import Preference
from adapt.engine.symbols import Identifier, Symbol
from adapt.engine.vocabulary import NO_CHANGE, ImpasseAttribute, ImpasseType, Support
from adapt.engine.wme import WME

__all__ = ["Goal", "SlotPreference", "ModuleLinks", "top_state_wmes", "substate_wmes",
           "item_wmes"]

Triple = tuple[Symbol, Symbol, Symbol]


class SlotPreference:
    """One preference in an operator slot, and the instantiation that made it."""

    __slots__ = ("preference", "inst")

    def __init__(self, preference: Preference, inst: Instantiation | None) -> None:
        self.preference = preference
        self.inst = inst

    def __repr__(self) -> str:
        p = self.preference
        ref = "" if p.referent is None else f" {p.referent}"
        return f"<{p.value} {p.kind.value}{ref}>"


class Goal:
    """One state of the goal stack.

    Attributes
    ----------
    id : Identifier
    level : int
        0 for the top state, 1 for its substate, ...
    superstate, lower : Goal or None
        The goal above and below.
    impasse, attribute : str or None
        For substates: the impasse type (``tie``, ``conflict``,
        ``constraint-failure``, ``no-change``) and attribute (``operator`` or
        ``state``).
    items : tuple
        The current ``^item`` values.
    prefs : list of SlotPreference
        The operator slot's preferences, oldest first.
    operator : Identifier or None
        The selected operator.
    changed : bool
        The slot's preferences changed since the last decision about it.
    pending_i, pending_o : dict
        Matches waiting to fire: flat key ``(name, timetag, ...)`` -> the
        matched WMEs.
    retractions : dict
        Fired instantiations whose match disappeared, waiting to retract.
    gds : set of int
        Timetags of the superstate WMEs this goal depends on.
    arch : list of WmeKey
        The goal's architectural WMEs (removed with it).
    ungrounded : list of (WmeKey, Instantiation)
        O-supported results of this goal's firings that had no grounds
        (no justification): they are removed with the goal, as in Soar.
    """

    __slots__ = ("id", "level", "superstate", "lower", "impasse", "attribute", "items",
                 "non_numeric", "prefs", "operator", "changed", "pending_i", "pending_o",
                 "retractions", "instantiations", "gds", "arch", "ungrounded", "saved_firing")

    def __init__(self, ident: Identifier, level: int, superstate: Goal | None) -> None:
        self.id = ident
        self.level = level
        self.superstate = superstate
        self.lower: Goal | None = None
        self.impasse: ImpasseType | None = None
        self.attribute: ImpasseAttribute | None = None
        self.items: tuple[Symbol, ...] = ()
        self.non_numeric: tuple[Symbol, ...] = ()
        self.prefs: list[SlotPreference] = []
        #: the selected operator: an identifier, or a constant (Soar selects
        #: ``(<s> ^operator go +)`` as it selects an identifier)
        self.operator: Symbol | None = None
        self.changed = False
        self.pending_i: dict[FlatKey, tuple[WME, ...]] = {}
        self.pending_o: dict[FlatKey, tuple[WME, ...]] = {}
        self.retractions: dict[object, Instantiation] = {}
        self.instantiations: dict[object, Instantiation] = {}
        self.gds: set[int] = set()
        self.arch: list[WmeKey] = []
        self.ungrounded: list[tuple[WmeKey, Instantiation]] = []
        self.saved_firing: Support | None = None

    def i_activity(self) -> bool:
        """i-assertions or retractions are pending here."""
        return bool(self.pending_i or self.retractions)

    def preferences(self) -> list[Preference]:
        """The slot's preferences, oldest first."""
        return [sp.preference for sp in self.prefs]

    def __repr__(self) -> str:
        return f"Goal({self.id}, level {self.level})"


class ModuleLinks(NamedTuple):
    """The identifiers of a state's links to Soar's memory modules, in the
    order Soar makes them (letters R E C R L C R)."""

    reward_link: Identifier
    epmem: Identifier
    epmem_command: Identifier
    epmem_result: Identifier
    smem: Identifier
    smem_command: Identifier
    smem_result: Identifier


def _state_wmes(state: Identifier, superstate: Symbol, links: ModuleLinks) -> list[Triple]:
    return [(state, "type", "state"), (state, "superstate", superstate),
            (state, "reward-link", links.reward_link),
            (state, "epmem", links.epmem), (links.epmem, "command", links.epmem_command),
            (links.epmem, "result", links.epmem_result), (links.epmem, "present-id", 1),
            (state, "smem", links.smem), (links.smem, "command", links.smem_command),
            (links.smem, "result", links.smem_result)]


def top_state_wmes(s1: Identifier, io: Identifier, input_link: Identifier,
                   output_link: Identifier, links: ModuleLinks) -> list[Triple]:
    """The top state's WMEs, in the order they are created."""
    return _state_wmes(s1, "nil", links) + [
        (s1, "io", io), (io, "input-link", input_link), (io, "output-link", output_link)]


def item_wmes(state: Identifier, impasse: str, items: tuple[Symbol, ...],
              non_numeric: tuple[Symbol, ...]) -> list[Triple]:
    """``^item``/``^item-count`` and ``^non-numeric``/``^non-numeric-count``.

    Soar adds ``^non-numeric`` to every impasse with items (tie, conflict and
    constraint failure), not only to ties.
    """
    if impasse == NO_CHANGE:
        return []
    out: list[Triple] = [(state, "item", v) for v in items]
    out.append((state, "item-count", len(items)))
    out.extend((state, "non-numeric", v) for v in non_numeric)
    out.append((state, "non-numeric-count", len(non_numeric)))
    return out


def substate_wmes(state: Identifier, superstate: Identifier, impasse: str, attribute: str,
                  items: tuple[Symbol, ...], non_numeric: tuple[Symbol, ...],
                  links: ModuleLinks) -> list[Triple]:
    """A new substate's WMEs, in the order they are created."""
    choices = "multiple" if impasse in ("tie", "conflict") else "none"
    out = _state_wmes(state, superstate, links)
    out += [(state, "attribute", attribute), (state, "impasse", impasse),
            (state, "choices", choices), (state, "quiescence", "t")]
    out.extend(item_wmes(state, impasse, items, non_numeric))
    return out
