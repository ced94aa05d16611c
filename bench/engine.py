"""Engine benchmarks: adapt's two engines and real Soar on the same rule files (figures, not tests).

Run ``python bench/engine.py`` (``--quick`` for a smoke run).  The systems,
side by side: ``soar`` -- the kernel driven directly through SML (no trace,
no callbacks: the kernel's own speed); ``soar-engine`` -- adapt's Soar engine
(``--engine soar``, :class:`adapt.soar.SoarAgent`: the same kernel in a child
process, with adapt's report -- operator selections, impasses, output --
read from its XML trace); ``adapt`` -- adapt's own engine as installed
(compiled where it could be built); ``adapt-py`` -- the own engine forced to
its pure-Python source.  The workloads are each written as a ``.soar`` file
that every system loads unchanged:

* counter: one operator per decision (propose ``count``, apply ``^count n+1``)
  until ^count reaches 100,000 -- decisions per second.  Target: adapt
  >= 0.25 x real Soar.
* value join: one operator builds N objects of kind ``a`` (``^v 1..N``) and N
  of kind ``b`` (``^w 1..N``) on the top state, and one rule joins every
  ``a`` with the ``b`` of equal value -- seconds.  With ``multi-attributes``
  hints for ``^a`` and ``^b`` (N values each), a matcher which hashes joins on
  values orders the join on ``<v>`` first and follows it in linear time.  Targets: adapt >= 10 x faster than real
  Soar at N = 5,000, and adapt's time(20,000) / time(5,000) <= 5.
* loading: N generated rules -- seconds to parse and build the matcher.
* one long production: a single production with N conditions on one
  identifier (``(state <s> ^a1 <v1> ^a2 <v2> ...)``) -- seconds to load.
  Target: N = 2,000 loads in under a second (issue 21: the reorderer's
  lookahead grew as N^3, 2 s at N = 200 and over 120 s at N = 800).
* towers of hanoi and fifteen puzzle: agents of the shape of Soar's own
  (``hanoi_file``, ``fifteen_file``: written here, not copied): many
  ``^holds`` / ``^binding`` structures on the top state and a goal test naming
  all of them in one condition, which only load-time condition reordering
  makes tractable -- firings per second and Soar's rate / adapt's.  Before
  timing, each runs once in both engines with a write per move and the two
  runs are compared decision by decision (``tests/engine/soar_harness.py``).

* trace cost: adapt untraced against adapt writing a trace at level 1
  (decision records only) and level 5 (everything, with every decision's
  candidates and their preferences), on the counter and on a growing agent
  (``growing_file``: each decision a state no-change substate adds two
  numeric-indifferent preferences for new operators to the top state's
  slot, as in Soar's ``Chunk_RL_Proposal`` test agent; after 2,000 decisions
  the slot holds about 2,000 preferences) -- seconds and traced / untraced.
  Target: level 1 costs at most 1.5 x untraced.  ``--trace-agent FILE`` times
  another agent (loaded with ``chunking="off"``) instead of the growing one.

Each child may use at most 8 GB of address space (real Soar's value join
needs N^2 partial matches and runs out of memory at N = 20,000).  Every
measurement is the wall time of the run alone (the rule file is already
loaded) in a fresh child process: adapt via ``Agent(seed=1, matcher="rete")``
(no trace), real Soar via SML with a kernel created in the child's own thread,
``chunk never``, ``trace 0`` (watch 0), ``timers`` left at the default (on), no
event callbacks, timed around ``run``.  Medians of several runs.  Nothing is
asserted: a slow engine or a run past its time limit is reported.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

COUNTER = """\
sp {counter*propose*init
   (state <s> ^superstate nil -^count)
-->
   (<s> ^operator <o> + !)
   (<o> ^name init)}

sp {counter*apply*init
   (state <s> ^operator.name init)
-->
   (<s> ^count 0)}

sp {counter*propose*count
   (state <s> ^count { <c> < LIMIT })
-->
   (<s> ^operator <o> +)
   (<o> ^name count)}

sp {counter*apply*count
   (state <s> ^operator.name count ^count <c>)
-->
   (<s> ^count <c> - (+ <c> 1))}

sp {counter*halt
   (state <s> ^count LIMIT)
-->
   (halt)}
"""

JOIN_RULES = """
sp {join*propose*finish
   (state <s> ^built yes)
-->
   (<s> ^operator <o> +)
   (<o> ^name finish)}

sp {join*apply*finish
   (state <s> ^operator.name finish)
-->
   (halt)}

sp {join*equal-values
   (state <s> ^a <x>)
   (<x> ^v <v>)
   (<y> ^w <v>)
   (<s> ^b <y>)
-->
   (<x> ^partner <y>)}
"""


GROWING = """\
sp {grow*init
   (state <s> ^superstate nil)
-->
   (<s> ^worth 0.5)}

sp {grow*propose*valued
   (state <s> ^superstate <top>)
   (<top> ^superstate nil ^worth <w>)
-->
   (<top> ^operator <o> = <w>)
   (<o> ^name grow)}

sp {grow*propose*flat
   (state <s> ^superstate <top>)
   (<top> ^superstate nil ^worth <w>)
-->
   (<top> ^operator <o> = 0.0)
   (<o> ^name grow)}
"""


def growing_file() -> str:
    """An agent whose top operator slot grows by two preferences a decision:
    no operator is ever acceptable, so each decision is a state no-change
    whose substate proposes (``=`` only) two more operators to the top state,
    which changes the slot and makes the next no-change."""
    return GROWING


def rules_file(n: int) -> str:
    """``n`` generated rules of a realistic shape: a proposal each, testing the top
    state, a linked object with a relational test and a negated condition
    (50 task values and 7 kinds shared among them, so the Rete shares nodes)."""
    out = []
    for i in range(n):
        out.append(f"""sp {{gen*rule*{i}
   (state <s> ^superstate nil ^task t{i % 50} ^item <x>)
   (<x> ^kind k{i % 7} ^value {{ <v> > {i % 13} }})
   -(<x> ^blocked v{i})
-->
   (<s> ^operator <o> + =)
   (<o> ^name op{i} ^arg <v>)}}
""")
    return "\n".join(out)


def long_rule_file(n: int) -> str:
    """One production whose ``n`` conditions all test the state."""
    tests = " ".join(f"^a{i} <v{i}>" for i in range(n))
    return f"sp {{long (state <s> {tests})\n-->\n   (write |matched|)}}\n"


def counter_file(limit: int) -> str:
    return COUNTER.replace("LIMIT", str(limit))


def join_file(n: int) -> str:
    """One operator whose application builds the 2N objects; one join rule.

    The ``multi-attributes`` hints say that ``^a`` and ``^b`` have N values:
    the conditions are reordered as Soar reorders them, and with the hints the
    join on ``<v>`` comes before the link ``(<s> ^b <y>)`` (see
    ``adapt/engine/reorder.py``); Soar, which joins on identifiers only,
    gets no help from them."""
    lines = [f"multi-attributes a {n}", f"multi-attributes b {n}", "",
             "sp {join*propose*build", "   (state <s> ^superstate nil -^built)", "-->",
             "   (<s> ^operator <o> + !)", "   (<o> ^name build)}", "",
             "sp {join*apply*build", "   (state <s> ^operator.name build)", "-->",
             "   (<s> ^built yes)"]
    for i in range(1, n + 1):
        lines.append(f"   (<s> ^a <a{i}> ^b <b{i}>) (<a{i}> ^v {i}) (<b{i}> ^w {i})")
    lines[-1] += "}"
    return "\n".join(lines) + "\n" + JOIN_RULES


# ---- the shapes of Soar's own agents -----------------------------------------------

HANOI_RULES = """
sp {hanoi*elaborate*clear
   (state <s> ^holds <h>)
   (<h> ^disk <d>)
   -{(<s> ^holds <x>)
     (<x> ^above <d>)}
-->
   (<s> ^clear <h>)}

sp {hanoi*elaborate*empty-peg
   (state <s> ^peg <p>)
   -{(<s> ^holds <x>)
     (<x> ^on <p>)}
-->
   (<s> ^empty <p>)}

sp {hanoi*propose*move-smallest
   (state <s> ^holds <h> ^last-moved <> 1 ^cycle <c>)
   (<h> ^disk 1 ^on <from>)
   (<c> ^from <from> ^to <to>)
-->
   (<s> ^operator <o> +)
   (<o> ^name move ^holds <h> ^disk 1 ^from <from> ^to <to>)}

sp {hanoi*propose*move-onto-disk
   (state <s> ^clear <h> ^clear <t> ^last-moved <l>)
   (<h> ^disk { <d> > 1 <> <l> } ^on <from>)
   (<t> ^disk > <d> ^on { <to> <> <from> })
-->
   (<s> ^operator <o> +)
   (<o> ^name move ^holds <h> ^disk <d> ^from <from> ^to <to>)}

sp {hanoi*propose*move-onto-peg
   (state <s> ^clear <h> ^empty <to> ^last-moved <l>)
   (<h> ^disk { <d> > 1 <> <l> } ^on { <from> <> <to> })
-->
   (<s> ^operator <o> +)
   (<o> ^name move ^holds <h> ^disk <d> ^from <from> ^to <to>)}

sp {hanoi*apply*move-onto-disk
   (state <s> ^operator <o> ^clear <t> ^last-moved <l> ^moves <m>)
   (<o> ^name move ^holds <h> ^disk <d> ^from <from> ^to <to>)
   (<t> ^on <to> ^disk <below>)
   (<h> ^above <old>)
-->
   (<h> ^on <from> - <to> ^above <old> - <below>)
   (<s> ^last-moved <l> - <d> ^moves <m> - (+ <m> 1))}

sp {hanoi*apply*move-onto-peg*from-disk
   (state <s> ^operator <o> ^empty <to> ^last-moved <l> ^moves <m>)
   (<o> ^name move ^holds <h> ^disk <d> ^from <from> ^to <to>)
   (<h> ^above { <old> <> 0 })
-->
   (<h> ^on <from> - <to> ^above <old> - 0)
   (<s> ^last-moved <l> - <d> ^moves <m> - (+ <m> 1))}

sp {hanoi*apply*move-onto-peg*from-peg
   (state <s> ^operator <o> ^empty <to> ^last-moved <l> ^moves <m>)
   (<o> ^name move ^holds <h> ^disk <d> ^from <from> ^to <to>)
   (<h> ^above 0)
-->
   (<h> ^on <from> - <to>)
   (<s> ^last-moved <l> - <d> ^moves <m> - (+ <m> 1))}
"""

#: Added for the decision-by-decision check only (not timed): one line per move.
HANOI_MONITOR = """
sp {hanoi*monitor*move
   (state <s> ^operator <o>)
   (<o> ^name move ^disk <d> ^from <from> ^to <to>)
-->
   (write |disk | <d> | | <from> |->| <to>)}
"""


def hanoi_file(disks: int = 11) -> str:
    """A Towers of Hanoi of ``disks`` disks on pegs a, b, c: ``2**disks - 1`` moves.

    The top state holds one ``^holds`` structure per disk (``^disk i ^on peg
    ^above j``, ``^above 0`` for a disk on the peg's floor).  The moves are the
    iterative solution, chosen by the rules alone: the smallest disk moves
    round the pegs in one direction (``^cycle``), every other move is the one
    legal move of another disk, and no disk moves twice in a row -- so exactly
    one operator is proposed at each decision.  The goal test names every
    ``^holds`` in one condition, ``(state <s> ^holds <h1> ... <hN>)``, and then
    each structure, as Soar's Towers of Hanoi agents do: written order builds
    ``N**N`` partial matches; reordered, one chain of joins.
    """
    cycle = ("a c", "c b", "b a") if disks % 2 else ("a b", "b c", "c a")
    holds = " ".join(f"<h{i}>" for i in range(1, disks + 1))
    init = [
        "sp {hanoi*propose*init",
        "   (state <s> ^superstate nil -^holds)",
        "-->",
        "   (<s> ^operator <o> + !)",
        "   (<o> ^name init)}",
        "",
        "sp {hanoi*apply*init",
        "   (state <s> ^operator.name init)",
        "-->",
        "   (<s> ^peg a b c ^last-moved 0 ^moves 0 ^cycle <c1> <c2> <c3>",
        f"        ^holds {holds})",
    ]
    for k, pair in enumerate(cycle, 1):
        src, dst = pair.split()
        init.append(f"   (<c{k}> ^from {src} ^to {dst})")
    for i in range(1, disks + 1):
        below = i + 1 if i < disks else 0
        init.append(f"   (<h{i}> ^disk {i} ^on a ^above {below})")
    init[-1] += "}"
    goal = ["sp {hanoi*detect*goal", f"   (state <s> ^holds {holds} ^moves <m>)"]
    for i in range(1, disks + 1):
        below = i + 1 if i < disks else 0
        goal.append(f"   (<h{i}> ^disk {i} ^on c ^above {below})")
    goal += ["-->", "   (write |done in | <m> | moves|)", "   (halt)}"]
    return "\n".join(init) + "\n" + HANOI_RULES + "\n" + "\n".join(goal) + "\n"


FIFTEEN_RULES = """
sp {fifteen*propose*move
   (state <s> ^binding <bb> <bt> ^last-tile <l>)
   (<bb> ^tile.name 0 ^cell <cb>)
   (<cb> ^cell <ct>)
   (<bt> ^cell <ct> ^tile { <t> <> <l> })
-->
   (<s> ^operator <o> +)
   (<o> ^name move ^tile <t> ^from <bt> ^to <bb>)}

sp {fifteen*evaluate*move
   (state <s> ^operator <o> +)
   (<o> ^name move ^tile <t> ^from <bt> ^to <bb>)
   (<t> ^name <n> ^goal-row <gr> ^goal-col <gc>)
   (<bt> ^cell <ct>)
   (<ct> ^row <r1> ^col <c1>)
   (<bb> ^cell <cb>)
   (<cb> ^row <r2> ^col <c2>)
-->
   (<o> ^score (+ <n> (* 100 (- (+ (abs (- <r2> <gr>)) (abs (- <c2> <gc>)))
                                (+ (abs (- <r1> <gr>)) (abs (- <c1> <gc>)))))))}

sp {fifteen*compare*moves
   (state <s> ^operator <o1> + ^operator { <o2> <> <o1> } +)
   (<o1> ^score <x>)
   (<o2> ^score > <x>)
-->
   (<s> ^operator <o1> > <o2>)}

sp {fifteen*apply*move
   (state <s> ^operator <o> ^last-tile <l> ^moves <m>)
   (<o> ^name move ^tile <t> ^from <bt> ^to <bb>)
   (<bb> ^tile <blank>)
-->
   (<bb> ^tile <blank> - <t>)
   (<bt> ^tile <t> - <blank>)
   (<s> ^last-tile <l> - <t> ^moves <m> - (+ <m> 1))}
"""

#: Added for the decision-by-decision check only (not timed): one line per move.
FIFTEEN_MONITOR = """
sp {fifteen*monitor*move
   (state <s> ^operator <o>)
   (<o> ^name move ^tile.name <n> ^score <x>)
-->
   (write |tile | <n> | score | <x>)}
"""


def fifteen_start(size: int = 4, scramble: int = 200, seed: int = 15) -> list[list[int]]:
    """A solvable start: the goal board (blank last) after ``scramble`` random
    moves of the blank (a fixed seed)."""
    import random

    rng = random.Random(seed)
    board = [[r * size + c + 1 for c in range(size)] for r in range(size)]
    board[-1][-1] = 0
    r = c = size - 1
    for _ in range(scramble):
        steps = [(r + dr, c + dc) for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1))
                 if 0 <= r + dr < size and 0 <= c + dc < size]
        nr, nc = rng.choice(steps)
        board[r][c], board[nr][nc] = board[nr][nc], 0
        r, c = nr, nc
    return board


def fifteen_file(size: int = 4, scramble: int = 200, seed: int = 15) -> str:
    """A fifteen puzzle (``size`` x ``size``) shaped like Soar's eight/fifteen-puzzle agents.

    The top state has one ``^binding`` per cell (``^cell <c> ^tile <t>``);
    cells link to their neighbours (``^cell``) and know their row and column,
    tiles know their goal row and column (tile 0 is the blank).  Each decision
    proposes moving every tile next to the blank into it (except the tile just
    moved), scores each move by the change of that tile's Manhattan distance
    to its goal (x 100, plus the tile's number as the tie-break) and prefers
    the lower score with binary ``>`` preferences between every pair: one
    best operator, no random choice, so both engines make the same moves.
    The goal test names all ``size**2`` bindings in one condition,
    ``(state <s> ^binding <b11> ... <b44>)``.
    """
    board = fifteen_start(size, scramble, seed)
    cells = [(r, c) for r in range(1, size + 1) for c in range(1, size + 1)]
    lines = ["sp {fifteen*propose*init",
             "   (state <s> ^superstate nil -^binding)",
             "-->",
             "   (<s> ^operator <o> + !)",
             "   (<o> ^name init)}",
             "",
             "sp {fifteen*apply*init",
             "   (state <s> ^operator.name init)",
             "-->",
             "   (<s> ^last-tile none ^moves 0 ^binding "
             + " ".join(f"<b{r}{c}>" for r, c in cells) + ")"]
    for r, c in cells:
        near = [(r + dr, c + dc) for dr, dc in ((-1, 0), (1, 0), (0, -1), (0, 1))
                if 1 <= r + dr <= size and 1 <= c + dc <= size]
        links = " ".join(f"<c{a}{b}>" for a, b in near)
        lines.append(f"   (<c{r}{c}> ^name c{r}{c} ^row {r} ^col {c} ^cell {links})")
        lines.append(f"   (<b{r}{c}> ^cell <c{r}{c}> ^tile <t{board[r - 1][c - 1]}>)")
    for n in range(size * size):
        goal = n - 1 if n else size * size - 1
        lines.append(f"   (<t{n}> ^name {n} ^goal-row {goal // size + 1} ^goal-col {goal % size + 1})")
    lines[-1] += "}"
    goal_test = ["sp {fifteen*detect*goal",
                 "   (state <s> ^binding " + " ".join(f"<b{r}{c}>" for r, c in cells)
                 + " ^moves <m>)"]
    for k, (r, c) in enumerate(cells, 1):
        goal_test.append(f"   (<b{r}{c}> ^cell.name c{r}{c} ^tile.name {k % (size * size)})")
    goal_test += ["-->", "   (write |solved in | <m> | moves|)", "   (halt)}"]
    return "\n".join(lines) + "\n" + FIFTEEN_RULES + "\n" + "\n".join(goal_test) + "\n"


# ---- children ---------------------------------------------------------------


def adapt_root() -> str:
    """The checkout whose ``adapt`` the bench runs: ``--adapt-root`` (e.g. a
    checkout with the compiled engine built), else this one."""
    return os.environ.get("ADAPT_BENCH_ROOT") or str(ROOT)


def child_adapt(path: str, max_decisions: int) -> dict[str, object]:
    sys.path.insert(0, adapt_root())
    from adapt.engine import Agent, engine_build
    from adapt.engine.agent import DEFAULT_GC_THRESHOLD

    gc_env = os.environ.get("ADAPT_BENCH_GC", "")  # set by --gc-threshold
    gc_threshold = DEFAULT_GC_THRESHOLD if not gc_env else int(gc_env) or None
    level = int(os.environ.get("ADAPT_BENCH_TRACE", "0"))  # set by measure() for adapt-t<level>
    with tempfile.TemporaryDirectory() as tmp:
        trace = Path(tmp) / "trace.jsonl"
        traced = {"trace": str(trace), "trace_level": level} if level else {}
        agent = Agent(seed=1, matcher="rete", gc_threshold=gc_threshold, **traced)
        if max_decisions < 0:  # loading alone: parse, build the Rete
            start = time.perf_counter()
            rules = agent.load_file(path)
            return {"seconds": time.perf_counter() - start, "rules": len(rules.productions),
                    "engine": engine_build()}
        agent.load_file(path, chunking="off")
        start, cpu = time.perf_counter(), time.process_time()
        report = agent.run(max_decisions=max_decisions).to_dict()
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
        agent.close()
        size = trace.stat().st_size if level else 0
    return {"seconds": seconds, "cpu": cpu, "decisions": report["decisions"],
            "halted": report["halted"], "firings": report["production_firings"],
            "engine": engine_build(), "trace_bytes": size}


def child_soar_engine(path: str, max_decisions: int) -> dict[str, object]:
    """adapt's Soar engine: the report of ``adapt rules run --engine soar`` without a trace."""
    sys.path.insert(0, adapt_root())
    from adapt.soar import KernelCrash, SoarAgent

    start = time.perf_counter()
    agent = SoarAgent(seed=1)
    started = time.perf_counter() - start
    if max_decisions < 0:  # loading alone: Soar's source, and the names of what it added
        start = time.perf_counter()
        rules = agent.load_file(path)
        seconds = time.perf_counter() - start
        agent.close()
        return {"seconds": seconds, "rules": len(rules.productions), "startup": started}
    agent.load_file(path)
    start, cpu = time.perf_counter(), time.process_time()
    try:
        report = agent.run(max_decisions=max_decisions).to_dict()
    except KernelCrash as exc:  # reported as the kernel's failure, as real Soar's is
        return {"error": f"the kernel crashed: {exc}"}
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    agent.close()
    return {"seconds": seconds, "cpu": cpu, "decisions": report["decisions"],
            "halted": report["halted"], "firings": report["production_firings"],
            "startup": started}


def child_soar(path: str, max_decisions: int) -> dict[str, object]:
    import soar_sml

    kernel = soar_sml.Kernel.CreateKernelInCurrentThread(True, soar_sml.Kernel.kSuppressListener)
    agent = kernel.CreateAgent("bench")
    for command in ("chunk never", "trace 0", "decide set-random-seed 1"):
        agent.ExecuteCommandLine(command)
    start = time.perf_counter()
    agent.ExecuteCommandLine(f'source "{path}"')
    loaded = time.perf_counter() - start
    if not agent.GetLastCommandLineResult():
        return {"error": "load failed"}
    if max_decisions < 0:
        return {"seconds": loaded}
    start = time.perf_counter()
    agent.ExecuteCommandLine(f"run {max_decisions}")
    seconds = time.perf_counter() - start
    stats = agent.ExecuteCommandLine("stats")
    firings = next((int(line.split()[0]) for line in stats.splitlines()
                    if " production firings" in line and line.split()[0].isdigit()), None)
    halted = agent.GetRunState() == soar_sml.sml_RUNSTATE_HALTED
    return {"seconds": seconds, "decisions": agent.GetDecisionCycleCounter(), "halted": halted,
            "firings": firings}


MEMORY_LIMIT_GB = 8.0  # per child: a quadratic run fails alone instead of starving the machine


def _limit_memory() -> None:
    import resource

    limit = int(MEMORY_LIMIT_GB * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


#: The systems a run compares: real Soar driven directly, adapt's Soar engine, adapt's own
#: engine as installed (compiled where it could be built) and forced to its pure-Python source.
SYSTEMS = ("soar", "soar-engine", "adapt", "adapt-py")
#: adapt's two engines (the own one, as installed, and the Soar kernel behind the interface).
ENGINES = ("adapt", "soar-engine")


def measure(system: str, path: Path, max_decisions: int, timeout: float) -> dict[str, object]:
    argv = [sys.executable, str(Path(__file__).resolve()), "--child", system, str(path),
            str(max_decisions)]
    env = dict(os.environ)
    env.pop("ADAPT_PURE_PYTHON", None)
    env.pop("ADAPT_BENCH_TRACE", None)
    base, _, level = system.partition("-t")  # adapt-t1: adapt writing a trace at level 1
    if level:
        env["ADAPT_BENCH_TRACE"] = level
    if base == "adapt-py":
        env["ADAPT_PURE_PYTHON"] = "1"
    try:
        proc = subprocess.run(argv, capture_output=True, timeout=timeout,
                              preexec_fn=_limit_memory, env=env)
    except subprocess.TimeoutExpired:
        return {"error": f"over the {timeout:.0f} s limit"}
    try:
        return dict(json.loads(proc.stdout.decode().strip().splitlines()[-1]))
    except (ValueError, IndexError):
        how = (f"killed by signal {-proc.returncode}" if proc.returncode < 0
               else f"exit status {proc.returncode}")
        hint = (f" (out of memory? each child may use {MEMORY_LIMIT_GB:g} GB)"
                if proc.returncode in (-9, -6, 134, 137) else "")
        return {"error": f"child failed: {how}{hint} {proc.stderr.decode()[-300:]}".rstrip()}


def interleaved(systems: tuple[str, ...], path: Path, max_decisions: int, runs: int,
                timeout: float) -> dict[str, tuple[float | None, dict[str, object]]]:
    """Median seconds and the first run's details of each system, the systems'
    runs interleaved round by round (so that a noisy neighbour hits all of them)."""
    good: dict[str, list[dict[str, object]]] = {s: [] for s in systems}
    failed: dict[str, dict[str, object]] = {}
    for _ in range(runs):
        for system in systems:
            if system in failed:
                continue
            result = measure(system, path, max_decisions, timeout)
            if "seconds" not in result:
                failed[system] = result  # no point repeating a failure or a timeout
            else:
                good[system].append(result)
    out: dict[str, tuple[float | None, dict[str, object]]] = {}
    for system in systems:
        if system in failed:
            out[system] = (None, failed[system])
            continue
        first = dict(good[system][0])
        if all("cpu" in r for r in good[system]):
            first["cpu"] = statistics.median(float(r["cpu"]) for r in good[system])
        out[system] = (statistics.median(float(r["seconds"]) for r in good[system]), first)
    return out


def fmt(seconds: float | None) -> str:
    return "   n/a" if seconds is None else f"{seconds:8.3f} s"


# ---- the two workloads -----------------------------------------------------------


def bench_counter(tmp: Path, limit: int, runs: int, timeout: float,
                  systems: tuple[str, ...] = SYSTEMS) -> None:
    path = tmp / "counter.soar"
    path.write_text(counter_file(limit))
    print(f"counter: one operator per decision, counting to {limit:,} (median of {runs})")
    rates: dict[str, float] = {}
    for system, (seconds, info) in interleaved(systems, path, limit + 10, runs, timeout).items():
        if seconds is None:
            print(f"  {system:<11} {info.get('error')}")
            continue
        decisions = int(info["decisions"])  # type: ignore[call-overload]
        rates[system] = decisions / seconds
        engine = f", {info['engine']}" if "engine" in info else ""
        print(f"  {system:<11} {decisions:,} decisions in {fmt(seconds)}  ->  "
              f"{rates[system]:,.0f} decisions/s  (halted: {info['halted']}{engine})")
    for system in ("adapt", "adapt-py"):
        if system in rates and "soar" in rates:
            ratio = rates[system] / rates["soar"]
            verdict = "meets" if ratio >= 0.25 else "MISSES"
            print(f"  ratio {system}/Soar = {ratio:.3f}  (target >= 0.25: {verdict})")
    if "adapt" in rates and "adapt-py" in rates:
        print(f"  adapt (as installed) / adapt pure Python = {rates['adapt'] / rates['adapt-py']:.2f}x")
    engines_side_by_side(rates, "decisions/s")


def engines_side_by_side(rates: dict[str, float], unit: str, higher: bool = True) -> None:
    """adapt's two engines beside each other, and the Soar engine beside the kernel it drives."""
    if "soar-engine" in rates and "adapt" in rates:
        ratio = rates["soar-engine"] / rates["adapt"] if higher else rates["adapt"] / rates["soar-engine"]
        print(f"  the two engines ({unit}): --engine soar is {ratio:.2f}x the own engine (as installed)")
    if "soar-engine" in rates and "adapt-py" in rates:
        ratio = (rates["soar-engine"] / rates["adapt-py"] if higher
                 else rates["adapt-py"] / rates["soar-engine"])
        print(f"  --engine soar / own engine in pure Python = {ratio:.2f}x")
    if "soar-engine" in rates and "soar" in rates:
        share = rates["soar-engine"] / rates["soar"] if higher else rates["soar"] / rates["soar-engine"]
        print(f"  --engine soar runs at {share:.2f}x the kernel driven directly (the cost of the "
              "report read from its XML trace, and of the process boundary)")


def bench_load(tmp: Path, sizes: list[int], runs: int, timeout: float,
               systems: tuple[str, ...] = SYSTEMS) -> None:
    print(f"loading N generated rules: parse and build the matcher (median of {runs})")
    times: dict[tuple[str, int], float] = {}
    for n in sizes:
        path = tmp / f"rules-{n}.soar"
        path.write_text(rules_file(n))
        row = []
        for system, (seconds, info) in interleaved(systems, path, -1, runs, timeout).items():
            if seconds is None:
                row.append(f"{system} {info.get('error')}")
                continue
            times[(system, n)] = seconds
            row.append(f"{system} {fmt(seconds)}")
        print(f"  N = {n:>6,}:  " + ",  ".join(row))
    for system in ("adapt", "adapt-py"):
        if (system, 10_000) in times and ("soar", 10_000) in times:
            ratio = times[(system, 10_000)] / times[("soar", 10_000)]
            verdict = "meets" if ratio <= 2 else "MISSES"
            print(f"  N = 10,000: {system} / Soar = {ratio:.1f}x the time (target <= 2: {verdict})")
        if (system, 10_000) in times and (system, 20_000) in times:
            growth = times[(system, 20_000)] / times[(system, 10_000)]
            verdict = "meets" if growth <= 2.5 else "MISSES"
            print(f"  {system} time(20,000) / time(10,000) = {growth:.2f} (target <= 2.5: {verdict})")
    if ("soar", 10_000) in times and ("soar", 20_000) in times:
        print(f"  soar time(20,000) / time(10,000) = "
              f"{times[('soar', 20_000)] / times[('soar', 10_000)]:.2f}")
    largest = max(sizes)
    engines_side_by_side({s: 1.0 / t for (s, n), t in times.items() if n == largest},
                         f"load speed at N = {largest:,}")


def bench_long_rule(tmp: Path, sizes: list[int], runs: int, timeout: float,
                    systems: tuple[str, ...] = SYSTEMS) -> None:
    print(f"one production with N conditions on one identifier: seconds to load (median of {runs})")
    times: dict[tuple[str, int], float] = {}
    for n in sizes:
        path = tmp / f"long-{n}.soar"
        path.write_text(long_rule_file(n))
        row = []
        for system, (seconds, info) in interleaved(systems, path, -1, runs, timeout).items():
            if seconds is None:
                row.append(f"{system} {info.get('error')}")
                continue
            times[(system, n)] = seconds
            row.append(f"{system} {fmt(seconds)}")
        print(f"  N = {n:>6,}:  " + ",  ".join(row))
    for system in ("adapt", "adapt-py"):
        if (system, 2000) in times:
            verdict = "meets" if times[(system, 2000)] < 1.0 else "MISSES"
            print(f"  N = 2,000: {system} {times[(system, 2000)]:.2f} s (target < 1 s: {verdict})")


def bench_join(tmp: Path, sizes: list[int], runs: int, timeout: float,
               systems: tuple[str, ...] = ("soar", "adapt")) -> None:
    print(f"value join: N objects of each of two kinds, one rule joining equal values "
          f"(median of {runs})")
    times: dict[tuple[str, int], float] = {}
    for n in sizes:
        path = tmp / f"join-{n}.soar"
        path.write_text(join_file(n))
        row = []
        for system, (seconds, info) in interleaved(systems, path, 10, runs, timeout).items():
            if seconds is not None:
                times[(system, n)] = seconds
                cpu = f", CPU {float(info['cpu']):.3f} s" if "cpu" in info else ""
                if "cpu" in info:
                    times[("adapt-cpu", n)] = float(info["cpu"])
                row.append(f"{system} {fmt(seconds)} ({info['firings']} firings{cpu})")
            else:
                row.append(f"{system} {info.get('error')}")
        speedup = ""
        if ("soar", n) in times and ("adapt", n) in times:
            speedup = f"  speed-up Soar/adapt {times[('soar', n)] / times[('adapt', n)]:.2f}x"
        print(f"  N = {n:>6,}:  " + ",  ".join(row) + speedup)
    if ("soar", 5000) in times and ("adapt", 5000) in times:
        speedup = times[("soar", 5000)] / times[("adapt", 5000)]
        verdict = "meets" if speedup >= 10 else "MISSES"
        print(f"  N = 5,000: adapt {speedup:.1f}x faster than Soar (target >= 10: {verdict})")
    if ("adapt", 5000) in times and ("adapt", 20000) in times:
        growth = times[("adapt", 20000)] / times[("adapt", 5000)]
        verdict = "meets" if growth <= 5 else "MISSES"
        print(f"  adapt time(20,000) / time(5,000) = {growth:.2f} (target <= 5: {verdict})")
        if ("adapt-cpu", 5000) in times and ("adapt-cpu", 20000) in times:
            print(f"  adapt CPU time(20,000) / CPU time(5,000) = "
                  f"{times[('adapt-cpu', 20000)] / times[('adapt-cpu', 5000)]:.2f}")
    if ("soar", 5000) in times and ("soar", 20000) in times:
        print(f"  Soar  time(20,000) / time(5,000) = "
              f"{times[('soar', 20000)] / times[('soar', 5000)]:.2f}")


def same_decisions(path: Path, max_decisions: int, timeout: float) -> str:
    """Run ``path`` once in real Soar and once in adapt through the differential
    harness (``tests/engine/soar_harness.py``) and compare them decision by
    decision: selections, impasses, every ``(write ...)`` with its decision,
    decisions, halt.  Not timed."""
    sys.path.insert(0, str(ROOT / "tests" / "engine"))
    sys.path.insert(0, adapt_root())
    from soar_harness import first_difference, run_adapt, run_soar

    soar = run_soar(path, max_decisions=max_decisions, timeout=timeout)
    adapt = run_adapt(path, max_decisions=max_decisions, trace_level=None)
    difference = first_difference(soar, adapt)
    if difference is not None:
        return f"DIFFER: {difference}"
    return (f"identical ({soar['decisions']:,} decisions, {len(soar.get('writes', [])):,} "
            f"writes, halted: {soar['halted']})")


def bench_agent(tmp: Path, name: str, text: str, monitor: str, max_decisions: int, runs: int,
                timeout: float, systems: tuple[str, ...] = SYSTEMS, check: bool = True) -> None:
    """Firings per second of one agent in each system and Soar's rate / adapt's.

    The timed file is ``text``; the check runs ``text + monitor`` (one write
    per move) once in each engine and compares them decision by decision."""
    path = tmp / f"{name}.soar"
    path.write_text(text)
    if check:
        checked = tmp / f"{name}-checked.soar"
        checked.write_text(text + monitor)
        print(f"  same decisions as Soar (with a write per move, not timed): "
              f"{same_decisions(checked, max_decisions, timeout)}")
    rates: dict[str, float] = {}
    seen: dict[str, tuple[object, object, object]] = {}
    for system, (seconds, info) in interleaved(systems, path, max_decisions, runs, timeout).items():
        if seconds is None:
            print(f"  {system:<11} {info.get('error')}")
            continue
        firings = int(info["firings"])  # type: ignore[call-overload]
        rates[system] = firings / seconds
        seen[system] = (info["decisions"], info["halted"], firings)
        engine = f", {info['engine']}" if "engine" in info else ""
        print(f"  {system:<11} {int(info['decisions']):,} decisions, "  # type: ignore[call-overload]
              f"{firings:,} firings in {fmt(seconds)}  ->  {rates[system]:,.0f} firings/s  "
              f"(halted: {info['halted']}{engine})")
    if len(set(seen.values())) > 1:
        print("  DIFFERENT WORK: decisions, halt or firings differ between the systems")
    for system in ("adapt", "adapt-py"):
        if system in rates and "soar" in rates:
            print(f"  Soar's rate / {system}'s = {rates['soar'] / rates[system]:.1f}x")
    engines_side_by_side(rates, "firings/s")


def bench_hanoi(tmp: Path, disks: int, runs: int, timeout: float,
                systems: tuple[str, ...] = SYSTEMS, check: bool = True) -> None:
    moves = 2**disks - 1
    print(f"towers of hanoi: {disks} disks, {moves:,} moves, a goal test naming all {disks} "
          f"^holds (median of {runs})")
    bench_agent(tmp, f"hanoi-{disks}", hanoi_file(disks), HANOI_MONITOR, moves + 10, runs,
                timeout, systems, check)


def bench_fifteen(tmp: Path, decisions: int, runs: int, timeout: float,
                  systems: tuple[str, ...] = SYSTEMS, check: bool = True) -> None:
    print(f"fifteen puzzle: 4 x 4 ^binding structures, best move by binary preferences, "
          f"{decisions:,} decisions (median of {runs})")
    bench_agent(tmp, "fifteen", fifteen_file(), FIFTEEN_MONITOR, decisions, runs, timeout,
                systems, check)


def bench_trace(tmp: Path, limit: int, decisions: int, runs: int, timeout: float,
                systems: tuple[str, ...] = SYSTEMS, agent: Path | None = None) -> None:
    """Seconds of adapt untraced, traced at level 1 and at level 5, and the
    traced / untraced ratios, on the counter and on the growing agent (or
    ``agent``)."""
    bases = [s for s in systems if s in ("adapt", "adapt-py")]
    print(f"trace cost: untraced vs a trace at level 1 and level 5 (median of {runs})")
    counter = tmp / "trace-counter.soar"
    counter.write_text(counter_file(limit))
    growing = agent if agent is not None else tmp / "growing.soar"
    if agent is None:
        growing.write_text(growing_file())
    workloads = [(f"counter to {limit:,}", counter, limit + 10),
                 (f"{growing.name}, {decisions:,} decisions", growing, decisions)]
    for base in bases:
        for title, path, bound in workloads:
            variants = (base, f"{base}-t1", f"{base}-t5")
            results = interleaved(variants, path, bound, runs, timeout)
            untraced = results[base][0]
            print(f"  {base}, {title}:")
            for variant in variants:
                seconds, info = results[variant]
                if seconds is None:
                    print(f"    {variant:<12} {info.get('error')}")
                    continue
                ratio = f"  {seconds / untraced:5.2f}x untraced" if untraced else ""
                size = int(info.get("trace_bytes", 0))  # type: ignore[call-overload]
                written = f", trace {size / 1e6:,.1f} MB" if size else ""
                print(f"    {variant:<12} {fmt(seconds)}{ratio}  ({int(info['decisions']):,} "  # type: ignore[call-overload]
                      f"decisions{written})")
            level1 = results[f"{base}-t1"][0]
            if untraced and level1:
                verdict = "meets" if level1 / untraced <= 1.5 else "MISSES"
                print(f"    level 1 / untraced = {level1 / untraced:.2f} (target <= 1.5: {verdict})")


def main() -> int:
    if len(sys.argv) == 5 and sys.argv[1] == "--child":
        runner = {"soar": child_soar, "soar-engine": child_soar_engine}.get(
            sys.argv[2], child_adapt)  # adapt, adapt-py
        print(json.dumps(runner(sys.argv[3], int(sys.argv[4]))), flush=True)
        os._exit(0)  # the native kernel sometimes misbehaves at interpreter exit
    parser = argparse.ArgumentParser(description="adapt vs real Soar: counter, value join, loading, "
                                                 "towers of hanoi, fifteen puzzle")
    parser.add_argument("--quick", action="store_true", help="small sizes, one run each")
    parser.add_argument("--runs", type=int, default=None, help="runs per figure (default 3)")
    parser.add_argument("--timeout", type=float, default=300.0,
                        help="limit per single run, seconds (default 300)")
    parser.add_argument("--only", choices=("counter", "join", "load", "long-rule", "hanoi",
                                           "fifteen", "trace"),
                        default=None,
                        help="run one workload only")
    parser.add_argument("--sizes", default=None,
                        help="value-join sizes, comma-separated (default 1000,5000,20000)")
    parser.add_argument("--load-sizes", default=None,
                        help="rule-base sizes, comma-separated (default 2500,5000,10000,20000)")
    parser.add_argument("--systems", default=",".join(SYSTEMS),
                        help="comma-separated subset of soar,soar-engine,adapt,adapt-py (default all; "
                             "adapt-py is adapt forced to its pure-Python source; the value "
                             "join runs soar and adapt)")
    parser.add_argument("--no-check", action="store_true",
                        help="skip the decision-by-decision comparison of the agent "
                             "workloads (hanoi, fifteen) with Soar")
    parser.add_argument("--gc-threshold", type=int, default=None,
                        help="adapt's Agent(gc_threshold=...); 0 leaves Python's collector "
                             "alone (default: the agent's default policy)")
    parser.add_argument("--adapt-root", type=Path, default=None,
                        help="run the adapt of another checkout (one whose compiled engine "
                             "is built, or a 'before' figure); default this checkout")
    parser.add_argument("--trace-agent", type=Path, default=None,
                        help="the trace-cost workload times this .soar file (e.g. Soar's "
                             "ChunkingTests_Chunk_RL_Proposal.soar) instead of the growing agent")
    opts = parser.parse_args()
    if opts.adapt_root is not None:
        os.environ["ADAPT_BENCH_ROOT"] = str(opts.adapt_root.resolve())
    runs = opts.runs or (1 if opts.quick else 3)
    limit = 5_000 if opts.quick else 100_000
    sizes = [500, 1_000] if opts.quick else [1_000, 5_000, 20_000]
    if opts.sizes:
        sizes = [int(n) for n in opts.sizes.split(",")]
    systems = tuple(s for s in SYSTEMS if s in opts.systems.split(","))
    load_sizes = [500, 1_000] if opts.quick else [2_500, 5_000, 10_000, 20_000]
    if opts.load_sizes:
        load_sizes = [int(n) for n in opts.load_sizes.split(",")]
    if opts.gc_threshold is not None:
        os.environ["ADAPT_BENCH_GC"] = str(opts.gc_threshold)
    gc_note = ("default" if opts.gc_threshold is None
               else "off" if opts.gc_threshold == 0 else str(opts.gc_threshold))
    sys.path.insert(0, adapt_root())
    from adapt.engine import engine_build

    print(f"bench/engine.py  {time.strftime('%Y-%m-%d %H:%M')}  python {sys.version.split()[0]}"
          f"  cpus {os.cpu_count()}  adapt {adapt_root()}  adapt gc_threshold: {gc_note}"
          f"  adapt engine: {engine_build()}")
    with tempfile.TemporaryDirectory() as tmp:
        if opts.only in (None, "counter"):
            bench_counter(Path(tmp), limit, runs, opts.timeout, systems)
        if opts.only in (None, "join"):
            bench_join(Path(tmp), sizes, runs, opts.timeout,
                       tuple(s for s in systems if s != "adapt-py"))
        if opts.only in (None, "load"):
            bench_load(Path(tmp), load_sizes, runs, opts.timeout, systems)
        if opts.only in (None, "long-rule"):
            bench_long_rule(Path(tmp), [200, 2_000] if opts.quick else [200, 400, 800, 2_000],
                            runs, opts.timeout, systems)
        if opts.only in (None, "hanoi"):
            bench_hanoi(Path(tmp), 11, runs, opts.timeout, systems, not opts.no_check)
        if opts.only in (None, "fifteen"):
            bench_fifteen(Path(tmp), 1_000 if opts.quick else 5_000, runs, opts.timeout,
                          systems, not opts.no_check)
        if opts.only in (None, "trace"):
            bench_trace(Path(tmp), 5_000 if opts.quick else 20_000, 500 if opts.quick else 2_000,
                        runs, opts.timeout, systems,
                        None if opts.trace_agent is None else opts.trace_agent.resolve())
    return 0


if __name__ == "__main__":
    sys.exit(main())
