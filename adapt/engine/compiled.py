"""Which engine is running: the modules compiled with mypyc, or their Python source.

The engine's source is pure, standard-library Python.  The same files may
also be compiled with mypyc when adapt is installed where a C compiler is
present (``tests/build_backend.py``, the project's build backend, does it);
the compiled modules are C extensions beside their sources, and Python
imports an extension before a source file of the same name.  Where no
compiler is found, or the compilation fails, installing still works and the
engine runs from source.

The source is used instead of the extensions when

* the environment variable ``ADAPT_PURE_PYTHON`` is set to anything but
  ``""`` or ``"0"`` when the engine is first imported (CI runs the engine
  tests this way too), or
* an extension is older than its source file: the source was edited after
  the build (an editable install), so the extension would run stale code.
  Reinstall (``pip install -e .``) to compile again.

:func:`engine_build` says which engine is in use (``adapt rules info``).

Examples
--------
>>> engine_build() in ("compiled (mypyc)", "pure Python (not compiled)",
...                    "pure Python (ADAPT_PURE_PYTHON is set)",
...                    "pure Python (the compiled modules are older than their source)")
True
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import os
import sys
from collections.abc import Sequence
from types import ModuleType

__all__ = ["COMPILED_MODULES", "engine_build", "is_compiled", "prefer_source"]

#: The engine modules the build compiles (the hot paths of matching, firing and
#: the decision cycle, and the rule parser).  The others stay Python: they
#: subclass built-in types (``floats``), are protocols (``matcher``), or are
#: not on a hot path.
COMPILED_MODULES: tuple[str, ...] = (
    "adapt.engine.agent",
    "adapt.engine.conditions",
    "adapt.engine.cycle",
    "adapt.engine.events",
    "adapt.engine.functions",
    "adapt.engine.goals",
    "adapt.engine.instantiation",
    "adapt.engine.io",
    "adapt.engine.kernel",
    "adapt.engine.lexer",
    "adapt.engine.memory",
    "adapt.engine.parse",
    "adapt.engine.preferences",
    "adapt.engine.production",
    "adapt.engine.results",
    "adapt.engine.support",
    "adapt.engine.symbols",
    "adapt.engine.rete.alpha",
    "adapt.engine.rete.build",
    "adapt.engine.rete.join",
    "adapt.engine.rete.ncc",
    "adapt.engine.rete.negative",
    "adapt.engine.rete.network",
    "adapt.engine.rete.pnode",
    "adapt.engine.rete.state",
    "adapt.engine.rete.token",
)

_ENGINE = os.path.dirname(os.path.abspath(__file__))
_PREFIX = "adapt.engine."


def _extension_of(module: str) -> str | None:
    """The path of ``module``'s compiled extension, if there is one."""
    base = os.path.join(os.path.dirname(_ENGINE), *module.split(".")[1:])
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        if os.path.exists(base + suffix):
            return base + suffix
    return None


def _stale() -> bool:
    """Whether some extension is older than its source file."""
    for module in COMPILED_MODULES:
        extension = _extension_of(module)
        if extension is None:
            continue
        source = os.path.join(os.path.dirname(_ENGINE), *module.split(".")[1:]) + ".py"
        if os.path.exists(source) and os.path.getmtime(source) > os.path.getmtime(extension):
            return True
    return False


def _forced() -> bool:
    return os.environ.get("ADAPT_PURE_PYTHON", "") not in ("", "0")


class _SourceOnly(importlib.abc.MetaPathFinder):
    """A meta path finder that finds ``adapt.engine.*`` modules as source files only."""

    def find_spec(self, fullname: str, path: Sequence[str] | None,
                  target: ModuleType | None = None) -> importlib.machinery.ModuleSpec | None:
        if not fullname.startswith(_PREFIX) or path is None:
            return None
        for entry in path:
            finder = importlib.machinery.FileFinder(
                entry, (importlib.machinery.SourceFileLoader,
                        importlib.machinery.SOURCE_SUFFIXES))
            spec = finder.find_spec(fullname)
            if spec is not None:
                return spec
        return None


_REASON: str | None = None


def prefer_source() -> None:
    """Import the engine from source when it must be (see the module docstring).

    Called once by :mod:`adapt.engine` before it imports anything else.
    """
    global _REASON
    if any(isinstance(f, _SourceOnly) for f in sys.meta_path):
        return
    if _forced():
        _REASON = "ADAPT_PURE_PYTHON is set"
    elif _stale():
        _REASON = "the compiled modules are older than their source"
    else:
        return
    sys.meta_path.insert(0, _SourceOnly())


def is_compiled() -> bool:
    """Whether the running engine's modules are the compiled ones."""
    from adapt.engine import kernel

    file = kernel.__file__ or ""
    return file.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES))


def engine_build() -> str:
    """Which engine is in use, in words."""
    if is_compiled():
        return "compiled (mypyc)"
    if _REASON is not None:
        return f"pure Python ({_REASON})"
    return "pure Python (not compiled)"
