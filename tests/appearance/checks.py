"""Issue 14's checks, run on a scenario's reality: the Scene Background schema alone
(no rules, so a ball stays an *unexpected* region and nothing monitors it) over its
frames, with the truth used only here, to say where the ball is.

Used by ``tests/appearance/test_checks.py`` and ``bench/appearance.py``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from adapt.geometry import Camera
from adapt.imagination import LABEL_FLOOR, Renderer
from adapt.mirror import Mirror
from adapt.reality import open_reality
from adapt.scenario import Scenario, load_scenario
from adapt.schemas import SchemaNetwork
from adapt.schemas.background import AppearanceStage, SceneBackground
from adapt.schemas.percepts import BackgroundPercept
from adapt.seeds import Streams
from adapt.vision.regions import find_regions
from adapt.vision.scale import image_scale

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
SYNTHETIC = HERE / "room.yaml"
VIDEO = ROOT / "scenarios" / "video-sequence.yaml"
#: The synthetic reality that made the video's frames (its camera offset is the video's truth).
VIDEO_MAKER = ROOT / "scenarios" / "video" / "synthetic.yaml"
#: A region at most this share of the frame's pixels is "small".
SMALL_SHARE = 0.001


@dataclass
class FrameCheck:
    """What one frame showed."""

    index: int
    stage: str
    aligned: bool
    pixel_error: float
    unexpected: list[tuple[tuple[int, int, int, int], int]]  # (bbox, area)
    ball: tuple[float, float] | None  # the true ball's centre in the frame's pixels (maybe outside)
    ball_radius_px: float = 0.0
    learn_ms: float = 0.0
    ms: float = 0.0


@dataclass
class Trial:
    """A run of the Scene Background schema over a reality."""

    scenario: Scenario
    frames: list[FrameCheck] = field(default_factory=list)
    network: SchemaNetwork | None = None
    background: SceneBackground | None = None
    images: dict[int, np.ndarray] = field(default_factory=dict)  # kept real frames
    renders: dict[int, np.ndarray] = field(default_factory=dict)  # the mirror's render then
    cameras: dict[int, Camera] = field(default_factory=dict)  # synthetic camera per kept frame
    true_cameras: dict[int, Camera] = field(default_factory=dict)
    wall_s: float = 0.0

    @property
    def mirror(self) -> Mirror:
        assert self.network is not None
        return self.network.mirror

    def learned(self) -> list[FrameCheck]:
        return [f for f in self.frames if f.stage == AppearanceStage.LEARNED.value]

    def background_only(self) -> list[FrameCheck]:
        """Learned frames in which no part of the ball (nor its shadow) is in view."""
        return [f for f in self.learned() if not _in_view(self, f, 2.5)]

    def with_ball(self) -> list[FrameCheck]:
        """Learned frames in which the ball is visible: its centre is in the image."""
        return [f for f in self.learned() if _in_view(self, f, 0.0)]


def video_true_camera() -> Camera:
    """The camera that filmed the shipped video: its maker's camera offset, applied."""
    from adapt.reality.camera import offset_camera

    maker = load_scenario(VIDEO_MAKER)
    off = maker.reality.camera  # type: ignore[union-attr]
    return offset_camera(maker.camera, off.position, off.rotation_deg)


def _in_view(trial: Trial, frame: FrameCheck, radii: float) -> bool:
    """The ball's centre is in the image, or within ``radii`` of its radius of it."""
    if frame.ball is None:
        return False
    w, h = trial.scenario.camera.width, trial.scenario.camera.height
    m = radii * frame.ball_radius_px
    x, y = frame.ball
    return -0.5 - m <= x <= w - 0.5 + m and -0.5 - m <= y <= h - 0.5 + m


def load(path: Path, **schema: Any) -> Scenario:
    """A scenario whose scene-background parameters are ``schema`` (on top of its own)."""
    overrides = [f"schemas.scene-background.{k}={v}" for k, v in schema.items()]
    return load_scenario(path, overrides)


def run_background(scenario: Scenario, *, frames: int | None = None, keep: tuple[int, ...] = (),
                   appearance: str = "on", parameters: dict[str, Any] | None = None,
                   camera: Camera | None = None) -> Trial:
    """Run the Scene Background schema alone over ``scenario``'s reality."""
    seed = scenario.seed or 0
    streams = Streams(seed)
    source = open_reality(scenario, streams=streams)
    fps = float(source.fps)
    mirror = Mirror(scenario.scene, camera or scenario.camera, seed=seed)
    if scenario.appearance is not None:
        mirror.load_appearance(scenario.appearance)
    network = SchemaNetwork(mirror, settings=scenario.schemas,
                            models={m.name: m for m in scenario.objects},
                            frame_interval=1.0 / fps, reality=scenario.reality.kind)
    params = {"appearance": appearance, **(parameters or {})}
    bg = network.instantiate("scene-background", parameters=params)
    assert isinstance(bg, SceneBackground)
    trial = Trial(scenario, network=network, background=bg)
    truth = getattr(source, "truth", None)
    filmed = video_true_camera() if scenario.reality.kind.value == "video" else scenario.camera
    limit = frames if frames is not None else scenario.run.frames
    started = time.perf_counter()
    try:
        for frame in source:
            if frame.index >= limit:
                break
            t0 = time.perf_counter()
            network.perceive(frame)
            ms = (time.perf_counter() - t0) * 1000.0
            at = truth.at(frame.index) if truth is not None else None
            true_cam = at.camera if at is not None and at.camera is not None else filmed
            ball, radius = None, 0.0
            if at is not None:
                obj = at.objects.get("ball")
                if obj is not None:
                    ball, radius = _seen_at(true_cam, obj.position,
                                            scenario.model("ball").ball.radius)
            seen = network.published(BackgroundPercept)[0]
            trial.frames.append(FrameCheck(
                frame.index, seen.stage.value, seen.aligned, seen.pixel_error,
                [(r.bbox, r.area) for r in seen.unexpected], ball, radius, seen.learn_ms, ms))
            if frame.index in keep:
                trial.images[frame.index] = frame.image
                trial.renders[frame.index] = mirror.render().image
                trial.cameras[frame.index] = mirror.camera
                trial.true_cameras[frame.index] = true_cam
            mirror.step_to(frame.time + 1.0 / fps)
    finally:
        source.close()
    trial.wall_s = time.perf_counter() - started
    return trial


def _seen_at(camera: Camera, position: tuple[float, float], radius: float
             ) -> tuple[tuple[float, float] | None, float]:
    """The pixel of a ball's centre (None behind the camera) and its radius in pixels."""
    centre = np.array([position[0], position[1], radius])
    p = camera.project(centre[None, :])[0]
    if not np.isfinite(p).all():
        return None, 0.0
    z = float(camera.to_camera(centre[None, :])[0, 2])
    return (float(p[0]), float(p[1])), camera.fx * radius / max(z, 1e-6)


def ball_region(frame: FrameCheck) -> tuple[tuple[int, int, int, int], int] | None:
    """The unexpected region that holds the ball's true centre (None: none does)."""
    if frame.ball is None:
        return None
    bx, by = frame.ball
    pad = 3
    for bbox, area in frame.unexpected:
        x, y, w, h = bbox
        if x - pad <= bx <= x + w + pad and y - pad <= by <= y + h + pad:
            return bbox, area
    return None


def look_regions(real: np.ndarray, synthetic: np.ndarray, *, threshold: float = 30.0
                 ) -> tuple[int, int]:
    """(count, total area) of the regions where ``real`` differs from ``synthetic`` more
    than ``threshold`` grey levels in some channel, with both in the same pixels (no
    alignment: the appearance, not the pose, is compared) after a per-channel gain and
    bias fitted by least squares; regions as the Scene Background finds them (the MMD's
    ``min_area`` and opening, scaled with the image)."""
    r = real.reshape(-1, 3).astype(np.float64)
    s = synthetic.reshape(-1, 3).astype(np.float64)
    adjusted = np.empty_like(s)
    for c in range(3):
        a = np.c_[s[:, c], np.ones(len(s))]
        coef, *_ = np.linalg.lstsq(a, r[:, c], rcond=None)
        adjusted[:, c] = a @ coef
    diff = np.abs(r - adjusted).max(axis=1).reshape(real.shape[:2]).astype(np.float32)
    scale = image_scale(real.shape)
    regions = find_regions(diff, threshold=threshold, min_area=max(1, round(40 * scale * scale)))
    return len(regions), int(sum(g.area for g in regions))


def scenario_look(scenario: Scenario, camera: Camera) -> np.ndarray:
    """The scenario's look (no appearance learned) through ``camera``: its render."""
    return Renderer(scenario.scene, camera).background.image


def true_pixel_error(synthetic: Camera, true: Camera, labels: np.ndarray) -> float:
    """Median distance, in pixels, between where the synthetic and the true camera
    see the floor points of the synthetic view (every 8th pixel of the floor)."""
    ys, xs = np.nonzero(labels[::8, ::8] == LABEL_FLOOR)
    pix = np.c_[xs * 8, ys * 8].astype(float)
    world = synthetic.pixel_to_plane(pix, 0.0)
    ok = np.isfinite(world).all(axis=1)
    seen = true.project(world[ok])
    return float(np.median(np.linalg.norm(seen - pix[ok], axis=1)))


def floor_redness(trial: Trial) -> float:
    """The largest share, over 5x5-texel windows of the learned floor, of texels whose
    red exceeds their blue and green by 60 grey levels (the ball is red; gravel is grey)."""
    t = trial.mirror.appearance.texture("floor")
    assert t is not None
    img = t.image.astype(int)
    red = ((img[:, :, 2] - np.maximum(img[:, :, 0], img[:, :, 1]) > 60) & t.mask)
    share = cv2.blur(red.astype(np.float32), (5, 5))
    return float(share.max())


def small_area(shape: tuple[int, ...]) -> float:
    """The largest region area that counts as small, pixels."""
    return SMALL_SHARE * shape[0] * shape[1]


def with_camera(scenario: Scenario, camera: Camera) -> Scenario:
    """The scenario with another starting camera."""
    return replace(scenario, camera=camera)


def nan_to_none(v: float) -> float | None:
    return None if math.isnan(v) else v
