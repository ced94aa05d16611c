"""Schema types registered by name, like Soar SVS's filter and command tables.

:data:`REGISTRY` holds the built-in types (``scene-background``,
``foreground-object``, ``drive``, ``intercept``); :meth:`Registry.register` adds a user's
own, usually from a plugin (:mod:`adapt.plugins`).  Each name keeps where it came from
(:meth:`Registry.origin`); a name may be registered once, and a type is checked when it
is registered (:func:`check_spec`): its name, its ports and its parameters.
``adapt schemas list [--json]`` prints them with their ports, parameters and origins.

Examples
--------
>>> names = REGISTRY.names()
>>> "scene-background" in names and "drive" in names
True
>>> REGISTRY.get("scene-backgrund")
Traceback (most recent call last):
...
adapt.errors.SchemaError: unknown schema type 'scene-backgrund' (did you mean 'scene-background'?); expected one of drive, foreground-object, ...intercept, ...scene-background, search
"""

from __future__ import annotations

import difflib
import re
from typing import Iterator

from adapt.errors import SchemaError
from adapt.parameters import REQUIRED, Parameter, ParameterError
from adapt.plugins import builtin, current_origin, registered
from adapt.schemas.spec import Port, SchemaKind, SchemaSpec

__all__ = ["Registry", "REGISTRY", "check_spec", "RESERVED"]

#: Names of rules' words: letters, digits and '-', starting with a letter.
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9-]*\Z")

#: Attributes the network itself writes under every schema or reads from ``^instantiate``:
#: no parameter may be called so.
RESERVED = ("name", "type", "kind", "status", "origin", "message")


def check_spec(spec: SchemaSpec) -> None:
    """Raise :class:`SchemaError` for a malformed schema type: a bad name, a kind that is not a
    :class:`SchemaKind`, a factory that cannot be called, a port or parameter that is not one,
    has a bad or repeated name, or a parameter whose default does not fit it.

    Examples
    --------
    >>> from adapt.schemas.spec import Port
    >>> check_spec(SchemaSpec("keeper", SchemaKind.MOTOR, "", factory=print,
    ...                       consumes=(Port("my camera"),)))
    Traceback (most recent call last):
    ...
    adapt.errors.SchemaError: schema type 'keeper': port 'my camera': expected a name of letters, digits and '-'
    """
    where = f"schema type {spec.name!r}"
    if not isinstance(spec.name, str) or not _NAME.match(spec.name):
        raise SchemaError(f"schema type names are letters, digits and '-', got {spec.name!r}")
    if not isinstance(spec.kind, SchemaKind):
        raise SchemaError(f"{where}: kind {spec.kind!r}; expected SchemaKind.PERCEPTUAL or "
                          "SchemaKind.MOTOR")
    if not callable(spec.factory):
        raise SchemaError(f"{where}: factory {spec.factory!r} cannot be called; expected "
                          "factory(name, parameters, network) -> Schema")
    for label, ports in (("provides", spec.provides), ("consumes", spec.consumes)):
        if not isinstance(ports, tuple):
            raise SchemaError(f"{where}: {label} is {type(ports).__name__}; expected a tuple of Port")
        seen: set[str] = set()
        for port in ports:
            if not isinstance(port, Port):
                raise SchemaError(f"{where}: {label} holds {port!r}; expected Port(name, doc)")
            if not isinstance(port.name, str) or not _NAME.match(port.name):
                raise SchemaError(f"{where}: port {port.name!r}: expected a name of letters, "
                                  "digits and '-'")
            if port.name in seen:
                raise SchemaError(f"{where}: {label} port {port.name!r} twice")
            seen.add(port.name)
    names: set[str] = set()
    for p in spec.parameters:
        if not isinstance(p, Parameter):
            raise SchemaError(f"{where}: parameters hold {p!r}; expected Parameter(...)")
        if not _NAME.match(p.name) and not re.fullmatch(r"[a-z][a-z0-9_]*", p.name):
            raise SchemaError(f"{where}: parameter {p.name!r}: expected a name of letters, "
                              "digits, '-' or '_'")
        if p.name in names or p.name in RESERVED:
            raise SchemaError(f"{where}: parameter {p.name!r} "
                              + ("twice" if p.name in names else "is a name the network writes"))
        names.add(p.name)
        if p.kind not in (float, int, bool, str):
            raise SchemaError(f"{where}: parameter {p.name!r} is of type {p.kind!r}; expected "
                              "float, int, bool or str")
        if p.default is not REQUIRED and not (p.kind is str and p.default == ""):  # "": unset
            try:
                p.check(p.default)
            except ParameterError as exc:
                raise SchemaError(f"{where}: parameter {p.name!r} default {p.default!r}: "
                                  f"{exc}") from None


class Registry:
    """Schema types by name."""

    def __init__(self) -> None:
        self._types: dict[str, SchemaSpec] = {}
        self._origins: dict[str, str] = {}

    def register(self, spec: SchemaSpec) -> SchemaSpec:
        """Add a type (checked with :func:`check_spec`); a name may be registered once.  The
        type's origin is the plugin being imported, or ``built-in``
        (:func:`adapt.plugins.current_origin`)."""
        if not isinstance(spec, SchemaSpec):
            raise SchemaError(f"expected a SchemaSpec to register, got {spec!r}")
        if spec.name in self._types:
            raise SchemaError(f"schema type {spec.name!r} is already registered "
                              f"({self._origins[spec.name]})")
        check_spec(spec)
        self._types[spec.name] = spec
        self._origins[spec.name] = current_origin()
        registered(f"schema type {spec.name}", lambda: self.unregister(spec.name))
        return spec

    def unregister(self, name: str) -> None:
        """Take type ``name`` back (a plugin that failed half-way; a test's own type)."""
        self._types.pop(name, None)
        self._origins.pop(name, None)

    def origin(self, name: str) -> str:
        """Where type ``name`` came from: ``built-in`` or a plugin (``plugin keeper (keeper.py)``).

        >>> REGISTRY.origin("drive")
        'built-in'
        """
        self.get(name)
        return self._origins[name]

    def get(self, name: str) -> SchemaSpec:
        """The type called ``name``; an unknown name is a :class:`SchemaError` with a suggestion."""
        try:
            return self._types[name]
        except KeyError:
            close = difflib.get_close_matches(name, list(self._types), n=1, cutoff=0.6)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise SchemaError(f"unknown schema type {name!r}{hint}; expected one of "
                              + ", ".join(self.names())) from None

    def names(self) -> list[str]:
        """The registered names, sorted."""
        return sorted(self._types)

    def __iter__(self) -> Iterator[SchemaSpec]:
        return iter(self._types[n] for n in self.names())

    def __contains__(self, name: object) -> bool:
        return name in self._types

    def copy(self) -> "Registry":
        """A registry with the same types (to add a user's own without touching this one)."""
        out = Registry()
        out._types = dict(self._types)
        out._origins = dict(self._origins)
        return out


def _builtin() -> Registry:
    from adapt.schemas.background import SCENE_BACKGROUND
    from adapt.schemas.drive import DRIVE
    from adapt.schemas.foreground import FOREGROUND_OBJECT
    from adapt.schemas.intercept import INTERCEPT
    from adapt.schemas.search import SEARCH

    reg = Registry()
    with builtin():
        for spec in (SCENE_BACKGROUND, FOREGROUND_OBJECT, DRIVE, INTERCEPT, SEARCH):
            reg.register(spec)
    return reg


#: The built-in schema types.
REGISTRY = _builtin()
