"""docs/schemas.md stays true: every parameter of every schema type, and every attribute a
schema writes on the input-link in a real run, is in its table."""

from __future__ import annotations

import re
from pathlib import Path

from adapt.plugins import BUILTIN
from adapt.runner import Runner
from adapt.scenario import OutputSettings, load_scenario
from adapt.schemas import REGISTRY, SchemaSpec

ROOT = Path(__file__).resolve().parents[2]
DOC = (ROOT / "docs" / "schemas.md").read_text()
SMALL = ("camera.width=320", "camera.height=240", "camera.fx=262.5", "camera.fy=262.5",
         "camera.cx=159.5", "camera.cy=119.5", "run.duration=1.5",
         "schemas.scene-background.mmd_pixels=76800")


def documented_parameters() -> dict[str, set[str]]:
    section = DOC.split("## Parameters", 1)[1].split("\n## ", 1)[0]
    out: dict[str, set[str]] = {}
    current = ""
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or not cells[1].startswith("`"):
            continue
        if cells[0]:
            current = cells[0].strip("`")
        out.setdefault(current, set()).add(cells[1].strip("`"))
    return out


def documented_attributes(type_name: str) -> set[str]:
    section = DOC.split(f"### `{type_name}`", 1)[1].split("\n#", 1)[0]
    names = set()
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("|") and len(cells) >= 2:
            # the attribute column: the first, or the second in a table of structures
            for cell in cells[:2]:
                names.update(re.findall(r"`\^?([a-z-]+)`", cell))
    return names


def _builtin() -> list[SchemaSpec]:
    """adapt's own schema types (a plugin another test loaded documents its own)."""
    return [spec for spec in REGISTRY if REGISTRY.origin(spec.name) == BUILTIN]


def test_every_parameter_is_documented() -> None:
    table = documented_parameters()
    for spec in _builtin():
        assert {p.name for p in spec.parameters} == table.get(spec.name, set()), spec.name


def test_every_numeric_parameter_is_bounded_as_documented() -> None:
    """Each number a schema takes has both bounds (a value beyond them could only fail later
    in a run), and docs/schemas.md shows them."""
    text = DOC.split("## Parameters", 1)[1].split("\n## ", 1)[0]
    cells: dict[tuple[str, str], str] = {}
    kind = ""
    for line in text.splitlines():
        if line.startswith("| `") or line.startswith("| | `"):
            row = [c.strip() for c in line.strip("|").split("|")]
            kind = row[0].strip("`") or kind
            cells[(kind, row[1].strip("`"))] = row[2]
    for spec in _builtin():
        for p in spec.parameters:
            if p.kind in (int, float):
                assert p.range_text, (spec.name, p.name)
                assert cells[(spec.name, p.name)] == p.range_text, (spec.name, p.name)


def test_every_attribute_a_schema_writes_is_documented() -> None:
    sc = load_scenario(ROOT / "scenarios" / "bouncing-ball.yaml", overrides=SMALL)
    written: dict[str, set[str]] = {}
    runner: Runner | None = None

    def collect(_: object) -> None:
        assert runner is not None
        wm = list(runner.agent.wm)
        types = {w.id: str(w.value) for w in wm if str(w.attr) == "type"}
        parents = {w.value: w.id for w in wm}
        for w in wm:
            kind = types.get(w.id)
            if kind is None:  # a child structure: the schema above it
                kind = types.get(parents.get(w.id))  # type: ignore[arg-type]
            if kind in ("scene-background", "foreground-object", "intercept", "drive"):
                written.setdefault(kind, set()).add(str(w.attr))

    runner = Runner(sc, out=None, on_progress=collect,
                    outputs=OutputSettings(report=False, trace=False, video=False, figures=False))
    runner.run()
    assert {"scene-background", "foreground-object", "intercept"} <= set(written)
    common = {"name", "type", "kind", "status", "origin"}
    for kind, attrs in written.items():
        missing = attrs - common - documented_attributes(kind)
        if kind == "intercept":
            missing -= documented_attributes("drive")
        assert not missing, (kind, sorted(missing))


def test_the_schema_type_written_against_the_contract_runs(capsys) -> None:  # type: ignore[no-untyped-def]
    import os
    import sys
    import types

    section = DOC.split("## Adding a schema type", 1)[1]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    module = types.ModuleType("docs_schemas_example")
    here = os.getcwd()
    os.chdir(ROOT)
    sys.modules[module.__name__] = module
    try:
        exec(compile(code, "docs/schemas.md", "exec"), module.__dict__)
    finally:
        os.chdir(here)
        del sys.modules[module.__name__]
    assert capsys.readouterr().out.strip() == "Strangers(frame=45, count=1)"
