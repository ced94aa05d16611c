"""Reality sources: where the "real" frames come from.

:func:`open_reality` turns a scenario's ``reality`` section into a
:class:`RealitySource`: a :class:`~adapt.frames.FrameSource` (``size``,
``fps``, iteration over :class:`~adapt.frames.Frame` s, ``close``) with two
optional extras kept apart from the frames:

* ``robot``: an :class:`~adapt.frames.Actuator` that moves the *real* robot
  (a synthetic reality with a robot), or None;
* ``truth``: a :class:`~adapt.reality.truth.GroundTruth` whose
  ``at(index)`` is the truth of a frame, **for evaluation only**, or None.

Modules, one noun each:

* :mod:`~adapt.reality.synthetic` - the synthetic reality (a ground-truth
  world seen through a true camera);
* :mod:`~adapt.reality.physics` - reality's own physics on top of the
  imagination's world (drag, spin, throws, a slipping robot);
* :mod:`~adapt.reality.camera` - the true camera pose (the nominal one moved
  by a mounting error);
* :mod:`~adapt.reality.appearance` - how the camera image differs from a
  render (tint, lighting, contrast, colour, blur, noise, spin markers);
* :mod:`~adapt.reality.surfaces` - the real surfaces' texture phase;
* :mod:`~adapt.reality.video` - a video file or an image sequence;
* :mod:`~adapt.reality.live` - a camera: a device, a stream URL, or a file
  played as a camera;
* :mod:`~adapt.reality.bullet` - a reality on PyBullet (another physics engine
  and renderer; the optional extra ``adapt[bullet]``);
* :mod:`~adapt.reality.truth` - ground-truth records and the CSV reader;
* :mod:`~adapt.reality.record` - a synthetic reality written out as an image
  sequence with its truth (how the bundled video scenario was made);
* :mod:`~adapt.reality.warning` - :class:`RealityWarning`.

This package imports the imagination, the scenario records, ``adapt.frames``
and ``adapt.seeds``; it never imports the engine or vision, and nothing on
the perceiving side imports it (``tests/test_architecture.py``).  See
``docs/reality.md``.

Examples
--------
>>> from adapt.scenario import loads_scenario
>>> from adapt.seeds import Streams
>>> sc = loads_scenario('''
... camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60,
...          position: [0, -2, 1], look_at: [0, 1, 0]}
... world: {objects: [{name: ball, velocity: [1, 0]}]}
... run: {fps: 10, max_frames: 2}
... ''')
>>> source = open_reality(sc, streams=Streams(sc.seed))
>>> isinstance(source, RealitySource), source.size, source.robot is None
(True, (80, 60), True)
>>> [f.index for f in source], source.truth.at(1).time
([0, 1], 0.1)
"""

from __future__ import annotations

from typing import Iterator, Protocol, runtime_checkable

from adapt.errors import AdaptError, RealityError
from adapt.frames import Actuator, Frame, FrameSource
from adapt.lens import distorted
from adapt.reality.synthetic import RealRobot, SyntheticSource, draw_parameters
from adapt.reality.truth import (
    CsvTruth,
    FrameTruth,
    GroundTruth,
    ObjectParameters,
    ObjectTruth,
    RecordedTruth,
    RobotState,
    TrueParameters,
)
from adapt.reality.video import VideoSource
from adapt.reality.warning import RealityWarning
from adapt.scenario import (
    REALITIES,
    BulletReality,
    CameraReality,
    PluginReality,
    Scenario,
    SyntheticReality,
)
from adapt.seeds import Streams

__all__ = [
    "open_reality",
    "RealitySource",
    "SyntheticSource",
    "VideoSource",
    "RealRobot",
    "RealityWarning",
    "GroundTruth",
    "FrameTruth",
    "ObjectTruth",
    "RobotState",
    "TrueParameters",
    "ObjectParameters",
    "RecordedTruth",
    "CsvTruth",
    "draw_parameters",
]


@runtime_checkable
class RealitySource(Protocol):
    """A frame source with an optional real robot and optional ground truth."""

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` of every frame."""
        ...

    @property
    def fps(self) -> float:
        """Frames per second."""
        ...

    @property
    def robot(self) -> Actuator | None:
        """The real robot, or None."""
        ...

    @property
    def truth(self) -> GroundTruth | None:
        """Ground truth for evaluation, or None."""
        ...

    def __iter__(self) -> Iterator[Frame]:
        """The frames, in order."""
        ...

    def close(self) -> None:
        """Release what the source holds."""
        ...


def open_reality(scenario: Scenario, *, streams: Streams) -> RealitySource:
    """The reality source of a scenario.

    A synthetic reality draws its true parameters from ``streams`` and shows its
    images through the scenario's lens (``camera.distortion``); a video
    opens its file (or lists its images) and reads its ground truth now, so
    that bad input fails before a run starts.

    Raises
    ------
    RealityError
        A video that cannot be opened, an unreadable first image, a first
        frame of the wrong size or channel count, a video without a frame
        rate.
    GroundTruthError
        A ground-truth file with a bad header or row.
    ScenarioError
        A camera that cannot be opened, states no frame rate, or gives images of
        another size (at the position of ``reality.device``).
    RealityError
        A ``bullet`` reality without PyBullet installed (the message says what to
        install), or one whose drawn camera ends up inside a wall.
    """
    reality = scenario.reality
    if isinstance(reality, SyntheticReality):  # seen through the camera's lens
        return distorted(SyntheticSource(scenario, streams=streams), scenario.lens)  # type: ignore[return-value]
    if isinstance(reality, BulletReality):
        from adapt.reality.bullet import BulletSource

        return distorted(BulletSource(scenario, streams=streams), scenario.lens)  # type: ignore[return-value]
    if isinstance(reality, CameraReality):
        from adapt.reality.live import CameraSource

        return CameraSource.from_scenario(scenario)
    if isinstance(reality, PluginReality):
        return _open_plugin(reality, scenario, streams)
    return VideoSource.from_scenario(scenario)


def _open_plugin(reality: PluginReality, scenario: Scenario, streams: Streams) -> RealitySource:
    """A plugin's kind: its ``open``, and a clear error when it fails or returns no source."""
    rt = REALITIES.get(reality.name)
    where = f"{reality.source.location}: reality kind {reality.name!r} ({REALITIES.origin(rt.name)})"
    try:
        source = rt.open(reality, scenario, streams)
    except AdaptError as exc:
        raise RealityError(f"{where}: {exc}") from None
    except Exception as exc:  # the plugin's code: its message, not a traceback
        raise RealityError(f"{where} failed to open: {type(exc).__name__}: {exc}") from None
    if not isinstance(source, FrameSource):
        raise RealityError(f"{where}: open returned {type(source).__name__}; expected a frame "
                           "source (size, fps, iteration, close)")
    if isinstance(source, RealitySource):
        return source
    return _Plain(source)


class _Plain:
    """A plugin's frame source without robot or truth, as a reality source."""

    def __init__(self, source: FrameSource) -> None:
        self._source = source
        self.robot: Actuator | None = None
        self.truth: GroundTruth | None = None

    @property
    def size(self) -> tuple[int, int]:
        return self._source.size

    @property
    def fps(self) -> float:
        return self._source.fps

    @property
    def length(self) -> int | None:
        """How many frames it has, when it says."""
        n = getattr(self._source, "length", None)
        return None if n is None else int(n)

    def __iter__(self) -> Iterator[Frame]:
        return iter(self._source)

    def close(self) -> None:
        self._source.close()
