"""The test room, written once: the bundled room (``scenarios/room.yaml``) at 320x240 with the
mirror's perception rules, for the tests that run scenarios (the runner's, the sweeps')."""

from __future__ import annotations

from pathlib import Path

#: The repository's root.
ROOT = Path(__file__).resolve().parents[1]
#: The mirror's perception rules.
RULES = ROOT / "rules" / "mirror" / "perception.soar"

CAMERA = """camera: {fx: 262.5, fy: 262.5, cx: 159.5, cy: 119.5, width: 320, height: 240,
         position: [0.0, -0.6, 0.6], look_at: [0.0, 3.0, 0.3]}
"""

WALLS = {
    "north": "{name: north, from: [-2.5, 3.0], to: [2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}",
    "east": "{name: east, from: [2.5, 3.0], to: [2.5, -1.0], height: 1.0, texture: brick, tile: 0.6}",
    "west": "{name: west, from: [-2.5, -1.0], to: [-2.5, 3.0], height: 1.0, texture: brick, tile: 0.6}",
}

OBSTACLES = {
    "crate": "{name: crate, polygon: [[-1.3, 2.35], [-0.75, 2.35], [-0.75, 2.85], [-1.3, 2.85]],\n"
             "       height: 0.4, color: [150, 110, 60]}",
    "bin": "{name: bin, polygon: [[1.45, 2.0], [1.85, 2.2], [1.7, 2.55], [1.3, 2.35]], height: 0.5,\n"
           "       color: [90, 150, 80]}",
}


def room_text(*, walls: tuple[str, ...] = ("north", "east", "west"),
              obstacles: tuple[str, ...] = ("crate", "bin"), objects: str = "",
              reality: str = "", run: str = "run: {fps: 30, max_frames: 60, seed: 3}") -> str:
    """The room's YAML: ``objects`` is the YAML of ``world.objects`` (indented by 2),
    ``reality`` a whole ``reality`` section."""
    lines = [CAMERA + "world:",
             "  floor: {texture: gravel, tile: 0.8, extent: [-2.5, -1.0, 2.5, 3.0]}",
             "  walls:", *(f"    - {WALLS[w]}" for w in walls)]
    if obstacles:
        lines += ["  obstacles:", *(f"    - {OBSTACLES[o]}" for o in obstacles)]
    if objects:
        lines.append(objects.rstrip("\n"))
    if reality:
        lines.append(reality.rstrip("\n"))
    lines += ["goals: [{name: watch}]", f"rules: [{RULES}]", run]
    return "\n".join(lines) + "\n"
