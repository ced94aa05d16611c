"""Lines of sight in 3D: what a wall or an obstacle hides from the camera.

A wall stands on its floor segment from ``z = 0`` to its height (no
thickness); an obstacle is a prism over its polygon from ``z = 0`` to its
height (``docs/conventions.md``).  A straight line from the camera's centre
(its height included) to a point is **blocked** by a wall when it crosses the
wall's floor segment below the wall's top, and by an obstacle when it passes
through the obstacle's prism.  A ball is **hidden** when the lines to its
centre and to its top are both blocked: a camera above a low wall sees over it,
and a camera outside the arena sees the floor inside it.

A perceiving schema uses :func:`hidden_by` to refuse a sighting that would put
an object where the camera cannot see it: whatever it saw, it was not that.

Examples
--------
>>> from adapt.imagination.scene import SceneSpec, Wall
>>> scene = SceneSpec(walls=(Wall("north", (-2.0, 3.0), (2.0, 3.0), height=1.0),))
>>> hidden_by(scene, (0.0, 0.0, 0.5), (0.5, 3.5), radius=0.1).name   # behind the wall
'north'
>>> hidden_by(scene, (0.0, 0.0, 9.0), (0.5, 3.5), radius=0.1) is None  # seen over it
True
>>> blocked_by(scene, (0.0, 0.0, 0.5), (0.0, 2.5, 0.1)) is None       # in front of it
True
"""

from __future__ import annotations

from typing import Sequence

from adapt.imagination.scene import Obstacle, SceneSpec, Wall

__all__ = ["blocked_by", "hidden_by", "segment_crossing", "prism_span"]

#: Parameter margin within which touching is not crossing.
_EPS = 1e-12


def _cross(o: Sequence[float], a: Sequence[float], b: Sequence[float]) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def segment_crossing(p: Sequence[float], q: Sequence[float], a: Sequence[float],
                     b: Sequence[float]) -> float | None:
    """Where the floor segment ``p-q`` properly crosses ``a-b``: the fraction ``s`` of the way
    from ``p`` to ``q`` (None when they do not cross; touching is not crossing).

    Examples
    --------
    >>> segment_crossing((0, 0), (0, 4), (-1, 1), (1, 1))
    0.25
    >>> segment_crossing((0, 0), (0, 1), (-1, 1), (1, 1)) is None   # ends on it
    True
    """
    d1, d2 = _cross(a, b, p), _cross(a, b, q)
    d3, d4 = _cross(p, q, a), _cross(p, q, b)
    if not (d1 * d2 < 0 and d3 * d4 < 0):
        return None
    return d1 / (d1 - d2)


def prism_span(p: Sequence[float], q: Sequence[float],
               polygon: Sequence[Sequence[float]]) -> tuple[float, float] | None:
    """The fractions ``(s_in, s_out)`` of the floor segment ``p-q`` inside a convex
    counter-clockwise polygon (None when it does not pass through its inside).

    Examples
    --------
    >>> square = ((1, -1), (3, -1), (3, 1), (1, 1))
    >>> prism_span((0, 0), (4, 0), square)
    (0.25, 0.75)
    >>> prism_span((0, 1), (4, 1), square) is None   # along an edge: touching
    True
    """
    s_in, s_out = 0.0, 1.0
    dx, dy = q[0] - p[0], q[1] - p[1]
    n = len(polygon)
    for i in range(n):
        ax, ay = polygon[i]
        bx, by = polygon[(i + 1) % n]
        ex, ey = bx - ax, by - ay
        # inside is to the left of each edge: cross(e, x - a) > 0
        start = ex * (p[1] - ay) - ey * (p[0] - ax)
        rate = ex * dy - ey * dx
        if abs(rate) < 1e-15:
            if start <= _EPS:
                return None
            continue
        s = -start / rate
        if rate > 0:
            s_in = max(s_in, s)
        else:
            s_out = min(s_out, s)
        if s_in >= s_out - _EPS:
            return None
    return s_in, s_out


def blocked_by(scene: SceneSpec, eye: Sequence[float], point: Sequence[float]
               ) -> Wall | Obstacle | None:
    """The first wall, then obstacle (each in the scene's order), that the straight line
    from ``eye`` to ``point`` (both ``(x, y, z)``, metres) passes through below its top,
    or None when nothing stands in between."""
    ez, pz = float(eye[2]), float(point[2])
    for wall in scene.walls:
        s = segment_crossing(eye, point, wall.start, wall.end)
        if s is not None and ez + s * (pz - ez) < wall.height:
            return wall
    for obstacle in scene.obstacles:
        span = prism_span(eye, point, obstacle.polygon)
        if span is not None and min(ez + s * (pz - ez) for s in span) < obstacle.height:
            return obstacle
    return None


def hidden_by(scene: SceneSpec, eye: Sequence[float], centre: Sequence[float],
              radius: float) -> Wall | Obstacle | None:
    """What hides a ball of ``radius`` whose centre is over the floor point ``centre``
    from a camera at ``eye`` (``(x, y, z)``): the wall or obstacle that blocks the line to
    its centre, when the line to its top is blocked too; None when the camera sees it."""
    x, y = float(centre[0]), float(centre[1])
    first = blocked_by(scene, eye, (x, y, radius))
    if first is None or blocked_by(scene, eye, (x, y, 2.0 * radius)) is None:
        return None
    return first
