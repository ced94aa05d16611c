"""Every file a scenario names: what a run of it reads, so that no output replaces it.

:func:`scenario_inputs` lists the YAML file itself, its rule files, every
texture image (of the world's floor, walls, obstacles and objects, and of
reality's objects), the learned-appearance folder, the video file or each
frame of an image sequence, the ground-truth file, the files a plugin's reality
kind names, and each plugin's own module file, each named by its key
path (``the scenario's world.floor.texture``).  The files a rule file
``source``\\ s are read by the rule loader, which adds them
(``adapt.runner.inputs``).  Built from the scenario's records, so a scenario
changed with :func:`dataclasses.replace` lists what it names now.

Examples
--------
>>> from adapt.scenario import loads_scenario
>>> sc = loads_scenario("camera: {fx: 1, fy: 1, cx: 0, cy: 0, width: 32, height: 32, "
...                     "position: [0, 0, 1], look_at: [0, 1, 1]}\\nworld: {}\\n")
>>> [i.what for i in scenario_inputs(sc)]
[]
"""

from __future__ import annotations

import glob
from pathlib import Path
from typing import TYPE_CHECKING, Iterator

from adapt.files import Input, Inputs
from adapt.scenario.records import CameraReality, PluginReality, VideoReality

if TYPE_CHECKING:
    from adapt.scenario import Scenario

__all__ = ["scenario_inputs", "scenario_files"]

_OWN = "the scenario's"


def scenario_inputs(scenario: "Scenario") -> Inputs:
    """Every file the scenario names (see the module docstring)."""
    return Inputs(scenario_files(scenario))


def scenario_files(sc: "Scenario") -> Iterator[Input]:
    """The files of :func:`scenario_inputs`, one by one, as named (not yet resolved: the
    grid of a sweep adds those of every cell to one :class:`~adapt.files.Inputs`, which
    resolves a path once)."""
    if sc.path is not None:
        yield Input("the scenario", sc.path)
    for i, plugin in enumerate(sc.plugins):
        if plugin.file is not None:
            yield Input(f"{_OWN} plugins[{i}] ({plugin.name}, a plugin)", plugin.file)
    for i, rf in enumerate(sc.rules):
        yield Input(f"{_OWN} {rf.source.path or f'rules[{i}]'} (a rule file)", rf.path)
    scene = sc.scene
    textures: list[tuple[str, str | None]] = [("world.floor.texture", scene.floor.texture)]
    textures += [(f"world.walls[{i}].texture", w.texture) for i, w in enumerate(scene.walls)]
    textures += [(f"world.obstacles[{i}].texture", o.texture)
                 for i, o in enumerate(scene.obstacles)]
    balls = {b.name: b for b in scene.balls}  # created at the start
    balls.update((m.name, m.ball) for m in sc.objects if m.name not in balls)  # when seen
    textures += [(f"world.objects.{name}.texture", b.texture) for name, b in balls.items()]
    reality = sc.reality
    if isinstance(reality, PluginReality):
        for key, path in reality.files:
            yield Input(f"{_OWN} reality.{key} (a file of reality kind {reality.name})", path)
    if reality is not None and not isinstance(reality, (VideoReality, CameraReality, PluginReality)):
        textures += [(f"reality.objects.{o.name}.texture", o.ball.texture)
                     for o in reality.objects]
    for key, texture in textures:
        if texture is not None and not texture.startswith("builtin:"):
            yield Input(f"{_OWN} {key}", Path(texture))
    if sc.appearance is not None:
        yield Input(f"{_OWN} world.appearance (a learned appearance)", sc.appearance, folder=True)
    if sc.lens is not None and sc.lens.file is not None:
        yield Input(f"{_OWN} camera.calibration", Path(sc.lens.file))
    if isinstance(reality, CameraReality) and isinstance(reality.device, str) \
            and "://" not in reality.device:
        yield Input(f"{_OWN} reality.device (a video file)", Path(reality.device))
    if isinstance(reality, VideoReality):
        if reality.pattern is None:
            yield Input(f"{_OWN} reality.path (the video)", reality.path)
        else:
            what = f"a frame of {_OWN} reality.path ({reality.pattern})"
            for frame in sorted(glob.glob(reality.pattern)):
                yield Input(what, Path(frame))
        if reality.ground_truth is not None:
            yield Input(f"{_OWN} reality.ground_truth", reality.ground_truth)

