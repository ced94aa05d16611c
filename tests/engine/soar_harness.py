"""Differential-testing harness: run one ``.soar`` file in real Soar and in adapt.

Real Soar (PyPI ``soar-sml``, the native 9.6 kernel) always runs in a child
process -- ``python soar_harness.py --child FILE ...`` -- so that a crash or a
runaway in the kernel is reported instead of killing pytest.  The child makes a
fresh kernel, turns chunking off, seeds the random generator, ``source``s the
file, runs ``run N`` and prints one JSON report.  Adapt runs in-process through
``adapt.engine.Agent``.  Both reports have the same shape::

    halted, stop_reason, decisions, output, operators [[d, level, name]],
    impasses [[d, level, type, attribute]], writes [[d, text]] (optional)

``writes`` holds every ``(write ...)`` action's text with its decision: ``d``
is the value of the decision counter while the text was written (0 = before
the first decision; ``n`` = the apply and output phases of decision ``n`` and
the next input and proposal phases), the convention of
``docs/trace-format.md``.  The writes of one decision are compared as a
multiset of texts, one per write action (Soar's order within an elaboration
cycle is its Rete's, which adapt does not reproduce).

An agent may state its own bound in a comment line ``# max-decisions: N``.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any, Iterable

Report = dict[str, Any]

DEFAULT_MAX_DECISIONS = 5000
DEFAULT_TIMEOUT_S = 60.0
COMPARED = ("halted", "stop_reason", "decisions", "output", "operators", "impasses")
_BOUND = re.compile(r"^#\s*max-decisions:\s*(\d+)", re.MULTILINE)


def max_decisions_of(path: Path) -> int:
    """The agent's ``# max-decisions: N`` comment, or the default bound."""
    found = _BOUND.search(Path(path).read_text(encoding="utf-8"))
    return int(found.group(1)) if found else DEFAULT_MAX_DECISIONS


# --------------------------------------------------------------------------
# Real Soar, parent side
# --------------------------------------------------------------------------


def run_soar(path: Path, *, max_decisions: int | None = None, seed: int = 1,
             timeout: float = DEFAULT_TIMEOUT_S, learning_off: bool = False) -> Report:
    """Run ``path`` in real Soar in a child process; never raises for agent trouble.

    ``learning_off``: ``chunk never`` again after loading (an agent that turns
    chunking on, run with learning off).
    """
    path = Path(path).resolve()
    bound = max_decisions if max_decisions is not None else max_decisions_of(path)
    argv = [sys.executable, str(Path(__file__).resolve()), "--child", str(path),
            str(bound), str(seed), str(timeout), "learning-off" if learning_off else "-"]
    try:
        proc = subprocess.run(argv, capture_output=True, timeout=timeout + 15.0)
    except subprocess.TimeoutExpired:
        return _failed(path, "killed", f"child killed after {timeout + 15.0:.0f}s")
    try:
        report: Report = json.loads(proc.stdout.decode("utf-8"))
    except ValueError:
        tail = proc.stderr.decode("utf-8", "replace")[-1500:]
        return _failed(path, "crashed", f"child exit {proc.returncode}: {tail}")
    return report


def run_soar_many(paths: Iterable[Path], *, jobs: int = 2) -> dict[Path, Report]:
    """Run several agents in parallel child processes (one kernel each)."""
    todo = [Path(p) for p in paths]
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        return dict(zip(todo, pool.map(run_soar, todo)))


def _failed(path: Path, reason: str, error: str) -> Report:
    return {"agent": path.name, "error": error, "halted": False, "stop_reason": reason}


# --------------------------------------------------------------------------
# Real Soar, child side (runs in its own interpreter)
# --------------------------------------------------------------------------


def _child(path: str, max_decisions: int, seed: int, timeout: float,
           learning_off: bool = False) -> Report:
    import xml.etree.ElementTree as ET

    import soar_sml  # only ever imported in the child

    kernel = soar_sml.Kernel.CreateKernelInCurrentThread(True, soar_sml.Kernel.kSuppressListener)
    agent = kernel.CreateAgent("harness")
    events: list[dict[str, Any]] = []
    flags = {"halted": False, "timed_out": False}
    clock = {"d": 0}  # decision phases begun, counted from the phase markers
    deadline = time.time() + timeout

    def on_xml(_eid: int, _data: object, _agent: object, xml: Any) -> None:
        raw = xml.GenerateXMLString(True)
        raw = raw.replace("\r", "&#13;").replace("\n", "&#10;").replace("\t", "&#9;")
        for el in ET.fromstring(raw).iter():
            a = el.attrib
            if el.tag == "phase" and a.get("name") == "decision" and "status" not in a:
                clock["d"] += 1
            elif el.tag == "operator" and "current_operator_id" in a:
                events.append({"t": "op", "d": int(a["decision_cycle_count"]),
                               "level": int(a.get("stack_level", 0)), "name": a.get("name")})
            elif el.tag == "state" and "current_state_id" in a:
                events.append({"t": "state", "d": int(a["decision_cycle_count"]),
                               "level": int(a.get("stack_level", 0)),
                               "type": a.get("impasse_type"), "attr": a.get("impasse_object")})
            elif el.tag == "rhs_write":
                events.append({"t": "write", "d": clock["d"],
                               "text": a.get("string", "")})
            elif el.tag in ("message", "warning", "error"):
                events.append({"t": "msg", "text": a.get("string", el.text or "")})

    def on_print(_eid: int, _data: object, _agent: object, text: str) -> None:
        # a rule's run-time errors are printed only (not in the XML trace)
        events.extend({"t": "msg", "text": line} for line in text.splitlines()
                      if line.startswith("Error"))

    def on_halt(*_args: object) -> None:
        flags["halted"] = True

    def on_after_dc(_eid: int, _data: object, ag: Any, _phase: object) -> None:
        if time.time() > deadline:
            flags["timed_out"] = True
            ag.StopSelf()

    agent.RegisterForXMLEvent(soar_sml.smlEVENT_XML_TRACE_OUTPUT, on_xml, None)
    agent.RegisterForPrintEvent(soar_sml.smlEVENT_PRINT, on_print, None)
    agent.RegisterForRunEvent(soar_sml.smlEVENT_AFTER_HALTED, on_halt, None)
    agent.RegisterForRunEvent(soar_sml.smlEVENT_AFTER_DECISION_CYCLE, on_after_dc, None)
    # XML trace events arrive in batches; phase markers in the stream date the writes.
    agent.ExecuteCommandLine("trace --phases")
    agent.ExecuteCommandLine("chunk never")
    agent.ExecuteCommandLine(f"decide set-random-seed {seed}")
    text = agent.ExecuteCommandLine(f'source "{path}"')
    if not agent.GetLastCommandLineResult():
        return {"agent": os.path.basename(path), "error": "load failed: " + text.strip(),
                "halted": False, "stop_reason": "load-error"}
    if learning_off:
        agent.ExecuteCommandLine("chunk never")
    # an agent's own `watch 0` would hide the decisions this harness reads
    agent.ExecuteCommandLine("trace 1")
    agent.ExecuteCommandLine("trace --phases")
    load_messages = [e["text"] for e in events if e["t"] == "msg"]
    events.clear()
    agent.ExecuteCommandLine(f"run {max_decisions}")
    stats = agent.ExecuteCommandLine("stats")
    messages = [e["text"] for e in events if e["t"] == "msg"]
    decisions = agent.GetDecisionCycleCounter()
    if flags["halted"]:
        stop = "halt"
    elif flags["timed_out"]:
        stop = "timeout"
    elif decisions >= max_decisions:
        stop = "max-decisions"
    elif any("infinite loop" in m or "Goal stack depth" in m for m in messages):
        stop = "max-goal-depth"
    else:
        stop = "interrupted"  # (interrupt), or a stop the agent asked for
    writes = [[e["d"], e["text"]] for e in events if e["t"] == "write"]
    firings = re.search(r"^(\d+) production firings", stats, re.MULTILINE)
    return {
        "agent": os.path.basename(path),
        "error": None,
        "halted": flags["halted"],
        "stop_reason": stop,
        "decisions": decisions,
        "output": "".join(text for _d, text in writes),
        "writes": writes,
        "operators": [[e["d"], e["level"], e["name"]] for e in events if e["t"] == "op"],
        "impasses": [[e["d"], e["level"], e["type"], e["attr"]]
                     for e in events if e["t"] == "state"],
        "messages": messages,
        "load_messages": load_messages,
        "production_firings": int(firings.group(1)) if firings else None,
    }


# --------------------------------------------------------------------------
# adapt (in-process)
# --------------------------------------------------------------------------


def run_adapt(path: Path, *, max_decisions: int | None = None, seed: int = 1,
              matcher: str = "rete", trace_level: int | None = 2,
              chunking: str = "refuse", engine: str = "adapt") -> Report:
    """Run ``path`` in adapt, on its own engine or (``engine="soar"``) on the Soar
    kernel through adapt's engine interface.

    Writes are segmented by decision from a trace of ``trace_level``; with
    ``trace_level=None`` the run has no trace and the writes are segmented by
    an ``on_write`` listener reading the decision counter.  An exception
    from the engine is reported in ``error`` rather than raised.  (The Soar
    engine runs an agent's chunking commands as Soar does: ``chunking`` is
    the own engine's.)
    """
    from adapt.engine import Agent
    from adapt.engines import make_agent

    path = Path(path).resolve()
    bound = max_decisions if max_decisions is not None else max_decisions_of(path)
    with tempfile.TemporaryDirectory() as tmp:
        trace = Path(tmp) / "trace.jsonl"
        options: dict[str, Any] = {} if trace_level is None else {
            "trace": str(trace), "trace_level": trace_level}
        agent = make_agent(engine, seed=seed, matcher=matcher, **options)
        heard: list[list[Any]] = []
        agent.on_write(lambda text: heard.append([agent.decisions, text]))
        try:
            if chunking == "refuse" or not isinstance(agent, Agent):
                agent.load_file(str(path))
            else:
                agent.load_file(str(path), chunking=chunking)
            report: Report = dict(agent.run(max_decisions=bound).to_dict())
        except Exception as exc:  # the test reports it against Soar's run
            return {"error": f"{type(exc).__name__}: {exc}", "halted": False,
                    "stop_reason": "error", "decisions": None}
        finally:
            agent.close()
        report["writes"] = heard
        if trace_level is not None and trace_level >= 2:
            from_trace = _merge(_writes_from_trace(trace))
            if from_trace != _merge(heard):
                report["error"] = (f"the trace's writes {from_trace!r} differ from the "
                                   f"writes heard {_merge(heard)!r}")
    return report


def _merge(heard: list[list[Any]]) -> list[list[Any]]:
    """Consecutive writes of one decision as one segment."""
    out: list[list[Any]] = []
    for d, text in heard:
        if out and out[-1][0] == d:
            out[-1][1] += text
        else:
            out.append([d, text])
    return out


def _writes_from_trace(trace: Path) -> list[list[Any]]:
    writes: list[list[Any]] = []
    for line in trace.read_text(encoding="utf-8").splitlines():
        try:
            rec = json.loads(line)
        except ValueError:
            break
        if rec.get("kind") == "phase" and rec.get("writes"):
            writes.append([rec["d"], rec["writes"]])
    return writes


# --------------------------------------------------------------------------
# Comparison
# --------------------------------------------------------------------------


def first_difference(soar: Report, adapt: Report) -> str | None:
    """The first way ``adapt`` departs from ``soar``, as one readable line, or None."""
    if soar.get("error"):
        return f"real Soar could not run the agent: {soar['error']}"
    if adapt.get("error"):
        return f"adapt failed: {adapt['error']}"
    last = max(int(soar.get("decisions", 0)), int(adapt.get("decisions", 0) or 0))
    segmented = "writes" in soar and "writes" in adapt
    for d in range(last + 1):
        for key, what in (("impasses", "impasse"), ("operators", "selection")):
            s = [e[1:] for e in soar.get(key, []) if e[0] == d]
            a = [e[1:] for e in adapt.get(key, []) if e[0] == d]
            if s != a:
                return f"decision {d}: {what}: Soar {_show(s)}, adapt {_show(a)}"
        if segmented:
            s_lines, a_lines = _segment(soar["writes"], d), _segment(adapt["writes"], d)
            if Counter(s_lines) != Counter(a_lines):
                return (f"decision {d}: writes after it: Soar {_show(s_lines)}, "
                        f"adapt {_show(a_lines)}")
    if not segmented and soar.get("output") != adapt.get("output"):
        return _output_difference(soar, str(adapt.get("output")))
    for key in ("decisions", "halted", "stop_reason"):
        if soar.get(key) != adapt.get(key):
            return f"{key}: Soar {soar.get(key)!r}, adapt {adapt.get(key)!r}"
    if "messages" in adapt:
        s_warn, a_warn = _warnings(soar), _warnings(adapt)
        if s_warn != a_warn:
            return f"max-elaborations warnings: Soar {s_warn}, adapt {a_warn}"
    return None


def _warnings(report: Report) -> int:
    return sum("max-elaborations" in str(m) for m in report.get("messages", []))


def _segment(writes: list[list[Any]], d: int) -> list[str]:
    """The texts of the ``(write ...)`` actions of decision ``d``, one per action."""
    return [t for dd, t in writes if dd == d]


def _output_difference(soar: Report, adapt_output: str) -> str:
    s_lines = str(soar.get("output", "")).splitlines(keepends=True)
    a_lines = adapt_output.splitlines(keepends=True)
    i = next((k for k, (x, y) in enumerate(zip(s_lines, a_lines)) if x != y),
             min(len(s_lines), len(a_lines)))
    s_line = s_lines[i] if i < len(s_lines) else "<end of output>"
    a_line = a_lines[i] if i < len(a_lines) else "<end of output>"
    where = ""
    if "writes" in soar:
        seen = 0
        for d, text in soar["writes"]:
            seen += len(text.splitlines(keepends=True))
            if seen > i:
                where = f" (Soar wrote it after decision {d})"
                break
    return f"output line {i + 1}{where}: Soar {s_line!r}, adapt {a_line!r}"


def _show(value: object, limit: int = 200) -> str:
    text = json.dumps(value)
    return text if len(text) <= limit else text[:limit] + "..."


if __name__ == "__main__" and len(sys.argv) == 7 and sys.argv[1] == "--child":
    try:
        result = _child(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]),
                        sys.argv[6] == "learning-off")
    except Exception as exc:  # reported, not raised: the parent reads stdout
        result = {"agent": os.path.basename(sys.argv[2]), "error": f"{type(exc).__name__}: {exc}",
                  "halted": False, "stop_reason": "crashed"}
    sys.stdout.write(json.dumps(result))
    sys.stdout.flush()
    os._exit(0)  # the native kernel sometimes misbehaves at interpreter exit
elif __name__ == "__main__":
    for arg in sys.argv[1:]:
        print(json.dumps(run_soar(Path(arg)), indent=1))
