"""The compiled build and the pure-Python fallback run the same source.

``adapt.engine.compiled`` decides at import time whether the mypyc-compiled
extensions (built by ``tests/build_backend.py`` at install) or the source
files run; ``ADAPT_PURE_PYTHON=1`` forces the source.  CI runs the whole
suite on the compiled build and the engine tests again with the variable
set.
"""

from __future__ import annotations

import importlib.machinery
import os
import subprocess
import sys
from pathlib import Path

import pytest

from adapt.cli import main
from adapt.engine import compiled, engine_build

ROOT = Path(__file__).resolve().parents[2]


def _extensions_present() -> list[str]:
    return [m for m in compiled.COMPILED_MODULES if compiled._extension_of(m) is not None]


def _in_child(code: str, **env: str) -> str:
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            cwd=ROOT, env={**os.environ, **env}, check=True)
    return result.stdout.strip()


def test_every_compiled_module_is_engine_source() -> None:
    for module in compiled.COMPILED_MODULES:
        path = ROOT.joinpath(*module.split(".")).with_suffix(".py")
        assert path.is_file(), module
    # the modules that cannot be compiled stay out of the list
    assert "adapt.engine.floats" not in compiled.COMPILED_MODULES
    assert "adapt.engine.compiled" not in compiled.COMPILED_MODULES


def test_pure_python_is_forced_by_the_environment() -> None:
    out = _in_child("import adapt.engine as e, adapt.engine.kernel as k, adapt.engine.rete.join as j;"
                    "print(e.engine_build()); print(k.__file__); print(j.__file__)",
                    ADAPT_PURE_PYTHON="1")
    build, kernel, join = out.splitlines()
    assert build == "pure Python (ADAPT_PURE_PYTHON is set)"
    assert kernel.endswith("kernel.py") and join.endswith("join.py")


def test_the_build_in_use_is_the_one_installed() -> None:
    """With extensions beside the source (a compiled install), they run, unless forced off."""
    present = _extensions_present()
    forced = os.environ.get("ADAPT_PURE_PYTHON", "") not in ("", "0")
    if forced:
        assert engine_build() == "pure Python (ADAPT_PURE_PYTHON is set)"
    elif present and not compiled._stale():
        assert sorted(present) == sorted(compiled.COMPILED_MODULES)
        assert compiled.is_compiled() and engine_build() == "compiled (mypyc)"
        from adapt.engine import kernel

        assert kernel.__file__.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES))
    elif present:
        assert engine_build() == "pure Python (the compiled modules are older than their source)"
    else:
        assert engine_build() == "pure Python (not compiled)"


def test_the_compiled_build_when_it_is_required() -> None:
    """``ADAPT_REQUIRE_COMPILED=1`` (the README's test command, so CI): the run must test the
    compiled engine, not a silent pure-Python fallback of the install."""
    if os.environ.get("ADAPT_REQUIRE_COMPILED", "") in ("", "0"):
        pytest.skip("ADAPT_REQUIRE_COMPILED is not set")
    assert engine_build() == "compiled (mypyc)", (
        f"the engine under test is {engine_build()}: the install did not compile it "
        "(see the 'adapt build:' lines of pip install -v)")


def test_rules_info_names_the_engine(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["rules", "info"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("adapt ") and f"engine: {engine_build()}" in out
