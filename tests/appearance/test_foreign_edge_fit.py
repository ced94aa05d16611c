"""A fixed camera off the scenario's pose is put back by its edges before the look is learned.

Throws 39 and 42 of ``bench/foreign.py --small``: a camera outside the arena, above a low
wall, 2 cm and 1 degree off where the scenario puts it.  The structure's alignment (a turn
of the image fitted to a flat look) leaves the floor mapped 4.7 and 24 cm off, and the ball
with it.  The edge fit (:mod:`adapt.vision.edge_pose`) fits the pose to the frame's edges at
the structure's seams, from the scenario's pose, before the first look is learned through it:
0.8 and 1.4 cm.  (Throws 15 and 36 were the cases until the reality's walls were drawn without
their collision boxes' white noise, 2026-11-28: the noise had misled the structure's alignment,
which now leaves throw 15 within 1 cm by itself.)
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from adapt.geometry import Camera
from adapt.runner import Runner
from adapt.schemas.background import SceneBackground

from .bench_throws import QUIET, throw

pytest.importorskip("pybullet")


def floor_error_m(cam: Camera, true_cam: Camera, extent: tuple[float, ...], z: float = 0.1) -> float:
    """Median distance between where ``cam`` and ``true_cam`` put points of the arena's floor
    (at about a ball's height) that ``true_cam`` sees."""
    x0, y0, x1, y1 = extent
    xs, ys = np.meshgrid(np.linspace(x0 + 0.15, x1 - 0.15, 12), np.linspace(y0 + 0.15, y1 - 0.15, 12))
    points = np.c_[xs.ravel(), ys.ravel(), np.full(xs.size, z)]
    px = true_cam.project(points)
    seen = (px[:, 0] >= 0) & (px[:, 0] < true_cam.width) & (px[:, 1] >= 0) & (px[:, 1] < true_cam.height)
    return float(np.median(np.linalg.norm(cam.pixel_to_plane(px[seen], z)[:, :2] - points[seen, :2],
                                          axis=1)))


class _Last:
    def __init__(self) -> None:
        self.runner: Any = None
        self.error: float = float("nan")
        self.fit: Any = None

    def frame(self, record: Any) -> None:
        bg = next(s for s in self.runner.network if isinstance(s, SceneBackground))
        extent = self.runner.scenario.scene.floor.extent
        self.error = floor_error_m(self.runner.mirror.camera, self.runner.truth.at(record.index).camera,
                                   extent)
        self.fit = bg.edge_fit


def _run(seed: int, *overrides: str) -> _Last:
    sc = throw(seed, 0.5, *overrides)
    last = _Last()
    runner = Runner(sc, out=None, seed=seed, outputs=QUIET, listeners=(last,))
    last.runner = runner
    runner.run()
    return last


@pytest.mark.parametrize("seed", [39, 42])
def test_the_edge_fit_puts_a_fixed_camera_back_on_the_floor(seed: int) -> None:
    fitted = _run(seed)
    unfitted = _run(seed, "schemas.scene-background.edge_fit=false")
    assert fitted.fit is not None and unfitted.fit is None
    assert unfitted.error > 0.04, unfitted.error  # what the structure's alignment left
    assert fitted.error < 0.025, fitted.error
    assert fitted.error < 0.4 * unfitted.error
