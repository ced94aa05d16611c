"""Every command in ``docs/mmd.md`` runs as written.

The ``sh`` blocks are run in order, from a scratch directory holding the
repository's ``scenarios/`` (the docs say "from the repository root"), with
``adapt`` meaning this checkout's ``python -m adapt``; each command must exit 0.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import cv2

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "mmd.md"


def sh_blocks(text: str) -> list[str]:
    return re.findall(r"```sh\n(.*?)```", text, flags=re.S)


def test_the_docs_commands_run_as_written(tmp_path):
    blocks = sh_blocks(DOC.read_text(encoding="utf-8"))
    assert len(blocks) >= 2
    (tmp_path / "scenarios").symlink_to(ROOT / "scenarios")
    (tmp_path / "bin").mkdir()
    shim = tmp_path / "bin" / "adapt"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m adapt "$@"\n')
    shim.chmod(0o755)
    env = dict(os.environ, PYTHONPATH=str(ROOT), PATH=f"{tmp_path / 'bin'}:{os.environ['PATH']}")
    for block in blocks:
        for command in [line for line in block.splitlines() if line.strip()]:
            proc = subprocess.run(["sh", "-c", command], cwd=tmp_path, env=env,
                                  capture_output=True, text=True, timeout=120)
            assert proc.returncode == 0, (command, proc.stdout, proc.stderr)
    # what the docs say the commands produce
    assert cv2.imread(str(tmp_path / "mmd-out" / "mmd.png"), cv2.IMREAD_UNCHANGED).shape == (480, 640)
    strips = sorted((tmp_path / "sync-out").glob("step_*.png"))
    assert strips and all(cv2.imread(str(p)) is not None for p in strips)
    assert (tmp_path / "sync-out" / "sync.json").exists()
