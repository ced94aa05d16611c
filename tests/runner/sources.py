"""A small reality for tests: the scene rendered through a true camera that differs
from the scenario's, with sensor noise and objects that appear at given frames.

It is a test double of a frame source (the project's own synthetic reality lives in
``adapt.reality``); it keeps the tests of the schemas and the runner independent of it.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Iterator, Sequence

import numpy as np

from adapt.frames import Frame
from adapt.geometry import Camera, rotation_exp
from adapt.imagination import Ball, Renderer, SceneSpec, World


class RenderedSource:
    """Frames of ``scene`` (plus ``extra`` balls, each shown from its frame on) seen
    through ``camera`` turned by ``turn`` (axis-angle, radians), with noise."""

    def __init__(self, scene: SceneSpec, camera: Camera, *, frames: int, fps: float = 30.0,
                 turn: Sequence[float] = (0.0, 0.0, 0.0), extra: Sequence[tuple[int, Ball]] = (),
                 noise: float = 2.0, seed: int = 0, fail_at: int | None = None,
                 interrupt_at: int | None = None) -> None:
        self.true_camera = camera.with_rotation(rotation_exp(turn) @ camera.rotation)
        self.scene = replace(scene, balls=(*scene.balls, *(b for _, b in extra)))
        self.appear = {b.name: k for k, b in extra}
        self.world = World(self.scene)
        self.renderer = Renderer(self.scene, self.true_camera)
        self.frames = frames
        self._fps = fps
        self.noise = noise
        self.seed = seed
        self.fail_at = fail_at
        self.interrupt_at = interrupt_at
        self.robot = None
        self.truth = None
        self.closed = False

    @property
    def size(self) -> tuple[int, int]:
        return (self.true_camera.width, self.true_camera.height)

    @property
    def fps(self) -> float:
        return self._fps

    def __iter__(self) -> Iterator[Frame]:
        rng = np.random.default_rng(self.seed)
        for i in range(self.frames):
            if i == self.fail_at:
                raise RuntimeError("the camera cable came loose")
            if i == self.interrupt_at:
                raise KeyboardInterrupt
            t = i / self._fps
            self.world.run_until(t)
            state = self.world.snapshot()
            hidden = {name for name, k in self.appear.items() if i < k}
            state = replace(state, bodies=tuple(b for b in state.bodies if b.name not in hidden))
            img = self.renderer.render(state).image.astype(np.float32)
            if self.noise:
                img += rng.normal(0.0, self.noise, img.shape).astype(np.float32)
            out = np.clip(img, 0, 255).astype(np.uint8)
            out.setflags(write=False)
            yield Frame(i, t, out)

    def close(self) -> None:
        self.closed = True
