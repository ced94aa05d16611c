"""Run every docstring example in the package (networkx / pymunk style)."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import adapt

MODULES = sorted(
    m.name
    for m in pkgutil.walk_packages(adapt.__path__, prefix="adapt.")
    if not m.name.endswith("__main__")
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name: str) -> None:
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} docstring example(s) failed in {name}"
