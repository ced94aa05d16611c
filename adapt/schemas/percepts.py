"""Percepts: what a schema publishes on the ports it provides, frame by frame.

Schemas meet each other only here.  A provider publishes one frozen record on
each port it provides (:meth:`SchemaNetwork.publish
<adapt.schemas.network.SchemaNetwork.publish>`); a consumer reads the records
of its providers through the graph's edges that carry the port
(:meth:`SchemaNetwork.percepts <adapt.schemas.network.SchemaNetwork.percepts>`),
never through another schema's members.  So a user's own schema type is
written against these records and the base class, not against our classes
(``docs/schemas.md``).

* :class:`BackgroundPercept` -- on ``regions`` and ``camera``, from the Scene
  Background schema: this frame's match-mediated difference, whether its
  alignment can be believed, the pixel error, the synthetic camera before and
  after this frame's correction, the render (image, static background,
  labels), and the tracked difference regions.  Its methods map pixels
  between the real frame and the render and take differences through the
  frame's ``H_e``: pure functions of the record.
* :class:`ObjectPercept` -- on ``object``, from a foreground object schema:
  the object's sighting in this frame, its filtered position and velocity,
  the imagined body's position, the prediction, the parameter estimates.

A percept describes one frame (``frame``, ``time``) and is replaced by the
next; nothing in it changes after it is published.

Examples
--------
>>> import numpy as np
>>> from adapt.geometry import Camera
>>> cam = Camera(100, 100, 40, 30, 80, 60, np.eye(3), np.zeros(3))
>>> p = BackgroundPercept(frame=3, time=0.1, camera_before=cam, camera_after=cam)
>>> p.aligned, p.to_real((10.0, 20.0)), p.region(1) is None
(False, (10.0, 20.0), True)
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import cv2
import numpy as np
from numpy.typing import NDArray

from adapt.geometry import Camera
from adapt.imagination.surface import LABEL_BALL, LABEL_ROBOT
from adapt.vision.texture import flat_over_texture

if TYPE_CHECKING:  # pragma: no cover
    from adapt.imagination import Ball
    from adapt.imagination.predict import Trajectory
    from adapt.schemas.estimator import Estimate
    from adapt.schemas.predictor import Prediction
    from adapt.vision.mmd import MMDResult
    from adapt.vision.regions import Region

__all__ = ["BackgroundPercept", "ObjectPercept", "RegionReport", "Sighting", "FirstLook",
           "AppearanceStage", "BBox", "Vec2", "LOOKS_LIKE_COLOR", "LOOKS_LIKE_SIZE", "LOOKS_LIKE_MARGIN",
           "looks_like", "colour_like", "mean_color"]

BBox = tuple[int, int, int, int]
Vec2 = tuple[float, float]


def mean_color(image: NDArray[np.uint8], bbox: BBox, silhouette: NDArray[np.bool_]
               ) -> tuple[int, int, int] | None:
    """The mean ``(r, g, b)`` of a BGR image's pixels in a region at ``bbox`` (its
    ``silhouette`` when it fits the box, else the whole box); None for an empty box.

    >>> image = np.zeros((4, 4, 3), np.uint8); image[1:3, 1:3] = (40, 220, 235)  # BGR
    >>> mean_color(image, (1, 1, 2, 2), np.ones((2, 2), bool))
    (235, 220, 40)
    """
    x, y, w, h = bbox
    patch = image[max(y, 0):y + h, max(x, 0):x + w]
    if patch.size == 0:
        return None
    pixels = patch[silhouette] if silhouette.shape == patch.shape[:2] and silhouette.any() \
        else patch.reshape(-1, 3)
    b, g, r = (int(round(float(v))) for v in pixels.mean(axis=0))
    return (r, g, b)


def looks_like(color: tuple[int, int, int] | None, size: float | None,
               objects: Mapping[str, tuple[tuple[int, int, int], float]]) -> str | None:
    """The object (name -> ``(colour, radius)``) a region of mean ``color`` and floor ``size``
    looks like: the nearest colour within :data:`LOOKS_LIKE_COLOR` among those whose
    diameter is within :data:`LOOKS_LIKE_SIZE` of ``size`` (any size when it is unknown);
    None when none is near enough, or when the next is within :data:`LOOKS_LIKE_MARGIN` of it
    (objects of one colour are told apart otherwise).  A colour is compared under the light
    that brings it nearest, up to :data:`LOOKS_LIKE_LIGHT` times brighter or darker: a
    scenario gives an object's colour as lit, a frame shows it shaded, its mean over a
    sphere darker still.

    >>> objects = {"red": ((230, 60, 30), 0.1), "blue": ((40, 80, 220), 0.1)}
    >>> looks_like((200, 70, 50), 0.18, objects), looks_like((60, 90, 200), None, objects)
    ('red', 'blue')
    >>> looks_like((120, 120, 120), 0.2, objects), looks_like((200, 70, 50), 1.5, objects)
    (None, None)
    >>> looks_like((200, 70, 50), 0.2, {"a": ((230, 60, 30), 0.1), "b": ((225, 65, 35), 0.1)})
    >>> looks_like((151, 143, 33), 0.2, {"ball": ((235, 220, 40), 0.1)})  # a yellow ball, shaded
    'ball'
    """
    if color is None:
        return None
    near = sorted((_lit_distance(color, c), name) for name, (c, radius) in objects.items()
                  if size is None or 1.0 / LOOKS_LIKE_SIZE <= size / (2.0 * radius) <= LOOKS_LIKE_SIZE)
    if not near or near[0][0] > LOOKS_LIKE_COLOR:
        return None
    if len(near) > 1 and near[1][0] - near[0][0] < LOOKS_LIKE_MARGIN:
        return None  # two objects look alike: the colour does not tell which
    return near[0][1]


def colour_like(pixels: NDArray[np.uint8], colors: Sequence[tuple[int, int, int]]
                ) -> NDArray[np.bool_]:
    """Which of ``pixels`` (``(N, 3)`` BGR) could show one of ``colors`` (RGB): within
    :data:`LOOKS_LIKE_COLOR` of it under the light that brings it nearest, as
    :func:`looks_like` asks of a region's mean colour, pixel by pixel.

    >>> px = np.array([[20, 150, 240], [128, 128, 128], [10, 75, 120]], np.uint8)  # BGR
    >>> colour_like(px, [(240, 150, 20)]).tolist()   # orange, grey, orange in the shade
    [True, False, True]
    """
    out = np.zeros(len(pixels), bool)
    if not len(pixels):
        return out
    rgb = np.asarray(pixels, float)[:, ::-1]
    for color in colors:
        out |= _lit_distances(rgb, color) <= LOOKS_LIKE_COLOR
    return out


def _lit_distance(color: tuple[int, int, int], declared: tuple[int, int, int]) -> float:
    """How far ``color`` is from ``declared`` (RGB) under the light, within
    :data:`LOOKS_LIKE_LIGHT` either way, that brings it nearest."""
    return float(_lit_distances(np.asarray([color], float), declared)[0])


def _lit_distances(seen: NDArray[np.float64], declared: tuple[int, int, int]
                   ) -> NDArray[np.float64]:
    """:func:`_lit_distance` of each row of ``seen`` (``(N, 3)`` RGB)."""
    lit = np.asarray(declared, float)
    power = np.einsum("ij,ij->i", seen, seen)
    gain = np.clip(seen @ lit / np.where(power > 0.0, power, 1.0), 1.0 / LOOKS_LIKE_LIGHT,
                   LOOKS_LIKE_LIGHT)
    gain[power <= 0.0] = 1.0
    return np.asarray(np.linalg.norm(gain[:, None] * seen - lit, axis=1), float)


class AppearanceStage(enum.Enum):
    """Where the Scene Background's appearance learning is (``docs/appearance.md``)."""

    OFF = "off"              # the scenario's look (or a loaded one), never changed
    STRUCTURE = "structure"  # aligning the camera to the scene's structure first
    LEARNED = "learned"      # the look is learned and refined


#: Largest distance between a region's mean colour and an object's (RGB, 0-255) for the
#: region to look like it: lighting, blur and the floor showing through move a ball's colour.
LOOKS_LIKE_COLOR = 90.0

#: A region's colour is compared with an object's under a light up to this many times brighter
#: or darker (a ball shaded by its own curve, a dimmer light than the scenario's colour says).
LOOKS_LIKE_LIGHT = 2.0

#: A region looks like none of two objects whose colours are this close to it alike.
LOOKS_LIKE_MARGIN = 25.0

#: A region looks like an object when its size on the floor is within this factor of the
#: object's diameter (either way): the box's bottom edge back-projected is a rough measure.
LOOKS_LIKE_SIZE = 2.5

#: The fewest pixels inside the imagined robot's outline that say the robot's colour in a
#: frame (:meth:`BackgroundPercept.robot_mask` with ``real``).
ROBOT_COLOUR_PIXELS = 20


@dataclass(frozen=True, slots=True)
class RegionReport:
    """One tracked difference region as the input-link reports it.

    ``bbox`` and ``centroid`` are real-image pixels; ``floor`` is the bottom of
    the box back-projected onto the floor and ``size`` its width there
    (metres); ``owner`` the schema that explains it (``expected``);
    ``imagined`` the imagined moving object it shows; ``still`` that the
    camera's pixels in its box have not changed over its last frames while
    the look is learned: a difference nothing moves in is the learned look's
    error (a ghost, background it never saw), not an object arriving;
    ``color`` the mean ``(r, g, b)`` of the real image's pixels in it;
    ``looks_like`` the declared object whose colour and size it has (the
    nearest colour within :data:`LOOKS_LIKE_COLOR`, a size within
    :data:`LOOKS_LIKE_SIZE` of its diameter), so that rules can tell one
    object from another before a schema claims it; ``unseen`` that most of its
    pixels are where imagined bodies covered the surfaces at the first look (the
    floor under the robot's start, with a margin), and held still: the look's
    ignorance there, not an object arriving either.
    """

    id: int
    bbox: BBox
    centroid: tuple[float, float]
    area: int
    age: int
    expected: bool
    owner: str | None
    floor: Vec2 | None
    size: float | None
    imagined: str | None = None
    at_edge: bool = False
    still: bool = False
    color: tuple[int, int, int] | None = None
    looks_like: str | None = None
    unseen: bool = False

    def as_json(self) -> dict[str, Any]:
        """JSON form (trace and report)."""
        return {"id": self.id, "bbox": list(self.bbox),
                "centroid": [round(self.centroid[0], 2), round(self.centroid[1], 2)],
                "area": self.area, "age": self.age, "expected": self.expected,
                "owner": self.owner,
                "floor": None if self.floor is None else [round(v, 4) for v in self.floor],
                "size": None if self.size is None else round(self.size, 4),
                "imagined": self.imagined, "at_edge": self.at_edge, "still": self.still,
                "color": None if self.color is None else list(self.color),
                "looks_like": self.looks_like, "unseen": self.unseen}


@dataclass(frozen=True, slots=True, eq=False)
class FirstLook:
    """The frame the surfaces' look was first learned from: the real image and the
    render before and after (references, for ``figures/appearance.png``)."""

    frame: int
    time: float
    real: NDArray[np.uint8]
    before: NDArray[np.uint8]
    after: NDArray[np.uint8]


@dataclass(frozen=True, slots=True, eq=False)
class BackgroundPercept:
    """What the Scene Background schema perceived in one frame (see the module docstring).

    Attributes
    ----------
    frame, time : int, float
        The frame it describes.
    camera_before, camera_after : Camera
        The synthetic camera the frame was rendered from, and after this
        frame's correction (the same camera when there was none).
    mmd : MMDResult or None
        The match-mediated difference of the frame against the render (None
        while the camera is aligned to the scene's structure first).
    trusted : bool
        Aligned, and not a sudden false jump: what depends on ``H_e`` may be
        believed.
    pixel_error : float
        How far ``H_e`` moves the image corners, real pixels (nan without
        alignment).
    threshold : float
        The difference (grey levels) that counts as a difference.
    tolerance : float
        The pixel error (real pixels) up to which the camera is not corrected: the
        schema's ``tolerance`` in the frame's pixels (it counts pixels of the image the
        MMD works on).
    synthetic, background : ndarray or None
        The render of the imagination through ``camera_before``, and its static
        background (no moving objects).
    labels : ndarray or None
        The render's label image; ``drawn`` maps each moving body drawn in it to
        its label.
    warped_labels : ndarray or None
        ``labels`` warped into the real frame by ``H_e`` (nearest neighbour),
        when the frame is trusted and a ball or the robot is drawn.
    regions : tuple of RegionReport
        The tracked difference regions (empty while the provider is still
        perceiving: it publishes once its camera step is done, then again with
        the regions).
    ms : float
        Milliseconds the provider took for the frame.
    stage : AppearanceStage
    learn_passes : int
        Learning passes of the surfaces' look so far; ``learn_ms`` this frame's.
    first_look : FirstLook or None
    structure_error : float
        While aligning the structure: how far it is from aligned, pixels.
    """

    frame: int
    time: float
    camera_before: Camera
    camera_after: Camera
    mmd: "MMDResult | None" = None
    trusted: bool = False
    pixel_error: float = math.nan
    threshold: float = 30.0
    tolerance: float = 0.5
    synthetic: NDArray[np.uint8] | None = None
    background: NDArray[np.uint8] | None = None
    labels: NDArray[np.int32] | None = None
    drawn: Mapping[str, int] = field(default_factory=lambda: MappingProxyType({}))
    warped_labels: NDArray[np.uint16] | None = None
    regions: tuple[RegionReport, ...] = ()
    ms: float = 0.0
    stage: AppearanceStage = AppearanceStage.OFF
    learn_passes: int = 0
    learn_ms: float = 0.0
    first_look: FirstLook | None = None
    structure_error: float = math.nan

    # -- what it says -----------------------------------------------------------------

    @property
    def aligned(self) -> bool:
        """The MMD found ``H_e`` this frame."""
        return self.mmd is not None and self.mmd.aligned

    @property
    def homography(self) -> NDArray[np.float64] | None:
        """``H_e`` (synthetic pixels to real pixels), or None without alignment."""
        return self.mmd.homography if self.aligned else None  # type: ignore[union-attr]

    @property
    def unexpected(self) -> tuple[RegionReport, ...]:
        """The regions no schema explains."""
        return tuple(r for r in self.regions if not r.expected)

    def region(self, region_id: int) -> RegionReport | None:
        """The tracked region ``region_id`` of this frame, or None."""
        for r in self.regions:
            if r.id == region_id:
                return r
        return None

    # -- pixels between the render and the real frame ---------------------------------

    def to_real(self, pixel: tuple[float, float]) -> tuple[float, float]:
        """A synthetic pixel in the real frame (through ``H_e``; unchanged without it)."""
        h = self.homography
        if h is None:
            return pixel
        p = h @ np.array([pixel[0], pixel[1], 1.0])
        return (float(p[0] / p[2]), float(p[1] / p[2]))

    def to_synthetic(self, pixels: NDArray[np.float64]) -> NDArray[np.float64]:
        """Real pixels ``(N, 2)`` in the synthetic frame (through ``H_e^-1``; unchanged
        without it)."""
        h = self.homography
        if h is None:
            return np.asarray(pixels, float)
        p = np.c_[pixels, np.ones(len(pixels))] @ np.linalg.inv(h).T
        return p[:, :2] / p[:, 2:]

    # -- differences through H_e -------------------------------------------------------

    def object_difference(self, real: NDArray[np.uint8], window: BBox, *,
                          flat: bool = False) -> NDArray[Any] | None:
        """How much ``real`` differs from the imagination's *background* (no moving
        objects) in ``window`` (real pixels ``(x, y, w, h)``), in grey levels (the largest
        over the channels), with the frame's gain and bias; None without alignment.

        This is the difference an object schema looks for its object in: the object
        wherever it really is, whatever the imagination shows of it.  The MMD mask is not
        applied: its Gaussians, centred on background corners matched next to the object,
        would eat into the object's outline and bias its fitted position.

        With ``flat``, where the real frame is flat over a textured background and of its
        mean colour, within ``threshold`` (:func:`~adapt.vision.texture.flat_over_texture`:
        a smooth object over gravel or grass, the colour of the texture's mean), the
        difference is at least ``threshold + 1``: the object shows whole, not only where a
        grain differs from it.
        """
        if self.background is None:
            return None
        return self._difference(real, self.background, window, flat=flat)

    def difference_with(self, real: NDArray[np.uint8], synthetic: NDArray[np.uint8]
                        ) -> NDArray[Any] | None:
        """The whole frame's difference (grey levels, no mask) between ``real`` and another
        synthetic image of ``camera_before`` (an uncorrected imagination, say), through
        this frame's ``H_e``, gain and bias; None without alignment."""
        h, w = real.shape[:2]
        return self._difference(real, synthetic, (0, 0, w, h))

    def _difference(self, real: NDArray[np.uint8], synthetic: NDArray[np.uint8],
                    window: BBox, flat: bool = False) -> NDArray[Any] | None:
        res = self.mmd
        if res is None or not res.aligned:
            return None
        x, y, w, h = window
        shift = np.array([[1.0, 0.0, -x], [0.0, 1.0, -y], [0.0, 0.0, 1.0]])
        warped = cv2.warpPerspective(synthetic, shift @ res.homography, (w, h),  # type: ignore[operator]
                                     flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        part = np.ascontiguousarray(real[y:y + h, x:x + w])
        if warped.ndim == 3:
            c = warped.shape[2]
            m = np.zeros((c, c + 1))
            m[np.arange(c), np.arange(c)] = res.gain
            m[:, -1] = res.bias
            adjusted = cv2.transform(warped, m)
            diff = cv2.absdiff(part, adjusted)
            out = diff[:, :, 0]
            for k in range(1, c):
                out = cv2.max(out, diff[:, :, k])
        else:
            adjusted = cv2.convertScaleAbs(warped, alpha=float(res.gain[0]),
                                           beta=float(res.bias[0]))
            out = cv2.absdiff(part, adjusted)
        if flat:
            # (cv2.transform keeps the frame's 8 bits: no copy)
            smooth = flat_over_texture(part, np.asarray(adjusted, np.uint8),
                                       mean_within=self.threshold)
            if smooth.any():
                out = np.where(smooth, np.maximum(out, min(int(self.threshold) + 1, 255)), out)
        return out

    # -- the imagined objects in the real frame ----------------------------------------

    def balls_except(self, name: str) -> list[int]:
        """Label ids of the moving balls drawn this frame, but ``name``'s."""
        return [lab for n, lab in self.drawn.items()
                if n != name and LABEL_BALL <= lab < LABEL_ROBOT]

    def robot_mask(self, margin: int = 0, box: tuple[int, int, int, int] | None = None,
                   real: NDArray[np.uint8] | None = None) -> NDArray[np.bool_] | None:
        """Pixels of the real frame where the imagination shows the robot, grown by ``margin``
        pixels, or None (no alignment, no robot drawn); within ``box`` (``x, y, w, h``) only,
        when given (the mask of that part of the frame).

        Given the ``real`` frame, the pixels whose colour there is not the robot's are left
        out: more than ``threshold`` grey levels (any channel) from the median colour of the
        pixels the imagined robot covers at least ``margin`` pixels inside its outline (at
        least :data:`ROBOT_COLOUR_PIXELS` of them in the box; else none is left out).  The
        imagined robot stands where the robot's odometry says, a few pixels off: what shows
        past the real robot's edge there (a ball resting against it) is not its image.

        >>> cam = Camera(100, 100, 40, 30, 80, 60, np.eye(3), np.zeros(3))
        >>> labels = np.pad(np.full((2, 2), LABEL_ROBOT, np.uint16), 3)
        >>> p = BackgroundPercept(0, 0.0, cam, cam, drawn={"robot": LABEL_ROBOT},
        ...                       warped_labels=labels)
        >>> int(p.robot_mask().sum()), int(p.robot_mask(margin=1).sum())
        (4, 16)
        >>> p.robot_mask(margin=1, box=(0, 0, 4, 4)).astype(int).tolist()[2:]
        [[0, 0, 1, 1], [0, 0, 1, 1]]
        """
        if self.warped_labels is None or LABEL_ROBOT not in self.drawn.values():
            return None
        h, w = self.warped_labels.shape
        x0, y0, bw, bh = (0, 0, w, h) if box is None else box
        # the box grown by the margin: a robot pixel just outside it grows into it
        gx0, gy0 = max(x0 - margin, 0), max(y0 - margin, 0)
        gx1, gy1 = min(x0 + bw + margin, w), min(y0 + bh + margin, h)
        drawn = self.warped_labels[gy0:gy1, gx0:gx1] == LABEL_ROBOT
        kernel = np.ones((2 * margin + 1, 2 * margin + 1), np.uint8) if margin > 0 else None
        mask = drawn
        if kernel is not None and mask.any():
            mask = cv2.dilate(drawn.view(np.uint8), kernel).astype(bool)
        inside = (slice(y0 - gy0, y0 - gy0 + bh), slice(x0 - gx0, x0 - gx0 + bw))
        out = mask[inside]
        if real is None or not out.any():
            return out
        core = drawn
        if kernel is not None:
            core = cv2.erode(drawn.view(np.uint8), kernel).astype(bool)
        core = core[inside]
        if int(np.count_nonzero(core)) < ROBOT_COLOUR_PIXELS:
            return out
        part = np.asarray(real[y0:y0 + bh, x0:x0 + bw], np.int16)
        if part.shape[:2] != out.shape:
            return out
        colour = np.median(part[core], axis=0)
        off = np.abs(part - colour)
        unlike = (off.max(axis=-1) if off.ndim == 3 else off) > self.threshold
        return out & ~unlike

    def imagined_mask(self, label: int) -> NDArray[np.bool_] | None:
        """Pixels of the real frame where the imagination shows the object of ``label``,
        or None (no alignment, or no ball drawn)."""
        return None if self.warped_labels is None else self.warped_labels == label

    def imagined_in(self, region: "Region") -> str | None:
        """The imagined moving ball that covers the most of ``region`` (at least a tenth of
        it), or None: the imagination's label image says which difference belongs to which
        imagined object."""
        balls = {lab: n for n, lab in self.drawn.items()
                 if LABEL_BALL <= lab < LABEL_ROBOT}
        warped = self.warped_labels if balls else None
        if warped is None:
            return None
        x, y, w, h = region.bbox
        patch = warped[y:y + h, x:x + w][region.silhouette[:h, :w]]
        best, count = None, 0
        for label, name in balls.items():
            c = int(np.count_nonzero(patch == label))
            if c > count:
                best, count = name, c
        return best if count >= 0.1 * max(region.area, 1) else None


@dataclass(frozen=True, slots=True)
class Sighting:
    """An object found in one frame: its blob in the real image and the floor position
    the fit gives."""

    frame: int
    time: float
    bbox: BBox
    centroid: tuple[float, float]
    area: int
    position: Vec2


@dataclass(frozen=True, slots=True, eq=False)
class ObjectPercept:
    """What a foreground object schema perceived of its object (see the module docstring).

    Attributes
    ----------
    frame, time : int, float
        The frame it describes (``frame`` -1: published when the schema joined,
        before it looked at a frame).
    object : str
        The world object (the imagined body's name).
    declared : bool
        The world declares it.
    ball : Ball or None
        What it is like: the model, its size measured for an object the
        scenario does not declare (None until then), its parameters as adapted.
    sighting : Sighting or None
        Where it was found in this frame (None: not seen).
    position, velocity : (x, y) or None
        The filtered floor position and velocity (None before the first
        sighting).
    imagined : (x, y) or None
        The imagined body's position (None while the imagination has no body).
    doubted : bool
        The imagined body has lost the object: since the object was last seen it
        showed in the view in more than ``lost_after`` frames, and the object was not
        found there (:data:`adapt.schemas.foreground.DOUBT_SHOWN`).
    prediction : Prediction or None
        The latest prediction.
    estimates : mapping of str to Estimate
        The parameter estimates (restitution, friction, rolling resistance).
    rollouts : (float, float)
        Seconds of imagination rolled out for predictions so far, and the wall
        seconds that took.
    """

    frame: int
    time: float
    object: str
    declared: bool = False
    ball: "Ball | None" = None
    sighting: Sighting | None = None
    position: Vec2 | None = None
    velocity: Vec2 | None = None
    imagined: Vec2 | None = None
    doubted: bool = False
    prediction: "Prediction | None" = None
    estimates: Mapping[str, "Estimate"] = field(default_factory=lambda: MappingProxyType({}))
    rollouts: tuple[float, float] = (0.0, 0.0)

    @property
    def seen(self) -> bool:
        """Found in this frame."""
        return self.sighting is not None

    @property
    def observed(self) -> Vec2 | None:
        """The filtered position when the object is seen in this frame, else None."""
        return self.position if self.sighting is not None else None

    @property
    def trajectory(self) -> "Trajectory | None":
        """The prediction's dense path, or None."""
        return None if self.prediction is None else self.prediction.trajectory
