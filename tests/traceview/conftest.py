"""Traces of a fake "counter" agent, written in the documented format.

The agent counts up: each decision cycle ``propose*count`` proposes an
operator ``count``, the decision selects it and ``apply*count`` replaces
``(S1 ^count n)`` by ``(S1 ^count n+1)``.  Every ``tie_every`` cycles a second
operator ``skip`` is proposed too, the decision is an operator tie with a
substate, and the next decision selects ``count`` and removes the substate.
The generator is seeded and deterministic; it writes records exactly as
``docs/trace-format.md`` describes them for the given trace level.
"""

from __future__ import annotations

import json
import random
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Callable

import pytest

_dumps = json.JSONEncoder(separators=(", ", ": ")).encode

PNG_1x1 = (
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR4"
    "2mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="
)


def S(name: str) -> dict[str, str]:
    return {"id": name}


class CounterAgent:
    """Writes the trace of ``decisions`` decision cycles of the counter agent."""

    def __init__(self, level: int, tie_every: int, schema_every: int, frames: bool,
                 diverge_at: int | None, seed: int) -> None:
        self.level, self.tie_every, self.schema_every = level, tie_every, schema_every
        self.frames, self.diverge_at = frames, diverge_at
        self.rng = random.Random(seed)
        self.tt = 0
        self.ops = 0
        self.states = 1
        self.live: dict[int, list[Any]] = {}
        self.firings = 0

    def wme(self, ident: str, attr: str, value: Any, acceptable: bool = False) -> list[Any]:
        self.tt += 1
        w = [self.tt, S(ident), attr, value, acceptable]
        self.live[self.tt] = w
        return w

    def tt_of(self, ident: str, attr: str, value: Any = None, acceptable: bool = False) -> int:
        for tt, w in self.live.items():
            if w[1]["id"] == ident and w[2] == attr and w[4] == acceptable and (
                value is None or w[3] == value
            ):
                return tt
        raise KeyError((ident, attr, value))

    def phase(self, d: int, phase: str, adds: list[Any] = (), removes: list[int] = (),
              firings: list[Any] = (), retractions: list[Any] = (), writes: str = "") -> str:
        for t in removes:
            self.live.pop(t, None)
        self.firings += len(firings)
        rec: dict[str, Any] = {"kind": "phase", "d": d, "phase": phase}
        if self.level >= 4:
            rec["adds"] = list(adds)
            rec["removes"] = list(removes)
        if self.level >= 3:
            rec["firings"] = list(firings)
            rec["retractions"] = list(retractions)
        if writes:
            rec["writes"] = writes
        rec["messages"] = []
        return _dumps(rec) if self.level >= 2 else ""

    def lines(self, decisions: int) -> Iterator[str]:
        count = 0
        selected: str | None = None
        substate: str | None = None
        for c in range(1, decisions + 1):
            d = c - 1
            # input
            adds = []
            if c == 1:
                adds = [self.wme("S1", "type", "state"), self.wme("S1", "superstate", "nil"),
                        self.wme("S1", "io", S("I1")), self.wme("I1", "input-link", S("I2")),
                        self.wme("I1", "output-link", S("I3")), self.wme("S1", "count", 0)]
            yield (self.phase(d, "input", adds))
            # proposal
            tie = self.tie_every and c % self.tie_every == 0
            firings, adds = [], []
            if substate is None:
                names = ["count", "skip"] if tie else ["count"]
                for name in names:
                    self.ops += 1
                    o = f"O{self.ops}"
                    firings.append({"rule": f"propose*{name}", "level": 0, "support": "i",
                                    "bindings": {"<s>": S("S1"), "<c>": count},
                                    "wmes": [self.tt_of("S1", "type"), self.tt_of("S1", "count")]})
                    adds += [self.wme(o, "name", name), self.wme("S1", "operator", S(o), True)]
            yield (self.phase(d, "proposal", adds, firings=firings))
            # decision
            proposed = sorted(
                (w[3]["id"] for w in self.live.values() if w[2] == "operator" and w[4]),
                key=lambda n: int(n[1:]))
            adds, removes = [], []
            if selected is not None:
                removes.append(self.tt_of("S1", "operator", S(selected)))
                removes.append(self.tt_of(selected, "name"))
            impasse = None
            removed_goals = None
            if tie and substate is None:
                self.states += 1
                substate = f"S{self.states}"
                adds = [self.wme(substate, "type", "state"),
                        self.wme(substate, "superstate", S("S1")),
                        self.wme(substate, "impasse", "tie"),
                        self.wme(substate, "attribute", "operator")]
                adds += [self.wme(substate, "item", S(o)) for o in proposed]
                impasse = {"type": "tie", "attribute": "operator", "items": [S(o) for o in proposed],
                           "state": S(substate)}
                selected = None
                level = 0
            else:
                if substate is not None:
                    removes += [t for t, w in self.live.items() if w[1]["id"] == substate]
                    removed_goals = [S(substate)]
                    substate = None
                selected = proposed[0]
                adds = [self.wme("S1", "operator", S(selected))]
                level = 0
            yield (self.phase(c, "decision", adds, removes))
            candidates = [{"id": S(o), "name": self.live[self.tt_of(o, "name")][3],
                           "preferences": [["+", None]] + ([[">", None]] if i == 0 and not impasse
                                                           else [])}
                          for i, o in enumerate(proposed)]
            rec: dict[str, Any] = {"kind": "decision", "d": c, "level": level}
            if self.level >= 5:
                rec["candidates"] = candidates
            rec["selected"] = (None if selected is None else
                               {"id": S(selected), "name": self.live[self.tt_of(selected, "name")][3]})
            rec["impasse"] = impasse
            if removed_goals:
                rec["removed_goals"] = removed_goals
            if self.frames:
                rec["mmd_frame"] = PNG_1x1
            yield (_dumps(rec))
            # apply
            firings, retractions, adds, removes = [], [], [], []
            if selected is not None:
                op_tt = self.tt_of("S1", "operator", S(selected))
                name_tt = self.tt_of(selected, "name")
                count_tt = self.tt_of("S1", "count")
                step = 2 if self.diverge_at is not None and c == self.diverge_at else 1
                firings.append({"rule": "apply*count", "level": 0, "support": "o",
                                "bindings": {"<s>": S("S1"), "<o>": S(selected), "<c>": count},
                                "wmes": [self.tt_of("S1", "type"), op_tt, count_tt, name_tt]})
                removes.append(count_tt)
                count += step
                adds.append(self.wme("S1", "count", count))
                for t, w in list(self.live.items()):
                    if w[2] == "operator" and w[4]:
                        retractions.append({"rule": "propose*count", "level": 0,
                                            "wmes": [self.tt_of("S1", "type"), count_tt]})
                        removes.append(t)
                        if w[3]["id"] != selected:
                            removes.append(self.tt_of(w[3]["id"], "name"))
            elif substate is not None:
                firings.append({"rule": "tie*prefer-count", "level": 1, "support": "o",
                                "bindings": {"<ss>": S(substate), "<s>": S("S1")},
                                "wmes": [self.tt_of(substate, "type"),
                                         self.tt_of(substate, "impasse")]})
            yield (self.phase(c, "apply", adds, removes, firings, retractions))
            if self.schema_every and c % self.schema_every == 0:
                yield (_dumps({"kind": "schema", "d": c, "event": "activated",
                                   "schema": "reach", "data": {"strength": round(self.rng.random(), 3)}}))
            yield (self.phase(c, "output", writes=f"count {count}\n" if selected else ""))


def write_counter_trace(
    path: Path, decisions: int, *, level: int = 5, tie_every: int = 0, schema_every: int = 0,
    frames: bool = False, truncate: bool = False, diverge_at: int | None = None, seed: int = 1,
    files: tuple[str, ...] = ("rules/counter.soar",), footer: bool = True,
) -> Path:
    """Write a counter-agent trace to ``path`` and return it."""
    agent = CounterAgent(level, tie_every, schema_every, frames, diverge_at, seed)
    out = [_dumps({"kind": "header", "format": "adapt-trace", "version": 1, "adapt": "0.1.0",
                   "files": list(files), "seed": seed, "level": level,
                   "created": "2026-11-22T01:40:00Z"})]
    with open(path, "w", encoding="utf-8") as f:
        for line in agent.lines(decisions):
            if line:
                out.append(line)
            if len(out) >= 20_000:
                f.write("\n".join(out) + "\n")
                out = []
        f.write("".join(line + "\n" for line in out))
        if footer:
            f.write(_dumps({"kind": "footer", "halted": False, "stop_reason": "max-decisions",
                            "decisions": decisions, "production_firings": agent.firings,
                            "wm_size_final": len(agent.live), "elapsed_s": 0.5}) + "\n")
    if truncate:
        data = Path(path).read_bytes().rstrip(b"\n")
        last = data.rfind(b"\n")
        Path(path).write_bytes(data[: last + 1 + (len(data) - last) // 2])
    return Path(path)


@pytest.fixture
def counter_trace(tmp_path: Path) -> Callable[..., Path]:
    """A factory: ``counter_trace(decisions, **options)`` writes a trace into tmp_path."""
    made = 0

    def make(decisions: int = 20, name: str | None = None, **options: Any) -> Path:
        nonlocal made
        made += 1
        return write_counter_trace(tmp_path / (name or f"trace{made}.jsonl"), decisions, **options)

    return make


@pytest.fixture(scope="session")
def big_trace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 100,000-decision level-5 trace (about 150 MB), written once per session."""
    path = tmp_path_factory.mktemp("big") / "counter-100k.jsonl"
    return write_counter_trace(path, 100_000, tie_every=50)


#: Rules in the shape of the counter agent's, for ``why`` (conditions and actions).
COUNTER_RULES = """
sp {propose*count
   (state <s> ^count <c>)
-->
   (<s> ^operator <o> +)
   (<o> ^name count)}

sp {propose*skip
   (state <s> ^count <c>)
-->
   (<s> ^operator <o> +)
   (<o> ^name skip)}

sp {apply*count
   (state <s> ^operator <o> ^count <c>)
   (<o> ^name count)
-->
   (<s> ^count (+ <c> 1) ^count <c> -)}

sp {tie*prefer-count
   (state <ss> ^impasse tie ^superstate <s>)
-->
   (write |tie|)}

sp {check*done
   (state <s> ^count {<c> >= 10})
  -(<s> ^done yes)
-->
   (<s> ^done yes)}

sp {stop*idle
   (state <s> ^count <c>)
  -(<s> ^operator <o>)
-->
   (halt)}

sp {watch*substate
   (state <s> ^superstate <ss>)
   (<ss> ^impasse tie)
-->
   (write |never|)}
"""


@pytest.fixture
def counter_rules(tmp_path: Path) -> Path:
    """The counter rules in ``tmp_path/rules/counter.soar`` (where the traces' headers point)."""
    path = tmp_path / "rules" / "counter.soar"
    path.parent.mkdir(exist_ok=True)
    path.write_text(COUNTER_RULES)
    return path
