"""Soar's own agents, run unchanged in adapt and in real Soar (figures, not tests).

    python bench/soar_agents.py --soar PATH/TO/Soar --agents PATH/TO/Agents
    python bench/soar_agents.py ... --group chunking      # the agents that need chunking
    python bench/soar_agents.py ... --only fifteen         # agents whose path contains a word
    python bench/soar_agents.py ... --select               # recompute the selection below
    python bench/soar_agents.py ... --engine soar          # adapt's Soar engine instead
    python bench/soar_agents.py ... --engine soar --group every   # every agent of the two

With ``--engine soar`` each agent runs through ``adapt rules run --engine soar
--json`` (adapt's Soar engine: the kernel behind adapt's interface, in a child
process) and directly in soar-sml (``tests/engine/soar_harness.py``, with the
learning the agent asks for), and the two reports must be the same:
``first_difference`` (halted, stop reason, decisions, selections and impasses
per decision, the output), the production firings and the kernel's messages.
``--group every`` takes every top-level agent file of the two repositories,
also those that need what adapt's own engine lacks (RL, smem, epmem, ...).

``--soar`` and ``--agents`` are local checkouts of the public SoarGroup/Soar and
SoarGroup/Agents repositories; nothing is fetched at run time.

**The selection.**  Every top-level agent file of the two repositories -- the
unit and functional test agents (``UnitTests/SoarTestAgents/*.soar`` and
``FullTests/*.soar``), the performance agents (``PerformanceTests/TestAgents/*.soar``),
the chunking tests (``UnitTests/SoarTestAgents/Chunking/tests/*.soar``) and the
demos (``*/*.soar`` of SoarGroup/Agents, not ``Deprecated Agents``) -- except the
files that are not agents but are sourced or loaded by hand into one
(``monitor.soar``, the ``problems-*.soar`` data files), read following ``source``:

* ``OWN``: the files hold only ``sp`` productions (flags ``:o-support``,
  ``:i-support``, ``:default``, ``:interrupt``) calling Soar 9.6's default RHS functions, and
  the agent-file commands adapt accepts (``adapt.engine.commands``: ``source``,
  ``pushd``, ``popd``, ``srand``, ``multi-attributes``, ``chunk never``,
  ``watch``, ``echo``, ``max-elaborations``, ``max-goal-depth``, ``output``,
  ``soar wait-snc off``, ``wma -s activation off``);
* ``CHUNKING``: the same plus chunking (``chunk always``, chunking settings,
  ``learn --on``, ``:chunk``), and every chunking test; they run with learning
  off in both systems (adapt: ``chunking="off"``; Soar: ``chunk never`` after
  loading).

Everything else needs what adapt does not have (reinforcement learning, semantic
or episodic memory, ``gp``, ``exec``/``cmd`` ...).  ``--select``
recomputes both lists from the checkouts with this rule and says where they
differ from the lists below.

**What is compared.**  Each agent runs in real Soar (``tests/engine/soar_harness.py``:
seed 1, ``run 5000`` unless it halts) and in adapt (``Agent(seed=1)``,
``load_file``, the same bound), each in its own child process with a time limit
and at most 6 GB of memory.  *Loads*: adapt loads the top file as shipped.
*Agrees*: the differential test's comparison (``first_difference``: halted, stop
reason, decisions, operator selections and impasses per decision, the writes
of every decision as a multiset).  *Same text*: also the same output text in the
same order (printed identifiers included).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HARNESS = ROOT / "tests" / "engine" / "soar_harness.py"

#: (repository, path) of the agents that use only what adapt supports.
OWN: tuple[tuple[str, str], ...] = (
    ("Soar", "UnitTests/SoarTestAgents/BasicTests_testBasicElaborationAndMatch.soar"),
    ("Soar", "UnitTests/SoarTestAgents/BasicTests_testInitialState.soar"),
    ("Soar", "UnitTests/SoarTestAgents/BuiltinRHSTests_testString.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testArithmetic.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testBlocksWorld.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testBlocksWorldLookAhead.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testBlocksWorldOperatorSubgoaling.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testEightPuzzle.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testTowersOfHanoi.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testTowersOfHanoiFast.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testWaterJug.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FunctionalTests_testWaterJugHierarchy.soar"),
    ("Soar", "UnitTests/SoarTestAgents/count-and-die.soar"),
    ("Soar", "UnitTests/SoarTestAgents/testGDS_Failed_Justification_Crash.soar"),
    ("Soar", "UnitTests/SoarTestAgents/testNegated_Operator_Crash.soar"),
    ("Soar", "UnitTests/SoarTestAgents/testOp_Augmentation_Crash.soar"),
    ("Soar", "UnitTests/SoarTestAgents/testPreferenceDeallocation.soar"),
    ("Soar", "UnitTests/SoarTestAgents/testRHSRand.soar"),
    ("Soar", "UnitTests/SoarTestAgents/testmulti.soar"),
    ("Soar", "UnitTests/SoarTestAgents/testoutputleak.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FullTests/pref-semantics-test.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FullTests/testGDSBug1011.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FullTests/testLearn.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FullTests/testMatchTimeInterrupt.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FullTests/testcopy.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FullTests/testinterrupt.soar"),
    ("Soar", "UnitTests/SoarTestAgents/FullTests/teststatuscomplete.soar"),
    ("Soar", "PerformanceTests/TestAgents/FactorizationStressTest.soar"),
    ("Soar", "PerformanceTests/TestAgents/arithmetic.soar"),
    ("Soar", "PerformanceTests/TestAgents/fifteen.soar"),
    ("Soar", "PerformanceTests/TestAgents/mac-planning.soar"),
    ("Soar", "PerformanceTests/TestAgents/wait.soar"),
    ("Soar", "PerformanceTests/TestAgents/water-jug-lookahead.soar"),
    ("Agents", "BW-Simple/BW-Simple.soar"),
    ("Agents", "BW-SoarManual/blocksworld.soar"),
    ("Agents", "algebra/algebra.soar"),
    ("Agents", "color-blocks/color-blocks-count.soar"),
    ("Agents", "color-blocks/color-blocks.soar"),
    ("Agents", "count/count.soar"),
    ("Agents", "count/fibonacci.soar"),
    ("Agents", "default/selection-optimal.soar"),
    ("Agents", "hello-world-operator/hello-world-operator.soar"),
    ("Agents", "hello-world-rule/hello-world-rule.soar"),
    ("Agents", "mac/mac.soar"),
    ("Agents", "towers-of-hanoi-recursive/towers-of-hanoi-recursive.soar"),
    ("Agents", "towers-of-hanoi-simple/towers-of-hanoi.soar"),
    ("Agents", "water-jug-simple/water-jug.soar"),
)

#: Agents that also need only chunking (run with learning off).
CHUNKING: tuple[tuple[str, str], ...] = tuple(
    [("Soar", f"UnitTests/SoarTestAgents/{p}.soar") for p in (
        "FunctionalTests_testCountTest", "FullTests/testGDSBug1144",
        "FullTests/testNegatedConjunctiveChunkLoopBug510")]
    + [("Soar", f"PerformanceTests/TestAgents/{p}_learning.soar") for p in (
        "FactorizationStressTest", "arithmetic", "fifteen", "mac-planning", "wait",
        "water-jug-lookahead")]
    + [("Soar", f"UnitTests/SoarTestAgents/Chunking/tests/{p}.soar") for p in (
        "ChunkingDemoTests_Demo_Arithmetic", "ChunkingDemoTests_Demo_Blocks_World_Hierarchical",
        "ChunkingDemoTests_Demo_Blocks_World_Hierarchical_Look_Ahead",
        "ChunkingDemoTests_Demo_Blocks_World_Look_Ahead",
        "ChunkingDemoTests_Demo_Blocks_World_Operator_Subgoaling",
        "ChunkingDemoTests_Demo_Eight_Puzzle", "ChunkingDemoTests_Demo_MaC_Planning",
        "ChunkingDemoTests_Demo_ToH_Recursive", "ChunkingDemoTests_Demo_Water_Jug_Hierarchy",
        "ChunkingDemoTests_Demo_Water_Jug_Look_Ahead", "ChunkingDemoTests_Demo_Water_Jug_Tie",
        "ChunkingTests_All_Test_Types", "ChunkingTests_BUNCPS_0", "ChunkingTests_BUNCPS_1",
        "ChunkingTests_BUNCPS_2", "ChunkingTests_BUNCPS_3", "ChunkingTests_BUNCPS_4",
        "ChunkingTests_BUNCPS_5", "ChunkingTests_BUNCPS_6_Four_Level",
        "ChunkingTests_BUNCPS_7_with_Constraints", "ChunkingTests_Chunk_All_Only_Except",
        "ChunkingTests_Chunk_Operator_Tie_Impasse", "ChunkingTests_Chunk_Operator_Tie_Item_Links",
        "ChunkingTests_Chunk_RL_Proposal", "ChunkingTests_Chunk_Superstate_Operator_Preference",
        "ChunkingTests_Conflated_Constants", "ChunkingTests_Constraint_Prop_Simple",
        "ChunkingTests_Constraint_Prop_from_Base_Conds", "ChunkingTests_Constraint_Ungrounded",
        "ChunkingTests_Deep_Copy_Identity_Expansion", "ChunkingTests_Disjunction_Merge",
        "ChunkingTests_Duplicates", "ChunkingTests_Faux_Operator",
        "ChunkingTests_Justification_RC_not_Ungrounded_STIs",
        "ChunkingTests_Justifications_Get_New_Identities", "ChunkingTests_Literalization_Simple",
        "ChunkingTests_Literalization_of_NC_and_NCC",
        "ChunkingTests_Literalization_with_BT_Constraints",
        "ChunkingTests_Literalization_with_BT_Constraints2",
        "ChunkingTests_Literalization_with_Constraints",
        "ChunkingTests_Maintain_Instantiation_Specific_Identity", "ChunkingTests_Max_Chunks",
        "ChunkingTests_Max_Dupes", "ChunkingTests_NCC_2_Conds_Simple_Literals",
        "ChunkingTests_NCC_Complex", "ChunkingTests_NCC_Simple_Literals",
        "ChunkingTests_NCC_from_Backtrace", "ChunkingTests_NCC_with_Relational_Constraint",
        "ChunkingTests_NC_Disjunction", "ChunkingTests_NC_Simple_No_Exist",
        "ChunkingTests_NC_with_RC_and_Local_Variable",
        "ChunkingTests_NC_with_Relational_Constraint", "ChunkingTests_No_Grounds",
        "ChunkingTests_No_Topstate_Match", "ChunkingTests_Opaque_State_Barrier",
        "ChunkingTests_Operator_Selection_Knowledge",
        "ChunkingTests_Operator_Selection_Knowledge_Ghost_Operator",
        "ChunkingTests_Operator_Selection_Knowledge_In_Propose",
        "ChunkingTests_Promoted_STI", "ChunkingTests_RHS_Math", "ChunkingTests_RHS_Math_Abs",
        "ChunkingTests_RHS_Math_Children_Force_Learn", "ChunkingTests_RHS_Math_Mixed",
        "ChunkingTests_RHS_Referent_Function", "ChunkingTests_RHS_Unbound_Multivalue",
        "ChunkingTests_Rhs_Func_Literalization",
        "ChunkingTests_Reorderer_Bad_Conjunction", "ChunkingTests_Result_On_Operator",
        "ChunkingTests_Rete_Bug_Deep_vs_Deep", "ChunkingTests_Rete_Bug_Deep_vs_Top",
        "ChunkingTests_STI_Variablization", "ChunkingTests_STI_Variablization_Same_Type",
        "ChunkingTests_STI_with_referents", "ChunkingTests_Singleton_Element_Types",
        "ChunkingTests_Singletons", "ChunkingTests_Singletons_Architectural",
        "ChunkingTests_Superstate_Identity_Opaque",
        "ChunkingTests_Superstate_Identity_Opaque_Old_Singleton_Behavior",
        "ChunkingTests_Ungrounded_Mixed", "ChunkingTests_Ungrounded_Relational_Constraint",
        "ChunkingTests_Ungrounded_STI_Promotion", "ChunkingTests_Ungrounded_STIs",
        "ChunkingTests_Ungrounded_in_BT_Constraint", "ChunkingTests_Unify_Ambiguous_Output",
        "ChunkingTests_Unify_Children_Results",
        "ChunkingTests_Unify_through_Two_Traces_Four_Deep")]
    + [("Agents", p) for p in (
        "BW-Hierarchical/BW-Hierarchical.soar",
        "BW-Hierarchical-LA/BW-Hierarchical-LA.soar", "BW-LA/BW-LA.soar",
        "BW-Op-Subgoal/BW-Op-Subgoal.soar", "arithmetic/arithmetic.soar",
        "count-test-files/count-test.soar", "default/selection-astar.soar",
        "default/selection.soar", "default/simple.soar", "eight-puzzle/eight-puzzle.soar",
        "fifteen-puzzle/fifteen-puzzle.soar", "mac-planning/mac-planning.soar",
        "water-jug-hierarchy/water-jug-hierarchy.soar",
        "water-jug-look-ahead/water-jug-look-ahead.soar", "water-jug-tie/water-jug-tie.soar")]
)

MEMORY_LIMIT_GB = 6.0
NOT_AGENTS = re.compile(r"(^|/)(monitor|problems-[^/]*)\.soar$")


# ---- the selection rule ----------------------------------------------------------------

#: Soar 9.6.5's default RHS functions (its kernel's list, and SML's concat and
#: interrupt; exec and cmd call out of Soar and are not counted); Soar 9.6.5
#: also reads (succeeded) and (failed), the unit tests' functions, as (halt).
SOAR_RHS = frozenset("""
count dont-learn force-learn halt link-stm-to-ltm wait write trace log @ capitalize-symbol crlf
dc make-constant-symbol strlen timestamp trim string accept deep-copy ifeq from-st-xml + * - /
div size sum product mod min max set-count set-sum set-multiply set-min set-max set-range
set-mean set-stdev sin cos atan2 sqrt abs int float round-off-heading round-off compute-heading
compute-range compute-dice-probability rand-int rand-float concat interrupt succeeded failed
""".split())
_FLAGS_OK = frozenset({":o-support", ":i-support", ":default", ":interrupt"})


def scan(top: Path) -> tuple[set[str], set[str]]:
    """What the agent whose top file is ``top`` uses beyond adapt's support:
    ``(missing, chunking)``, read by the rule of the module docstring."""
    sys.path.insert(0, str(ROOT))
    from adapt.engine.commands import (
        CommandSyntaxError,
        Popd,
        Pushd,
        Refusal,
        Source,
        interpret,
        read_command,
        skip_blank,
    )

    missing: set[str] = set()
    chunking: set[str] = set()
    dirs = [str(top.parent)]

    def read(path: str, depth: int) -> None:
        try:
            text = Path(path).read_text(encoding="utf-8-sig")
        except (OSError, UnicodeDecodeError):
            missing.add(f"unreadable {os.path.basename(path)}")
            return
        pos = 0
        while True:
            pos = skip_blank(text, pos)
            if pos >= len(text):
                return
            try:
                command = read_command(text, pos)
            except CommandSyntaxError:
                missing.add("syntax")
                return
            pos = command.end
            words = command.words
            if words[0] == "sp":
                body = words[1] if len(words) > 1 else ""
                lhs, _, rhs = body.partition("-->")
                for flag in re.findall(r"(?<![\w|])(:[a-z-]+)", lhs):
                    if flag == ":chunk":
                        chunking.add(flag)
                    elif flag not in _FLAGS_OK:
                        missing.add(f"flag {flag}")
                for name in re.findall(r"\(\s*([^\s()<>^|{}]+)", re.sub(r"\|[^|]*\|", "", rhs)):
                    if name not in SOAR_RHS:
                        missing.add(f"function {name}")
                continue
            try:
                meaning = interpret(command, "refuse")
            except Refusal:
                try:
                    interpret(command, "off")
                    chunking.add(" ".join(words[:2]))
                except Refusal:
                    missing.add(" ".join(words[:2])[:40])
                continue
            if isinstance(meaning, Source):
                folder, slash, name = meaning.path.replace("\\", "/").rpartition("/")
                if slash:
                    dirs.append(os.path.normpath(os.path.join(dirs[-1], folder)))
                if depth < 50:
                    read(os.path.join(dirs[-1], name), depth + 1)
                if slash:
                    dirs.pop()
            elif isinstance(meaning, Pushd):
                dirs.append(os.path.normpath(os.path.join(dirs[-1], meaning.path)))
            elif isinstance(meaning, Popd) and len(dirs) > 1:
                dirs.pop()

    read(str(top), 0)
    return missing, chunking


def select(roots: dict[str, Path]) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
    """The two lists, recomputed from the checkouts."""
    tops: list[tuple[str, Path]] = []
    for folder in ("UnitTests/SoarTestAgents", "UnitTests/SoarTestAgents/FullTests",
                   "PerformanceTests/TestAgents", "UnitTests/SoarTestAgents/Chunking/tests"):
        tops += [("Soar", p) for p in sorted((roots["Soar"] / folder).glob("*.soar"))]
    tops += [("Agents", p) for p in sorted(roots["Agents"].glob("*/*.soar"))]
    own, chunking = [], []
    for repo, top in tops:
        rel = top.relative_to(roots[repo]).as_posix()
        if NOT_AGENTS.search(rel):
            continue
        missing, needs = scan(top)
        if missing:
            continue
        if needs or "/Chunking/" in rel:
            chunking.append((repo, rel))
        else:
            own.append((repo, rel))
    return own, chunking


# ---- running -------------------------------------------------------------------------------


def _limit_memory() -> None:
    import resource

    limit = int(MEMORY_LIMIT_GB * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def child_adapt(path: str, bound: int, chunking: str) -> dict[str, object]:
    sys.path.insert(0, os.environ.get("ADAPT_BENCH_ROOT") or str(ROOT))
    sys.path.insert(0, str(HARNESS.parent))
    from adapt.engine import Agent

    from soar_harness import run_adapt

    loads = True
    try:
        agent = Agent(seed=1)
        if chunking == "refuse":
            agent.load_file(path)
        else:
            agent.load_file(path, chunking="off")
    except Exception as exc:  # reported: the figure is whether it loads
        loads = False
        error = f"{type(exc).__name__}: {str(exc).splitlines()[0]}"
    start = time.perf_counter()
    report = run_adapt(Path(path), max_decisions=bound, trace_level=None,
                       chunking=chunking) if loads else {"error": error}
    report["seconds"] = time.perf_counter() - start
    report["loads"] = loads
    return report


def run_child(argv: list[str], timeout: float) -> dict[str, object]:
    try:
        proc = subprocess.run(argv, capture_output=True, timeout=timeout,
                              preexec_fn=_limit_memory)
    except subprocess.TimeoutExpired:
        return {"error": f"over the {timeout:.0f} s limit", "stop_reason": "timeout"}
    try:
        return dict(json.loads(proc.stdout.decode().strip().splitlines()[-1]))
    except (ValueError, IndexError):
        how = (f"killed by signal {-proc.returncode}" if proc.returncode < 0
               else f"exit status {proc.returncode}")
        return {"error": f"child failed: {how} {proc.stderr.decode()[-200:]}".rstrip(),
                "stop_reason": "crashed"}


def compare(path: Path, chunking: str, bound: int, timeout: float) -> dict[str, object]:
    sys.path.insert(0, str(HARNESS.parent))
    from soar_harness import first_difference

    start = time.perf_counter()
    soar = run_child([sys.executable, str(HARNESS), "--child", str(path), str(bound), "1",
                      str(timeout), "learning-off" if chunking == "off" else "-"], timeout + 30)
    soar_seconds = time.perf_counter() - start
    adapt = run_child([sys.executable, str(Path(__file__).resolve()), "--child", str(path),
                       str(bound), chunking], timeout)
    out: dict[str, object] = {"soar": soar.get("stop_reason"), "soar_seconds": soar_seconds,
                              "loads": bool(adapt.get("loads")),
                              "adapt_seconds": adapt.get("seconds")}
    if soar.get("error"):
        out["result"] = "soar-failed"
        out["detail"] = str(soar["error"])[:150]
        return out
    difference = first_difference(soar, adapt)
    if difference is None:
        same = soar.get("output") == adapt.get("output")
        out["result"] = "agrees" if same else "agrees (other write order or names)"
        if not same:
            out["detail"] = _text_difference(str(soar.get("output")), str(adapt.get("output")))
    else:
        out["result"] = "differs"
        out["detail"] = difference[:200]
    return out


def compare_engine(path: Path, bound: int, timeout: float) -> dict[str, object]:
    """The agent through ``adapt rules run --engine soar --json`` and in soar-sml directly."""
    from collections import Counter

    sys.path.insert(0, str(HARNESS.parent))
    from soar_harness import first_difference

    start = time.perf_counter()
    soar = run_child([sys.executable, str(HARNESS), "--child", str(path), str(bound), "1",
                      str(timeout), "-"], timeout + 30)
    soar_seconds = time.perf_counter() - start
    start = time.perf_counter()
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([os.environ.get("ADAPT_BENCH_ROOT") or str(ROOT)]
                                        + [p for p in [env.get("PYTHONPATH")] if p])
    try:
        proc = subprocess.run([sys.executable, "-m", "adapt", "rules", "run", str(path),
                               "--engine", "soar", "--json", "--max-decisions", str(bound)],
                              capture_output=True, timeout=timeout, env=env)
        ours: dict[str, object] = json.loads(proc.stdout.decode() or "{}")
        if not ours:
            ours = {"error": proc.stderr.decode().strip()[-200:]}
    except subprocess.TimeoutExpired:
        ours = {"error": f"over the {timeout:.0f} s limit", "stop_reason": "timeout"}
    engine_seconds = time.perf_counter() - start
    out: dict[str, object] = {"soar": soar.get("stop_reason"), "soar_seconds": soar_seconds,
                              "loads": "error" not in ours, "adapt_seconds": engine_seconds}
    if soar.get("error"):
        out["result"] = "soar-failed"
        out["detail"] = str(soar["error"])[:150]
        return out
    difference = first_difference(soar, ours)
    if difference is None and ours.get("production_firings") != soar.get("production_firings"):
        difference = (f"production firings: Soar {soar.get('production_firings')}, "
                      f"the Soar engine {ours.get('production_firings')}")
    if difference is None and Counter(ours.get("messages") or []) != Counter(  # type: ignore[arg-type]
            soar.get("messages") or []):
        difference = "kernel messages differ"
    out["result"] = "same report" if difference is None else "differs"
    if difference is not None:
        out["detail"] = difference[:200]
    return out


def every_agent(roots: dict[str, Path]) -> list[tuple[str, str]]:
    """Every top-level agent file of the two repositories (the selection rule's files)."""
    tops: list[tuple[str, Path]] = []
    for folder in ("UnitTests/SoarTestAgents", "UnitTests/SoarTestAgents/FullTests",
                   "PerformanceTests/TestAgents", "UnitTests/SoarTestAgents/Chunking/tests"):
        tops += [("Soar", p) for p in sorted((roots["Soar"] / folder).glob("*.soar"))]
    tops += [("Agents", p) for p in sorted(roots["Agents"].glob("*/*.soar"))
             if "Deprecated" not in str(p)]
    return [(repo, top.relative_to(roots[repo]).as_posix()) for repo, top in tops
            if not NOT_AGENTS.search(top.relative_to(roots[repo]).as_posix())]


def _text_difference(a: str, b: str) -> str:
    for k, (x, y) in enumerate(zip(a.splitlines(), b.splitlines())):
        if x != y:
            return f"line {k + 1}: Soar {x[:60]!r}, adapt {y[:60]!r}"
    return "output lengths differ"


def main() -> int:
    if len(sys.argv) == 5 and sys.argv[1] == "--child":
        print(json.dumps(child_adapt(sys.argv[2], int(sys.argv[3]), sys.argv[4]), default=str))
        sys.stdout.flush()
        os._exit(0)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--soar", type=Path, required=True, help="a checkout of SoarGroup/Soar")
    parser.add_argument("--agents", type=Path, required=True,
                        help="a checkout of SoarGroup/Agents")
    parser.add_argument("--group", choices=("own", "chunking", "all", "every"), default="own",
                        help="own, chunking, both (all); every: every agent file (with "
                             "--engine soar)")
    parser.add_argument("--engine", choices=("adapt", "soar"), default="adapt",
                        help="the engine compared with soar-sml (default adapt's own)")
    parser.add_argument("--only", default=None, help="agents whose path contains this text")
    parser.add_argument("--select", action="store_true",
                        help="recompute the selection from the checkouts and compare")
    parser.add_argument("--max-decisions", type=int, default=5000)
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds per run")
    parser.add_argument("--json", type=Path, default=None, help="also write the rows here")
    parser.add_argument("--adapt-root", type=Path, default=None,
                        help="run the adapt of another checkout (a 'before' figure)")
    opts = parser.parse_args()
    if opts.adapt_root is not None:
        os.environ["ADAPT_BENCH_ROOT"] = str(opts.adapt_root.resolve())
    roots = {"Soar": opts.soar.resolve(), "Agents": opts.agents.resolve()}
    if opts.select:
        own, chunking = select(roots)
        for name, found, listed in (("OWN", own, OWN), ("CHUNKING", chunking, CHUNKING)):
            print(f"{name}: {len(found)} found, {len(listed)} listed")
            for item in sorted(set(found) - set(listed)):
                print(f"  found, not listed: {item}")
            for item in sorted(set(listed) - set(found)):
                print(f"  listed, not found: {item}")
        return 0
    groups = {"own": [(a, "refuse") for a in OWN], "chunking": [(a, "off") for a in CHUNKING]}
    if opts.group == "every":
        if opts.engine != "soar":
            parser.error("--group every needs --engine soar (most agents need what the own "
                         "engine lacks)")
        todo = [(a, "as-written") for a in every_agent(roots)]
    elif opts.group == "all":
        todo = groups["own"] + groups["chunking"]
    else:
        todo = groups[opts.group]
    if opts.only:
        todo = [t for t in todo if opts.only in t[0][1]]
    sys.path.insert(0, os.environ.get("ADAPT_BENCH_ROOT") or str(ROOT))
    from adapt.engine import engine_build

    print(f"bench/soar_agents.py  {time.strftime('%Y-%m-%d %H:%M')}  adapt "
          f"{os.environ.get('ADAPT_BENCH_ROOT') or ROOT}, engine: {engine_build()}  "
          f"{len(todo)} agents")
    rows = []
    for (repo, rel), chunking in todo:
        if opts.engine == "soar":
            row = compare_engine(roots[repo] / rel, opts.max_decisions, opts.timeout)
        else:
            row = compare(roots[repo] / rel, chunking, opts.max_decisions, opts.timeout)
        row["agent"] = f"{repo}/{rel}"
        rows.append(row)
        adapt_s = row["adapt_seconds"]
        times = f"Soar {row['soar_seconds']:.1f} s, adapt " + (
            f"{adapt_s:.1f} s" if isinstance(adapt_s, float) else "-")
        print(f"{row['result']:<36} {'loads' if row['loads'] else 'NO LOAD':<8} "
              f"{repo}/{rel}  ({times})" + (f"\n    {row['detail']}" if row.get("detail") else ""),
              flush=True)
    loads = sum(1 for r in rows if r["loads"])
    if opts.engine == "soar":
        same = sum(1 for r in rows if r["result"] == "same report")
        failed = sum(1 for r in rows if r["result"] == "soar-failed")
        soar_s = sorted(float(r["soar_seconds"]) for r in rows)  # type: ignore[arg-type]
        ours_s = sorted(float(r["adapt_seconds"]) for r in rows)  # type: ignore[arg-type]
        print(f"\n{len(rows)} agents on the Soar engine: {loads} load, {same} give soar-sml's "
              f"own report ({failed} fail in soar-sml itself); median seconds per agent: "
              f"soar-sml {soar_s[len(soar_s) // 2]:.2f}, adapt rules run --engine soar "
              f"{ours_s[len(ours_s) // 2]:.2f} (each a fresh process and kernel)")
    else:
        agree = sum(1 for r in rows if str(r["result"]).startswith("agrees"))
        strict = sum(1 for r in rows if r["result"] == "agrees")
        print(f"\n{len(rows)} agents: {loads} load as shipped, {agree} agree with Soar "
              f"({strict} with the same output text in the same order)")
    if opts.json:
        opts.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
