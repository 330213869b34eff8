"""Object placement: the reachability shortcut is exact, and placement draws as before."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention.config import WorldConfig
from jointattention.world.kinematics import CENTRED, centring_angles, forward_axis
from jointattention.world.placement import _REACHABLE, all_reachable, place_into, region_of


@st.composite
def regions(draw):
    """An object region, a camera offset and joint limits, near and beyond the default's."""
    # + 0.0 makes -0.0 plain 0.0: sorted keeps (0.0, -0.0) as drawn, and uniform refuses it
    pan = sorted(draw(st.floats(-70, 70)) + 0.0 for _ in range(2))
    tilt = sorted(draw(st.floats(-60, 50)) + 0.0 for _ in range(2))
    d_lo = draw(st.floats(0.1, 1.0))
    region = np.array([*pan, *tilt, d_lo, d_lo + draw(st.floats(0, 1)), 0.02, 0.04, 3, 15, 0])
    offset = np.array([draw(st.floats(-0.1, 0.1)) for _ in range(3)])
    limits = np.radians([-draw(st.floats(30, 90)), draw(st.floats(30, 90)),
                         -draw(st.floats(20, 80)), draw(st.floats(20, 80))])
    return region, offset, limits


@settings(max_examples=300, deadline=None)
@given(regions(), st.integers(0, 2**32 - 1))
def test_a_region_called_reachable_has_no_point_that_cannot_be_centred(case, seed):
    """Where all_reachable says so, centring_angles accepts every point of the region."""
    region, offset, limits = case
    if not all_reachable(region, offset, limits):
        return
    rng = np.random.default_rng(seed)
    corners = np.array(np.meshgrid(region[0:2], region[2:4], region[4:6])).reshape(3, -1).T
    for pan, tilt, dist in np.r_[corners, rng.uniform(region[[0, 2, 4]], region[[1, 3, 5]],
                                                      (200, 3))]:
        point = dist * np.array(forward_axis(math.radians(pan), math.radians(tilt)))
        p, t, status = centring_angles(point, offset)
        assert status == CENTRED
        assert limits[0] <= p <= limits[1] and limits[2] <= t <= limits[3]


def test_a_region_a_rounding_error_in_front_of_the_camera_is_not_called_reachable():
    """Points at the camera's own depth, in front by one ulp, may round to behind it."""
    offset = np.array([0.0, np.nextafter(0.1, 0.0), 0.0])  # the camera a hair short of 0.1 m
    region = np.array([0.0, 0.0, 0.0, 1.0, 0.1, 0.1, 0.02, 0.04, 3, 15, 0])
    assert not all_reachable(region, offset, np.radians([-30.0, 30.0, -20.0, 20.0]))
    behind = [centring_angles(0.1 * np.array(forward_axis(0.0, math.radians(t))), offset)[2]
              for t in np.linspace(0.0, 1.0, 200)]
    assert any(status != CENTRED for status in behind)  # what the margin keeps out


def test_a_region_beyond_the_limits_is_not_called_reachable():
    """A region that reaches past a joint limit keeps the check."""
    region, offset, limits = region_of(WorldConfig())
    assert region[_REACHABLE] == 1.0  # the default world's region is all reachable
    wide = region.copy()
    wide[0] = math.degrees(limits[0]) - 1.0
    assert not all_reachable(wide, offset, limits)


def test_placing_with_the_shortcut_draws_the_same_objects():
    """The default region placed with and without the shortcut gives identical objects."""
    region, offset, limits = region_of(WorldConfig())
    checked = region.copy()
    checked[_REACHABLE] = 0.0
    face = np.array([0.0, 1.2, 0.3])
    for seed in range(50):
        placed = []
        for reg in (region, checked):
            pos, rad = np.zeros((6, 3)), np.zeros(6)
            pos[0], rad[0] = [0.1, 0.6, 0.0], 0.03
            n = place_into(np.random.default_rng(seed), pos, rad, 1, face, 0.1, reg, offset,
                           limits)
            placed.append((n, pos, rad))
        assert placed[0][0] == placed[1][0] == 6
        np.testing.assert_array_equal(placed[0][1], placed[1][1])
        np.testing.assert_array_equal(placed[0][2], placed[1][2])
