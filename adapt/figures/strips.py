"""Rows of labelled image panels, written as one figure (PNG, PDF or SVG).

A *strip* is what the paper's Figures 4, 5, 7 and 8 show: rows of images
side by side, each with a label above it, and an optional title.  Panels are
``(label, image)`` pairs or :class:`Panel` records (which add point and box
overlays and the grey-level range).  Images are NumPy arrays as adapt uses
them:

* ``(H, W, 3)`` ``uint8`` **BGR** (OpenCV's order; shown as colour),
  ``(H, W, 4)`` BGRA, or ``uint16`` colour;
* ``(H, W)`` grey: ``uint8`` shown from 0 to 255, ``uint16`` from 0 to 65535,
  ``bool`` from 0 to 1; floats from 0 to 1 when all their values lie there
  (a mask), else from their smallest to their largest finite value (an MMD
  image in grey levels, a depth map); ``NaN`` is left blank.

Panels of one figure may differ in size: each is scaled to the same cell,
keeping its aspect.  Rows may differ in length (missing cells stay empty).
The file is written atomically (:mod:`adapt.files`), so an interrupted or
failed write never leaves a partial figure or destroys the previous one.

Examples
--------
>>> import numpy as np, tempfile, pathlib
>>> grey = np.tile(np.arange(64, dtype=np.uint8) * 4, (48, 1))
>>> mask = np.linspace(0.0, 1.0, 48 * 64).reshape(48, 64)
>>> out = pathlib.Path(tempfile.mkdtemp()) / "strip.png"
>>> write_strip(out, [[("grey", grey), Panel("mask", mask, boxes=[((8, 8, 20, 10), "red")])]],
...             title="two panels") == out
True
>>> out.read_bytes()[:8] == b"\\x89PNG\\r\\n\\x1a\\n"
True
"""

from __future__ import annotations

import io
import os
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.errors import ImageError
from adapt.files import write_atomic

__all__ = ["Panel", "write_strip", "FORMATS", "PANEL_WIDTH", "DPI"]

#: Extensions :func:`write_strip` writes, and matplotlib's format names for them.
FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}
#: Widest a panel is drawn, pixels (at :data:`DPI`); smaller images keep their width.
PANEL_WIDTH = 640
#: Pixels per inch of the written figure.
DPI = 100
#: Label and title sizes, points, for panels :data:`PANEL_WIDTH` wide (smaller
#: panels get smaller text, down to :data:`SMALLEST_POINTS`).
LABEL_POINTS = 14.0
TITLE_POINTS = 16.0
SMALLEST_POINTS = 8.0


@dataclass(frozen=True, slots=True, eq=False)
class Panel:
    """One labelled image of a strip.

    Parameters
    ----------
    label : str
        Text above the panel (may hold ``\\n`` for a second line).
    image : ndarray
        See the module docstring for the shapes and dtypes shown.
    points : sequence of (points, colour)
        Overlays of hollow circles: ``(N, 2)`` pixel positions ``(x, y)`` in
        this image, and a matplotlib colour (``"lime"``, ``"#ff0000"``).
    boxes : sequence of (box, colour)
        Rectangles ``(x, y, w, h)`` in this image's pixels, and their colour.
    vmin, vmax : float, optional
        Grey range of a single-channel image (defaults as in the module docstring).
    cmap : str
        matplotlib colour map of a single-channel image.
    """

    label: str
    image: NDArray = field(repr=False)
    points: Sequence[tuple[ArrayLike, str]] = ()
    boxes: Sequence[tuple[Sequence[float], str]] = ()
    vmin: float | None = None
    vmax: float | None = None
    cmap: str = "gray"


PanelLike = Union[Panel, tuple[str, NDArray]]


def _panel(item: Any, where: str) -> Panel:
    if isinstance(item, Panel):
        p = item
    elif isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str):
        p = Panel(item[0], item[1])
    else:
        raise TypeError(f"{where}: expected a Panel or a (label, image) pair, got {type(item).__name__}")
    img = p.image
    if not isinstance(img, np.ndarray):
        raise TypeError(f"{where} ({p.label!r}): the image is a {type(img).__name__}, expected a NumPy array")
    ok_shape = img.ndim == 2 or (img.ndim == 3 and img.shape[2] in (1, 3, 4))
    if not ok_shape or img.size == 0:
        raise ValueError(
            f"{where} ({p.label!r}): image of shape {img.shape}: expected (H, W), (H, W, 3) BGR "
            "or (H, W, 4) BGRA"
        )
    if not (img.dtype == np.bool_ or np.issubdtype(img.dtype, np.integer)
            or np.issubdtype(img.dtype, np.floating)):
        raise ValueError(f"{where} ({p.label!r}): image of dtype {img.dtype}: expected numbers")
    return p


def _display(p: Panel) -> tuple[NDArray, dict[str, Any]]:
    """The array matplotlib draws and the ``imshow`` keywords for it."""
    img = p.image
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[:, :, 0]
    if img.ndim == 3:
        rgb = img[:, :, 2::-1]  # BGR(A) -> RGB
        if img.dtype == np.uint8:
            return np.ascontiguousarray(rgb), {}
        if img.dtype == np.uint16:
            return rgb.astype(np.float32) / 65535.0, {}
        return np.clip(np.nan_to_num(rgb.astype(np.float32)), 0.0, 1.0), {}
    if img.dtype == np.bool_:
        lo, hi = 0.0, 1.0
        img = img.astype(np.uint8)
    elif img.dtype == np.uint8:
        lo, hi = 0.0, 255.0
    elif img.dtype == np.uint16:
        lo, hi = 0.0, 65535.0
    else:
        finite = img[np.isfinite(img)] if np.issubdtype(img.dtype, np.floating) else img
        if finite.size == 0:
            lo, hi = 0.0, 1.0
        else:
            lo, hi = float(finite.min()), float(finite.max())
            if lo >= 0.0 and hi <= 1.0:
                lo, hi = 0.0, 1.0
            elif hi <= lo:
                lo, hi = lo - 1.0, hi + 1.0
        img = np.ma.masked_invalid(img) if np.issubdtype(img.dtype, np.floating) else img
    lo = lo if p.vmin is None else float(p.vmin)
    hi = hi if p.vmax is None else float(p.vmax)
    return img, {"cmap": p.cmap, "vmin": lo, "vmax": hi}


def _wrap(text: str, width: int) -> str:
    return "\n".join(textwrap.fill(line, width) if line else "" for line in text.split("\n"))


def write_strip(
    path: str | os.PathLike[str],
    rows: Sequence[Sequence[PanelLike]],
    *,
    title: str | None = None,
    panel_width: int = PANEL_WIDTH,
) -> Path:
    """Write ``rows`` of labelled panels as one figure at ``path``.

    Parameters
    ----------
    path : str or PathLike
        The file to write: ``.png``, ``.pdf`` or ``.svg``.  Its directory
        must exist.
    rows : sequence of sequences of Panel or (label, image)
        The panels, row by row (at least one panel).
    title : str, optional
        Text above the whole figure.
    panel_width : int
        Widest a panel is drawn, pixels (smaller images keep their width).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ImageError
        If the extension is not one of :data:`FORMATS` or the file cannot be
        written (nothing is left behind).
    TypeError, ValueError
        If a panel is not a ``Panel`` / ``(label, image)`` pair of a drawable
        image.
    """
    p = Path(path)
    fmt = FORMATS.get(p.suffix.lower())
    if fmt is None:
        raise ImageError(
            f"{path}: cannot write a figure as {p.suffix or 'a file without an extension'!r}: "
            f"expected one of {', '.join(FORMATS)}"
        )
    grid = [[_panel(item, f"row {i} panel {j}") for j, item in enumerate(row)] for i, row in enumerate(rows)]
    grid = [row for row in grid if row]
    if not grid:
        raise ValueError("a strip needs at least one panel")
    ncols = max(len(row) for row in grid)
    nrows = len(grid)
    panels = [q for row in grid for q in row]
    width_px = float(min(max(q.image.shape[1] for q in panels), max(int(panel_width), 16)))
    aspect = max(q.image.shape[0] / q.image.shape[1] for q in panels)
    height_px = width_px * aspect
    label_pt = max(SMALLEST_POINTS, LABEL_POINTS * min(1.0, width_px / PANEL_WIDTH))
    title_pt = max(SMALLEST_POINTS, TITLE_POINTS * min(1.0, ncols * width_px / PANEL_WIDTH))
    # wrap labels to the panel (about 0.55 em per character) so neighbours never overlap
    per_line = max(8, int(width_px / (0.55 * label_pt * DPI / 72.0)))
    labels = {id(q): _wrap(q.label, per_line) for q in panels}
    label_lines = max(t.count("\n") + 1 for t in labels.values())
    label_px = label_pt * DPI / 72.0 * (1.3 * label_lines + 0.6)
    title_text = _wrap(title, max(8, int(ncols * width_px / (0.6 * title_pt * DPI / 72.0)))) if title else ""
    title_px = title_pt * DPI / 72.0 * (1.4 * (title_text.count("\n") + 1) + 0.8) if title else 0.0
    gap_px = 12.0
    fig_w = ncols * width_px + (ncols + 1) * gap_px
    fig_h = nrows * (height_px + label_px) + (nrows + 1) * gap_px + title_px

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    fig = Figure(figsize=(fig_w / DPI, fig_h / DPI), dpi=DPI, facecolor="white")
    FigureCanvasAgg(fig)
    if title:
        fig.text(0.5, 1.0 - gap_px / fig_h, title_text, ha="center", va="top",
                 fontsize=title_pt, fontweight="bold")
    for i, row in enumerate(grid):
        top = title_px + gap_px + i * (height_px + label_px + gap_px) + label_px
        for j, q in enumerate(row):
            left = gap_px + j * (width_px + gap_px)
            ax = fig.add_axes((left / fig_w, 1.0 - (top + height_px) / fig_h,
                               width_px / fig_w, height_px / fig_h))
            img, kw = _display(q)
            h, w = q.image.shape[:2]
            ax.imshow(img, interpolation="antialiased", aspect="equal", **kw)
            ax.set_xlim(-0.5, w - 0.5)
            ax.set_ylim(h - 0.5, -0.5)
            ax.set_xticks([])
            ax.set_yticks([])
            ax.set_title(labels[id(q)], fontsize=label_pt, pad=4)
            marker = max(2.0, 0.006 * width_px)
            for pts, colour in q.points:
                xy = np.asarray(pts, dtype=float).reshape(-1, 2)
                if len(xy):
                    ax.plot(xy[:, 0], xy[:, 1], linestyle="none", marker="o", markersize=marker,
                            markerfacecolor="none", markeredgecolor=colour, markeredgewidth=1.0)
            for box, colour in q.boxes:
                x, y, bw, bh = (float(v) for v in box)
                ax.add_patch(Rectangle((x - 0.5, y - 0.5), bw, bh, fill=False, edgecolor=colour,
                                       linewidth=1.5))
    buf = io.BytesIO()
    extra = {"pil_kwargs": {"compress_level": 3}} if fmt == "png" else {}
    fig.savefig(buf, format=fmt, dpi=DPI, facecolor="white", **extra)  # type: ignore[arg-type]
    try:
        write_atomic(p, buf.getvalue())
    except OSError as exc:
        raise ImageError(f"{path}: cannot write ({exc.strerror or exc})") from exc
    return p
