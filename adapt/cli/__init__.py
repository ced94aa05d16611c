"""The ``adapt`` command line.

One thin layer: it parses arguments, calls the library and renders the result.
Each subcommand group lives in its own module of this package and exposes
``register(subparsers)``; heavy libraries (numpy, OpenCV, pymunk) are imported
inside the handlers, so ``adapt rules ...`` starts without them.

Every :class:`adapt.errors.AdaptError` is printed as ``adapt: error: ...`` on
standard error with exit status 1; so is an :class:`OSError` (a file that
cannot be read or written), with its path.  A bad command line is ``adapt:
error: SUBCOMMAND: ...`` after the usage line, with status 2, as argparse's
own.  Ctrl-C is status 130.  Anything else is a bug in adapt: one line,
``adapt: internal error: ... (please report it ...)``, with status 70
(``EX_SOFTWARE``), and the Python traceback only when the environment
variable ``ADAPT_DEBUG`` is set to ``1``.  The statuses are
:class:`adapt.cli.exits.Exit`; ``docs/cli.md`` lists them per subcommand.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import traceback
from collections.abc import Sequence
from typing import NoReturn

from adapt import __version__
from adapt.cli.exits import Exit
from adapt.errors import AdaptError

__all__ = ["main", "build_parser"]

#: Modules of this package that add subcommands, in the order ``--help`` lists them.
SUBCOMMAND_MODULES = (
    "adapt.cli.run",
    "adapt.cli.sweep",
    "adapt.cli.schemas",
    "adapt.cli.rules",
    "adapt.cli.imagination",
    "adapt.cli.vision",
    "adapt.cli.trace",
)


#: Set to ``1`` to see the Python traceback of an internal error.
DEBUG_VARIABLE = "ADAPT_DEBUG"

#: Where to report internal errors.
REPORT_TO = "the adapt issue tracker"


class _Parser(argparse.ArgumentParser):
    """argparse, with its errors worded as every other ``adapt: error: ...`` line."""

    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        where = self.prog.removeprefix("adapt").strip()
        self.exit(int(Exit.USAGE), f"adapt: error: {where + ': ' if where else ''}{message}\n")


class _Version(argparse.Action):
    """``--version``: the version and the engine build (``rules info`` says the same); the
    engine is imported only when asked."""

    def __init__(self, option_strings: list[str], dest: str = argparse.SUPPRESS,
                 default: str = argparse.SUPPRESS, help: str | None = None) -> None:
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: object, option_string: str | None = None) -> None:
        from adapt.engine.compiled import engine_build

        sys.stdout.write(f"adapt {__version__}, engine: {engine_build()}\n")
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    """Build the argument parser with every subcommand module that is present."""
    parser = _Parser(
        prog="adapt",
        description="ADAPT mirror system: rules, imagination, MMD and traces.",
    )
    parser.add_argument("--version", action=_Version,
                        help="show adapt's version and which rule engine runs (compiled or pure Python)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in SUBCOMMAND_MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:  # that group is not built yet
                continue
            raise
        module.register(sub)
    return parser


def _internal_error(exc: BaseException) -> int:
    """The last resort: one line (the traceback with ``ADAPT_DEBUG=1``), status 70."""
    if os.environ.get(DEBUG_VARIABLE) == "1":
        traceback.print_exception(exc, file=sys.stderr)
    detail = str(exc).splitlines()[0][:200] if str(exc) else ""
    print(f"adapt: internal error: {type(exc).__name__}{': ' + detail if detail else ''} "
          f"(a bug in adapt, not in your input: please report it to {REPORT_TO} with the "
          f"command line; set {DEBUG_VARIABLE}=1 to see the traceback)", file=sys.stderr)
    return int(Exit.INTERNAL)


def _quiet_stdout() -> None:
    """After a broken pipe, point standard output at /dev/null so that the
    interpreter's final flush does not complain."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass


def _safe_streams() -> None:
    """File names that are not UTF-8 reach Python as surrogates (U+DC80..U+DCFF):
    standard output writes them back as the bytes they were (as ``ls`` does),
    standard error as ``\\udcff`` (Python's own choice for it).  Standard output is
    line-buffered, so that lines written to both streams (``2>&1`` into a pipe or a
    file) come in the order they were written, as on a terminal."""
    for stream, errors in ((sys.stdout, "surrogateescape"), (sys.stderr, "backslashreplace")):
        if getattr(stream, "errors", None) == "strict" and hasattr(stream, "reconfigure"):
            try:
                stream.reconfigure(errors=errors)
            except (ValueError, OSError):
                pass
    if hasattr(sys.stdout, "reconfigure") and not getattr(sys.stdout, "line_buffering", True):
        try:
            sys.stdout.reconfigure(line_buffering=True)
        except (ValueError, OSError):
            pass


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    _safe_streams()
    try:
        args = build_parser().parse_args(argv)
        status = args.func(args)
    except AdaptError as exc:
        print(f"adapt: error: {exc}", file=sys.stderr)
        return int(Exit.ERROR)
    except KeyboardInterrupt:
        print("adapt: interrupted", file=sys.stderr)
        return int(Exit.INTERRUPTED)
    except BrokenPipeError:  # `adapt trace show ... | head`
        _quiet_stdout()
        return int(Exit.OK)
    except OSError as exc:  # a file that cannot be read or written
        where = f"{exc.filename}: " if exc.filename is not None else ""
        print(f"adapt: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return int(Exit.ERROR)
    except Exception as exc:  # noqa: BLE001 - the last resort: never a traceback by default
        return _internal_error(exc)
    return int(status or 0)
