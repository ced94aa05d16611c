"""``geometry.look_at_parameters`` inverts ``look_at_rotation``: the corrected
camera ``adapt sync`` prints as scenario keys is the camera it found."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adapt.errors import ImaginationError
from adapt.geometry import Camera, look_at_parameters, look_at_rotation, rotation_exp

coord = st.floats(-5.0, 5.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(
    position=st.tuples(coord, coord, st.floats(0.05, 3.0)),
    target=st.tuples(coord, coord, st.floats(-1.0, 3.0)),
    roll=st.floats(-179.0, 179.0),
)
def test_round_trip_with_look_at_rotation(position, target, roll):
    p, t = np.array(position), np.array(target)
    d = t - p
    dist = float(np.linalg.norm(d))
    if dist < 1e-3 or abs(d[2]) / dist > 0.999:  # no look_at (or no roll) is defined
        return
    r = look_at_rotation(p, t, roll)
    back, roll_back = look_at_parameters(r, p, distance=dist)
    assert np.allclose(back, t, atol=1e-6 * max(1.0, dist))
    assert roll_back == pytest.approx(roll, abs=1e-6)
    assert np.allclose(look_at_rotation(p, back, roll_back), r, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(rotvec=st.tuples(*[st.floats(-0.5, 0.5)] * 3))
def test_any_corrected_rotation_becomes_scenario_keys(rotvec):
    # a camera turned by a correction (not built by look_at) still has look_at keys
    nominal = Camera.look_at(fx=525, fy=525, cx=319.5, cy=239.5, width=640, height=480,
                             position=(0.0, -0.6, 0.6), look_at=(0.0, 3.0, 0.3))
    turned = nominal.with_rotation(rotation_exp(rotvec) @ nominal.rotation)
    target, roll = look_at_parameters(turned.rotation, turned.position, 3.6)
    pasted = Camera.look_at(fx=525, fy=525, cx=319.5, cy=239.5, width=640, height=480,
                            position=turned.position, look_at=target, roll_deg=roll)
    assert np.allclose(pasted.rotation, turned.rotation, atol=1e-9)


def test_undefined_cases_are_errors():
    down = look_at_rotation((0, 0, 1), (0, 1, 1))
    straight_down = np.array([[1.0, 0, 0], [0, -1, 0], [0, 0, -1]])  # viewing axis -z
    with pytest.raises(ImaginationError, match="straight down"):
        look_at_parameters(straight_down, (0, 0, 1))
    with pytest.raises(ImaginationError, match="rotation"):
        look_at_parameters(2 * down, (0, 0, 1))
    with pytest.raises(ImaginationError, match="distance"):
        look_at_parameters(down, (0, 0, 1), distance=0.0)
