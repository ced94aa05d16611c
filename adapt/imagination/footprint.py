"""A robot's footprint on the floor plan: where it fits, and a way round what is in its way.

A robot is a disc of its body's radius (a box robot: half its diagonal).  Its
centre must stay that far from the walls and the obstacles, inside the
floor's extent when the floor has one.  :meth:`Footprint.clear` says whether it
fits at a point, :meth:`Footprint.path_clear` whether it can drive straight
from one point to another, and :meth:`Footprint.route` finds the shortest way
when it cannot: straight lines between the start, the goal, and points just
off the obstacles' corners and the walls' free ends (a visibility graph).

Examples
--------
>>> from adapt.imagination.scene import Obstacle, SceneSpec
>>> box = Obstacle("box", ((-0.5, 1.0), (0.5, 1.0), (0.5, 1.5), (-0.5, 1.5)), 0.5)
>>> fp = Footprint(SceneSpec(obstacles=(box,)), 0.25)
>>> fp.clear((0.0, 0.7)), fp.clear((0.0, 0.8))
(True, False)
>>> fp.path_clear((0.0, 0.0), (0.0, 2.5))
False
>>> way = fp.route((0.0, 0.0), (0.0, 2.5))
>>> len(way), [round(v, 2) for v in way[-1]]
(3, [0.0, 2.5])
>>> round(path_length((0.0, 0.0), way), 2)     # round a corner of the box
3.18
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass
from typing import Sequence

from adapt.geometry import point_segment_distance, segment_distance
from adapt.imagination.scene import Obstacle, SceneSpec, Vec2, Wall

__all__ = ["Footprint", "Collision", "path_length"]

#: Corner points stand this much more than the radius off the obstacle (metres).
CLEARANCE = 0.03


def _inside(p: Sequence[float], polygon: Sequence[Vec2]) -> bool:
    """Inside a convex counter-clockwise polygon."""
    n = len(polygon)
    for i in range(n):
        (ax, ay), (bx, by) = polygon[i], polygon[(i + 1) % n]
        if (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax) < 0:
            return False
    return True


def path_length(start: Sequence[float], way: Sequence[Vec2]) -> float:
    """The length of the polyline from ``start`` through ``way``."""
    total, (x, y) = 0.0, (float(start[0]), float(start[1]))
    for p in way:
        total += math.hypot(p[0] - x, p[1] - y)
        x, y = p
    return total


@dataclass(frozen=True, slots=True)
class Collision:
    """What a disc overlaps: the ``index``-th wall or obstacle of the scene, how far the
    disc's centre is from it (``gap``, metres), and whether the centre is inside it (an
    obstacle)."""

    index: int
    wall: Wall | None
    obstacle: Obstacle | None
    gap: float
    inside: bool = False

    @property
    def name(self) -> str:
        """The wall's or the obstacle's name."""
        return self.wall.name if self.wall is not None else self.obstacle.name  # type: ignore[union-attr]


class Footprint:
    """Where a disc of ``radius`` may be on ``scene``'s floor (see the module docstring)."""

    def __init__(self, scene: SceneSpec, radius: float) -> None:
        self.scene = scene
        self.radius = float(radius)
        self.segments: list[tuple[Vec2, Vec2]] = [(w.start, w.end) for w in scene.walls]
        for ob in scene.obstacles:
            poly = ob.polygon
            self.segments.extend((poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly)))
        self._nodes: list[Vec2] | None = None
        self._edges: list[list[tuple[int, float]]] = []

    # -- fitting -------------------------------------------------------------------------------

    def clear(self, p: Sequence[float]) -> bool:
        """Whether the disc fits with its centre at ``p``: on the floor's extent, and
        overlapping no wall or obstacle (:meth:`collision`)."""
        x, y = float(p[0]), float(p[1])
        r = self.radius
        extent = self.scene.floor.extent
        if extent is not None:
            x0, y0, x1, y1 = extent
            if not (x0 + r <= x <= x1 - r and y0 + r <= y <= y1 - r):
                return False
        return self.collision((x, y)) is None

    def collision(self, p: Sequence[float], *, touch: float = 0.0) -> Collision | None:
        """The first wall (then obstacle) the disc at ``p`` overlaps by more than ``touch``
        metres (touching is allowed up to it), or None.

        Examples
        --------
        >>> from adapt.imagination.scene import Wall
        >>> fp = Footprint(SceneSpec(walls=(Wall("north", (-1, 1), (1, 1)),)), 0.25)
        >>> c = fp.collision((0.0, 0.9))
        >>> c.name, round(c.gap, 3), fp.collision((0.0, 0.75)) is None
        ('north', 0.1, True)
        """
        x, y = float(p[0]), float(p[1])
        limit = self.radius - touch
        for i, wall in enumerate(self.scene.walls):
            (ax, ay), (bx, by) = wall.start, wall.end
            gap = point_segment_distance((x, y), (ax, ay), (bx, by))
            if gap < limit:
                return Collision(i, wall, None, gap)
        for i, ob in enumerate(self.scene.obstacles):
            poly = ob.polygon
            n = len(poly)
            gap = min(point_segment_distance((x, y), poly[k], poly[(k + 1) % n]) for k in range(n))
            inside = _inside((x, y), poly)
            if inside or gap < limit:
                return Collision(i, None, ob, gap, inside)
        return None

    def obstacle_at(self, p: Sequence[float]) -> Obstacle | None:
        """The obstacle whose footprint holds the point ``p`` (the disc's size aside), or None."""
        for ob in self.scene.obstacles:
            if _inside(p, ob.polygon):
                return ob
        return None

    def path_clear(self, a: Sequence[float], b: Sequence[float]) -> bool:
        """Whether the disc can drive straight from ``a`` to ``b`` (both ends fitting)."""
        pa, pb = (float(a[0]), float(a[1])), (float(b[0]), float(b[1]))
        if not (self.clear(pa) and self.clear(pb)):
            return False
        r = self.radius
        return all(segment_distance(pa, pb, s, e) >= r for s, e in self.segments)

    # -- a way round ---------------------------------------------------------------------------

    def _corner_points(self) -> list[Vec2]:
        r = self.radius + CLEARANCE
        out: list[Vec2] = []
        for ob in self.scene.obstacles:
            poly = ob.polygon
            n = len(poly)
            for i in range(n):
                (px, py), (vx, vy), (nx, ny) = poly[i - 1], poly[i], poly[(i + 1) % n]
                # outward normals of the two edges at the corner (counter-clockwise polygon)
                e1 = (vx - px, vy - py)
                e2 = (nx - vx, ny - vy)
                l1, l2 = math.hypot(*e1), math.hypot(*e2)
                n1 = (e1[1] / l1, -e1[0] / l1)
                n2 = (e2[1] / l2, -e2[0] / l2)
                ux, uy = n1[0] + n2[0], n1[1] + n2[1]
                lu = math.hypot(ux, uy)
                if lu < 1e-9:
                    continue
                ux, uy = ux / lu, uy / lu
                cos_half = ux * n1[0] + uy * n1[1]
                d = r / max(cos_half, 0.2)
                out.append((vx + d * ux, vy + d * uy))
        for w in self.scene.walls:
            (ax, ay), (bx, by) = w.start, w.end
            length = math.hypot(bx - ax, by - ay)
            tx, ty = (bx - ax) / length, (by - ay) / length
            for (ex, ey), sign in (((ax, ay), -1.0), ((bx, by), 1.0)):
                for side in (-1.0, 1.0):
                    out.append((ex + sign * r * tx - side * r * ty, ey + sign * r * ty + side * r * tx))
        return [p for p in out if self.clear(p)]

    def _graph(self) -> list[Vec2]:
        if self._nodes is None:
            nodes = self._corner_points()
            edges: list[list[tuple[int, float]]] = [[] for _ in nodes]
            for i in range(len(nodes)):
                for j in range(i + 1, len(nodes)):
                    if self.path_clear(nodes[i], nodes[j]):
                        d = math.dist(nodes[i], nodes[j])
                        edges[i].append((j, d))
                        edges[j].append((i, d))
            self._nodes, self._edges = nodes, edges
        return self._nodes

    def route(self, start: Sequence[float], goal: Sequence[float]) -> list[Vec2] | None:
        """The shortest way for the disc from ``start`` to ``goal``: the points to drive
        through, ending at ``goal`` (``[goal]`` when the straight line is clear), or None
        when there is none (the goal does not fit, or every way is blocked).

        The start need not fit (a robot pressed against an obstacle): it is then left by
        the first point it can see.
        """
        s = (float(start[0]), float(start[1]))
        g = (float(goal[0]), float(goal[1]))
        if not self.clear(g):
            return None
        if self.path_clear(s, g) or (not self.clear(s) and self._sees(s, g)):
            return [g]
        nodes = self._graph()
        n = len(nodes)
        # Dijkstra from the start over the corner points; the goal is node n
        dist = [math.inf] * (n + 1)
        prev = [-1] * (n + 1)
        heap: list[tuple[float, int]] = []
        for i, p in enumerate(nodes):
            if self._sees(s, p):
                dist[i] = math.dist(s, p)
                heapq.heappush(heap, (dist[i], i))
        to_goal = [self.path_clear(p, g) for p in nodes]
        while heap:
            d, i = heapq.heappop(heap)
            if d > dist[i]:
                continue
            if i == n:
                break
            if to_goal[i]:
                nd = d + math.dist(nodes[i], g)
                if nd < dist[n]:
                    dist[n], prev[n] = nd, i
                    heapq.heappush(heap, (nd, n))
            for j, w in self._edges[i]:
                if d + w < dist[j]:
                    dist[j], prev[j] = d + w, i
                    heapq.heappush(heap, (d + w, j))
        if not math.isfinite(dist[n]):
            return None
        way = [g]
        k = prev[n]
        while k != -1:
            way.append(nodes[k])
            k = prev[k]
        return way[::-1]

    def _sees(self, a: Vec2, b: Vec2) -> bool:
        """Like :meth:`path_clear`, but ``a`` need not fit: only what the disc would cross
        moving away from where it stands counts (it may start touching an obstacle)."""
        if self.clear(a):
            return self.path_clear(a, b)
        if not self.clear(b):
            return False
        r = self.radius
        for s, e in self.segments:
            here = point_segment_distance(a, s, e)
            if segment_distance(a, b, s, e) < min(r, here) - 1e-9:
                return False
        return True
