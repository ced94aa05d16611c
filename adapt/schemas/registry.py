"""Schema types registered by name, like Soar SVS's filter and command tables.

:data:`REGISTRY` holds the built-in types (``scene-background``,
``foreground-object``, ``drive``, ``intercept``); :meth:`Registry.register` adds a user's
own.  ``adapt schemas list [--json]`` prints them with their ports and
parameters.

Examples
--------
>>> names = REGISTRY.names()
>>> "scene-background" in names and "drive" in names
True
>>> REGISTRY.get("scene-backgrund")
Traceback (most recent call last):
...
adapt.errors.SchemaError: unknown schema type 'scene-backgrund' (did you mean 'scene-background'?); expected one of drive, foreground-object, intercept, scene-background
"""

from __future__ import annotations

import difflib
from typing import Iterator

from adapt.errors import SchemaError
from adapt.schemas.spec import SchemaSpec

__all__ = ["Registry", "REGISTRY"]


class Registry:
    """Schema types by name."""

    def __init__(self) -> None:
        self._types: dict[str, SchemaSpec] = {}

    def register(self, spec: SchemaSpec) -> SchemaSpec:
        """Add a type; a name may be registered once."""
        if spec.name in self._types:
            raise SchemaError(f"schema type {spec.name!r} is already registered")
        if not spec.name or not all(c.isalnum() or c == "-" for c in spec.name):
            raise SchemaError(f"schema type names are letters, digits and '-', got {spec.name!r}")
        self._types[spec.name] = spec
        return spec

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
        return out


def _builtin() -> Registry:
    from adapt.schemas.background import SCENE_BACKGROUND
    from adapt.schemas.drive import DRIVE
    from adapt.schemas.foreground import FOREGROUND_OBJECT
    from adapt.schemas.intercept import INTERCEPT

    reg = Registry()
    for spec in (SCENE_BACKGROUND, FOREGROUND_OBJECT, DRIVE, INTERCEPT):
        reg.register(spec)
    return reg


#: The built-in schema types.
REGISTRY = _builtin()
