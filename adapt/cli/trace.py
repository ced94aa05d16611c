"""``adapt trace show|wm|why|stats|diff|html``: reading a run's trace.

Thin: parse arguments, call :mod:`adapt.traceview`, print.  Warnings about a
truncated trace go to standard error as ``adapt: warning: ...``.  A trace
record that breaks the format is an ``adapt: error: FILE:LINE: ...`` (the
reader checks every record); ``show`` with ``--rule`` or ``--id`` that matches
nothing says so and exits 1; ``html`` refuses an ``--out`` that is the trace
or not an ``.html`` file name, and creates its folder (``adapt/files.py``).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from adapt.errors import AdaptError, TraceError

__all__ = ["register", "parse_range", "parse_wme"]


def parse_range(text: str) -> tuple[int | None, int | None]:
    """``A..B``, ``A..``, ``..B`` or ``N`` as inclusive bounds.

    >>> parse_range("10..20"), parse_range("5"), parse_range("..7"), parse_range("3..")
    ((10, 20), (5, 5), (None, 7), (3, None))
    """
    try:
        if ".." in text:
            lo, hi = text.split("..", 1)
            first = int(lo) if lo.strip() else None
            last = int(hi) if hi.strip() else None
        else:
            first = last = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a decision range like 10..20") from None
    if first is not None and last is not None and first > last:
        raise argparse.ArgumentTypeError(f"{text!r}: the range is empty ({first} > {last})")
    return first, last


def _depth(text: str) -> int:
    """``--depth`` of ``trace why``: 0 to :data:`adapt.traceview.why.MAX_DEPTH`.

    >>> _depth("3")
    3
    """
    from adapt.traceview.why import MAX_DEPTH

    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value <= MAX_DEPTH:
        raise argparse.ArgumentTypeError(f"{text!r}: expected a depth from 0 to {MAX_DEPTH}")
    return value


def _level(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if not 1 <= value <= 5:
        raise argparse.ArgumentTypeError(f"{text!r}: the level is 1..5")
    return value


@contextmanager
def _warnings_to_stderr() -> Iterator[None]:
    from adapt.traceview.reader import TraceWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", TraceWarning)
        try:
            yield
        finally:
            seen: set[str] = set()
            for w in caught:
                if issubclass(w.category, TraceWarning) and str(w.message) not in seen:
                    seen.add(str(w.message))
                    print(f"adapt: warning: {w.message}", file=sys.stderr)


def _open(path: str):  # type: ignore[no-untyped-def]
    from adapt.traceview.reader import Trace

    return Trace(path)


def _cmd_show(args: argparse.Namespace) -> int:
    from adapt.traceview.show import ShowFilter, show_lines

    trace = _open(args.trace)
    first, last = args.decisions or (None, None)
    if args.level > trace.header.level:
        print(f"adapt: note: the trace was written at level {trace.header.level}; "
              f"showing what it has", file=sys.stderr)
    flt = ShowFilter(first=first, last=last, rule=args.rule, ident=args.id, level=args.level)
    out = sys.stdout
    shown = 0
    for line in show_lines(trace, flt):
        out.write(line + "\n")
        shown += 1
    if not shown:
        from adapt.traceview.show import nothing_shown

        reason = nothing_shown(trace, flt)
        if reason is not None:
            raise TraceError(reason)
    return 0


def _cmd_wm(args: argparse.Namespace) -> int:
    from adapt.traceview.memory import format_tree, memory_at

    trace = _open(args.trace)
    wm = memory_at(trace, args.at)
    end = " (the end of the trace)" if args.at is None else ""
    print(f"; working memory at the end of decision {wm.cycle}{end}: {len(wm)} WMEs")
    print(format_tree(wm, args.root, args.depth, internal=args.internal))
    return 0


def _cmd_stats(args: argparse.Namespace) -> int:
    from adapt.traceview.stats import compute_stats, format_stats

    stats = compute_stats(_open(args.trace))
    if args.json:
        print(json.dumps(stats.to_json(), indent=2))
    else:
        print(format_stats(stats))
    return 0


def parse_wme(text: str) -> tuple[int | None, tuple[str, str, str | None, bool | None] | None]:
    """``231`` (a timetag) or ``(S1 ^operator O3 +)`` / ``S1 ^count`` (id, attr, value, +).

    >>> parse_wme("231"), parse_wme("(S1 ^count 3)"), parse_wme("S1 ^io")
    ((231, None), (None, ('S1', 'count', '3', False)), (None, ('S1', 'io', None, None)))
    >>> parse_wme("(S1 ^operator O3 +)")
    (None, ('S1', 'operator', 'O3', True))
    """
    text = text.strip()
    if text.isascii() and text.isdigit():
        return int(text), None
    parts = text.strip("()").replace("^", " ^").split()
    acceptable = None if len(parts) == 2 else bool(parts) and parts[-1] == "+"
    if acceptable:
        parts = parts[:-1]
    if len(parts) in (2, 3) and parts[1].startswith("^") and len(parts[1]) > 1:
        return None, (parts[0], parts[1][1:], parts[2] if len(parts) == 3 else None, acceptable)
    raise argparse.ArgumentTypeError(
        f"{text!r} is not a timetag or a WME like '(S1 ^count 3)'")


def _cmd_why(args: argparse.Namespace) -> int:
    from adapt.traceview.rules import load_join_orders, load_productions
    from adapt.traceview.why import explain, find_timetag, format_origin, format_why_not, why_not

    trace = _open(args.trace)
    if args.rule is not None:
        if args.at is None:
            raise TraceError("--rule needs --at D (the decision to check the rule at)")
        rules, orders = load_join_orders(trace, args.rules)
        result = why_not(trace, args.rule, args.at, rules, orders.get(args.rule))
        print(format_why_not(result))
        return 0
    if args.wme is None:
        raise TraceError("say what to explain: --wme TIMETAG|'(ID ^attr value)' or --rule NAME --at D")
    timetag, pattern = args.wme
    if timetag is None:
        assert pattern is not None
        ident, attr, value, acceptable = pattern
        timetag = find_timetag(trace, ident, attr, value, at=args.at, acceptable=acceptable)
    try:
        productions = load_productions(trace, args.rules)
    except AdaptError as exc:
        productions = None
        print(f"adapt: note: without the rules, makers are told only by the firings' own "
              f"records ({exc})", file=sys.stderr)
    print(format_origin(explain(trace, timetag, args.depth, productions)))
    return 0


def _cmd_diff(args: argparse.Namespace) -> int:
    from adapt.traceview.diff import diff_traces, format_divergence

    result = diff_traces(_open(args.a), _open(args.b))
    print(format_divergence(result, args.a, args.b))
    return 0 if result.cycle is None else 1 if args.exit_code else 0


def _cmd_html(args: argparse.Namespace) -> int:
    from adapt.files import Output, check_outputs, write_output
    from adapt.traceview.html import page_payload, render_page

    trace = _open(args.trace)
    target = args.out if args.out is not None else os.path.splitext(args.trace)[0] + ".html"
    out = Output("--out" if args.out is not None else "the HTML page", target,
                 (".html", ".htm"))
    check_outputs([out], [("the trace", args.trace)])
    # backslashreplace: a file name that is not UTF-8 (in the header) stays valid UTF-8 in the page
    # a run's mmd.mp4 beside the trace is shown in the page (linked, not embedded)
    write_output(out, render_page(page_payload(trace, target)).encode("utf-8", "backslashreplace"))
    print(target)
    return 0


def _with_warnings(func: Callable[[argparse.Namespace], int]) -> Callable[[argparse.Namespace], int]:
    def run(args: argparse.Namespace) -> int:
        with _warnings_to_stderr():
            return func(args)

    run.__doc__ = func.__doc__
    return run


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Add ``adapt trace ...`` to the top-level parser's subcommands."""
    parser = sub.add_parser("trace", help="inspect a run's trace (show, wm, why, stats, diff, html)",
                            description="Inspect a JSON Lines trace written by "
                                        "`adapt rules run --trace PATH`.")
    cmds = parser.add_subparsers(dest="trace_command", metavar="COMMAND")
    cmds.required = True

    p = cmds.add_parser("show", help="Soar-style text of the run")
    p.add_argument("trace", metavar="TRACE")
    p.add_argument("--decisions", type=parse_range, metavar="A..B",
                   help="only these decision cycles (A..B, A.., ..B or N)")
    p.add_argument("--rule", metavar="NAME", help="only where this rule fired or retracted")
    p.add_argument("--id", metavar="ID", help="only what mentions this identifier")
    p.add_argument("--level", type=_level, default=1, metavar="1..5",
                   help="1 decisions, 2 phases, 3 firings, 4 WME changes, 5 preferences (default 1)")
    p.set_defaults(func=_with_warnings(_cmd_show))

    p = cmds.add_parser("wm", help="working memory at a decision, as a tree")
    p.add_argument("trace", metavar="TRACE")
    p.add_argument("--at", type=int, default=None, metavar="D",
                   help="the decision cycle (memory as it was when the cycle ended; "
                        "default: the end of the trace)")
    p.add_argument("--root", default="S1", metavar="ID", help="the identifier to print from (S1)")
    p.add_argument("--depth", type=int, default=2, metavar="N", help="levels to print (2)")
    p.add_argument("--internal", action="store_true", help="one WME per line, with timetags")
    p.set_defaults(func=_with_warnings(_cmd_wm))

    p = cmds.add_parser("why", help="which firing made a WME; why a rule did not fire")
    p.add_argument("trace", metavar="TRACE")
    p.add_argument("--wme", type=parse_wme, metavar="WME",
                   help="a timetag, or '(ID ^attr value)' (the latest such WME by --at)")
    p.add_argument("--rule", metavar="NAME", help="why this rule did not fire at --at D")
    p.add_argument("--at", type=int, metavar="D", help="the decision cycle")
    p.add_argument("--depth", type=_depth, default=1, metavar="N",
                   help="explain the matched WMEs this many levels deep (1; at most 100)")
    p.add_argument("--rules", nargs="+", metavar="FILE",
                   help="the rule files (default: those named in the trace header)")
    p.set_defaults(func=_with_warnings(_cmd_why))

    p = cmds.add_parser("diff", help="the first decision where two traces diverge")
    p.add_argument("a", metavar="A")
    p.add_argument("b", metavar="B")
    p.add_argument("--exit-code", action="store_true",
                   help="exit with status 1 when the traces differ (like git diff --exit-code)")
    p.set_defaults(func=_with_warnings(_cmd_diff))

    p = cmds.add_parser("html", help="one self-contained HTML page to browse the trace")
    p.add_argument("trace", metavar="TRACE")
    p.add_argument("--out", metavar="FILE.html",
                   help="where to write it (default: TRACE with .html); missing folders are made")
    p.set_defaults(func=_with_warnings(_cmd_html))

    p = cmds.add_parser("stats", help="decisions, firings per rule, WM size, impasses")
    p.add_argument("trace", metavar="TRACE")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(func=_with_warnings(_cmd_stats))
