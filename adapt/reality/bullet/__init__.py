"""A reality on PyBullet: another physics engine and another renderer.

``reality: {kind: bullet, ...}`` makes frames with PyBullet (a 3D ball with
restitution, lateral, rolling and spinning friction and spin; walls as boxes,
obstacles as prisms, a robot body that slips) rendered by PyBullet's CPU
renderer (TinyRenderer) with its own textures, light, blur and noise.  Every
number is drawn per run from the scenario's ranges.  See ``docs/reality.md``.

PyBullet is an optional extra: this package imports without it, and opening a
``bullet`` reality without it raises a :class:`~adapt.errors.RealityError`
that names ``pip install 'adapt[bullet]'`` (:mod:`~adapt.reality.bullet.client`
is the only module that imports PyBullet).

Modules, one noun each:

* :mod:`~adapt.reality.bullet.source` - the frame source;
* :mod:`~adapt.reality.bullet.draw` - what a run draws from the ranges;
* :mod:`~adapt.reality.bullet.bodies` - the bodies, from the world's geometry;
* :mod:`~adapt.reality.bullet.robot` - the robot's drive, with wheel slip;
* :mod:`~adapt.reality.bullet.textures` - the surfaces' and balls' images;
* :mod:`~adapt.reality.bullet.view` - the camera's matrices and a render;
* :mod:`~adapt.reality.bullet.sensor` - from render to frame (gain, vignette,
  blur, noise);
* :mod:`~adapt.reality.bullet.calibrate` - what the balls' contacts really do;
* :mod:`~adapt.reality.bullet.client` - one PyBullet client; PyBullet's import.
"""

from __future__ import annotations

from adapt.reality.bullet.client import INSTALL, Client, load_pybullet
from adapt.reality.bullet.draw import BulletDraw, draw
from adapt.reality.bullet.source import BulletSource, model_parameters

__all__ = ["BulletSource", "BulletDraw", "draw", "model_parameters", "Client", "load_pybullet",
           "INSTALL"]
