"""A camera on the robot keeps its history through its own corrections, and relearns a look
its corrections cannot settle on.

Throw 8 of ``bench/foreign.py --small``: the camera rides on the robot, which stands still,
turns about 3 degrees towards the ball at 0.7 s, and stands still again until 1.8 s.  The
turn shows the far wall's texture aliased anew by the foreign renderer (a band the look
learned at the start never had), so ``H_e`` from the matches moves the image by 3 to 15
pixels from frame to frame while the camera does not move.  Two things kept it so for the
rest of the throw: every correction moved the imagined robot, and the frame history
restarted whenever the imagined robot moved, so nothing ever held still long enough to be
learned afresh; and the look is refined only by a synchronised camera, which this one
never was again.
"""

from __future__ import annotations

import math
import statistics
from typing import Any

import pytest

from adapt.runner import Runner
from adapt.schemas.background import SceneBackground

from .bench_throws import QUIET, throw

pytest.importorskip("pybullet")



class _Rows:
    """Per frame: the Scene Background's state, and the true camera's heading (evaluation)."""

    def __init__(self) -> None:
        self.runner: Any = None
        self.rows: list[dict[str, Any]] = []

    def frame(self, record: Any) -> None:
        bg = next(s for s in self.runner.network if isinstance(s, SceneBackground))
        forward = self.runner.truth.at(record.index).camera.rotation[2]
        self.rows.append({"history": len(bg.history), "depth": bg.history.depth,
                          "passes": bg.learn_passes, "corrections": bg.corrections,
                          "error": bg.pixel_error, "moving": bg.camera_moving,
                          "heading": math.degrees(math.atan2(forward[1], forward[0]))})


def test_a_robot_camera_that_stands_still_learns_afresh_what_its_corrections_cannot_settle() -> None:
    # Without the edge fit (adapt.vision.edge_pose): with it, the first look is learned
    # through a better pose, the ball is seen, and the robot drives after it -- no longer
    # the camera standing still this test is about.
    sc = throw(8, 1.9, "schemas.scene-background.edge_fit=false")
    rows = _Rows()
    runner = Runner(sc, out=None, seed=8, outputs=QUIET, listeners=(rows,))
    rows.runner = runner
    runner.run()
    r = rows.rows
    turned = [i for i in range(1, len(r)) if abs(r[i]["heading"] - r[i - 1]["heading"]) > 0.5]
    assert turned and max(turned) < 25, turned  # the real robot turned once, then stood
    after = r[max(turned):]
    assert after[0]["moving"] and not after[-1]["moving"]
    # its own corrections move no camera: the history fills while it corrects
    full = [i for i, row in enumerate(after) if row["history"] == row["depth"]]
    assert full and after[-1]["corrections"] - after[full[0]]["corrections"] >= 10
    assert all(row["history"] == row["depth"] for row in after[full[0]:])
    # far from synchronised for a while, it learns afresh what held still (the first look
    # took two passes), and its corrections settle
    assert after[-1]["passes"] >= r[max(turned) - 1]["passes"] + 2
    assert statistics.median(row["error"] for row in r[-10:]) < 2.0
