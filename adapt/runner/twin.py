"""The uncorrected imagination: the paper's comparison, run beside the mirror.

The paper's Figures 7 and 8 show the imagined ball uncorrected (top rows)
against corrected (bottom rows).  :class:`UncorrectedTwin` is that top row:
a second world of the same scene in which every object is created where and
when the mirror created it, with the model's nominal parameters, and then
left alone -- no spring, no learned parameters, and no robot to run into
(the robot is the rules' doing; drawn, it stands where the mirror's is).  It
is evaluation only:
nothing perceives through it; the runner scores it against the truth and
draws it in the figures.

Examples
--------
>>> from adapt.imagination import Ball, SceneSpec
>>> twin = UncorrectedTwin(SceneSpec())
>>> twin.create(Ball("b", radius=0.1), (0.0, 0.0), (1.0, 0.0))
>>> twin.step_to(0.5)
>>> [round(v, 3) for v in twin.positions()["b"]]
[0.5, 0.0]
"""

from __future__ import annotations

from dataclasses import replace
from typing import Sequence

from adapt.geometry import Camera
from adapt.imagination import Ball, Renderer, RenderResult, SceneSpec, World
from adapt.imagination.world import BodyState

__all__ = ["UncorrectedTwin"]


class UncorrectedTwin:
    """A world that only ever runs on (see the module docstring)."""

    def __init__(self, scene: SceneSpec, seed: int | None = None) -> None:
        self.world = World(replace(scene, robot=None), seed=seed, record_contacts=False)
        self._renderer: Renderer | None = None

    def create(self, ball: Ball, position: Sequence[float], velocity: Sequence[float]) -> None:
        """The mirror created ``ball``: create it here too (once)."""
        if ball.name not in self.world.names:
            self.world.add_ball(ball, position=position, velocity=velocity)

    def step_to(self, time: float) -> None:
        """Run on to ``time``."""
        self.world.run_until(time)

    def positions(self) -> dict[str, tuple[float, float]]:
        """Every ball's ``(x, y)``."""
        return {b.name: self.world.position(b.name) for b in self.world.balls}

    def render(self, camera: Camera, renderer: Renderer,
               also: Sequence[BodyState] = ()) -> RenderResult:
        """What ``camera`` would see of the twin (sharing ``renderer``'s backdrop and scene),
        with the bodies ``also`` (the mirror's robot, say) drawn where they are given."""
        if self._renderer is None or self._renderer.camera is not camera:
            self._renderer = renderer.with_camera(camera)
        state = self.world.snapshot()
        if also:
            state = replace(state, bodies=state.bodies + tuple(also))
        return self._renderer.render(state, balls=self.world.balls)
