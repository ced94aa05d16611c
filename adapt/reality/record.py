"""Recording a synthetic reality as an image sequence with its ground truth.

:func:`record_sequence` plays a synthetic scenario and writes what a video
scenario reads back: numbered images (``frame_0000.jpg``, ...) and a
ground-truth CSV ``t,object,x,y,vx,vy`` with one row per frame and present
object.  The bundled ``scenarios/video-sequence.yaml`` plays such a sequence,
made from ``scenarios/video/synthetic.yaml`` by
``python bench/make_video_sequence.py``.

Every file is written atomically (:mod:`adapt.files`).

Examples
--------
>>> import tempfile, pathlib
>>> from adapt.scenario import loads_scenario
>>> sc = loads_scenario('''
... camera: {fx: 100, fy: 100, cx: 40, cy: 30, width: 80, height: 60,
...          position: [0, -2, 1], look_at: [0, 1, 0]}
... world: {objects: [{name: ball, velocity: [1, 0]}]}
... run: {fps: 10, max_frames: 3}
... ''')
>>> out = pathlib.Path(tempfile.mkdtemp())
>>> written = record_sequence(sc, out, seed=1)
>>> sorted(p.name for p in (out / "frames").iterdir()), written.frames
(['frame_0000.jpg', 'frame_0001.jpg', 'frame_0002.jpg'], 3)
>>> (out / "truth.csv").read_text().splitlines()[:2]
['t,object,x,y,vx,vy', '0,ball,0,0,1,0']
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import cv2

from adapt.errors import ImageError, RealityError
from adapt.files import write_atomic
from adapt.reality.synthetic import SyntheticSource
from adapt.scenario import Scenario
from adapt.seeds import Streams

__all__ = ["record_sequence", "Recording"]


@dataclass(frozen=True, slots=True)
class Recording:
    """What :func:`record_sequence` wrote: the frames' folder, the truth file,
    the number of frames and their total size in bytes."""

    frames_dir: Path
    truth: Path
    frames: int
    bytes: int


def _fmt(v: float, digits: int = 6) -> str:
    """A number for the CSV, trailing zeros dropped."""
    s = f"{v:.{digits}f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def record_sequence(scenario: Scenario, out: str | Path, *, seed: int | None = None,
                    quality: int = 85, extension: str = ".jpg") -> Recording:
    """Play ``scenario`` (a synthetic reality, no robot commands) into ``out``.

    Writes ``out/frames/frame_NNNN<extension>`` and ``out/truth.csv``.
    ``seed`` defaults to the scenario's; ``quality`` is the JPEG quality.

    Raises
    ------
    RealityError
        If the scenario's reality is not synthetic.
    ImageError
        If a frame cannot be encoded.
    """
    out = Path(out)
    frames_dir = out / "frames"
    frames_dir.mkdir(parents=True, exist_ok=True)
    source = SyntheticSource(scenario, streams=Streams(scenario.seed if seed is None else seed))
    if extension not in (".jpg", ".png"):
        raise RealityError(f"expected .jpg or .png frames, got {extension!r}")
    params = [int(cv2.IMWRITE_JPEG_QUALITY), int(quality)] if extension == ".jpg" else []
    csv = io.StringIO()
    csv.write("t,object,x,y,vx,vy\n")
    total = 0
    count = 0
    for frame in source:
        ok, data = cv2.imencode(extension, frame.image, params)
        if not ok:
            raise ImageError(f"frame {frame.index} could not be encoded as {extension}")
        blob = data.tobytes()
        write_atomic(frames_dir / f"frame_{frame.index:04d}{extension}", blob)
        total += len(blob)
        count += 1
        truth = source.truth.at(frame.index)
        assert truth is not None
        for name, o in truth.objects.items():
            if o is None:
                continue
            assert o.velocity is not None
            csv.write(",".join([_fmt(frame.time, 9), name, *(_fmt(v) for v in o.position),
                                *(_fmt(v) for v in o.velocity)]) + "\n")
    source.close()
    data_csv = csv.getvalue().encode("utf-8")
    write_atomic(out / "truth.csv", data_csv)
    return Recording(frames_dir, out / "truth.csv", count, total + len(data_csv))
