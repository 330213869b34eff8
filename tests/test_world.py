"""The world: determinism, randomness of scenes, placement rules, ground truth, rendering."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointattention.agent.detections import equal_area_radius
from jointattention.config import ObjectsConfig, WorldConfig
from jointattention.errors import ConfigError
from jointattention.rng import stream
from jointattention.world.scene import gaze_angles, sample_scene
from jointattention.world.simulator import World


def _render_at_face(seed: int) -> np.ndarray:
    with World(seed=seed) as world:
        world.reset()
        world.set_head_angle(world.face_angle_rad)
        return world.render()


def test_same_seed_gives_byte_identical_images(needs_gl):
    """Two worlds with one seed render the same bytes."""
    assert _render_at_face(7).tobytes() == _render_at_face(7).tobytes()


def test_different_seeds_give_different_scenes(needs_gl):
    """Other seeds give other caregivers, objects and images."""
    a, b = World(seed=1), World(seed=2)
    assert a.caregiver != b.caregiver
    assert not np.allclose(a.state.object_pos_m, b.state.object_pos_m)
    assert not np.array_equal(_render_at_face(1), _render_at_face(2))


def test_initial_state_really_is_random():
    """Across seeds the first scene's target, object count in view and positions vary."""
    targets = {World(seed=s).target_index for s in range(20)}
    firsts = np.array([World(seed=s).state.object_pos_m[0] for s in range(20)])
    assert len(targets) > 2
    assert np.std(firsts, axis=0).min() > 0.05


def test_objects_are_apart_reachable_and_clear_of_the_face():
    """Over many scenes, objects are apart, reachable and clear of the face.

    No two objects overlap, all can be centred within the joint limits, none covers the caregiver's
    face.
    """
    cfg = WorldConfig()
    rng = stream(0, "test")
    from jointattention.world.kinematics import HeadKinematics

    kin = HeadKinematics.from_config(cfg)
    for _ in range(200):
        s = sample_scene(cfg, rng)
        p, r = s.object_pos_m, s.object_radius_m
        gaps = np.linalg.norm(p[:, None] - p[None], axis=2) - r[:, None] - r[None]
        assert np.all(gaps[~np.eye(len(r), dtype=bool)] > 0)
        for q in p:
            assert kin.within_limits(kin.centring_angles(q))
        face_dir = s.head_pos_m / np.linalg.norm(s.head_pos_m)
        cos = p @ face_dir / np.linalg.norm(p, axis=1)
        assert np.all(np.rad2deg(np.arccos(cos)) > cfg.objects.face_clearance_deg)


def test_impossible_placement_is_a_clear_error():
    """Too many large objects in a small region fail with a ConfigError, not a hang."""
    cfg = WorldConfig(objects=ObjectsConfig(
        radius_range_m=(0.2, 0.3), pan_range_deg=(-5, 5), tilt_range_deg=(-5, 5)))
    with pytest.raises(ConfigError, match="could not place 20 objects"):
        sample_scene(cfg, stream(0, "test"), n_objects=20)


def test_caregiver_gaze_points_at_the_target():
    """Head plus eye rotation equals the direction from the caregiver's head to its target."""
    world = World(seed=4)
    for _ in range(20):
        s = world.reset()
        total = s.head_yaw_pitch_rad + s.eye_yaw_pitch_rad
        np.testing.assert_allclose(total, gaze_angles(s.head_pos_m, s.target_pos_m), atol=1e-12)


def test_object_at_centre_is_ground_truth_of_the_view():
    """Centring the head on an object makes it the object at the centre.

    The face alone is not an object.
    """
    world = World(seed=3)
    for i in range(world.state.n_objects):
        theta = world.kinematics.centring_angles(world.state.object_pos_m[i])
        assert world.object_at_centre(radius_px=5, theta_rad=theta) == i
    assert world.object_at_centre(radius_px=5, theta_rad=world.face_angle_rad) is None


def test_projection_matches_rendered_centroids(needs_gl):
    """Fast projection agrees with rendered segmentation: centre 2 px, area 5%.

    For every unoccluded object fully in view over many random scenes and head angles.
    """
    world = World(seed=11)
    rng = np.random.default_rng(0)
    ids = world.object_geom_ids()
    w, h = world.kinematics.width_px, world.kinematics.height_px
    checked = 0
    for _ in range(40):
        world.reset()
        aim = world.state.object_pos_m[rng.integers(world.state.n_objects)]
        world.set_head_angle(world.kinematics.centring_angles(aim) + rng.normal(0, 0.15, 2))
        seg = world.render(segmentation=True)
        scene = world.fast_scene()
        det = scene.observe(world.head_angle_rad)
        for j, i in enumerate(scene.visible_ids):
            c, area = det.centre_px[j], det.colour_area_px[j]
            r = equal_area_radius(area)
            if not (r + 1 < c[0] < w - r - 2 and r + 1 < c[1] < h - r - 2):
                continue
            ys, xs = np.nonzero(seg == ids[i])
            if len(xs) < 0.95 * area:  # partly hidden behind another object
                continue
            assert np.hypot(xs.mean() - c[0], ys.mean() - c[1]) < 2.0
            assert len(xs) == pytest.approx(area, rel=0.05)
            checked += 1
    assert checked >= 30


def test_render_shape_and_type(needs_gl):
    """Renders are RGB uint8 at the configured size."""
    with World(WorldConfig(), seed=0) as world:
        img = world.render()
    assert img.shape == (240, 320, 3) and img.dtype == np.uint8


def test_antialiasing_changes_only_the_edges(needs_gl):
    """antialias_samples = 0 renders the same scene: same shape, edges alone differ."""
    import dataclasses

    plain = WorldConfig()
    jagged = dataclasses.replace(plain, camera=dataclasses.replace(plain.camera,
                                                                   antialias_samples=0))
    with World(plain, seed=3) as a, World(jagged, seed=3) as b:
        x, y = a.render().astype(int), b.render().astype(int)
    assert x.shape == y.shape and not np.array_equal(x, y)
    assert np.mean(np.abs(x - y).max(axis=2) > 40) < 0.05  # most pixels agree


def test_coarser_spheres_change_only_the_outlines(needs_gl):
    """sphere_slices / sphere_stacks set MuJoCo's facets: fewer move only a few pixels."""
    import dataclasses

    plain = WorldConfig()
    coarse = dataclasses.replace(plain, camera=dataclasses.replace(
        plain.camera, sphere_slices=8, sphere_stacks=4))
    with World(plain, seed=3) as a, World(coarse, seed=3) as b:
        assert (b.model.vis.quality.numslices, b.model.vis.quality.numstacks) == (8, 4)
        a.set_head_angle(a.face_angle_rad)
        b.set_head_angle(b.face_angle_rad)
        x, y = a.render().astype(int), b.render().astype(int)
    assert not np.array_equal(x, y)
    assert np.mean(np.abs(x - y).max(axis=2) > 40) < 0.05


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 60))
@settings(max_examples=80, deadline=None)
def test_the_compiled_permutation_draws_as_numpy(seed, n):
    """world.fast.permutation gives numpy's rng.permutation(n) and leaves the stream alike."""
    from jointattention.world.fast import permutation

    a, b = np.random.default_rng(seed), np.random.default_rng(seed)
    assert np.array_equal(permutation(a, n), b.permutation(n))
    assert a.random() == b.random()


@given(seed=st.integers(0, 2**32 - 1),
       ns=st.lists(st.one_of(st.integers(1, 200), st.integers(1, 2**40)), min_size=1,
                   max_size=20))
@settings(max_examples=80, deadline=None)
def test_the_compiled_index_draw_draws_as_numpy(seed, ns):
    """world.fast.draw_index gives numpy's rng.integers(n), draw after draw, 32 and 64 bits."""
    from jointattention.world.fast import draw_index

    a, b = np.random.default_rng(seed), np.random.default_rng(seed)
    assert [draw_index(a, n) for n in ns] == [int(b.integers(n)) for n in ns]
    assert a.random() == b.random()
