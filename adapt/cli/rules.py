"""``adapt rules run`` and ``adapt rules check``: run and lint Soar rule files.

``adapt rules run FILE...`` loads the files into one agent and runs it,
printing what the rules ``write`` as they write it (as Soar does), then a
one-line summary -- or, with ``--json``, one JSON object with the run report's
keys.  Ctrl-C stops the run and still prints the summary (or the report) of
what ran.  Each way a run can end has its exit status (:func:`run_status`,
``docs/cli.md``).  ``--trace PATH`` is checked before the rules are loaded (a
``.jsonl`` file name that is not one of the rule files), again once they are
(nor a file they ``source``), and written as the run goes (missing folders are
made).

``adapt rules check FILE...`` parses every file (an agent's top file: its
``source`` lines are followed) and prints its first positioned error or its
warnings; ``--verbose`` also prints each production's conditions in the order
they are joined (Soar's reorderer, :mod:`adapt.engine.reorder`, with the
file's ``multi-attributes`` hints).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from typing import Any

from adapt.cli.exits import Exit
from adapt.errors import AdaptError, EngineError, RuleError

__all__ = ["register", "run_command", "check_command", "info_command", "run_status",
           "TRACE_SUFFIXES"]

#: File name extensions ``--trace`` accepts (JSON Lines).
TRACE_SUFFIXES = (".jsonl", ".ndjson")

#: The exit status of each stop reason of a run report.
STOP_STATUS = {
    "halt": Exit.OK,
    "max-decisions": Exit.DECISION_LIMIT,
    "max-goal-depth": Exit.GOAL_DEPTH,
    "interrupted": Exit.RULE_INTERRUPT,
}


def run_status(stop_reason: str, messages: list[str]) -> Exit:
    """The exit status of a run: :attr:`Exit.RULE_ERROR` if a rule had a run-time
    error (an ``Error:`` message, such as a division by zero), however the run
    ended; otherwise that of its stop reason.

    >>> run_status("halt", ["This Agent halted."]).name
    'OK'
    >>> run_status("max-decisions", []), run_status("interrupted", [])
    (<Exit.DECISION_LIMIT: 3>, <Exit.RULE_INTERRUPT: 5>)
    >>> run_status("halt", ["Error: attempt to divide ('/') by zero."]).name
    'RULE_ERROR'
    """
    if any(m.startswith("Error") for m in messages):
        return Exit.RULE_ERROR
    return STOP_STATUS.get(stop_reason, Exit.ERROR)


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add the ``rules`` command group."""
    rules = sub.add_parser("rules", help="run and check Soar rule files")
    rsub = rules.add_subparsers(dest="rules_command", metavar="SUBCOMMAND")
    rsub.required = True

    run = rsub.add_parser("run", help="run rule files in the engine")
    run.add_argument("files", nargs="+", metavar="FILE")
    run.add_argument("--max-decisions", type=int, default=None, metavar="N",
                     help="stop before the apply phase of the N-th decision")
    run.add_argument("--seed", type=int, default=1, metavar="N", help="random seed (default 1)")
    run.add_argument("--json", action="store_true", help="print the report as one JSON object")
    run.add_argument("--trace", metavar="PATH.jsonl",
                     help="write a JSON Lines trace as the run goes (missing folders are made)")
    run.add_argument("--trace-level", type=int, default=5, choices=range(1, 6),
                     metavar="1..5", help="trace detail (default 5)")
    run.add_argument("--matcher", choices=("rete", "naive"), default="rete",
                     help="the Rete matcher (default) or the brute-force one (for checking)")
    run.add_argument("--engine", default="adapt", metavar="adapt|soar",
                     help="adapt's own engine (default) or soar, the Soar kernel (soar-sml: "
                          "chunking, RL, smem, epmem; pip install 'adapt[soar]')")
    run.set_defaults(func=run_command)

    info = rsub.add_parser("info", help="say which engine is installed (compiled or pure Python)")
    info.set_defaults(func=info_command)

    check = rsub.add_parser("check", help="parse and lint rule files")
    check.add_argument("files", nargs="+", metavar="FILE")
    check.add_argument("--verbose", action="store_true",
                       help="also print each production's conditions in the order they are "
                            "joined")
    check.set_defaults(func=check_command)


def _warning_line(warning: object) -> str:
    """``file:line:col: warning: ...`` as the loader words it, with ``warning:`` once.

    Examples
    --------
    >>> _warning_line("a.soar:5:1: warning: production 'a' replaces an earlier one")
    "a.soar:5:1: warning: production 'a' replaces an earlier one"
    >>> _warning_line("no productions")
    'warning: no productions'
    """
    text = str(warning)
    return text if "warning:" in text else f"warning: {text}"


class _Echo:
    """Prints ``write`` text as the rules produce it; remembers whether a line is open."""

    def __init__(self) -> None:
        self.open_line = False

    def __call__(self, text: str) -> None:
        if text:
            sys.stdout.write(text)
            sys.stdout.flush()
            self.open_line = not text.endswith("\n")

    def end_line(self) -> None:
        if self.open_line:
            sys.stdout.write("\n")
            self.open_line = False


def _check_trace(args: argparse.Namespace, read: Sequence[str] = ()) -> Any:
    """Refuse a ``--trace`` that cannot be written, is a rule file or a file the rules
    ``source`` (``read``: every file loaded); return it as an :class:`adapt.files.Output`."""
    from adapt.files import Output, check_outputs

    out = Output("--trace", args.trace, TRACE_SUFFIXES)
    check_outputs([out], [("a rule file of the run", f) for f in args.files]
                  + [("a file sourced by the rule files", f) for f in read])
    return out


def run_command(args: argparse.Namespace) -> int:
    """Run the files; the exit status says how the run ended (:func:`run_status`)."""
    from adapt.engines import EngineName, engine_name, make_agent

    engine = engine_name(args.engine)
    if args.max_decisions is not None and args.max_decisions < 0:
        raise AdaptError(f"--max-decisions must be >= 0, got {args.max_decisions}")
    if engine is EngineName.SOAR and args.matcher != "rete":
        raise AdaptError("--matcher chooses the matcher of adapt's own engine; the Soar kernel "
                         "(--engine soar) matches with its own Rete")
    trace = _check_trace(args) if args.trace is not None else None
    agent = make_agent(engine, seed=args.seed, matcher=args.matcher, trace=args.trace,
                       trace_level=args.trace_level)
    echo = _Echo()
    if not args.json:
        agent.on_write(echo)
    try:
        ctrl_c, failure, crashed = _load_and_run(args, agent, trace)
    finally:
        agent.close()
    report = agent.report()
    if ctrl_c:
        status = Exit.INTERRUPTED
    elif crashed is not None:
        status = Exit.ERROR
    elif failure is not None:
        status = Exit.RULE_ERROR
    else:
        status = run_status(report.stop_reason, report.messages)
    _print_outcome(args, report, echo, ctrl_c, status, crashed)
    if failure is not None or crashed is not None:
        print(f"adapt: error: {crashed or failure}", file=sys.stderr)
    return int(status)


def _load_and_run(args: argparse.Namespace, agent: Any, trace: Any
                  ) -> tuple[bool, EngineError | None, str | None]:
    """Load the files (warnings to standard error), then run: (interrupted, a rule's
    failure at run time, why the Soar kernel's process died)."""
    from adapt.soar.process import KernelCrash

    loaded = sum(len(agent.load_file(path).productions) for path in args.files)
    if loaded == 0:
        print("warning: the rule files hold no productions; the run will only make "
              "state no-change impasses", file=sys.stderr)
    for warning in agent.warnings:
        print(_warning_line(warning), file=sys.stderr)
    if trace is not None:  # the rules loaded: check the files they sourced, make the folder
        from adapt.files import make_folder

        make_folder(_check_trace(args, agent.files))
    try:
        agent.run(args.max_decisions)
    except KeyboardInterrupt:
        return True, None, None
    except KernelCrash as exc:  # the Soar kernel's process died: report what ran
        return False, None, (f"{exc}; the report and the trace hold the {agent.decisions} "
                             "decisions it reported")
    except EngineError as exc:  # a rule's action failed at run time
        return False, exc, None
    return False, None, None


def _print_outcome(args: argparse.Namespace, report: Any, echo: _Echo, ctrl_c: bool,
                   status: Exit, crashed: str | None = None) -> None:
    if args.json:
        data = report.to_dict()
        data["exit_status"] = int(status)
        data["engine"] = str(args.engine)
        if crashed is not None:
            data["error"] = crashed
        print(json.dumps(data))
    else:
        echo.end_line()
        how = ("interrupted by Ctrl-C" if ctrl_c else "the Soar kernel crashed" if crashed
               else report.stop_reason)
        print(f"-- {how}: {report.decisions} decisions, "
              f"{report.production_firings} firings, {len(report.operators)} operators, "
              f"{len(report.impasses)} impasses, {report.wm_size_final} WMEs")
    for message in report.messages:
        if message.startswith("Warning") or message.startswith("Error"):
            print(message.strip(), file=sys.stderr)
    if ctrl_c:
        print("adapt: interrupted", file=sys.stderr)


def info_command(args: argparse.Namespace) -> int:
    """Print which engine runs: the mypyc-compiled modules or the pure-Python source."""
    from adapt import __version__
    from adapt.engine import engine_build
    from adapt.engines import soar_status

    print(f"adapt {__version__}, engine: {engine_build()}")
    print(f"Soar engine (--engine soar): {soar_status()}")
    return 0


def check_command(args: argparse.Namespace) -> int:
    """Parse every file; print errors (first per file) and warnings; with
    ``--verbose`` each production's join order."""
    from adapt.engine.functions import default_functions
    from adapt.engine.parse import load_rule_file

    table = default_functions()
    failed = False
    for path in args.files:
        try:
            rules = load_rule_file(path, functions=table)
        except RuleError as exc:
            print(f"adapt: error: {exc}", file=sys.stderr)
            failed = True
            continue
        for warning in rules.warnings:
            print(_warning_line(warning), file=sys.stderr)
        count = len(rules.productions)
        print(f"{path}: {count} production{'' if count == 1 else 's'} ok")
        if getattr(args, "verbose", False):
            for line in _join_orders(rules):
                print(line)
    return 1 if failed else 0


def _join_orders(rules: Any) -> list[str]:
    """Each production's conditions in join order, numbered as written (1-based)."""
    from adapt.engine.joins import join_orders
    from adapt.traceview.conditions import condition_text

    lines: list[str] = []
    for p, order in join_orders(rules):
        moved = "" if order == sorted(order) else "  (reordered)"
        lines.append(f"  sp {p.name}{moved}")
        lines.extend(f"    {n + 1:>3}  {condition_text(p.conditions[n])}" for n in order)
    return lines
