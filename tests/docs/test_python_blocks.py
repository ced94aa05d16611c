"""The Python examples of ``docs/extending.md`` and ``docs/api.md`` run as written, in order,
each page in a scratch folder of its own (with the repository's ``scenarios``, ``rules`` and
``examples``), and print what the page says they print (``It prints `...```)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from .shell import ROOT

PAGES = [ROOT / "docs" / "extending.md", ROOT / "docs" / "api.md"]


def blocks(page: Path) -> list[tuple[str, str]]:
    """Each ``python`` block with what the text after it says it prints."""
    text = page.read_text(encoding="utf-8")
    out = []
    for m in re.finditer(r"```python\n(.*?)```\n(.*?)(?=```|\Z)", text, re.S):
        said = re.search(r"It prints `([^`]*)`", m.group(2))
        out.append((m.group(1), said.group(1) if said else ""))
    return out


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_the_python_examples_of_a_page_run_and_print_what_it_says(page: Path,
                                                                  tmp_path: Path) -> None:
    found = blocks(page)
    assert found and all(said for _, said in found), "every example says what it prints"
    for folder in ("scenarios", "rules", "examples"):
        (tmp_path / folder).symlink_to(ROOT / folder)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for code, said in found:
        proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env,
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, (code[:200], proc.stderr[-2000:])
        assert proc.stdout.strip().splitlines()[-1] == said, (code[:200], proc.stdout)
