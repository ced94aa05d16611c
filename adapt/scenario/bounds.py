"""The bounds of every number a scenario gives: declared once, here, by its documented key.

:data:`BOUNDS` maps each numeric key of ``docs/scenario.md`` (list items as
``[i]``: ``world.walls[i].height``) to its :class:`Bound`.  The scenario
reader looks a number's bound up by the key path it reads
(:func:`generic`), so ``adapt check`` refuses what ``adapt run`` would
refuse, at the value's position and under the scenario's own key; the
documentation's type column shows :attr:`Bound.text` (a test keeps the page
and this table in step, and another tries every key at its bounds through
``check`` and ``run``).

The bounds are those of the records the values become (the imagination's
:mod:`~adapt.imagination.scene` limits, the camera's
:mod:`~adapt.geometry` limits, with the smallest image vision works on), made
narrower where a wider value could only fail later in a run: a physics step
of a tenth of a second at most, speeds of at most 100 m/s, angles within a
turn.  Values that bound each other (a ball's speed and the physics step, a
prediction ensemble and its horizon, the texture scale and the tiles) are
checked together by the reader after the single values.

Examples
--------
>>> BOUNDS["world.walls[i].height"].text
'number from 0.001 to 10000'
>>> BOUNDS["run.fps"].text, BOUNDS["world.objects[i].restitution"].text
('number from 0.1 to 1000', 'number from 0 to 1')
>>> BOUNDS["world.walls[i].height"].problem(-1.0)
'expected a positive number, at least 0.001 metres, got -1'
>>> BOUNDS["run.max_frames"].problem(10**300)
'expected an integer from 1 to 1000000, got a 301-digit number'
>>> generic("world.walls[2].height"), generic("reality.objects[0].throw.x")
('world.walls[i].height', 'reality.objects[i].throw.x')
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from adapt.geometry import MAX_COORDINATE, MAX_FOCAL, MAX_IMAGE_SIDE, MIN_IMAGE_SIDE
from adapt.imagination.scene import (
    MAX_ACCEL,
    MAX_COEFFICIENT,
    MAX_MASS,
    MIN_MASS,
    MIN_SIZE,
)

__all__ = ["Bound", "BOUNDS", "BULLET_BOUNDS", "CHANNEL", "generic", "bound_of", "bullet_bound",
           "show", "MAX_STEP", "MIN_STEP", "MAX_BODY_SPEED",
           "MAX_OFFSET", "MAX_ANGLE", "MAX_SEED", "MAX_DISTORTION", "MAX_DEVICE"]

#: The physics steps a scenario may choose (``world.dt``, ``reality.dt``), seconds.
MIN_STEP, MAX_STEP = 1.0e-5, 0.1
#: The fastest a ball or the robot may be said to go, m/s.
MAX_BODY_SPEED = 100.0
#: The farthest the true camera may be from the scenario's, metres.
MAX_OFFSET = 100.0
#: Angles are within one turn either way, degrees.
MAX_ANGLE = 360.0
#: The largest lens distortion coefficient, either sign (OpenCV's rational model's k4..k6
#: reach tens; beyond this no real lens is described).
MAX_DISTORTION = 1000.0
#: The highest camera device index (OpenCV adds its capture API's number, up to a few
#: thousand, to an index).
MAX_DEVICE = 9999
#: The largest seed (numpy's generators take any, the report's JSON readers do not).
MAX_SEED = 2**63 - 1


def show(value: float) -> str:
    """A value as an error message shows it: ``:g``, an integer of many digits by its length.

    Examples
    --------
    >>> show(7), show(0.25), show(1e300), show(10**40)
    ('7', '0.25', '1e+300', 'a 41-digit number')
    >>> show(1e6), show(1e-5)
    ('1000000', '1e-05')
    """
    if isinstance(value, int) and abs(value) >= 10**16:
        return f"a {len(str(abs(value)))}-digit number"
    if float(value).is_integer() and abs(value) < 10**16:
        return str(int(value))
    return f"{value:g}"


def _plain(value: float) -> str:
    """A bound as written: whole numbers in full, others by ``:g``."""
    return str(int(value)) if float(value).is_integer() else f"{value:g}"


@dataclass(frozen=True, slots=True)
class Bound:
    """The numbers a key accepts: ``low`` to ``high`` (None: no bound on that side),
    ``low_open`` / ``high_open`` exclude the bound itself; ``integer`` asks for a whole
    number; ``unit`` is shown in messages."""

    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    integer: bool = False
    unit: str = ""

    @property
    def text(self) -> str:
        """How the documentation states the bound (``number > 0, at most 1000``)."""
        kind = "integer" if self.integer else "number"
        lo, hi = self.low, self.high
        if lo is not None and hi is not None and not self.low_open and not self.high_open:
            return f"{kind} from {_plain(lo)} to {_plain(hi)}"
        parts = [kind]
        if lo is not None:
            parts[0] += f" {'>' if self.low_open else '≥'} {_plain(lo)}"
        if hi is not None:
            parts.append(f"{'below' if self.high_open else 'at most'} {_plain(hi)}")
        return ", ".join(parts)

    def contains(self, v: float) -> bool:
        """Whether ``v`` is within the bound."""
        lo, hi = self.low, self.high
        if lo is not None and (v < lo or (self.low_open and v == lo)):
            return False
        return not (hi is not None and (v > hi or (self.high_open and v == hi)))

    def problem(self, v: float) -> str | None:
        """What is wrong with ``v`` (``expected ..., got ...``), or None when it fits."""
        if self.contains(v):
            return None
        unit = f" {self.unit}" if self.unit else ""
        got = f", got {show(v)}"
        lo, hi = self.low, self.high
        kind = "integer" if self.integer else "number"
        if lo is not None and (v < lo or v == lo):
            if lo == 0:
                return f"expected {'a positive' if self.low_open else 'a non-negative'} {kind}{got}"
            if v <= 0 < lo:
                return f"expected a positive {kind}, at least {_plain(lo)}{unit}{got}"
        if lo is not None and hi is not None and not self.low_open and not self.high_open:
            return f"expected {'an' if self.integer else 'a'} {kind} from {_plain(lo)} to {_plain(hi)}{unit}{got}"
        if lo is not None and (v < lo or v == lo):
            return f"expected {'more than' if self.low_open else 'at least'} {_plain(lo)}{unit}{got}"
        assert hi is not None
        return f"expected {'less than' if self.high_open else 'at most'} {_plain(hi)}{unit}{got}"


def _b(low: float | None, high: float | None, unit: str = "", *, low_open: bool = False,
       integer: bool = False) -> Bound:
    return Bound(low, high, low_open=low_open, integer=integer, unit=unit)


_UNIT = _b(0.0, 1.0)
_COORD = _b(-MAX_COORDINATE, MAX_COORDINATE, "metres")
_SIZE = _b(MIN_SIZE, MAX_COORDINATE, "metres")
_MASS = _b(MIN_MASS, MAX_MASS, "kilograms")
_COEFF = _b(0.0, MAX_COEFFICIENT)
_DRAG = _b(0.0, MAX_COEFFICIENT, "per metre")
_SPEED = _b(-MAX_BODY_SPEED, MAX_BODY_SPEED, "m/s")
_TOP_SPEED = _b(0.0, MAX_BODY_SPEED, "m/s", low_open=True)
_ACCEL = _b(0.0, MAX_ACCEL, "m/s²", low_open=True)
_ANGLE = _b(-MAX_ANGLE, MAX_ANGLE, "degrees")
_STEP = _b(MIN_STEP, MAX_STEP, "seconds")
_GREY = _b(-255.0, 255.0, "grey levels")
_SURFACE = {"height": _SIZE, "tile": _SIZE, "restitution": _UNIT, "friction": _COEFF}
#: PyBullet's rolling and spinning friction (a length).
_BULLET_FRICTION = _b(0.0, 1.0, "metres")
#: A PyBullet reality's contact parameters of the floor, the walls and the obstacles.
_BULLET_SURFACE = {"restitution": _UNIT, "friction": _COEFF,
                   "rolling_friction": _BULLET_FRICTION, "spinning_friction": _BULLET_FRICTION}

#: Every numeric key of a scenario and its bound (a vector's bound holds for each of its
#: numbers; a range's for both ends).
BOUNDS: dict[str, Bound] = {
    "seed": _b(0, MAX_SEED, integer=True),
    "camera.fx": _b(0.0, MAX_FOCAL, "pixels", low_open=True),
    "camera.fy": _b(0.0, MAX_FOCAL, "pixels", low_open=True),
    "camera.cx": _b(-MAX_FOCAL, MAX_FOCAL, "pixels"),
    "camera.cy": _b(-MAX_FOCAL, MAX_FOCAL, "pixels"),
    "camera.width": _b(MIN_IMAGE_SIDE, MAX_IMAGE_SIDE, "pixels", integer=True),
    "camera.height": _b(MIN_IMAGE_SIDE, MAX_IMAGE_SIDE, "pixels", integer=True),
    "camera.position": _COORD,
    "camera.look_at": _COORD,
    "camera.roll_deg": _ANGLE,
    "camera.distortion": _b(-MAX_DISTORTION, MAX_DISTORTION),
    "world.dt": _STEP,
    "world.gravity": _ACCEL,
    "world.floor.tile": _SIZE,
    "world.floor.extent": _COORD,
    **{f"world.walls[i].{k}": b for k, b in _SURFACE.items()},
    "world.walls[i].from": _COORD,
    "world.walls[i].to": _COORD,
    **{f"world.obstacles[i].{k}": b for k, b in _SURFACE.items()},
    "world.obstacles[i].polygon": _COORD,
    "world.objects[i].radius": _SIZE,
    "world.objects[i].mass": _MASS,
    "world.objects[i].restitution": _UNIT,
    "world.objects[i].friction": _COEFF,
    "world.objects[i].rolling_resistance": _COEFF,
    "world.objects[i].floor_friction": _COEFF,
    "world.objects[i].drag": _DRAG,
    "world.objects[i].position": _COORD,
    "world.objects[i].velocity": _SPEED,
    "world.objects[i].ranges.restitution": _UNIT,
    "world.objects[i].ranges.friction": _COEFF,
    "world.objects[i].ranges.rolling_resistance": _COEFF,
    "world.objects[i].ranges.floor_friction": _COEFF,
    "world.objects[i].ranges.drag": _DRAG,
    "world.robot.radius": _SIZE,
    "world.robot.size": _SIZE,
    "world.robot.position": _COORD,
    "world.robot.heading_deg": _ANGLE,
    "world.robot.max_speed": _TOP_SPEED,
    "world.robot.max_accel": _ACCEL,
    "world.robot.mass": _MASS,
    "world.robot.height": _SIZE,
    "reality.dt": _STEP,
    "reality.fps": _b(0.1, 1000.0, "frames/s"),
    "reality.device": _b(0, MAX_DEVICE, integer=True),
    "reality.stall_s": _b(0.0, 3600.0, "seconds", low_open=True),
    "reality.camera_offset": _b(-MAX_OFFSET, MAX_OFFSET, "metres"),
    "reality.camera_offset_deg": _b(-180.0, 180.0, "degrees"),
    "reality.appearance.brightness": _GREY,
    "reality.appearance.contrast": _b(0.0, 10.0, low_open=True),
    "reality.appearance.color_shift": _GREY,
    "reality.appearance.gradient": _UNIT,
    "reality.appearance.gradient_deg": _ANGLE,
    "reality.appearance.blur": _b(0.0, 20.0, "pixels"),
    "reality.appearance.noise": _b(0.0, 100.0, "grey levels"),
    "reality.appearance.texture_scale": _b(0.01, 100.0),
    "reality.appearance.texture_phase": _COORD,
    "reality.appearance.tint": _b(0.0, 4.0, low_open=True),
    "reality.robot.max_speed": _TOP_SPEED,
    "reality.robot.max_accel": _ACCEL,
    "reality.robot.slip": _UNIT,
    "reality.robot.slip_interval": _b(0.0, 3600.0, "seconds", low_open=True),
    "reality.objects[i].radius": _SIZE,
    "reality.objects[i].position": _COORD,
    "reality.objects[i].velocity": _SPEED,
    "reality.objects[i].restitution": _UNIT,
    "reality.objects[i].friction": _COEFF,
    "reality.objects[i].rolling_resistance": _COEFF,
    "reality.objects[i].mass": _MASS,
    "reality.objects[i].drag": _b(0.0, 10.0, "per metre"),
    "reality.objects[i].spin": _UNIT,
    "reality.objects[i].throw.t": _b(0.0, 1.0e6, "seconds"),
    "reality.objects[i].throw.x": _COORD,
    "reality.objects[i].throw.y": _COORD,
    "reality.objects[i].throw.speed": _b(0.0, MAX_BODY_SPEED, "m/s"),
    "reality.objects[i].throw.heading_deg": _ANGLE,
    # kind: bullet (a key it shares with kind: synthetic has the bound above unless
    # BULLET_BOUNDS narrows it)
    "reality.wall_thickness": _b(MIN_SIZE, 100.0, "metres"),
    **{f"reality.{group}.{k}": b for group in ("floor", "walls", "obstacles")
       for k, b in _BULLET_SURFACE.items()},
    "reality.objects[i].rolling_friction": _BULLET_FRICTION,
    "reality.objects[i].spinning_friction": _BULLET_FRICTION,
    "reality.objects[i].damping": _UNIT,
    "reality.objects[i].side_spin": _b(-1000.0, 1000.0, "rad/s"),
    "reality.objects[i].throw.height": _b(0.0, 100.0, "metres"),
    "reality.look.texture_scale": _b(0.0, 100.0, low_open=True),
    "reality.look.light_elevation_deg": _b(5.0, 90.0, "degrees"),
    "reality.look.light_azimuth_deg": _ANGLE,
    "reality.look.light_warmth": _b(-1.0, 1.0),
    "reality.look.ambient": _b(0.0, 2.0),
    "reality.look.diffuse": _b(0.0, 2.0),
    "reality.look.specular": _b(0.0, 2.0),
    "reality.look.gain": _b(0.0, 4.0, low_open=True),
    "reality.look.vignette": _UNIT,
    "reality.look.blur": _b(0.0, 20.0, "pixels"),
    "reality.look.noise": _b(0.0, 100.0, "grey levels"),
    "run.fps": _b(0.1, 1000.0, "frames/s"),
    "run.duration": _b(0.0, None, "seconds", low_open=True),
    "run.max_frames": _b(1, 1_000_000, integer=True),
    "run.seed": _b(0, MAX_SEED, integer=True),
    "run.decisions_per_frame": _b(1, 1000, integer=True),
    "predict.horizons": _b(0.0, 60.0, "seconds", low_open=True),
    "predict.every": _b(1, 1_000_000, integer=True),
    "predict.ensemble": _b(1, 1000, integer=True),
    "predict.evidence": _b(0, 100, integer=True),
    "outputs.trace_level": _b(1, 5, integer=True),
}

#: The keys a ``kind: bullet`` reality bounds otherwise than :data:`BOUNDS` (the same key
#: path means another thing there, or PyBullet needs less).
BULLET_BOUNDS: dict[str, Bound] = {
    "reality.dt": _b(MIN_STEP, 0.01, "seconds"),  # restitution needs fine steps
    "reality.objects[i].spin": _b(-10.0, 10.0),  # a share of rolling, negative: back-spin
}

#: A colour's channel (``[r, g, b]``).
CHANNEL = Bound(0.0, 255.0)

_INDEX = re.compile(r"\[\d+\]")


def generic(path: str) -> str:
    """A key path with its list indices as ``[i]`` (the key :data:`BOUNDS` knows it by)."""
    return _INDEX.sub("[i]", path)


def bound_of(path: str) -> Bound:
    """The bound of the number at ``path`` (a vector's or a range's own key path).

    Raises
    ------
    KeyError
        For a key that has no declared bound (a reader reading an undeclared number).
    """
    return BOUNDS[generic(path)]


def bullet_bound(path: str) -> Bound:
    """The bound of the number at ``path`` in a ``kind: bullet`` reality.

    Examples
    --------
    >>> bullet_bound("reality.dt").text, bound_of("reality.dt").text
    ('number from 1e-05 to 0.01', 'number from 1e-05 to 0.1')
    >>> bullet_bound("reality.objects[0].restitution").text
    'number from 0 to 1'
    """
    key = generic(path)
    return BULLET_BOUNDS[key] if key in BULLET_BOUNDS else BOUNDS[key]

