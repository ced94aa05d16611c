"""Running the commands the documentation shows, as a user would type them.

A :class:`DocShell` is a scratch directory that looks like the repository root
to the commands (``scenarios/``, ``rules/`` and ``bench/`` are linked into it),
with ``adapt`` and ``python`` on the ``PATH`` meaning this checkout's
``python -m adapt`` and this interpreter.  :func:`code_blocks` finds the
fenced blocks of a page and :func:`commands` the commands in one: every line of
a ``sh``/``bash`` block, the ``$ `` lines of a ``console`` block (with the
output shown under each), and the lines of an unlabelled block that start with
``adapt`` or ``python``.  Used by ``tests/docs/test_commands.py`` and
``tests/vision/test_docs.py``.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


@dataclass(frozen=True)
class Block:
    """A fenced code block: its language tag, text and first line in the page."""

    lang: str
    text: str
    line: int


@dataclass(frozen=True)
class Command:
    """A command of a page, the output the page shows under it, and where it is."""

    text: str
    shown: tuple[str, ...]
    page: str
    line: int


def code_blocks(page: Path) -> list[Block]:
    text = page.read_text(encoding="utf-8")
    return [Block(m.group(1), m.group(2), text.count("\n", 0, m.start()) + 2)
            for m in re.finditer(r"^```(\w*)\n(.*?)^```", text, re.S | re.M)]


def commands(page: Path, block: Block) -> list[Command]:
    found: list[Command] = []
    name = page.name
    lines = block.text.splitlines()
    if block.lang in ("sh", "bash"):
        pending = ""
        start = 0
        for i, line in enumerate(lines):
            if not pending and (not line.strip() or line.lstrip().startswith("#")):
                continue
            if not pending:
                start = i
            text = line.strip()
            if text.endswith("\\"):  # a continued line: one command with the next
                pending += text[:-1] + " "
                continue
            found.append(Command(pending + text, (), name, block.line + start))
            pending = ""
        return found
    if block.lang == "console":
        for i, line in enumerate(lines):
            if line.startswith("$ "):
                found.append(Command(line[2:].strip(), (), name, block.line + i))
            elif found:
                last = found[-1]
                found[-1] = Command(last.text, last.shown + (line,), name, last.line)
        return found
    if block.lang == "":
        return [Command(line.strip(), (), name, block.line + i) for i, line in enumerate(lines)
                if re.match(r"(adapt|python) ", line.strip())]
    return []


class DocShell:
    """A scratch repository root to run documented commands in (see the module docstring)."""

    def __init__(self, scratch: Path) -> None:
        self.cwd = scratch
        for folder in ("scenarios", "rules", "bench", "examples"):
            (scratch / folder).symlink_to(ROOT / folder)
        bin_dir = scratch / "bin"
        bin_dir.mkdir()
        for name, exe in (("adapt", f'"{sys.executable}" -m adapt'), ("python", f'"{sys.executable}"')):
            shim = bin_dir / name
            shim.write_text(f'#!/bin/sh\nexec {exe} "$@"\n')
            shim.chmod(0o755)
        self.env = dict(os.environ, PYTHONPATH=str(ROOT), PATH=f"{bin_dir}:{os.environ['PATH']}")

    def run(self, command: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
        """Run one command line with ``sh -c``."""
        return subprocess.run(["sh", "-c", command], cwd=self.cwd, env=self.env,
                              capture_output=True, text=True, timeout=timeout)
