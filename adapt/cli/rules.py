"""``adapt rules run`` and ``adapt rules check``: run and lint Soar rule files.

``adapt rules run FILE...`` loads the files into one agent, runs it, prints
what the rules wrote and a one-line summary (or, with ``--json``, one JSON
object with the run report's keys).  ``adapt rules check FILE...`` parses
every file and prints its first positioned error or its warnings.
"""

from __future__ import annotations

import argparse
import json
import sys

from adapt.errors import AdaptError, RuleError

__all__ = ["register", "run_command", "check_command", "info_command"]


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
    run.add_argument("--trace", metavar="PATH", help="write a JSON Lines trace")
    run.add_argument("--trace-level", type=int, default=5, choices=range(1, 6),
                     metavar="1..5", help="trace detail (default 5)")
    run.add_argument("--matcher", choices=("rete", "naive"), default="rete",
                     help="the Rete matcher (default) or the brute-force one (for checking)")
    run.set_defaults(func=run_command)

    info = rsub.add_parser("info", help="say which engine is installed (compiled or pure Python)")
    info.set_defaults(func=info_command)

    check = rsub.add_parser("check", help="parse and lint rule files")
    check.add_argument("files", nargs="+", metavar="FILE")
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


def run_command(args: argparse.Namespace) -> int:
    """Run the files; exit 0 (a run that stops on its bound is not an error)."""
    from adapt.engine import Agent

    if args.max_decisions is not None and args.max_decisions < 0:
        raise AdaptError("--max-decisions must be >= 0")
    agent = Agent(seed=args.seed, matcher=args.matcher, trace=args.trace,
                  trace_level=args.trace_level)
    try:
        loaded = sum(len(agent.load_file(path).productions) for path in args.files)
        if loaded == 0:
            print("warning: the rule files hold no productions; the run will only make "
                  "state no-change impasses", file=sys.stderr)
        for warning in agent.warnings:
            print(_warning_line(warning), file=sys.stderr)
        report = agent.run(args.max_decisions)
    finally:
        agent.close()
    if args.json:
        print(json.dumps(report.to_dict()))
        return 0
    out = report.output
    sys.stdout.write(out)
    if out and not out.endswith("\n"):
        sys.stdout.write("\n")
    print(f"-- {report.stop_reason}: {report.decisions} decisions, "
          f"{report.production_firings} firings, {len(report.operators)} operators, "
          f"{len(report.impasses)} impasses, {report.wm_size_final} WMEs")
    for message in report.messages:
        if message.startswith("Warning") or message.startswith("Error"):
            print(message.strip(), file=sys.stderr)
    return 0


def info_command(args: argparse.Namespace) -> int:
    """Print which engine runs: the mypyc-compiled modules or the pure-Python source."""
    from adapt import __version__
    from adapt.engine import engine_build

    print(f"adapt {__version__}, engine: {engine_build()}")
    return 0


def check_command(args: argparse.Namespace) -> int:
    """Parse every file; print errors (first per file) and warnings."""
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
    return 1 if failed else 0
