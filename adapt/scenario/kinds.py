"""Reality kinds from plugins: a frame source with its own ``reality`` section.

The built-in kinds (``synthetic``, ``video``) are read by
:mod:`adapt.scenario.reality`.  A plugin adds a kind by registering a
:class:`RealityType` in :data:`REALITIES`: its name (``reality.kind``), its
parameters (the section's keys, each a :class:`~adapt.parameters.Parameter`
with a type, default, bounds and a line of documentation), which of them
name files, and ``open(reality, scenario, streams) -> FrameSource``.  The
scenario reader checks the section against the parameters like a built-in
section, with ``file:line:col`` and the key path; the runner calls ``open``
(:func:`adapt.reality.open_reality`).  The source it returns may have a
``robot`` (an :class:`~adapt.frames.Actuator`) and a ``truth``
(:class:`~adapt.reality.GroundTruth`) like the built-in ones.

Examples
--------
>>> from adapt.parameters import Parameter, REQUIRED
>>> kinds = RealityRegistry()
>>> _ = kinds.register(RealityType("replay", "frames of a log", open=print,
...                    parameters=(Parameter("log", str, REQUIRED, "the log file"),
...                                Parameter("fps", float, 30.0, "frame rate", low=0)),
...                    files=("log",)))
>>> kinds.names(), kinds.origin("replay"), REALITIES.origin("external")
(['replay'], 'built-in', 'built-in')
>>> kinds.get("replai")
Traceback (most recent call last):
...
adapt.errors.PluginError: unknown reality kind 'replai' (did you mean 'replay'?)
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass
from typing import Any, Callable, Iterator

from adapt.errors import PluginError, RealityError
from adapt.parameters import REQUIRED, Parameter, ParameterError
from adapt.plugins import builtin, current_origin, registered
from adapt.scenario.records import RealityKind

__all__ = ["RealityType", "RealityRegistry", "REALITIES", "BUILTIN_KINDS"]

#: The kinds the scenario reader knows itself.
BUILTIN_KINDS = tuple(k.value for k in RealityKind)


@dataclass(frozen=True, slots=True, eq=False)
class RealityType:
    """A reality kind (see the module docstring).

    Attributes
    ----------
    name : str
        ``reality.kind``.
    doc : str
        What its frames are, in a sentence.
    open : callable
        ``open(reality, scenario, streams) -> FrameSource``: ``reality`` is the checked
        :class:`~adapt.scenario.PluginReality`, ``streams`` the run's
        :class:`~adapt.seeds.Streams`.  It raises :class:`~adapt.errors.RealityError`
        (with ``reality.where(key).location``) for a source that cannot start.
    parameters : tuple of Parameter
        The section's keys besides ``kind``; a default of
        :data:`~adapt.parameters.REQUIRED` makes a key required.
    files : tuple of str
        The ``str`` parameters that name files: resolved relative to the scenario, required
        to exist, and inputs of the run (no output may replace them).
    like : RealityKind
        What the schemas may assume of its frames (``video``: a real camera's).
    """

    name: str
    doc: str
    open: Callable[..., Any]
    parameters: tuple[Parameter, ...] = ()
    files: tuple[str, ...] = ()
    like: RealityKind = RealityKind.VIDEO

    def parameter(self, name: str) -> Parameter:
        """The declaration of key ``name``."""
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    def as_json(self) -> dict[str, Any]:
        """The kind as JSON (``adapt plugins list --json``)."""
        return {"name": self.name, "doc": self.doc, "like": self.like.value,
                "files": list(self.files),
                "parameters": [{**p.as_json(), "required": p.default is REQUIRED,
                                "default": None if p.default is REQUIRED else p.default}
                               for p in self.parameters]}


def _check(rt: RealityType) -> None:
    where = f"reality kind {rt.name!r}"
    if not isinstance(rt.name, str) or not re.fullmatch(r"[a-z][a-z0-9-]*", rt.name):
        raise PluginError(f"reality kind names are lower-case letters, digits and '-', got "
                            f"{rt.name!r}")
    if not callable(rt.open):
        raise PluginError(f"{where}: open {rt.open!r} cannot be called; expected "
                            "open(reality, scenario, streams) -> FrameSource")
    if not isinstance(rt.like, RealityKind):
        raise PluginError(f"{where}: like {rt.like!r}; expected a RealityKind")
    names: set[str] = set()
    for p in rt.parameters:
        if not isinstance(p, Parameter):
            raise PluginError(f"{where}: parameters hold {p!r}; expected Parameter(...)")
        if p.name in names or p.name == "kind" or not re.fullmatch(r"[a-z][a-z0-9_]*", p.name):
            raise PluginError(f"{where}: parameter {p.name!r}: "
                                + ("given twice" if p.name in names else
                                   "'kind' is the section's own key" if p.name == "kind" else
                                   "expected a YAML key of lower-case letters, digits and '_'"))
        names.add(p.name)
        if p.kind not in (float, int, bool, str):
            raise PluginError(f"{where}: parameter {p.name!r} is of type {p.kind!r}; expected "
                                "float, int, bool or str")
        if p.default is not REQUIRED and not (p.kind is str and p.default == ""):
            try:
                p.check(p.default)
            except ParameterError as exc:
                raise PluginError(f"{where}: parameter {p.name!r} default {p.default!r}: "
                                    f"{exc}") from None
    for f in rt.files:
        if f not in names or rt.parameter(f).kind is not str:
            raise PluginError(f"{where}: files names {f!r}; expected one of its str parameters")


class RealityRegistry:
    """Reality kinds by name, each with where it came from."""

    def __init__(self) -> None:
        self._types: dict[str, RealityType] = {}
        self._origins: dict[str, str] = {}

    def register(self, rt: RealityType) -> RealityType:
        """Add a kind (checked); a name may be registered once and may not be a built-in one.

        Raises
        ------
        PluginError
            A name that is taken, or a malformed kind.
        """
        if not isinstance(rt, RealityType):
            raise PluginError(f"expected a RealityType to register, got {rt!r}")
        if rt.name in BUILTIN_KINDS or rt.name in self._types:
            taken = "built-in" if rt.name in BUILTIN_KINDS else self._origins[rt.name]
            raise PluginError(f"reality kind {rt.name!r} is already registered ({taken})")
        _check(rt)
        self._types[rt.name] = rt
        self._origins[rt.name] = current_origin()
        registered(f"reality kind {rt.name}", lambda: self.unregister(rt.name))
        return rt

    def unregister(self, name: str) -> None:
        """Take kind ``name`` back."""
        self._types.pop(name, None)
        self._origins.pop(name, None)

    def get(self, name: str) -> RealityType:
        """The kind called ``name``."""
        try:
            return self._types[name]
        except KeyError:
            close = difflib.get_close_matches(name, [*BUILTIN_KINDS, *self._types], n=1,
                                              cutoff=0.6)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise PluginError(f"unknown reality kind {name!r}{hint}") from None

    def origin(self, name: str) -> str:
        """Where kind ``name`` came from."""
        self.get(name)
        return self._origins[name]

    def names(self) -> list[str]:
        """The registered names, sorted (the built-in ones are not here)."""
        return sorted(self._types)

    def __iter__(self) -> Iterator[RealityType]:
        return iter(self._types[n] for n in self.names())

    def __contains__(self, name: object) -> bool:
        return name in self._types


def _external(reality: Any, scenario: Any, streams: Any) -> Any:
    raise RealityError("its frames come from Python: adapt.run(scenario, source=...), "
                       "adapt.start(scenario, source=...) or Runner(scenario, source=...)")


#: The reality kinds plugins registered, and ``external``: frames a Python caller gives
#: (``adapt.run(..., source=...)``), for a scenario whose objects appear when seen.
REALITIES = RealityRegistry()
with builtin():
    REALITIES.register(RealityType(
        "external", "frames given from Python: adapt.run(scenario, source=...)", open=_external))
