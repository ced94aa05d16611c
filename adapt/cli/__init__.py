"""The ``adapt`` command line.

One thin layer: it parses arguments, calls the library and renders the result.
Each subcommand group lives in its own module of this package and exposes
``register(subparsers)``; heavy libraries (numpy, OpenCV, pymunk) are imported
inside the handlers, so ``adapt rules ...`` starts without them.

Every :class:`adapt.errors.AdaptError` is printed as ``adapt: error: ...`` on
standard error with exit status 1 (2 for usage errors, as argparse does); so is
an :class:`OSError` (an output path that cannot be written), with its path.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from adapt import __version__
from adapt.errors import AdaptError

__all__ = ["main", "build_parser"]

#: Modules of this package that add subcommands, in the order ``--help`` lists them.
SUBCOMMAND_MODULES = (
    "adapt.cli.run",
    "adapt.cli.schemas",
    "adapt.cli.rules",
    "adapt.cli.imagination",
    "adapt.cli.vision",
    "adapt.cli.trace",
)


def build_parser() -> argparse.ArgumentParser:
    """Build the argument parser with every subcommand module that is present."""
    parser = argparse.ArgumentParser(
        prog="adapt",
        description="ADAPT mirror system: rules, imagination, MMD and traces.",
    )
    parser.add_argument("--version", action="version", version=f"adapt {__version__}")
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


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        status = args.func(args)
    except AdaptError as exc:
        print(f"adapt: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("adapt: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except OSError as exc:  # an output path in a missing directory, unwritable, a directory...
        where = f"{exc.filename}: " if exc.filename is not None else ""
        print(f"adapt: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return 1
    return int(status or 0)
