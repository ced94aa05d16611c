"""The camera's pose from the image's edges at the seams of the known structure.

Where two surfaces of the model meet, or one ends against what lies beyond it (the
floor-wall line, a wall's top, an obstacle's outline), the real image has an edge
wherever its textures and light, if the camera is where the model says.  The
structure alignment (:func:`~adapt.vision.registration.structure_homography`)
registers a flat look by an image motion, a turn of the camera; it cannot tell a
turned camera from a moved one, and a wall seen from above shows three parallel
seams (its foot, its inner and its outer top edge) that a motion of the image can
trade for each other.  A camera a degree off maps the floor 3-10 cm off.

:func:`fit_edges` fits the whole pose instead.  :func:`seam_points` takes the seams
of a render with their depth (the nearer of the two sides: the edge in front), so
each is a point in the camera's frame.  A pose change -- a small turn ``w`` and a
shift ``t`` of the camera, in its own frame -- moves the points to ``R(w) X + t``.
The score of a pose is the weighted mean over the projected seams of the square root of
the contrast across each, ``|C(q + d e) - C(q - d e)|`` of the blurred colour image
``C``, with ``e`` the axis along which the render crossed the seam and ``d`` about
the blur.  A texture's edges point every way and fall away in the blur; a seam's
contrast is there along its whole length; the square root makes many seams on their
edges outweigh a few on very strong ones.  Seams where two modelled surfaces meet (a
wall's foot, a corner, an obstacle's foot) weigh 1; occluding contours, where a surface
ends against what lies far behind it (a wall's top against the ground beyond, an
obstacle's outline against the floor), weigh :data:`OCCLUDING_WEIGHT`: there the real
body may go on past the model's outline (a wall the model draws as a plane is a box
some centimetres thick, and its real top edge against the ground beyond, the strongest
edge in view, lies behind the model's), and fitted as strongly as the rest they pull
the camera off by that much.

The search:

1. a grid over the turn (the large part of any offset: :data:`SEARCH_DEG` each way)
   at a coarse blur, on at most 1,500 of the seams;
2. from the start, from any ``starts`` given (where another alignment put the
   camera) and from the grid's five best peaks, a compass search over the turn alone
   at two finer blurs;
3. from the five that score best, weighed by a prior on the turn (flat for
   :data:`PRIOR_FLAT` about the start -- a camera set up by hand is that far off what
   the scenario says -- then a Gaussian of :data:`PRIOR_DEG`, floored at
   :data:`PRIOR_FLOOR`: a far turn that puts a seam on its parallel neighbour must fit
   much better, and one that fits 18 % better wins however far), a compass search over
   all six at the finest blur; the shift (at most :data:`SEARCH_M` each way) is kept
   only if it scores :data:`SHIFT_GAIN` better than the turn alone -- a shift is told
   from a turn only by a few pixels of parallax between near and far seams.

Measured on the first frames of the 33 fixed-camera throws of ``bench/foreign.py``
(the camera 2 cm and 1 degree off the scenario's pose), as the ball's position fitted
from its silhouettes over the throw's first 3 s through the fitted camera against
through the true one: at 640x480 from 6.2 cm off through the scenario's camera
(median; mean 7.2 cm) to 0.8 cm (mean 1.2 cm, worst 4.9 cm; 4 throws over 2 cm),
where the same fit with every seam weighing 1 and a Gaussian prior of 2 degrees gave
1.0 cm (mean 1.8 cm, worst 10 cm; 10 over 2 cm); at 320x240 from 6.5 cm to 0.95 cm
(mean 1.7 cm, worst 6.4 cm; 9 over 2 cm), against 1.5 cm (mean 1.9 cm, worst 5.5 cm;
10).  About 0.2 s at 320x240 and 0.35 s at 640x480 on this machine, once before the look
is learned.

Examples
--------
Two boxes' seams seen by a camera turned by about 1.4 degrees; the fit finds the turn:

>>> import cv2
>>> import numpy as np
>>> from adapt.geometry import rotation_exp, rotation_log
>>> K = np.array([[160.0, 0, 79.5], [0, 160.0, 59.5], [0, 0, 1]])
>>> labels = np.zeros((120, 160), np.int32); depth = np.full((120, 160), 3.0, np.float32)
>>> labels[40:90, 50:120] = 1; depth[40:90, 50:120] = 2.5
>>> labels[60:75, 20:45] = 2; depth[60:75, 20:45] = 2.8
>>> look = np.choose(labels, [60, 200, 120]).astype(np.uint8)
>>> turn = rotation_exp(np.radians([0.8, -0.9, 0.7]))
>>> image = cv2.warpPerspective(look, K @ turn @ np.linalg.inv(K), (160, 120),
...                             borderValue=60)
>>> fit = fit_edges(image, seam_points(labels, depth, K), K)
>>> bool(np.degrees(np.linalg.norm(rotation_log(fit.rotation @ turn.T))) < 0.3)
True
>>> fit.score > 2 * fit.start_score
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import cv2
import numpy as np
from numpy.typing import ArrayLike, NDArray

from adapt.geometry import Camera, rotation_exp, rotation_log
from adapt.vision.scale import image_scale

__all__ = ["SeamPoints", "EdgePose", "seam_points", "fit_edges", "edge_score", "apply_pose", "relative_pose",
           "SEARCH_DEG", "SEARCH_M", "SHIFT_GAIN", "PRIOR_FLAT", "PRIOR_DEG", "PRIOR_FLOOR",
           "OCCLUDING_JUMP", "OCCLUDING_WEIGHT", "MAX_SEAM_POINTS"]

FloatArray = NDArray[np.float64]

#: The turn the grid searches, each way about each axis (degrees).
SEARCH_DEG = 3.0
#: The largest shift of the camera the fit may make, each way along each axis (metres).
SEARCH_M = 0.05
#: Turns (degrees) from the start the prior does not weigh against: a camera set up by hand,
#: its pose measured with a tape and a level, is about this far off what the scenario says.
PRIOR_FLAT = 1.0
#: Beyond :data:`PRIOR_FLAT`, the further turn (degrees) at which a fit's score is weighed
#: down by exp(-1/2) against the start.
PRIOR_DEG = 1.0
#: The least weight of the prior: a turn however far from the start wins if it fits this
#: many times better than one near it (1 / 0.85: 18 % better).
PRIOR_FLOOR = 0.85
#: A seam is an occluding contour when what lies behind it is this many times as far as
#: its edge (or nothing: the sky) ...
OCCLUDING_JUMP = 1.05
#: ... and weighs this much in the score against a seam where two surfaces meet.  (Where
#: two modelled surfaces meet -- a wall's foot, a corner -- the real edge is where the model
#: says; where a surface ends against what lies beyond it, the real body may go on past the
#: model's outline: a wall modelled as a plane is a box some centimetres thick, its real top
#: edge against the ground beyond lies behind the model's, and pulls the camera off.)
OCCLUDING_WEIGHT = 0.25
#: How much better (a share of the score) a fit with the shift must be than the turn alone.
SHIFT_GAIN = 0.03
#: At most this many seam points are scored (spread evenly: :meth:`SeamPoints.thinned`):
#: enough for a pose, bounded in time at any resolution.
MAX_SEAM_POINTS = 6000
#: The grid's step over the turn about the two axes across the view, and about the
#: view's axis (degrees; a turn about the view's axis moves the image least).
_GRID_STEP = (0.5, 1.0)
#: The peaks of the grid refined (and the start, always).
_PEAKS = 5
#: The compass search's levels: blur (pixels at 640x480), first turn step (degrees),
#: first shift step (metres); each halves its steps twice.
_LEVELS = ((2.0, 0.25, 0.01), (1.4, 0.05, 0.005))
#: At most this many seam points are scored on the grid.
_COARSE_POINTS = 1500
#: The grid's blur (pixels at 640x480).
_COARSE_BLUR = 4.0
#: The golden ratio's fractional part: its multiples modulo 1 spread evenly (thinning).
_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


@dataclass(frozen=True)
class SeamPoints:
    """Seams of a render as points in its camera's frame.

    Attributes
    ----------
    points : (N, 3) float array
        Camera coordinates (metres) of the seam points.
    axes : (N, 2) float array
        The image axis the render crossed each seam along (``(1, 0)`` or ``(0, 1)``).
    weights : (N,) float array, optional
        What each seam weighs in the score (:data:`OCCLUDING_WEIGHT` for an occluding
        contour, 1 where two surfaces meet); all 1 when not given.
    """

    points: FloatArray
    axes: FloatArray
    weights: FloatArray | None = None

    def __post_init__(self) -> None:
        if self.weights is None:
            object.__setattr__(self, "weights", np.ones(len(self.points)))
        elif len(self.weights) != len(self.points):
            raise ValueError(f"{len(self.weights)} weights for {len(self.points)} seam points")

    def __len__(self) -> int:
        return len(self.points)

    def thinned(self, most: int) -> "SeamPoints":
        """At most ``most`` of them, spread evenly over all (all when they are fewer).

        The pick is the golden ratio's multiples modulo 1, scaled to the points: a stride
        through points in raster order keeps the same seam's crossing on every row and
        drops others whole (a row with two seams and a stride of 2), and the fit then
        holds on to half the structure.

        Examples
        --------
        >>> labels = np.zeros((100, 100), np.int32); labels[:, 30:] = 1; labels[:, 60:] = 2
        >>> s = seam_points(labels, np.full((100, 100), 2.0), np.diag([100.0, 100.0, 1.0]))
        >>> half = s.thinned(100)
        >>> len(half) <= 100, sorted({round(float(x), 2) for x in half.points[:, 0]})  # both
        (True, [0.59, 1.19])
        """
        n = len(self)
        if n <= most:
            return self
        k = np.arange(most, dtype=np.float64)
        pick = np.unique(np.floor((k * _GOLDEN) % 1.0 * n).astype(np.intp))
        assert self.weights is not None  # (set by __post_init__)
        return SeamPoints(self.points[pick], self.axes[pick], self.weights[pick])


@dataclass(frozen=True)
class EdgePose:
    """A fitted pose change of the camera, in its own frame (see the module docstring).

    Attributes
    ----------
    rotation : (3, 3) float array
        ``dR``: the fitted camera's world-to-camera rotation is ``dR @ R``.
    translation : (3,) float array
        ``dt`` (metres): camera points move to ``dR X + dt``, so the fitted camera's
        centre is ``C - (dR R)^T dt``.
    score, start_score : float
        The score at the fit and at the start: the mean square root of the contrast
        across the seams (grey levels).
    points : int
        Seam points scored.
    """

    rotation: FloatArray
    translation: FloatArray
    score: float
    start_score: float
    points: int

    @property
    def angle_deg(self) -> float:
        """The fitted turn (degrees)."""
        return math.degrees(float(np.linalg.norm(rotation_log(self.rotation))))


def seam_points(labels: ArrayLike, depth: ArrayLike, intrinsics: ArrayLike) -> SeamPoints:
    """The seams of a render (where neighbouring labels differ) as camera-frame points.

    A seam between pixels ``(x, y)`` and ``(x + 1, y)`` lies at ``(x + 0.5, y)``; its
    depth is the nearer of the two (the edge in front of what it occludes).  Seams
    with no finite depth on either side are left out.  A seam whose far side is
    :data:`OCCLUDING_JUMP` times as far as its near side, or nothing, is an occluding
    contour and weighs :data:`OCCLUDING_WEIGHT` (see there).

    Parameters
    ----------
    labels : (H, W) integer array
    depth : (H, W) float array
        Camera ``z`` of each pixel (``inf`` where nothing is).
    intrinsics : (3, 3) array_like

    Examples
    --------
    >>> labels = np.zeros((4, 4), np.int32); labels[:, 2:] = 1
    >>> s = seam_points(labels, np.full((4, 4), 2.0), np.diag([100.0, 100.0, 1.0]))
    >>> len(s), s.points[0].round(3).tolist(), s.axes[0].tolist(), s.weights[0].item()
    (4, [0.03, 0.0, 2.0], [1.0, 0.0], 1.0)
    >>> depth = np.full((4, 4), 2.0); depth[:, 2:] = np.inf  # a surface ending against the sky
    >>> seam_points(labels, depth, np.diag([100.0, 100.0, 1.0])).weights.tolist()
    [0.25, 0.25, 0.25, 0.25]
    """
    lab = np.asarray(labels)
    z = np.asarray(depth, np.float64)
    if lab.shape != z.shape:
        raise ValueError(f"labels {lab.shape} and depth {z.shape} differ in size")
    pts, axes, zs, weights = [], [], [], []
    for axis, (a, b, za, zb) in enumerate((
            (lab[:, :-1], lab[:, 1:], z[:, :-1], z[:, 1:]),
            (lab[:-1], lab[1:], z[:-1], z[1:]))):
        ys, xs = np.nonzero(a != b)
        pts.append(np.c_[xs + 0.5, ys] if axis == 0 else np.c_[xs, ys + 0.5])
        axes.append(np.tile([1.0, 0.0] if axis == 0 else [0.0, 1.0], (len(ys), 1)))
        near = np.minimum(za[ys, xs], zb[ys, xs])
        far = np.maximum(za[ys, xs], zb[ys, xs])
        zs.append(near)
        with np.errstate(invalid="ignore"):  # inf against inf: left out below
            occluding = ~(far <= OCCLUDING_JUMP * near)
        weights.append(np.where(occluding, OCCLUDING_WEIGHT, 1.0))
    p = np.concatenate(pts).astype(np.float64)
    e = np.concatenate(axes)
    d = np.concatenate(zs)
    ok = np.isfinite(d) & (d > 0)
    rays = np.c_[p[ok], np.ones(int(ok.sum()))] @ np.linalg.inv(np.asarray(intrinsics, float)).T
    return SeamPoints(rays * d[ok, None], e[ok].reshape(-1, 2), np.concatenate(weights)[ok])


def _blurred(image: NDArray[np.uint8], sigma: float) -> NDArray[np.float32]:
    return np.asarray(cv2.GaussianBlur(np.asarray(image, np.float32), (0, 0), max(0.3, sigma)),
                      np.float32)


def _rotations(turns: FloatArray) -> FloatArray:
    """Rodrigues' formula for each row of ``turns`` (rotation vectors): ``(M, 3, 3)``.

    :func:`~adapt.geometry.rotation_exp` row by row gives the same fits but made the whole
    fit 1.5x slower (0.25 against 0.38 s on the 33 fixed cameras' first frames)."""
    angle = np.linalg.norm(turns, axis=1)
    k = turns / np.where(angle > 1e-12, angle, 1.0)[:, None]
    cross = np.zeros((len(turns), 3, 3))
    cross[:, 0, 1], cross[:, 0, 2], cross[:, 1, 2] = -k[:, 2], k[:, 1], -k[:, 0]
    cross -= cross.transpose(0, 2, 1)
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * cross + (1.0 - c) * (cross @ cross)


def _scores(colour: NDArray[np.float32], seams: SeamPoints, K: FloatArray,
            poses: FloatArray, step: float) -> FloatArray:
    """The score (the weighted mean square root of the contrast across the seams) of each
    pose ``(wx, wy, wz, tx, ty, tz)``."""
    x = seams.points.astype(np.float32)
    off = (step * seams.axes).astype(np.float32)
    weights = np.asarray(seams.weights, np.float32)[None]
    out = np.empty(len(poses))
    chunk = max(1, 60000 // max(1, len(x)))
    for start in range(0, len(poses), chunk):
        block = poses[start:start + chunk]
        # world-free: the camera's own points, turned and shifted, projected by K
        m = (K @ _rotations(block[:, :3])).astype(np.float32)
        q = np.matmul(x[None], m.transpose(0, 2, 1)) + (K @ block[:, 3:].T).T[:, None, :].astype(
            np.float32)
        z = q[..., 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.where(z > 1e-6, z, np.nan).astype(np.float32)
            u, v = q[..., 0] / z, q[..., 1] / z
        a = cv2.remap(colour, u + off[:, 0], v + off[:, 1], cv2.INTER_LINEAR,
                      borderMode=cv2.BORDER_CONSTANT, borderValue=(np.nan,) * 4)
        b = cv2.remap(colour, u - off[:, 0], v - off[:, 1], cv2.INTER_LINEAR,
                      borderMode=cv2.BORDER_CONSTANT, borderValue=(np.nan,) * 4)
        diff = np.asarray(a, np.float32) - np.asarray(b, np.float32)
        contrast = np.sqrt((diff * diff).sum(axis=-1)) if diff.ndim == 3 else np.abs(diff)
        # the square root: many seams on edges outweigh a few on very strong ones (a
        # bright wall top against a dark ground beyond can otherwise pull the fit off the
        # rest)
        contrast = np.sqrt(contrast)
        seen = np.isfinite(contrast)
        n = seen.sum(axis=1)
        total = np.where(seen, contrast * weights, 0.0).sum(axis=1, dtype=np.float64)
        weighed = np.where(seen, weights, 0.0).sum(axis=1, dtype=np.float64)
        out[start:start + len(block)] = np.where(n > len(x) // 4,
                                                 total / np.maximum(weighed, 1e-12), 0.0)
    return out


def edge_score(image: NDArray[np.uint8], seams: SeamPoints, intrinsics: ArrayLike, *,
               blur: float = _LEVELS[-1][0]) -> float:
    """The score of ``seams`` as they are (no pose change), ``blur`` pixels at 640x480: the
    mean square root of the contrast across them (grey levels).

    Examples
    --------
    >>> labels = np.zeros((40, 40), np.int32); labels[:, 20:] = 1
    >>> s = seam_points(labels, np.full((40, 40), 2.0), np.diag([50.0, 50.0, 1.0]))
    >>> image = np.zeros((40, 40, 3), np.uint8); image[:, 20:] = 100
    >>> round(edge_score(image, s, np.diag([50.0, 50.0, 1.0])), 1)
    5.9
    >>> edge_score(np.full((40, 40, 3), 50, np.uint8), s, np.diag([50.0, 50.0, 1.0]))
    0.0
    """
    scale = image_scale(np.shape(image))
    colour = _blurred(image, blur * scale)
    return float(_scores(colour, seams, np.asarray(intrinsics, float), np.zeros((1, 6)),
                         blur * scale)[0])


def _peaks(values: FloatArray, shape: tuple[int, int, int], count: int) -> list[int]:
    """Indices of the ``count`` best local maxima of ``values`` on a 3-D grid."""
    grid = values.reshape(shape)
    padded = np.pad(grid, 1, constant_values=-np.inf)
    best = np.ones(shape, bool)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                if dx or dy or dz:
                    best &= grid >= padded[1 + dx:1 + dx + shape[0], 1 + dy:1 + dy + shape[1],
                                           1 + dz:1 + dz + shape[2]]
    idx = np.flatnonzero(best.ravel())
    return [int(i) for i in idx[np.argsort(-values[idx], kind="stable")][:count]]


def _compass(colour: NDArray[np.float32], seams: SeamPoints, K: FloatArray, start: FloatArray,
             step: float, turn: float, shift: float, bound: float) -> tuple[FloatArray, float]:
    best = start.copy()
    score = float(_scores(colour, seams, K, best[None], step)[0])
    steps = np.diag(np.r_[[turn] * 3, [shift] * 3])[: 6 if shift > 0 else 3]
    factor = 1.0
    while factor >= 1.0 / 4:
        moves = np.concatenate([best + factor * steps, best - factor * steps])
        moves = moves[(np.abs(moves[:, 3:]) <= bound).all(axis=1)]
        values = _scores(colour, seams, K, moves, step)  # the turns are never out of bounds
        i = int(np.argmax(values))
        if values[i] > score:
            best, score = moves[i], float(values[i])
        else:
            factor /= 2
    return best, score


def _prior(score: float, pose: FloatArray) -> float:
    """``score`` weighed by how far the turn goes from the start: a far turn that puts one
    seam on its parallel neighbour (a wall's foot on its top) must fit much better -- but
    never impossibly (:data:`PRIOR_FLOOR`: a camera far off the scenario's pose, which
    another alignment found, still wins by fitting clearly better)."""
    turn = float(np.degrees(np.linalg.norm(pose[:3])))
    beyond = max(0.0, turn - PRIOR_FLAT)
    return score * max(PRIOR_FLOOR, math.exp(-0.5 * (beyond / PRIOR_DEG) ** 2))


def fit_edges(image: NDArray[np.uint8], seams: SeamPoints, intrinsics: ArrayLike, *,
              search_deg: float = SEARCH_DEG, search_m: float = SEARCH_M,
              starts: Sequence[ArrayLike] = ()) -> EdgePose | None:
    """The pose change that puts ``seams`` on ``image``'s edges (the module docstring).

    Parameters
    ----------
    image : (H, W, 3) or (H, W) uint8
        The real image.
    seams : SeamPoints
        The render's seams (:func:`seam_points`) through the camera to correct.
    intrinsics : (3, 3) array_like
        The camera's ``K`` (the same for the render and the image).
    search_deg, search_m : float
        The turn the grid searches and the largest shift, each way.
    starts : sequence of (6,) array_like
        More poses ``(wx, wy, wz, tx, ty, tz)`` to search from (where another
        alignment put the camera); the prior on the turn stays centred on ``seams``'
        own camera.

    Returns
    -------
    EdgePose or None
        None when there are no seams to fit.
    """
    if len(seams) == 0:
        return None
    seams = seams.thinned(MAX_SEAM_POINTS)
    K = np.asarray(intrinsics, float)
    scale = image_scale(np.shape(image))
    across = np.radians(np.arange(-search_deg, search_deg + 1e-9, _GRID_STEP[0]))
    about = np.radians(np.arange(-search_deg, search_deg + 1e-9, _GRID_STEP[1]))
    grid = np.array([[a, b, c, 0.0, 0.0, 0.0] for a in across for b in across for c in about])
    coarse = _scores(_blurred(image, _COARSE_BLUR * scale),
                     seams.thinned(_COARSE_POINTS), K, grid,  # a coarse blur needs fewer
                     _COARSE_BLUR * scale)
    given = [np.clip(np.asarray(p, float).reshape(6), [-np.inf] * 3 + [-search_m] * 3,
                     [np.inf] * 3 + [search_m] * 3) for p in starts]
    origins = [np.zeros(6), *given] + [grid[i] for i in _peaks(
        coarse, (len(across), len(across), len(about)), _PEAKS)]
    colours = [(_blurred(image, blur * scale), blur * scale, math.radians(turn), shift)
               for blur, turn, shift in _LEVELS]
    start_score = float(_scores(colours[-1][0], seams, K, np.zeros((1, 6)), colours[-1][1])[0])
    turned: list[tuple[float, FloatArray]] = []
    for pose in origins:  # the turn alone
        score = 0.0
        for colour, step, turn, _ in colours:
            pose, score = _compass(colour, seams, K, pose, step, turn, 0.0, search_m)
        turned.append((score, pose))
    turned.sort(key=lambda t: -_prior(t[0], t[1]))
    best = turned[0]
    moved: tuple[float, FloatArray] | None = None
    for score, pose in turned[:_PEAKS]:  # and the shift, from the turns that fit best
        for colour, step, turn, shift in colours[1:]:
            pose, score = _compass(colour, seams, K, pose, step, turn, shift, search_m)
        if moved is None or _prior(score, pose) > _prior(*moved):
            moved = (score, pose)
    # The shift is weakly told from a turn (a few pixels of parallax between near and far
    # seams): it is taken only when it fits clearly better than the turn alone.
    if moved is not None and _prior(*moved) > (1.0 + SHIFT_GAIN) * _prior(*best):
        best = moved
    score, pose = best
    return EdgePose(rotation_exp(pose[:3]), pose[3:].copy(), score, start_score, len(seams))


def relative_pose(camera: Camera, other: Camera) -> FloatArray:
    """The pose change ``(wx, wy, wz, tx, ty, tz)`` in ``camera``'s frame that moves it to
    ``other`` (what :func:`apply_pose` undoes; a ``starts`` entry of :func:`fit_edges`).

    Examples
    --------
    >>> a = Camera(100, 100, 50, 50, 100, 100, np.eye(3), np.zeros(3))
    >>> b = a.with_pose(rotation_exp([0.01, 0.0, 0.02]), [0.03, 0.0, 0.0])
    >>> p = relative_pose(a, b)
    >>> back = apply_pose(a, EdgePose(rotation_exp(p[:3]), p[3:], 0.0, 0.0, 0))
    >>> bool(np.allclose(back.rotation, b.rotation) and np.allclose(back.position, b.position))
    True
    """
    return np.r_[rotation_log(other.rotation @ camera.rotation.T),
                 other.rotation @ (camera.position - other.position)]


def apply_pose(camera: Camera, fit: EdgePose) -> Camera:
    """``camera`` moved by ``fit``: rotation ``dR R``, centre ``C - (dR R)^T dt``.

    Examples
    --------
    >>> cam = Camera(100, 100, 50, 50, 100, 100, np.eye(3), np.zeros(3))
    >>> fit = EdgePose(np.eye(3), np.array([0.0, 0.0, 0.1]), 1.0, 0.0, 10)
    >>> apply_pose(cam, fit).position.tolist()
    [0.0, 0.0, -0.1]
    """
    rotation = fit.rotation @ camera.rotation
    return camera.with_pose(rotation, camera.position - rotation.T @ fit.translation)
