"""Figures: image strips and grids written with matplotlib.

:func:`~adapt.figures.strips.write_strip` lays out rows of labelled image
panels (the paper's Figures 4, 5, 7 and 8: real | synthetic | warped | mask |
MMD, or MMD images over time) and writes them atomically.  matplotlib is
imported inside the functions (Agg, no window, no global ``pyplot`` state),
so importing :mod:`adapt.figures` costs nothing.

This package imports only NumPy, matplotlib, :mod:`adapt.files` and
:mod:`adapt.errors`: any layer's command or runner may draw with it.
"""

from __future__ import annotations

from adapt.figures.strips import Panel, write_strip

__all__ = ["Panel", "write_strip"]
