"""Option values every command reads the same way: a seed, an output folder.

Each is an argparse ``type``: a value it refuses is a usage error (status 2)
that names the option, before any work.

>>> seed_number("7"), folder_name("runs/x")
(7, 'runs/x')
>>> seed_number("-1")
Traceback (most recent call last):
...
argparse.ArgumentTypeError: expected a seed, an integer >= 0; got '-1'
>>> folder_name("")
Traceback (most recent call last):
...
argparse.ArgumentTypeError: expected a folder name, got an empty one
"""

from __future__ import annotations

import argparse

__all__ = ["seed_number", "folder_name"]


def seed_number(text: str) -> int:
    """``--seed``: an integer >= 0 (``docs/cli.md``)."""
    try:
        value = int(text.strip())
    except ValueError:
        value = -1
    if value < 0 or not text.strip().lstrip("+").isdigit():
        raise argparse.ArgumentTypeError(f"expected a seed, an integer >= 0; got {text!r}")
    return value


def folder_name(text: str) -> str:
    """``--out DIR``: a folder name, not empty (an empty one is not the default folder)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a folder name, got an empty one")
    return text
