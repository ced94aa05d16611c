"""Preference semantics: what one slot's preferences decide, as Soar decides it.

This module is a pure function of a slot's preferences.  The decision cycle
collects every preference for one context slot (in practice ``(S ^operator
?)``), calls :func:`decide`, and acts on the returned :class:`SlotDecision`:
install the selected value, or create (or update) an impasse whose ``^item``
WMEs are :attr:`SlotDecision.items`.

The filters run in Soar's order (``run_preference_semantics`` in Soar's
``decide.cpp``):

1. **require** (``!``).  If any value is required, nothing else matters except
   prohibits: one required value is selected (even without ``+``, even if it is
   rejected); two or more distinct required values, or a required value that is
   also prohibited, are a *constraint failure* whose items are the required
   values.
2. **acceptable** (``+``) values are the candidates, minus every value that is
   **prohibited** (``~``) or **rejected** (``-``).  No candidate left: outcome
   ``"none"`` (the cycle turns it into a state no-change).
3. **better / worse** (``A > B``, ``B < A``): every candidate that some *other
   candidate* is better than is dominated.  Not transitive: ``A > B``, ``B > C``
   removes ``B`` and ``C`` and keeps ``A``.  Preferences that mention a value
   that is no longer a candidate are ignored.  If every candidate is
   dominated, the outcome is a *conflict* whose items are all those
   candidates; otherwise the dominated candidates are dropped (so ``A > B``,
   ``B > A`` and an unrelated ``C`` select ``C``).
4. **best** (``>``): if some candidates are best, only they remain.
5. **worst** (``<``): if some candidates are not worst, the worst ones go.
6. **indifferent**: if every remaining candidate is unary indifferent
   (``=``), numeric indifferent (``= 0.5``, which implies unary), or binary
   indifferent (``A = B``) to *every* other remaining candidate, one of them is
   chosen at random (see :func:`choose`); otherwise the outcome is a *tie*
   whose items are the remaining candidates.

Whenever one candidate is left after a filter it is selected at once.

Order of candidates and items
-----------------------------
Soar keeps a slot's preferences newest first and builds its candidate list by
prepending, so candidates (and the ``^item`` WMEs of an impasse, created in that
order) are ordered by each value's *most recent* acceptable (or require)
preference, oldest first.  :func:`decide` reproduces this when the
preferences are passed oldest first: a value's position is the position of
its last acceptable (require) preference in the input.  (Soar also puts
preferences made by rules matching a lower goal first; the cycle can order its
input that way if it wants that detail.)

Retention
---------
Soar does not re-decide a selected operator.  It keeps it while the current
preferences would still allow it: :func:`should_keep` is Soar's consistency
check, and ``decide(..., current=op)`` returns ``op`` selected whenever
:func:`should_keep` holds, without drawing a random number.

Examples
--------
>>> from adapt.engine.symbols import IdentifierFactory
>>> ids = IdentifierFactory()
>>> o1, o2, o3 = ids.new("O"), ids.new("O"), ids.new("O")
>>> A, R = PreferenceKind.ACCEPTABLE, PreferenceKind.REJECT
>>> decide([Preference(A, o1)])
SlotDecision(outcome='select', selected=O1, items=(), non_numeric=(), candidates=(O1,))
>>> d = decide([Preference(A, o1), Preference(A, o2), Preference(A, o3), Preference(R, o3)])
>>> d.outcome, d.items, d.non_numeric
('tie', (O1, O2), (O1, O2))
>>> decide([Preference(A, o1), Preference(A, o2),
...         Preference(PreferenceKind.BETTER, o2, o1)]).selected
O2
"""

from __future__ import annotations

import math
import random
from typing import Final, Iterable, Literal, NamedTuple, Sequence

from adapt.engine.production import PreferenceKind
from adapt.engine.symbols import Identifier, Symbol, is_number

__all__ = [
    "Preference",
    "SlotDecision",
    "Outcome",
    "POLICIES",
    "NUMERIC_MODES",
    "decide",
    "should_keep",
    "numeric_values",
    "choose",
    "same_symbol",
]

#: What :func:`decide` can conclude about a slot.
Outcome = Literal["select", "tie", "conflict", "constraint-failure", "none"]

#: Indifferent-selection policies (Soar's ``indifferent-selection`` command).
POLICIES = ("softmax", "boltzmann", "epsilon-greedy", "random", "first", "last")
#: Numeric-indifference modes (Soar's ``numeric-indifferent-mode``).
NUMERIC_MODES = ("sum", "avg")

_ACCEPTABLE: Final = PreferenceKind.ACCEPTABLE
_REQUIRE: Final = PreferenceKind.REQUIRE
_PROHIBIT: Final = PreferenceKind.PROHIBIT
_REJECT: Final = PreferenceKind.REJECT
_BETTER: Final = PreferenceKind.BETTER
_WORSE: Final = PreferenceKind.WORSE
_BEST: Final = PreferenceKind.BEST
_WORST: Final = PreferenceKind.WORST
_UNARY: Final = PreferenceKind.UNARY_INDIFFERENT
_BINARY: Final = PreferenceKind.BINARY_INDIFFERENT
_NUMERIC: Final = PreferenceKind.NUMERIC_INDIFFERENT


class Preference(NamedTuple):
    """One preference for one value of a slot.

    An immutable record (a named tuple: the cycle makes one per operator
    preference, and a named tuple costs about a third of a frozen
    dataclass to build).

    Parameters
    ----------
    kind : PreferenceKind
        Which preference (``+ - ! ~ > < =`` and the binary/numeric forms).
    value : Symbol
        The value the preference is about (an operator identifier).
    referent : Symbol or None
        For better, worse and binary indifferent: the other value; for
        numeric indifferent: the number; otherwise ``None``.

    Examples
    --------
    >>> Preference(PreferenceKind.NUMERIC_INDIFFERENT, "a", 0.5)
    Preference(kind=<PreferenceKind.NUMERIC_INDIFFERENT: '=n'>, value='a', referent=0.5)
    """

    kind: PreferenceKind
    value: Symbol
    referent: Symbol | None = None


class SlotDecision(NamedTuple):
    """What the preferences of one slot decide.

    Attributes
    ----------
    outcome : str
        ``"select"``, ``"tie"``, ``"conflict"``, ``"constraint-failure"`` or
        ``"none"`` (no candidate at all).
    selected : Symbol or None
        The winner when ``outcome == "select"``, else ``None``.
    items : tuple of Symbol
        For an impasse: the values its substate's ``^item`` WMEs hold, in the
        order Soar creates them.  Empty for ``select`` and ``none``.
    non_numeric : tuple of Symbol
        For an impasse: the items without a numeric-indifferent preference
        (the substate's ``^non-numeric`` WMEs), in item order.
    candidates : tuple of Symbol
        The candidates left after the filters: for a random selection all the
        indifferent candidates it chose from; for an impasse the same as
        ``items``.

    Examples
    --------
    >>> SlotDecision("none", None, (), (), ()).is_impasse
    False
    """

    outcome: Outcome
    selected: Symbol | None
    items: tuple[Symbol, ...]
    non_numeric: tuple[Symbol, ...]
    candidates: tuple[Symbol, ...]

    @property
    def is_impasse(self) -> bool:
        """True for a tie, conflict or constraint failure."""
        return self.outcome in ("tie", "conflict", "constraint-failure")


_NONE_DECISION: Final = SlotDecision("none", None, (), (), ())


def same_symbol(a: Symbol, b: Symbol) -> bool:
    """The same symbol (``2`` and ``2.0`` differ; identifiers by identity).

    Examples
    --------
    >>> from adapt.engine.symbols import Float
    >>> same_symbol("go", "go"), same_symbol(2, Float(2.0))
    (True, False)
    """
    return a is b or (type(a) is type(b) and not isinstance(a, Identifier) and a == b)


class _Slot:
    """The preferences of one slot, bucketed by kind (internal)."""

    __slots__ = (
        "require", "acceptable", "excluded", "prohibit", "dominance", "best",
        "worst", "unary", "numeric", "binary", "valued",
    )

    def __init__(self, preferences: Iterable[Preference]) -> None:
        # dicts used as insertion-ordered sets; a value moves to the end when
        # it gets another acceptable/require preference (Soar's order).
        self.require: dict[Symbol, None] = {}
        self.acceptable: dict[Symbol, None] = {}
        self.excluded: set[Symbol] = set()  # prohibited or rejected
        self.prohibit: set[Symbol] = set()
        self.dominance: list[tuple[Symbol, Symbol]] = []  # (better, worse)
        self.best: set[Symbol] = set()
        self.worst: set[Symbol] = set()
        self.unary: set[Symbol] = set()
        self.numeric: set[Symbol] = set()
        self.binary: list[tuple[Symbol, Symbol]] = []
        self.valued: list[Preference] = []  # numeric and binary indifferent
        for p in preferences:
            kind = p.kind
            v = p.value
            if kind is _ACCEPTABLE:
                acc = self.acceptable
                if v in acc:
                    del acc[v]
                acc[v] = None
            elif kind is _REQUIRE:
                req = self.require
                if v in req:
                    del req[v]
                req[v] = None
            elif kind is _REJECT:
                self.excluded.add(v)
            elif kind is _PROHIBIT:
                self.excluded.add(v)
                self.prohibit.add(v)
            elif kind is _BETTER:
                self.dominance.append((v, p.referent))  # type: ignore[arg-type]
            elif kind is _WORSE:
                self.dominance.append((p.referent, v))  # type: ignore[arg-type]
            elif kind is _BEST:
                self.best.add(v)
            elif kind is _WORST:
                self.worst.add(v)
            elif kind is _UNARY:
                self.unary.add(v)
            elif kind is _NUMERIC:
                self.numeric.add(v)
                self.valued.append(p)
            elif kind is _BINARY:
                self.binary.append((v, p.referent))  # type: ignore[arg-type]
                self.valued.append(p)

    def impasse(self, outcome: Outcome, items: list[Symbol]) -> SlotDecision:
        numeric = self.numeric
        t = tuple(items)
        non_numeric = tuple(v for v in items if v not in numeric) if numeric else t
        return SlotDecision(outcome, None, t, non_numeric, t)

    def run(self) -> SlotDecision | list[Symbol]:
        """Every filter but the final random choice.

        Returns a finished decision, or the list (two or more) of mutually
        indifferent candidates to choose from.
        """
        # --- require ---
        if self.require:
            required = list(self.require)
            if len(required) > 1 or required[0] in self.prohibit:
                return self.impasse("constraint-failure", required)
            return SlotDecision("select", required[0], (), (), (required[0],))

        # --- acceptable, prohibit, reject ---
        excluded = self.excluded
        if excluded:
            cands = [v for v in self.acceptable if v not in excluded]
        else:
            cands = list(self.acceptable)
        if len(cands) <= 1:
            if not cands:
                return _NONE_DECISION
            return SlotDecision("select", cands[0], (), (), (cands[0],))

        # --- better / worse (not transitive) ---
        if self.dominance:
            present = set(cands)
            dominated = {
                worse
                for better, worse in self.dominance
                if better in present and worse in present and not same_symbol(better, worse)
            }
            if dominated:
                if len(dominated) == len(present):
                    return self.impasse("conflict", cands)
                cands = [v for v in cands if v not in dominated]
                if len(cands) == 1:
                    return SlotDecision("select", cands[0], (), (), (cands[0],))

        # --- best ---
        if self.best:
            best = [v for v in cands if v in self.best]
            if best:
                cands = best
                if len(cands) == 1:
                    return SlotDecision("select", cands[0], (), (), (cands[0],))

        # --- worst ---
        if self.worst:
            rest = [v for v in cands if v not in self.worst]
            if rest:
                cands = rest
                if len(cands) == 1:
                    return SlotDecision("select", cands[0], (), (), (cands[0],))

        # --- indifferent ---
        unary = self.unary
        numeric = self.numeric
        pairs: set[tuple[Symbol, Symbol]] | None = None
        for c in cands:
            if c in unary or c in numeric:
                continue
            if pairs is None:
                pairs = set()
                for a, b in self.binary:
                    pairs.add((a, b))
                    pairs.add((b, a))
            for other in cands:
                if other is not c and (c, other) not in pairs:
                    return self.impasse("tie", cands)
        return cands


def _check_options(numeric_mode: str, policy: str) -> None:
    if numeric_mode not in NUMERIC_MODES:
        raise ValueError(f"numeric_mode must be one of {NUMERIC_MODES}, not {numeric_mode!r}")
    if policy not in POLICIES:
        raise ValueError(f"policy must be one of {POLICIES}, not {policy!r}")


def decide(
    preferences: Iterable[Preference],
    *,
    current: Symbol | None = None,
    rng: random.Random | None = None,
    numeric_mode: str = "sum",
    policy: str = "softmax",
    temperature: float = 1.0,
    epsilon: float = 0.1,
) -> SlotDecision:
    """Run Soar's preference semantics on one slot's preferences.

    Parameters
    ----------
    preferences : iterable of Preference
        Every preference for the slot, oldest first (the order only affects
        the order of candidates and items, see the module docstring).
    current : Symbol, optional
        The value selected in the slot now (the current operator).  If the
        preferences still allow it (:func:`should_keep`), it stays selected:
        no random number is drawn.
    rng : random.Random, optional
        The generator used for a random choice among indifferent candidates
        (see :func:`choose` for exactly which calls are made).  ``None`` uses
        a fresh ``random.Random(0)`` for this call: reproducible, but the same
        draw every time; an agent should pass its own seeded generator.
    numeric_mode : {"sum", "avg"}
        How several numeric-indifferent preferences for one value combine.
    policy : {"softmax", "boltzmann", "epsilon-greedy", "random", "first", "last"}
        Soar's indifferent-selection policy; Soar's default is ``softmax``.
    temperature : float
        Used by ``boltzmann`` only.
    epsilon : float
        Used by ``epsilon-greedy`` only.

    Returns
    -------
    SlotDecision

    Raises
    ------
    ValueError
        For an unknown ``numeric_mode`` or ``policy``.

    Examples
    --------
    Two acceptable operators, one better:

    >>> A = PreferenceKind.ACCEPTABLE
    >>> prefs = [Preference(A, "o1"), Preference(A, "o2"),
    ...          Preference(PreferenceKind.UNARY_INDIFFERENT, "o1"),
    ...          Preference(PreferenceKind.UNARY_INDIFFERENT, "o2")]
    >>> d = decide(prefs, rng=random.Random(7))
    >>> d.outcome, d.selected in ("o1", "o2"), d.candidates
    ('select', True, ('o1', 'o2'))
    >>> decide(prefs, current="o2").selected
    'o2'

    Two required values are a constraint failure:

    >>> decide([Preference(PreferenceKind.REQUIRE, "o1"),
    ...         Preference(PreferenceKind.REQUIRE, "o2")]).items
    ('o1', 'o2')
    """
    if type(preferences) is list and preferences:
        # fast path: acceptable preferences for one value only (the common case)
        value = preferences[0].value
        for p in preferences:
            if p.kind is not _ACCEPTABLE or p.value is not value:
                break
        else:
            if numeric_mode in NUMERIC_MODES and policy in POLICIES:
                return SlotDecision("select", value, (), (), (value,))
    _check_options(numeric_mode, policy)
    slot = _Slot(preferences)
    result = slot.run()
    if type(result) is SlotDecision:
        return result
    cands: list[Symbol] = result  # type: ignore[assignment]
    if current is not None:
        for c in cands:
            if same_symbol(c, current):
                return SlotDecision("select", c, (), (), tuple(cands))
    values = numeric_values(slot.valued, cands, numeric_mode)
    chosen = choose(
        cands, values, rng if rng is not None else random.Random(0),
        policy=policy, temperature=temperature, epsilon=epsilon,
    )
    return SlotDecision("select", chosen, (), (), tuple(cands))


def should_keep(preferences: Iterable[Preference], current: Symbol) -> bool:
    """Soar's consistency check: may the selected value ``current`` stay?

    True iff the preferences, run through every filter, end without an
    impasse and with ``current`` among the remaining candidates (alone, or
    indifferent to the others).  So the current operator is removed when its
    acceptable preference is gone, when it is rejected or prohibited, or when a
    newcomer is better, best, required, or merely ties with it; a newcomer
    that is worse, or indifferent to it, changes nothing.  No random number is
    used.

    Examples
    --------
    >>> A, W = PreferenceKind.ACCEPTABLE, PreferenceKind.WORSE
    >>> should_keep([Preference(A, "o1")], "o1")
    True
    >>> should_keep([Preference(A, "o1"), Preference(A, "o2")], "o1")  # a tie
    False
    >>> should_keep([Preference(A, "o1"), Preference(A, "o2"), Preference(W, "o2", "o1")], "o1")
    True
    """
    result = _Slot(preferences).run()
    if isinstance(result, SlotDecision):
        sel = result.selected
        return result.outcome == "select" and sel is not None and same_symbol(sel, current)
    for c in result:
        if same_symbol(c, current):
            return True
    return False


def numeric_values(
    preferences: Sequence[Preference], candidates: Sequence[Symbol], mode: str = "sum"
) -> list[float]:
    """The value of each candidate for indifferent selection, as Soar computes it.

    A candidate's value is the sum (``mode="sum"``) or mean (``"avg"``) over
    its numeric-indifferent preferences (their numbers) and its binary
    indifferent preferences (the referent if it is a number, else 0); a
    candidate with neither has value 0.

    Examples
    --------
    >>> N = PreferenceKind.NUMERIC_INDIFFERENT
    >>> prefs = [Preference(N, "a", 0.5), Preference(N, "a", 0.25), Preference(N, "b", 3)]
    >>> numeric_values(prefs, ["a", "b", "c"]), numeric_values(prefs, ["a"], "avg")
    ([0.75, 3.0, 0.0], [0.375])
    """
    totals: dict[Symbol, float] = {}
    counts: dict[Symbol, int] = {}
    for p in preferences:
        kind = p.kind
        if kind is _NUMERIC or kind is _BINARY:
            r = p.referent
            number = float(r) if is_number(r) else 0.0  # type: ignore[arg-type]
            totals[p.value] = totals.get(p.value, 0.0) + number
            counts[p.value] = counts.get(p.value, 0) + 1
    out: list[float] = []
    for c in candidates:
        total = totals.get(c, 0.0)
        if mode == "avg" and c in counts:
            total /= counts[c]
        out.append(total)
    return out


def choose(
    candidates: Sequence[Symbol],
    values: Sequence[float],
    rng: random.Random,
    *,
    policy: str = "softmax",
    temperature: float = 1.0,
    epsilon: float = 0.1,
) -> Symbol:
    """Pick one of several indifferent candidates, as Soar's exploration policies do.

    The RNG calls are part of the contract (a seeded run is reproducible):

    * ``softmax`` (Soar's default; despite the name, proportional to value):
      if no value is positive, ``candidates[rng.randrange(n)]``; otherwise
      ``r = total * rng.random()`` with ``total`` the sum of the positive
      values, and the first candidate (in order, counting positive values
      only) whose running sum reaches ``r``.  Candidates with a value <= 0 are
      then never chosen.
    * ``boltzmann``: weights ``exp((v - max) / temperature)``, ``r = sum *
      rng.random()``, first candidate whose running sum reaches ``r``.
    * ``epsilon-greedy``: ``rng.random() < epsilon`` picks uniformly
      (``rng.randrange(n)``); otherwise the highest value, several highest
      broken by ``rng.randrange(k)`` in candidate order.
    * ``random``: ``candidates[rng.randrange(n)]``.
    * ``first`` / ``last``: no random number.

    Examples
    --------
    >>> choose(["a", "b"], [0.0, 0.9], random.Random(1))
    'b'
    >>> choose(["a", "b"], [0.0, 0.0], random.Random(1), policy="last")
    'b'
    """
    n = len(candidates)
    if policy == "softmax":
        total = 0.0
        for v in values:
            if v > 0:
                total += v
        if total == 0.0:
            return candidates[rng.randrange(n)]
        r = total * rng.random()
        running = 0.0
        last = None
        for c, v in zip(candidates, values):
            if v > 0:
                running += v
                last = c
                if r <= running:
                    return c
        return last  # type: ignore[return-value]  # rounding at the very top
    if policy == "boltzmann":
        top = max(values)
        weights = [math.exp((v - top) / temperature) for v in values]
        r = sum(weights) * rng.random()
        running = 0.0
        for c, w in zip(candidates, weights):
            running += w
            if running >= r:
                return c
        return candidates[-1]
    if policy == "epsilon-greedy":
        if rng.random() < epsilon:
            return candidates[rng.randrange(n)]
        top = max(values)
        tops = [c for c, v in zip(candidates, values) if v == top]
        return tops[0] if len(tops) == 1 else tops[rng.randrange(len(tops))]
    if policy == "random":
        return candidates[rng.randrange(n)]
    if policy == "first":
        return candidates[0]
    if policy == "last":
        return candidates[-1]
    raise ValueError(f"policy must be one of {POLICIES}, not {policy!r}")
