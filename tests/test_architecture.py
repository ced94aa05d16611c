"""Import direction between the layers, checked on the source with ``ast``.

The engine imports only the standard library (and ``adapt.errors``); vision and
imagination know nothing of rules; nothing below the CLI imports the CLI.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "adapt"

STDLIB = set(sys.stdlib_module_names)


def imports_of(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module)
    return found


def modules_in(subpackage: str) -> list[Path]:
    return sorted((PACKAGE / subpackage).rglob("*.py"))


@pytest.mark.parametrize("path", modules_in("engine"), ids=lambda p: p.name)
def test_engine_imports_only_stdlib_and_errors(path: Path) -> None:
    for name in imports_of(path):
        top = name.split(".")[0]
        if top == "adapt":
            assert name == "adapt.errors" or name.startswith("adapt.engine"), (
                f"{path.name} imports {name}: the engine may import only adapt.errors"
            )
        else:
            assert top in STDLIB or top == "__future__", (
                f"{path.name} imports {name}: the engine imports only the standard library"
            )


@pytest.mark.parametrize(
    "sub", ["vision", "imagination"],
)
def test_vision_and_imagination_know_nothing_of_rules(sub: str) -> None:
    for path in modules_in(sub):
        for name in imports_of(path):
            assert not name.startswith(("adapt.engine", "adapt.cli", "adapt.traceview")), (
                f"{sub}/{path.name} imports {name}"
            )
            other = "imagination" if sub == "vision" else "vision"
            assert not name.startswith(f"adapt.{other}"), f"{sub}/{path.name} imports {name}"


def test_nothing_imports_the_cli() -> None:
    for path in PACKAGE.rglob("*.py"):
        if "cli" in path.relative_to(PACKAGE).parts or path.name == "__main__.py":
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.cli"), f"{path} imports {name}"


def test_geometry_errors_and_files_are_leaves() -> None:
    for leaf, allowed in (("errors.py", set()), ("files.py", set()),
                          ("geometry.py", {"numpy", "adapt.errors"})):
        for name in imports_of(PACKAGE / leaf):
            top = name.split(".")[0]
            assert top in STDLIB or top == "__future__" or name in allowed or top in allowed, (
                f"{leaf} imports {name}"
            )


@pytest.mark.parametrize("path", modules_in("figures"), ids=lambda p: p.name)
def test_figures_draw_without_knowing_the_layers(path: Path) -> None:
    # figures: NumPy, matplotlib, adapt.files and adapt.errors only, so any layer's command may draw
    for name in imports_of(path):
        top = name.split(".")[0]
        if top == "adapt":
            assert name in ("adapt.files", "adapt.errors") or name.startswith("adapt.figures"), (
                f"figures/{path.name} imports {name}"
            )
        else:
            assert top in STDLIB or top in ("__future__", "numpy", "matplotlib"), (
                f"figures/{path.name} imports {name}"
            )


def test_vision_does_not_draw_figures() -> None:
    for path in modules_in("vision"):
        for name in imports_of(path):
            assert not name.startswith(("adapt.figures", "matplotlib")), f"vision/{path.name} imports {name}"
