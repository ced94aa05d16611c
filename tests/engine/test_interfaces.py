"""The engine's modules use each other through public, typed names only.

No ``_private`` name is imported across modules, no module reaches into
another object's ``_private`` attribute, and nothing probes for an
attribute with ``getattr`` / ``hasattr`` (a fast path is a typed interface,
such as :class:`adapt.engine.matcher.RawMatcher`).
"""

from __future__ import annotations

import ast
from pathlib import Path

ENGINE = Path(__file__).resolve().parents[2] / "adapt" / "engine"
TRACEVIEW = ENGINE.parent / "traceview"
SOURCES = sorted(ENGINE.rglob("*.py")) + sorted(TRACEVIEW.rglob("*.py"))


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def test_no_private_name_is_imported_across_modules() -> None:
    found = []
    for path in SOURCES:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("adapt"):
                found += [f"{path.name}: {node.module}.{a.name}" for a in node.names
                          if _private(a.name)]
    assert not found


def test_no_private_attribute_of_another_object() -> None:
    found = []
    for path in SOURCES:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (isinstance(node, ast.Attribute) and _private(node.attr)
                    and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))):
                found.append(f"{path.name}:{node.lineno}: .{node.attr}")
    # the agent's own RHS context reaches into the agent of its module: allowed
    found = [f for f in found if not f.startswith("agent.py:")]
    assert not found


def test_no_attribute_probing_in_the_engine() -> None:
    found = []
    for path in sorted(ENGINE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                    and node.func.id in ("getattr", "hasattr")):
                found.append(f"{path.name}:{node.lineno}: {node.func.id}")
    assert not found
