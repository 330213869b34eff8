"""Head kinematics: closed-form centring for the offset camera, and parity with MuJoCo."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention.config import WorldConfig
from jointattention.world.kinematics import (
    HeadKinematics,
    Unreachable,
    forward_axis,
    rotation_into,
    rotation_matrix,
)
from jointattention.world.simulator import World

KIN = HeadKinematics.from_config(WorldConfig())
angles = st.tuples(st.floats(-1.0, 1.0), st.floats(-0.7, 0.55))


@settings(max_examples=200, deadline=None)
@given(theta=angles, depth=st.floats(0.3, 3.0), du=st.floats(-100, 100), dv=st.floats(-80, 80))
def test_centring_angles_put_the_point_at_the_image_centre(theta, depth, du, dv):
    """For any visible point, the solved head angle projects it onto the image centre."""
    # Build a world point from a pixel and depth at head angle theta.
    x = (du / KIN.focal_px) * depth
    z = -(dv / KIN.focal_px) * depth
    rot = KIN.rotation(theta)
    point = rot @ (np.array([x, depth, z]) + np.array(KIN.offset_m))
    solved = KIN.centring_angles(point)
    uv, d = KIN.project(point, solved)
    assert d[0] > 0
    np.testing.assert_allclose(uv[0], KIN.centre_px, atol=1e-6)


@settings(max_examples=200, deadline=None)
@given(theta=angles, dist=st.floats(0.3, 3.0))
def test_round_trip_from_head_angle(theta, dist):
    """A point on the optical axis at head angle theta gives theta back."""
    point = KIN.camera_position(theta) + dist * KIN.gaze_direction(theta)
    np.testing.assert_allclose(KIN.centring_angles(point), theta, atol=1e-9)


@settings(max_examples=50, deadline=None)
@given(st.floats(-3.2, 3.2), st.floats(-1.6, 1.6))
def test_forward_axis_is_the_rotation_s_middle_column(pan, tilt):
    """forward_axis and rotation_into give rotation_matrix's values, to the bit."""
    rot = rotation_matrix(pan, tilt)
    assert forward_axis(pan, tilt) == tuple(rot[:, 1])
    into = np.full((3, 3), np.nan)
    rotation_into(pan, tilt, into)
    assert np.array_equal(into, rot)


def test_project_takes_many_points_at_once():
    """Several points project in one call, each as it does alone (a scalar radius broadcasts)."""
    rng = np.random.default_rng(0)
    theta = np.array([0.2, -0.1])
    points = KIN.camera_position(theta) + rng.uniform(0.5, 2.0, (5, 1)) * (
        KIN.gaze_direction(theta) + rng.normal(0, 0.1, (5, 3)))
    uv, depth = KIN.project(points, theta)
    for p, q, d in zip(points, uv, depth, strict=True):
        one_uv, one_depth = KIN.project(p, theta)
        np.testing.assert_allclose(one_uv[0], q)
        assert one_depth[0] == pytest.approx(d)


def test_offset_matters():
    """The offset camera needs a different angle than a plain atan2 would give."""
    point = np.array([0.3, 0.5, 0.2])
    naive = np.array([np.arctan2(0.3, 0.5), np.arctan2(0.2, np.hypot(0.3, 0.5))])
    assert np.max(np.abs(KIN.centring_angles(point) - naive)) > np.deg2rad(2)


def test_points_too_close_are_unreachable():
    """A point within the camera's offset cannot be centred."""
    with pytest.raises(Unreachable):
        KIN.centring_angles([0.01, 0.0, 0.0])


def test_mujoco_camera_matches_kinematics():
    """MuJoCo's camera pose equals the closed-form kinematics at random head angles."""
    world = World(seed=0)
    cam = world.model.camera("eye").id
    rng = np.random.default_rng(0)
    for _ in range(50):
        theta = world.kinematics.clip(rng.uniform(-1, 1, 2))
        world.set_head_angle(theta)
        np.testing.assert_allclose(world.data.cam_xpos[cam], KIN.camera_position(theta),
                                   atol=1e-9)
        xmat = world.data.cam_xmat[cam].reshape(3, 3)
        # MuJoCo cameras look along their -z axis.
        np.testing.assert_allclose(-xmat[:, 2], KIN.gaze_direction(theta), atol=1e-9)
        np.testing.assert_allclose(world.head_angle_rad, theta, atol=1e-12)


def test_fovy_matches_horizontal_fov():
    """The vertical field of view given to MuJoCo keeps pixels square."""
    f_vertical = (KIN.height_px / 2) / np.tan(np.deg2rad(KIN.fovy_deg) / 2)
    assert f_vertical == pytest.approx(KIN.focal_px)
