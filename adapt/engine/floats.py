"""Floating-point constants: :class:`Float`, never equal to an int.

In Soar ``2`` and ``2.0`` are different values.  This class is its own
module because it subclasses ``float``: it stays Python when the engine is
compiled (see :mod:`adapt.engine.compiled`), while :mod:`adapt.engine.symbols`
is compiled.  Import it from :mod:`adapt.engine.symbols`.

Examples
--------
>>> Float(2.0) == 2, Float(2.0) == Float(2.0), len({2, Float(2.0)})
(False, True, 2)
"""

from __future__ import annotations

__all__ = ["Float"]


class Float(float):
    """A floating-point constant: equal only to floats, hashed apart from ints.

    Arithmetic on a :class:`Float` returns a plain ``float``; wrap results with
    :func:`to_symbol` before they go into working memory.
    """

    __slots__ = ()

    def __eq__(self, other: object) -> bool:
        return isinstance(other, float) and float.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self.__eq__(other)

    def __hash__(self) -> int:
        return hash((float(self), "f"))

    def __repr__(self) -> str:
        return f"Float({float.__repr__(self)})"
