"""The bodies of a PyBullet reality, built from the scenario's world records.

Only the geometry comes from the scenario (``world``: the floor's extent, the
walls' lines and heights, the obstacles' polygons and heights, the balls' radii,
the robot's shape); everything else -- contact parameters, textures, spin --
comes from the run's draw (:mod:`adapt.reality.bullet.draw`).

* the **floor** is PyBullet's infinite plane at ``z = 0``; what is drawn is its
  extent (or 40 m x 40 m round the arena's centre without one) and, around an
  extent, a **ground** of another look out to 30 m;
* a **wall** is a box as high as the scenario's wall and ``wall_thickness`` thick,
  standing behind the wall's line (away from the arena's centre,
  :func:`~adapt.scenario.bullet.wall_body`), so its face is where the model's is;
* an **obstacle** is a prism over its polygon (a convex hull), as high as the
  scenario says;
* a **ball** is a sphere with PyBullet's restitution, lateral, rolling and
  spinning friction and damping, created when it appears with its drawn velocity
  and spin;
* the **robot** is a cylinder (``disc``) or a box of the robot's height and mass,
  sliding without friction on the floor: :mod:`~adapt.reality.bullet.robot`
  sets its velocity each step.

Every visible surface is a mesh whose texture coordinates are its face
coordinates in metres divided by the tile (plus the drawn phase), so a texture
repeats at its real size.  Every body's contact processing threshold is 0 (else
PyBullet drops restitution, ``docs/reality.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

from adapt.imagination.scene import RobotShape, RobotSpec, SceneSpec
from adapt.reality.bullet.client import Client
from adapt.reality.bullet.draw import BallDraw, BulletDraw, SurfaceDraw, SurfaceLook
from adapt.scenario.bullet import arena_centre, wall_body

__all__ = ["Mesh", "Bodies", "build", "add_ball", "spin_velocity", "GROUND_REACH",
           "UNBOUNDED_FLOOR"]

Vec3 = tuple[float, float, float]

#: How far the ground reaches round a floor with an extent, metres.
GROUND_REACH = 30.0
#: Side of the floor drawn when the scenario's floor has no extent, metres.
UNBOUNDED_FLOOR = 40.0
#: The largest quad drawn in one piece, metres (TinyRenderer clips big triangles poorly).
CELL = 2.0


@dataclass
class Mesh:
    """Vertices, triangles, texture coordinates and normals of a visual shape."""

    vertices: list[Vec3] = field(default_factory=list)
    indices: list[int] = field(default_factory=list)
    uvs: list[tuple[float, float]] = field(default_factory=list)
    normals: list[Vec3] = field(default_factory=list)

    def quad(self, corners: Sequence[Vec3], uv: Sequence[tuple[float, float]], normal: Vec3,
             cells: tuple[int, int] = (1, 1)) -> None:
        """A planar quad ``c0 c1 c2 c3`` (counter-clockwise seen from ``normal``'s side),
        split into ``cells`` pieces along ``c0 -> c1`` and ``c0 -> c3``."""
        n_u, n_v = cells
        c0, c1, _, c3 = corners

        def at(i: int, j: int) -> tuple[Vec3, tuple[float, float]]:
            a, b = i / n_u, j / n_v
            p = tuple(c0[k] + a * (c1[k] - c0[k]) + b * (c3[k] - c0[k]) for k in range(3))
            t = tuple(uv[0][k] + a * (uv[1][k] - uv[0][k]) + b * (uv[3][k] - uv[0][k])
                      for k in range(2))
            return (p[0], p[1], p[2]), (t[0], t[1])

        base = len(self.vertices)
        for j in range(n_v + 1):
            for i in range(n_u + 1):
                p, t = at(i, j)
                self.vertices.append(p)
                self.uvs.append(t)
                self.normals.append(normal)
        row = n_u + 1
        for j in range(n_v):
            for i in range(n_u):
                a = base + j * row + i
                self.indices += [a, a + 1, a + row + 1, a, a + row + 1, a + row]

    def rectangle(self, x0: float, y0: float, x1: float, y1: float, look: SurfaceLook) -> None:
        """A floor rectangle at ``z = 0``, facing up."""
        corners = [(x0, y0, 0.0), (x1, y0, 0.0), (x1, y1, 0.0), (x0, y1, 0.0)]
        self.quad(corners, [_uv(look, c[0], c[1]) for c in corners], (0.0, 0.0, 1.0),
                  (max(1, math.ceil((x1 - x0) / CELL)), max(1, math.ceil((y1 - y0) / CELL))))


def _uv(look: SurfaceLook, s: float, t: float) -> tuple[float, float]:
    return ((s + look.phase[0]) / look.tile, (t + look.phase[1]) / look.tile)


def _vertical_faces(mesh: Mesh, polygon: Sequence[tuple[float, float]], height: float,
                    look: SurfaceLook, top: bool = True) -> None:
    """The sides (outwards) and the top of a prism over a counter-clockwise polygon."""
    n = len(polygon)
    s0 = 0.0
    for k in range(n):
        (ax, ay), (bx, by) = polygon[k], polygon[(k + 1) % n]
        length = math.hypot(bx - ax, by - ay)
        if length < 1e-9:
            continue
        normal = ((by - ay) / length, -(bx - ax) / length, 0.0)
        corners = [(ax, ay, 0.0), (bx, by, 0.0), (bx, by, height), (ax, ay, height)]
        uv = [_uv(look, s0, height), _uv(look, s0 + length, height), _uv(look, s0 + length, 0.0),
              _uv(look, s0, 0.0)]
        mesh.quad(corners, uv, normal, (max(1, math.ceil(length / CELL)),
                                        max(1, math.ceil(height / CELL))))
        s0 += length
    if top:
        # a fan of triangles from the first corner
        base = len(mesh.vertices)
        for x, y in polygon:
            mesh.vertices.append((x, y, height))
            mesh.uvs.append(_uv(look, x, y))
            mesh.normals.append((0.0, 0.0, 1.0))
        for k in range(1, n - 1):
            mesh.indices += [base, base + k, base + k + 1]


@dataclass
class Bodies:
    """The ids of a reality's bodies, and what each is called (for the segmentation)."""

    floor: int
    walls: list[int]
    obstacles: list[int]
    robot: int | None
    balls: dict[str, int] = field(default_factory=dict)
    names: dict[int, str] = field(default_factory=dict)


def _visual(client: Client, mesh: Mesh, texture: int) -> int:
    shape = client.createVisualShape(client.GEOM_MESH, vertices=mesh.vertices,
                                     indices=mesh.indices, uvs=mesh.uvs, normals=mesh.normals,
                                     rgbaColor=[1, 1, 1, 1])
    return int(shape)


def _contacts(client: Client, body: int, surface: SurfaceDraw) -> None:
    client.changeDynamics(body, -1, restitution=surface.restitution,
                          lateralFriction=surface.friction,
                          rollingFriction=surface.rolling_friction,
                          spinningFriction=surface.spinning_friction,
                          contactProcessingThreshold=0.0)


def _static(client: Client, collision: int, visual: int, texture: int | None,
            position: Vec3 = (0.0, 0.0, 0.0), orientation: Sequence[float] = (0, 0, 0, 1)) -> int:
    body = int(client.createMultiBody(baseMass=0, baseCollisionShapeIndex=collision,
                                      baseVisualShapeIndex=visual, basePosition=position,
                                      baseOrientation=orientation))
    if texture is not None:
        client.changeVisualShape(body, -1, textureUniqueId=texture)
    return body


def build(client: Client, scene: SceneSpec, drawn: BulletDraw, thickness: float,
          textures: dict[str, int], robot: RobotSpec | None) -> Bodies:
    """Build the static world and the robot in ``client`` (balls come with
    :func:`add_ball`); ``textures`` maps each surface's name to its texture id."""
    look = drawn.look
    centre = arena_centre(scene)
    floor_mesh = Mesh()
    flook = look.surface("floor")
    ext = scene.floor.extent
    if ext is None:
        half = UNBOUNDED_FLOOR / 2
        ext_drawn = (centre[0] - half, centre[1] - half, centre[0] + half, centre[1] + half)
    else:
        ext_drawn = ext
    floor_mesh.rectangle(*ext_drawn, flook)
    plane = int(client.createCollisionShape(client.GEOM_PLANE))
    floor = _static(client, plane, _visual(client, floor_mesh, textures["floor"]), textures["floor"])
    _contacts(client, floor, drawn.floor)
    names = {floor: "floor"}
    if ext is not None:
        ground = Mesh()
        glook = look.surface("ground")
        x0, y0, x1, y1 = ext
        r = GROUND_REACH
        for rect in ((x0 - r, y0 - r, x1 + r, y0), (x0 - r, y1, x1 + r, y1 + r),
                     (x0 - r, y0, x0, y1), (x1, y0, x1 + r, y1)):
            ground.rectangle(*rect, glook)
        body = _static(client, -1, _visual(client, ground, textures["ground"]), textures["ground"])
        names[body] = "ground"
    walls = []
    for i, wall in enumerate(scene.walls):
        corners = wall_body(wall, thickness, centre)
        mesh = Mesh()
        wlook = look.surface(f"walls[{i}]")
        _vertical_faces(mesh, corners, wall.height, wlook)
        (ax, ay), (bx, by) = wall.start, wall.end
        length = math.hypot(bx - ax, by - ay)
        cx = sum(c[0] for c in corners) / 4
        cy = sum(c[1] for c in corners) / 4
        yaw = math.atan2(by - ay, bx - ax)
        box = int(client.createCollisionShape(client.GEOM_BOX,
                                              halfExtents=[length / 2, thickness / 2, wall.height / 2]))
        collision_body = int(client.createMultiBody(
            baseMass=0, baseCollisionShapeIndex=box, basePosition=[cx, cy, wall.height / 2],
            baseOrientation=client.getQuaternionFromEuler([0, 0, yaw])))
        _contacts(client, collision_body, drawn.walls)
        # a body without a visual shape is drawn as its collision shape, plain white: this
        # box's faces lie on the textured mesh's, and the two would fight for every pixel
        # (a noise of white and texture that changes as the camera moves a centimetre)
        client.changeVisualShape(collision_body, -1, rgbaColor=[1, 1, 1, 0])
        body = _static(client, -1, _visual(client, mesh, textures[f"walls[{i}]"]),
                       textures[f"walls[{i}]"])
        walls.append(collision_body)
        names[body] = names[collision_body] = wall.name
    obstacles = []
    for i, o in enumerate(scene.obstacles):
        mesh = Mesh()
        _vertical_faces(mesh, o.polygon, o.height, look.surface(f"obstacles[{i}]"))
        hull = int(client.createCollisionShape(
            client.GEOM_MESH, vertices=[(x, y, z) for z in (0.0, o.height) for x, y in o.polygon]))
        body = _static(client, hull, _visual(client, mesh, textures[f"obstacles[{i}]"]),
                       textures[f"obstacles[{i}]"])
        _contacts(client, body, drawn.obstacles)
        obstacles.append(body)
        names[body] = o.name
    robot_body = None
    if robot is not None:
        robot_body = _robot(client, robot)
        names[robot_body] = robot.name
    return Bodies(floor, walls, obstacles, robot_body, {}, names)


def _robot(client: Client, robot: RobotSpec) -> int:
    rgba = [c / 255.0 for c in robot.color] + [1.0]
    if robot.shape is RobotShape.DISC:
        collision = client.createCollisionShape(client.GEOM_CYLINDER, radius=robot.radius,
                                                height=robot.height)
        visual = client.createVisualShape(client.GEOM_CYLINDER, radius=robot.radius,
                                          length=robot.height, rgbaColor=rgba)
    else:
        half = [robot.size[0] / 2, robot.size[1] / 2, robot.height / 2]
        collision = client.createCollisionShape(client.GEOM_BOX, halfExtents=half)
        visual = client.createVisualShape(client.GEOM_BOX, halfExtents=half, rgbaColor=rgba)
    x, y = robot.position
    body = int(client.createMultiBody(
        baseMass=robot.mass, baseCollisionShapeIndex=collision, baseVisualShapeIndex=visual,
        basePosition=[x, y, robot.height / 2 + 1e-4],
        baseOrientation=client.getQuaternionFromEuler([0, 0, math.radians(robot.heading_deg)])))
    client.changeDynamics(body, -1, lateralFriction=0.0, rollingFriction=0.0,
                          spinningFriction=0.0, restitution=0.5, linearDamping=0.0,
                          angularDamping=0.0, contactProcessingThreshold=0.0,
                          activationState=client.ACTIVATION_STATE_DISABLE_SLEEPING)
    return body


def spin_velocity(velocity: Sequence[float], radius: float, spin: float,
                  side_spin: float) -> Vec3:
    """The angular velocity of a ball on the floor moving at ``velocity`` with ``spin``
    times its rolling spin and ``side_spin`` rad/s about the vertical.

    Examples
    --------
    >>> spin_velocity((1.0, 0.0), 0.1, 1.0, 0.0)   # rolling along +x turns it about +y
    (-0.0, 10.0, 0.0)
    """
    vx, vy = velocity[0], velocity[1]
    return (-spin * vy / radius, spin * vx / radius, side_spin)


def add_ball(client: Client, ball: BallDraw, texture: int | None) -> int:
    """Create a drawn ball where and as it appears; returns its body id."""
    r = ball.radius
    collision = client.createCollisionShape(client.GEOM_SPHERE, radius=r)
    visual = client.createVisualShape(client.GEOM_SPHERE, radius=r, rgbaColor=[1, 1, 1, 1])
    x, y = ball.position
    body = int(client.createMultiBody(baseMass=ball.mass, baseCollisionShapeIndex=collision,
                                      baseVisualShapeIndex=visual,
                                      basePosition=[x, y, r + ball.height]))
    if texture is not None:
        client.changeVisualShape(body, -1, textureUniqueId=texture)
    client.changeDynamics(body, -1, restitution=ball.restitution, lateralFriction=ball.friction,
                          rollingFriction=ball.rolling_friction,
                          spinningFriction=ball.spinning_friction, linearDamping=ball.damping,
                          angularDamping=ball.damping, contactProcessingThreshold=0.0,
                          activationState=client.ACTIVATION_STATE_DISABLE_SLEEPING)
    client.resetBaseVelocity(body, [ball.velocity[0], ball.velocity[1], 0.0],
                             list(spin_velocity(ball.velocity, r, ball.spin, ball.side_spin)))
    return body
