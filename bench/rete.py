"""Matcher-only benchmarks of the Rete (figures, not tests).

Run ``python bench/rete.py`` (``--quick`` for a smoke run).

* value join: N objects of kind ``a`` (``^v 1..N``) and N of kind ``b``
  (``^w 1..N``) hang off one state, and one production joins each ``a`` with
  the ``b`` of equal value -- the conditions of ``join*equal-values`` in
  ``bench/engine.py``.  Seconds to add the 4N WMEs and take the N matches,
  for N = 1,000 / 5,000 / 20,000, and time(20,000) / time(5,000) (linear
  means about 4; the target is at most 5).
* WME churn on a counter: the counter agent's productions and, per decision,
  the WME changes its cycle makes (propose: operator ``+`` and its ``^name``;
  decide: the operator; apply: the count is replaced; then the proposal and
  the selection retract), 8 changes and 3 ``take_changes`` calls per
  decision -- WME changes per second and decisions per second for the
  matcher alone (the figures include about 2 us per decision of making the
  WMEs and identifiers).

Medians and best runs are printed: on a shared machine the best run is the
steadier figure; compare revisions in alternating runs.

:func:`value_join` and :func:`counter_productions` are reusable (e.g. by
``bench/engine.py``).
"""

from __future__ import annotations

import argparse
import gc
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from adapt.engine.matcher import Matcher  # noqa: E402
from adapt.engine.production import (  # noqa: E402
    Condition,
    EqualityTest,
    Production,
    RelationalTest,
    Variable,
)
from adapt.engine.rete import Rete  # noqa: E402
from adapt.engine.symbols import Identifier, IdentifierFactory  # noqa: E402
from adapt.engine.wme import WME  # noqa: E402


def _c(ident: str, attr: str, value: object = None, *, negated: bool = False) -> Condition:
    """``(<ident> ^attr value)``; a value written ``<v>`` is a variable."""
    if isinstance(value, str) and value.startswith("<"):
        test: object = EqualityTest(Variable(value))
    elif value is None:
        test = None
    else:
        test = EqualityTest(value)  # type: ignore[arg-type]
    return Condition(Variable(ident), EqualityTest(attr), test, False, negated)  # type: ignore[arg-type]


def value_join(n: int) -> tuple[list[Production], list[WME]]:
    """The value-join production and its 4N + 1 WMEs (timetags from 1).

    ``(<s> ^type state) (<s> ^a <x>) (<x> ^v <v>) (<y> ^w <v>) (<s> ^b <y>)``
    over ``(S1 ^a A_i) (A_i ^v i) (S1 ^b B_i) (B_i ^w i)``: N matches.
    """
    production = Production("join*equal-values", (
        _c("<s>", "type", "state"),
        _c("<s>", "a", "<x>"),
        _c("<x>", "v", "<v>"),
        _c("<y>", "w", "<v>"),
        _c("<s>", "b", "<y>"),
    ), ())
    ids = IdentifierFactory()
    s1 = ids.new("S")
    wmes = [WME(s1, "type", "state", False, 1)]
    for i in range(1, n + 1):
        a, b = ids.new("A"), ids.new("B")
        for ident, attr, value in ((s1, "a", a), (a, "v", i), (s1, "b", b), (b, "w", i)):
            wmes.append(WME(ident, attr, value, False, len(wmes) + 1))
    return [production], wmes


def time_value_join(n: int, matcher_factory: type = Rete, collect: bool = True) -> float:
    """Seconds to add the value-join WMEs and take the N matches; with
    ``collect`` false, Python's cyclic garbage collector is off while timing
    (the Rete frees deleted tokens by reference counting: it breaks the
    token tree's cycles itself)."""
    productions, wmes = value_join(n)
    matcher: Matcher = matcher_factory()
    for p in productions:
        matcher.add_production(p)
    gc.collect()
    if not collect:
        gc.disable()
    try:
        start = time.perf_counter()
        for w in wmes:
            matcher.add_wme(w)
        added, _ = matcher.take_changes()
        elapsed = time.perf_counter() - start
    finally:
        gc.enable()
    assert len(added) == n, (len(added), n)
    return elapsed


def counter_productions(limit: int) -> list[Production]:
    """The counter agent's conditions (as the parser normalises them)."""
    s, o, c = Variable("<s>"), Variable("<o>"), Variable("<c>")
    state = _c("<s>", "type", "state")
    return [
        Production("counter*propose*init", (
            state, _c("<s>", "superstate", "nil"), _c("<s>", "count", None, negated=True)), ()),
        Production("counter*apply*init", (
            state, _c("<s>", "operator", "<o>"), _c("<o>", "name", "init")), ()),
        Production("counter*propose*count", (
            state,
            Condition(s, EqualityTest("count"), RelationalTest("<", limit)),
            Condition(s, EqualityTest("count"), EqualityTest(c))), ()),
        Production("counter*apply*count", (
            state,
            Condition(s, EqualityTest("operator"), EqualityTest(o)),
            _c("<o>", "name", "count"),
            _c("<s>", "count", "<c>")), ()),
        Production("counter*halt", (state, _c("<s>", "count", limit)), ()),
    ]


def time_counter(decisions: int) -> tuple[float, int]:
    """Seconds for ``decisions`` decisions' worth of counter WME changes, and
    the number of WME changes made."""
    rete = Rete()
    for p in counter_productions(decisions + 10):
        rete.add_production(p)
    ids = IdentifierFactory()
    s1 = ids.new("S")
    tt = 0

    def wme(ident: Identifier, attr: str, value: object, plus: bool = False) -> WME:
        nonlocal tt
        tt += 1
        return WME(ident, attr, value, plus, tt)  # type: ignore[arg-type]

    for w in (wme(s1, "type", "state"), wme(s1, "superstate", "nil")):
        rete.add_wme(w)
    count = wme(s1, "count", 0)
    rete.add_wme(count)
    rete.take_changes()
    changes = 0
    gc.collect()
    start = time.perf_counter()
    for i in range(decisions):
        op = ids.new("O")
        plus, name = wme(s1, "operator", op, True), wme(op, "name", "count")
        rete.add_wme(plus)          # propose
        rete.add_wme(name)
        rete.take_changes()
        chosen = wme(s1, "operator", op)
        rete.add_wme(chosen)        # decide
        rete.take_changes()
        rete.remove_wme(count)      # apply
        count = wme(s1, "count", i + 1)
        rete.add_wme(count)
        rete.remove_wme(plus)       # retractions
        rete.remove_wme(name)
        rete.remove_wme(chosen)
        rete.take_changes()
        changes += 8
    return time.perf_counter() - start, changes


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes, one run")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    sizes = [200, 1000, 4000] if args.quick else [1000, 5000, 20000]
    runs = 1 if args.quick else args.runs
    for collect, label in ((True, "default gc"), (False, "cyclic gc off while timing")):
        print(f"value join (matcher only, {label}): add 4N+1 WMEs, take N matches")
        medians = {}
        for n in sizes:
            times = [time_value_join(n, collect=collect) for _ in range(runs)]
            medians[n] = statistics.median(times)
            print(f"  N={n:>6}: median {medians[n]:.3f} s  best {min(times):.3f} s  runs "
                  + " ".join(f"{t:.3f}" for t in times))
        ratio = medians[sizes[2]] / medians[sizes[1]]
        print(f"  time({sizes[2]}) / time({sizes[1]}) = {ratio:.2f}"
              f"  (linear ~ {sizes[2] / sizes[1]:.0f}, target <= 5)")

    decisions = 2000 if args.quick else 20000
    print(f"counter WME churn (matcher only): {decisions} decisions, 8 WME changes each")
    results = [time_counter(decisions) for _ in range(runs)]
    changes = results[0][1]
    for label, seconds in (("median", statistics.median(t for t, _ in results)),
                           ("best", min(t for t, _ in results))):
        print(f"  {label} {seconds:.3f} s: {changes / seconds:,.0f} WME changes/s, "
              f"{decisions / seconds:,.0f} decisions/s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
