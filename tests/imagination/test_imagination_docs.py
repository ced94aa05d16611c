"""The code in docs/imagination.md runs as written."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import numpy as np
import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "imagination.md"


def blocks() -> list[str]:
    found = re.findall(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S)
    return [textwrap.dedent(b) for b in found]


def test_the_examples_in_docs_imagination_md_run(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(DOC.parents[1])
    first, hook, back_projection = blocks()
    ns: dict[str, object] = {}
    exec(first, ns)
    assert ns["frame"].boxes["ball"][2] > 10  # type: ignore[attr-defined]
    assert ns["path"].positions.shape == (3, 2)  # type: ignore[attr-defined]
    ns.update(k=40.0, c=8.0, ox=0.0, oy=1.0)
    exec(hook, ns)
    world = ns["world"]
    world.run(3.0)  # type: ignore[attr-defined]
    assert np.hypot(*np.subtract(world.position("ball"), (0.0, 1.0))) < 0.05  # type: ignore[attr-defined]
    renderer = ns["renderer"]
    ns["camera"] = ns["sc"].camera  # type: ignore[attr-defined]
    ns["render"] = renderer.render()  # type: ignore[attr-defined]
    ns["frame"] = ns["render"].image  # type: ignore[attr-defined]
    exec(back_projection, ns)
    assert "north" in renderer.backdrop.appearances  # type: ignore[attr-defined]
