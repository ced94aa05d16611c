"""Every command in ``docs/mmd.md`` runs as written.

The ``sh`` blocks are run in order, from a scratch repository root
(``tests/docs/shell.py``, the mechanism ``tests/docs/test_commands.py`` runs
the other pages with), with ``adapt`` meaning this checkout's
``python -m adapt``; each command must exit 0.
"""

from __future__ import annotations

import cv2
from docs.shell import ROOT, DocShell, code_blocks, commands

DOC = ROOT / "docs" / "mmd.md"


def test_the_docs_commands_run_as_written(tmp_path):
    blocks = [b for b in code_blocks(DOC) if b.lang == "sh"]
    assert len(blocks) >= 2
    shell = DocShell(tmp_path)
    for block in blocks:
        for command in commands(DOC, block):
            proc = shell.run(command.text)
            assert proc.returncode == 0, (command.text, proc.stdout, proc.stderr)
    # what the docs say the commands produce
    assert cv2.imread(str(tmp_path / "mmd-out" / "mmd.png"), cv2.IMREAD_UNCHANGED).shape == (480, 640)
    strips = sorted((tmp_path / "sync-out").glob("step_*.png"))
    assert strips and all(cv2.imread(str(p)) is not None for p in strips)
    assert (tmp_path / "sync-out" / "sync.json").exists()
