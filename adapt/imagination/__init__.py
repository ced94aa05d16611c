"""The imagination: a 2D physics world seen through a pinhole camera.

* :mod:`~adapt.imagination.scene` - frozen records describing a scene
  (:class:`SceneSpec`, :class:`Wall`, :class:`Obstacle`, :class:`Ball`,
  :class:`Floor`, :class:`RobotSpec`);
* :mod:`~adapt.imagination.world` - the pymunk :class:`World`, its
  :class:`WorldState` snapshots and :class:`Contact` events;
* :mod:`~adapt.imagination.surface` - the static :class:`Surface` planes of a
  scene in world metres; :mod:`~adapt.imagination.appearance` - an
  :class:`Appearance` that replaces a surface's look at run time;
* :mod:`~adapt.imagination.backdrop` - the :class:`Backdrop`: surfaces with
  prepared textures, drawn for any camera pose by one warp per surface;
  :mod:`~adapt.imagination.raycast` - the exact per-pixel reference;
* :mod:`~adapt.imagination.render` - the :class:`Renderer` (BGR image and
  label image through an :class:`adapt.geometry.Camera`);
* :mod:`~adapt.imagination.predict` - rollouts, contact prediction, intercepts
  and seeded ensembles; :mod:`~adapt.imagination.outlook` - a scene's expected
  future (``adapt imagine``);
* :mod:`~adapt.imagination.footprint` - where a robot fits and the way round
  what is in its way; :mod:`~adapt.imagination.reach` - where it can meet a
  moving object; :mod:`~adapt.imagination.sight` - what a wall hides.

This package imports numpy, pymunk, OpenCV (for drawing), ``adapt.geometry``
and ``adapt.errors`` only.
"""

from __future__ import annotations

from adapt.imagination.appearance import Appearance
from adapt.imagination.backdrop import Backdrop
from adapt.imagination.predict import (
    ENSEMBLE_PARAMETERS,
    MAX_ENSEMBLE_STEPS,
    MAX_ENSEMBLE_VALUES,
    MAX_MEMBERS,
    MAX_SAMPLES,
    Ensemble,
    Intercept,
    Trajectory,
    ensemble,
    intercept,
    intercept_reach,
    rollout,
    time_to_reach,
)
from adapt.imagination.render import (
    LABEL_BALL,
    LABEL_FLOOR,
    LABEL_OBSTACLE,
    LABEL_ROBOT,
    LABEL_SKY,
    LABEL_WALL,
    Box,
    Renderer,
    RenderResult,
    initial_state,
    label_names,
)
from adapt.imagination.scene import (
    Ball,
    Floor,
    Obstacle,
    RobotShape,
    RobotSpec,
    SceneSpec,
    Wall,
)
from adapt.imagination.surface import Surface, scene_surfaces
from adapt.imagination.texture import Texture, load_texture
from adapt.imagination.world import (
    MAX_STEPS,
    MAX_SUBSTEPS,
    BodyState,
    Contact,
    StepHook,
    World,
    WorldState,
)

__all__ = [
    "ENSEMBLE_PARAMETERS",
    "LABEL_BALL",
    "LABEL_FLOOR",
    "LABEL_OBSTACLE",
    "LABEL_ROBOT",
    "LABEL_SKY",
    "LABEL_WALL",
    "MAX_ENSEMBLE_STEPS",
    "MAX_ENSEMBLE_VALUES",
    "MAX_MEMBERS",
    "MAX_SAMPLES",
    "MAX_STEPS",
    "MAX_SUBSTEPS",
    "Appearance",
    "Backdrop",
    "Ball",
    "BodyState",
    "Box",
    "Contact",
    "Ensemble",
    "Floor",
    "Intercept",
    "Obstacle",
    "RenderResult",
    "Renderer",
    "RobotSpec",
    "RobotShape",
    "SceneSpec",
    "StepHook",
    "Surface",
    "Texture",
    "Trajectory",
    "Wall",
    "World",
    "WorldState",
    "ensemble",
    "initial_state",
    "intercept",
    "intercept_reach",
    "label_names",
    "load_texture",
    "rollout",
    "scene_surfaces",
    "time_to_reach",
]
