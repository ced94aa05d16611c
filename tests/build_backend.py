"""adapt's PEP 517 build backend: setuptools, plus the engine compiled with mypyc.

``pyproject.toml`` names this module as its build backend (``backend-path``
puts ``tests/`` on the path of the build only).  It is setuptools'
``build_meta`` with one change: when a wheel is built (``pip install .`` or
``pip install -e .``), the engine modules listed in
``adapt.engine.compiled.COMPILED_MODULES`` are compiled with mypyc from the
same source files, and installed beside them.

The compiled build is optional, all or nothing:

* with ``ADAPT_PURE_PYTHON=1`` in the environment of the install, nothing is
  compiled;
* where no C compiler is found, or mypyc cannot be imported, nothing is
  compiled;
* where the compilation or the link fails, a warning is printed, whatever
  was built is removed, and the install goes on with the pure-Python engine.

``python -m adapt rules info`` says which engine an installation runs.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import sys
import sysconfig
from pathlib import Path
from typing import Any

from setuptools import build_meta as _meta
from setuptools.command.build_ext import build_ext

__all__ = [
    "get_requires_for_build_wheel",
    "get_requires_for_build_sdist",
    "get_requires_for_build_editable",
    "prepare_metadata_for_build_wheel",
    "prepare_metadata_for_build_editable",
    "build_wheel",
    "build_sdist",
    "build_editable",
]

ROOT = Path(__file__).resolve().parents[1]
#: setup.py commands that build extensions (metadata commands need none)
_BUILDS = {"bdist_wheel", "editable_wheel", "build_ext", "build", "install"}


def _say(text: str) -> None:
    print(f"adapt build: {text}", file=sys.stderr, flush=True)


def _compiled_modules() -> tuple[str, ...]:
    """``adapt.engine.compiled.COMPILED_MODULES``, loaded from its file alone
    (it imports only the standard library; the package is not importable yet)."""
    path = ROOT / "adapt" / "engine" / "compiled.py"
    spec = importlib.util.spec_from_file_location("_adapt_engine_compiled", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return tuple(module.COMPILED_MODULES)


def _compiler_present() -> bool:
    cc = (os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc").split()
    return bool(cc) and shutil.which(cc[0]) is not None


def _extensions() -> list[Any]:
    """The mypyc extensions of the engine, or ``[]`` for a pure-Python build."""
    if os.environ.get("ADAPT_PURE_PYTHON", "") not in ("", "0"):
        _say("ADAPT_PURE_PYTHON is set: the engine stays pure Python")
        return []
    if not _compiler_present():
        _say("no C compiler found: the engine stays pure Python")
        return []
    try:
        from mypyc.build import mypycify
    except ImportError as exc:
        _say(f"mypyc is not available ({exc}): the engine stays pure Python")
        return []
    paths = [str(Path(*m.split(".")).with_suffix(".py")) for m in _compiled_modules()]
    _say(f"compiling {len(paths)} engine modules with mypyc (about a minute)")
    try:
        # the shared library is adapt/engine/native__mypyc.*.so, beside the modules
        # errors only in the engine: ``import adapt`` names the whole public API for type
        # checkers, and the isolated build environment has no stubs for OpenCV and the rest
        return list(mypycify([*paths, "--follow-imports=silent"], opt_level="3",
                             debug_level="0", group_name="adapt.engine.native"))
    except Exception as exc:  # mypy found a type error, or mypyc could not translate
        _say(f"mypyc failed ({type(exc).__name__}: {exc}): the engine stays pure Python")
        return []


class OptionalBuildExt(build_ext):
    """``build_ext`` that falls back to the pure-Python engine when compiling fails."""

    def run(self) -> None:
        try:
            super().run()
        except Exception as exc:  # noqa: BLE001  (a compiler or linker error of any kind)
            for output in self.get_outputs():
                Path(output).unlink(missing_ok=True)
            _say(f"compiling the engine failed ({type(exc).__name__}: {exc}); "
                 "the engine stays pure Python")


class _Backend(_meta._BuildMetaBackend):
    """setuptools' backend, with ``setup()`` called here instead of from a setup.py."""

    def run_setup(self, setup_script: str = "setup.py") -> None:
        from setuptools import setup

        building = bool(_BUILDS & set(sys.argv[1:]))
        setup(ext_modules=_extensions() if building else [],
              cmdclass={"build_ext": OptionalBuildExt})


_BACKEND = _Backend()
get_requires_for_build_wheel = _BACKEND.get_requires_for_build_wheel
get_requires_for_build_sdist = _BACKEND.get_requires_for_build_sdist
get_requires_for_build_editable = _BACKEND.get_requires_for_build_editable
prepare_metadata_for_build_wheel = _BACKEND.prepare_metadata_for_build_wheel
prepare_metadata_for_build_editable = _BACKEND.prepare_metadata_for_build_editable
build_wheel = _BACKEND.build_wheel
build_sdist = _BACKEND.build_sdist
build_editable = _BACKEND.build_editable
