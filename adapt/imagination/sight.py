"""Lines of sight over the floor plan: what a wall hides.

A wall stands on its floor segment up to its height; a ball on the floor
behind it (seen from a camera on the other side, at most the wall's height
above the floor) is hidden.  A perceiving schema uses this to refuse a
sighting that would put an object on the far side of a wall: whatever it saw,
it was not that.

Examples
--------
>>> from adapt.imagination.scene import SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2.0, 3.0), (2.0, 3.0)),))
>>> behind_wall(scene, (0.0, 0.0), (0.5, 3.5)).name
'north'
>>> behind_wall(scene, (0.0, 0.0), (0.5, 2.5)) is None
True
"""

from __future__ import annotations

from typing import Sequence

from adapt.imagination.scene import SceneSpec, Wall

__all__ = ["behind_wall"]


def _cross(o: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _crosses(p: Sequence[float], q: Sequence[float], a: Sequence[float],
             b: Sequence[float]) -> bool:
    """Whether segment ``p-q`` properly crosses segment ``a-b`` (touching is not crossing)."""
    d1, d2 = _cross(a, b, p), _cross(a, b, q)
    d3, d4 = _cross(p, q, a), _cross(p, q, b)
    return d1 * d2 < 0 and d3 * d4 < 0


def behind_wall(scene: SceneSpec, eye: Sequence[float], point: Sequence[float]) -> Wall | None:
    """The first wall (in the scene's order) between ``eye`` and ``point`` on the floor plan.

    Parameters
    ----------
    scene : SceneSpec
        The walls.
    eye : (x, y)
        Where the camera stands, metres.
    point : (x, y)
        Where something was seen, metres.

    Returns
    -------
    Wall or None
        The wall whose floor segment the line of sight crosses, or None when
        no wall stands in between.
    """
    for wall in scene.walls:
        if _crosses(eye, point, wall.start, wall.end):
            return wall
    return None
