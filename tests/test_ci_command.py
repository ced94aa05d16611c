"""CI runs exactly the README's test command."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_ci_runs_the_readme_test_command() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("## Tests"):]
    block = re.search(r"```bash\n(.+?)\n```", section, re.DOTALL)
    assert block is not None, "the README's Tests section has no bash block"
    command = block.group(1).strip()
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").strip().splitlines()
    assert ci[-1] == command
    # the compiled build and the pure-Python engine are both tested
    assert "ADAPT_REQUIRE_COMPILED=1 python -m pytest -q -n 2 --dist loadfile &&" in command
    assert "ADAPT_PURE_PYTHON=1 python -m pytest" in command
    # two worker processes, one per core of the 2-core machine CI is budgeted on (pytest-xdist,
    # in the test extra); a module's tests stay on one worker, which builds its fixtures once
    assert "pytest-xdist" in (ROOT / "pyproject.toml").read_text(encoding="utf-8")
