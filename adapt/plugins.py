"""Plugins: code outside adapt that registers schema types and reality kinds.

A plugin is a Python module.  Importing it registers what it adds -- with
:meth:`adapt.schemas.Registry.register` (a schema type) or
:meth:`adapt.scenario.RealityRegistry.register` (a reality kind) -- the way a
pytest plugin or a gymnasium environment registers itself.  adapt finds
plugins in three places:

* **installed**: the entry-point groups ``adapt.schemas`` and
  ``adapt.realities`` (:data:`ENTRY_POINT_GROUPS`) of any installed
  distribution; each entry point names a module (imported) or a function
  ``module:register`` (imported, then called with no arguments).  They are
  loaded once, before the first scenario is read (:func:`load_installed`);
* **named by a scenario**: its ``plugins:`` key lists module names or
  ``.py`` files relative to the scenario, imported before the rest of the
  scenario is read;
* **named from Python**: ``adapt.run(..., plugins=[...])`` and
  :func:`load_plugin`.

Each plugin is imported once per process (a second scenario naming it reuses
it), with its **origin** set (:func:`registering`), so every registry records
where each of its names came from (``adapt schemas list``, ``adapt plugins
list``).  A plugin that cannot be found, raises on import or registers a name
that is taken is a :class:`~adapt.errors.PluginError` naming the plugin and
what went wrong, never a traceback, and whatever it registered before it
failed is taken back.

This module imports only the standard library and :mod:`adapt.errors`, so
every layer may ask where something came from.

Examples
--------
>>> current_origin()
'built-in'
>>> with registering("plugin demo (demo.py)"):
...     current_origin()
'plugin demo (demo.py)'
>>> load_plugin("no_such_adapt_plugin")
Traceback (most recent call last):
...
adapt.errors.PluginError: plugin 'no_such_adapt_plugin': no module named 'no_such_adapt_plugin'; expected a module on the Python path or a .py file
"""

from __future__ import annotations

import contextlib
import enum
import hashlib
import importlib
import importlib.metadata
import importlib.util
import sys
from contextvars import ContextVar
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Callable, Iterator

from adapt.errors import AdaptError, PluginError

__all__ = ["ENTRY_POINT_GROUPS", "BUILTIN", "PluginFrom", "Plugin", "current_origin",
           "registering", "registered", "builtin", "load_plugin", "load_installed", "loaded_plugins",
           "is_file_reference"]

#: The entry-point groups adapt reads: schema types, reality kinds.
ENTRY_POINT_GROUPS = ("adapt.schemas", "adapt.realities")

#: The origin of what adapt itself registers.
BUILTIN = "built-in"

_origin: ContextVar[str] = ContextVar("adapt_plugin_origin", default=BUILTIN)
_undo: ContextVar["list[tuple[str, Callable[[], None]]] | None"] = ContextVar(
    "adapt_plugin_undo", default=None)


class PluginFrom(enum.Enum):
    """How a plugin was found."""

    ENTRY_POINT = "entry-point"   # an installed distribution's entry point
    SCENARIO = "scenario"         # a scenario's ``plugins:`` key
    PYTHON = "python"             # ``adapt.run(plugins=...)`` or :func:`load_plugin`


@dataclass(frozen=True, slots=True)
class Plugin:
    """A loaded plugin.

    Attributes
    ----------
    name : str
        As it was named (a module name, a ``.py`` path, an entry point's name).
    found : PluginFrom
    module : str
        The imported module's name.
    file : str or None
        The module's file.
    origin : str
        The label every name it registered carries (``plugin keeper (keeper.py)``).
    registered : tuple of str
        What it registered (``schema type goal-keeper``, ``reality kind replay``).
    """

    name: str
    found: PluginFrom
    module: str
    file: str | None
    origin: str
    registered: tuple[str, ...] = ()

    def as_json(self) -> dict[str, object]:
        """The plugin as JSON (``adapt plugins list --json``)."""
        return {"name": self.name, "found": self.found.value, "module": self.module,
                "file": self.file, "origin": self.origin, "registered": list(self.registered)}


_loaded: dict[str, Plugin] = {}
_installed_done = False


def current_origin() -> str:
    """Where what is being registered now comes from: :data:`BUILTIN`, or the origin of the
    plugin being imported."""
    return _origin.get()


@contextlib.contextmanager
def registering(origin: str) -> Iterator[list[tuple[str, Callable[[], None]]]]:
    """Registrations inside this block come from ``origin``; yields the list of what they
    registered (``(what, undo)`` pairs, filled by :func:`registered`)."""
    done: list[tuple[str, Callable[[], None]]] = []
    t1 = _origin.set(origin)
    t2 = _undo.set(done)
    try:
        yield done
    finally:
        _origin.reset(t1)
        _undo.reset(t2)


@contextlib.contextmanager
def builtin() -> Iterator[None]:
    """Registrations inside this block are adapt's own, even while a plugin is being imported
    (a plugin's ``import adapt.schemas`` registers the built-in types)."""
    t1 = _origin.set(BUILTIN)
    t2 = _undo.set(None)
    try:
        yield
    finally:
        _origin.reset(t1)
        _undo.reset(t2)


def registered(what: str, undo: Callable[[], None]) -> None:
    """A registry says it registered ``what`` (``schema type goal-keeper``); ``undo`` takes it
    back if the plugin doing it fails.  Outside a plugin's import this does nothing."""
    done = _undo.get()
    if done is not None:
        done.append((what, undo))


def is_file_reference(name: str) -> bool:
    """Whether a plugin name is a file (``keeper.py``, ``lib/keeper.py``) rather than a
    module name.

    >>> is_file_reference("keeper.py"), is_file_reference("adapt_keeper.schemas")
    (True, False)
    """
    return name.endswith(".py") or "/" in name or "\\" in name


def load_plugin(name: str, *, base: str | Path | None = None,
                found: PluginFrom = PluginFrom.PYTHON) -> Plugin:
    """Import plugin ``name`` (a module name, or a ``.py`` file relative to ``base``), once.

    A module name is looked up on the Python path, then in ``base`` (a scenario's folder).

    Raises
    ------
    PluginError
        The module or file is missing, it raised on import (its message, not the
        traceback), or it registered a name that is taken.
    """
    folder = Path.cwd() if base is None else Path(base)
    if is_file_reference(name):
        path = (folder / name).resolve()
        key = f"file:{path}"
        if key in _loaded:
            return _loaded[key]
        if not path.is_file():
            raise PluginError(f"plugin {name!r}: no such file {str(path)!r}; expected a .py file "
                              "(relative to the scenario)")
        digest = hashlib.sha1(str(path).encode()).hexdigest()[:8]
        module_name = f"adapt_plugin_{path.stem}_{digest}"
        origin = f"plugin {path.stem} ({name})"
        plugin = _import(name, found, origin, lambda: _import_file(module_name, path))
    else:
        key = f"module:{name}"
        if key in _loaded:
            return _loaded[key]
        plugin = _import(name, found, f"plugin {name}", lambda: _import_module(name, folder))
    _loaded[key] = plugin
    return plugin


def _import(name: str, found: PluginFrom, origin: str,
            do: Callable[[], ModuleType]) -> Plugin:
    with registering(origin) as done:
        try:
            module = do()
        except ModuleNotFoundError as exc:
            _take_back(done)
            if exc.name == name or (exc.name and name.startswith(exc.name + ".")):
                raise PluginError(f"plugin {name!r}: no module named {exc.name!r}; expected a "
                                  "module on the Python path or a .py file") from None
            raise PluginError(f"plugin {name!r} failed on import: {exc}") from None
        except SyntaxError as exc:
            _take_back(done)
            raise PluginError(f"plugin {name!r} failed on import: {exc.msg} "
                              f"({exc.filename}:{exc.lineno}:{exc.offset or 1})") from None
        except Exception as exc:  # its message, not a traceback: the plugin is not ours
            _take_back(done)
            raise PluginError(f"plugin {name!r} failed on import: {_says(exc)}") from None
    return Plugin(name, found, module.__name__, getattr(module, "__file__", None), origin,
                  tuple(what for what, _ in done))


def _says(exc: BaseException) -> str:
    text = str(exc)
    if isinstance(exc, AdaptError):  # adapt's own message says it all (a taken name)
        return text
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def _take_back(done: list[tuple[str, Callable[[], None]]]) -> None:
    for _, undo in reversed(done):
        undo()
    done.clear()


def _import_module(name: str, folder: Path) -> ModuleType:
    if name in sys.modules:  # imported before (by the user, or as another plugin's part)
        return importlib.import_module(name)
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name != name.split(".")[0] or not folder.is_dir():
            raise
    sys.path.insert(0, str(folder))  # a module next to the scenario
    try:
        return importlib.import_module(name)
    finally:
        with contextlib.suppress(ValueError):
            sys.path.remove(str(folder))


def _import_file(module_name: str, path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise ImportError("cannot be imported; expected a .py file")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module  # by name, so that Dask and pickle find its functions
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(module_name, None)
        raise
    return module


def load_installed() -> tuple[Plugin, ...]:
    """Load every installed plugin (:data:`ENTRY_POINT_GROUPS`), once per process; returns
    those loaded now or before.

    Raises
    ------
    PluginError
        An entry point that cannot be loaded or raises, naming it and its distribution.
    """
    global _installed_done
    if not _installed_done:
        _installed_done = True
        for group in ENTRY_POINT_GROUPS:
            for ep in sorted(importlib.metadata.entry_points(group=group), key=lambda e: e.name):
                _load_entry_point(ep, group)
    return tuple(p for p in _loaded.values() if p.found is PluginFrom.ENTRY_POINT)


def _load_entry_point(ep: importlib.metadata.EntryPoint, group: str) -> None:
    key = f"entry-point:{group}:{ep.name}:{ep.value}"
    if key in _loaded:
        return
    dist = getattr(ep, "dist", None)
    label = f"{dist.name} {dist.version}" if dist is not None else ep.value
    name = f"{ep.name} ({group} of {label})"

    def do() -> ModuleType:
        module_name = ep.value.split(":")[0].strip()
        module = importlib.import_module(module_name)
        target = ep.load()
        if not isinstance(target, ModuleType):
            if not callable(target):
                raise TypeError(f"entry point {ep.value!r} is neither a module nor a function")
            target()
        return module

    _loaded[key] = _import(name, PluginFrom.ENTRY_POINT, f"installed {ep.name} ({label})", do)


def loaded_plugins() -> tuple[Plugin, ...]:
    """Every plugin loaded so far, in the order they were loaded."""
    return tuple(_loaded.values())
