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


def _module_of(path: Path) -> list[str]:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return parts


def imports_of(path: Path, source: str | None = None) -> set[str]:
    """Absolute names of every module ``path`` imports, relative imports resolved."""
    text = path.read_text(encoding="utf-8") if source is None else source
    tree = ast.parse(text, filename=str(path))
    found: set[str] = set()
    here = _module_of(path)
    package = here if path.name == "__init__.py" else here[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                if node.module:
                    found.add(node.module)
                continue
            base = package[: len(package) - (node.level - 1)]
            if node.module:
                found.add(".".join([*base, node.module]))
            else:
                found.update(".".join([*base, alias.name]) for alias in node.names)
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
    for leaf, allowed in (("errors.py", set()), ("files.py", {"adapt.errors"}), ("native.py", set()),
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


#: What each layer above the foundations may import from adapt (prefixes).
ALLOWED = {
    # the mirror (the imagination kept in step, and the appearance it learns): no vision, no rules
    "mirror": ("adapt.mirror", "adapt.imagination", "adapt.geometry", "adapt.errors",
               "adapt.files", "adapt.native"),
    "kalman.py": (),
    "seeds.py": (),
    "frames.py": ("adapt.errors", "adapt.files"),
    "scenario": ("adapt.scenario", "adapt.imagination", "adapt.geometry", "adapt.errors",
                 "adapt.files"),
    "schemas": ("adapt.schemas", "adapt.engine", "adapt.vision", "adapt.imagination",
                "adapt.mirror", "adapt.geometry", "adapt.errors", "adapt.kalman",
                "adapt.frames", "adapt.scenario"),
    # reality: never the engine or vision (it is what perception looks at, not a perceiver)
    "reality": ("adapt.reality", "adapt.imagination", "adapt.scenario", "adapt.geometry",
                "adapt.errors", "adapt.files", "adapt.frames", "adapt.seeds", "adapt.native"),
    # sweep: runs the runner; checks a grid with the scenario reader, the schema registry's
    # check_settings and the rule parser before running it
    "sweep": ("adapt.sweep", "adapt.runner", "adapt.scenario", "adapt.schemas",
              "adapt.engine.parse", "adapt.engine.functions", "adapt.errors", "adapt.files"),
}


@pytest.mark.parametrize("layer", sorted(ALLOWED))
def test_layers_import_only_what_is_below_them(layer: str) -> None:
    target = PACKAGE / layer
    paths = [target] if target.is_file() else modules_in(layer)
    for path in paths:
        for name in imports_of(path):
            if name.split(".")[0] != "adapt" or name == "adapt":  # the version only
                continue
            assert name.startswith(ALLOWED[layer]), f"{layer}: {path.name} imports {name}"


PERCEIVING = ("engine", "vision", "imagination", "schemas", "mirror", "kalman.py")


@pytest.mark.parametrize("layer", PERCEIVING)
def test_nothing_that_perceives_can_reach_ground_truth(layer: str) -> None:
    target = PACKAGE / layer
    paths = [target] if target.is_file() else modules_in(layer)
    for path in paths:
        for name in imports_of(path):
            assert not name.startswith(("adapt.reality", "adapt.runner")), (
                f"{path} imports {name}: the perceiving side never sees the reality's truth"
            )
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            word = node.attr if isinstance(node, ast.Attribute) else (
                node.id if isinstance(node, ast.Name) else None)
            assert word not in ("truth", "ground_truth"), f"{path} reads {word}"


def test_only_the_runner_and_the_cli_open_the_reality() -> None:
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).parts
        if parts[0] in ("runner", "cli", "reality"):
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.reality"), f"{path} imports {name}"
            if parts[0] == "sweep":  # a sweep runs whole runs: the runner, never the reality
                continue
            assert not name.startswith("adapt.runner"), f"{path} imports {name}"


def test_only_the_cli_imports_the_sweep() -> None:
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).parts
        if parts[0] in ("sweep", "cli"):
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.sweep"), f"{path} imports {name}"


def test_the_sweep_imports_dask_only_inside_functions() -> None:
    # `import adapt.sweep` works without the optional extra; the command says how to install it
    for path in modules_in("sweep"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] if isinstance(node, ast.Import) else [
                    node.module or ""]
                assert not any(n.split(".")[0] in ("dask", "distributed") for n in names), (
                    f"sweep/{path.name} imports Dask at module level")


def test_relative_imports_are_resolved() -> None:
    path = PACKAGE / "schemas" / "network.py"
    found = imports_of(path, "from . import links\nfrom .base import Schema\nfrom ..engine import Agent\n")
    assert found == {"adapt.schemas.links", "adapt.schemas.base", "adapt.engine"}
    init = PACKAGE / "schemas" / "__init__.py"
    assert imports_of(init, "from .network import X\n") == {"adapt.schemas.network"}
