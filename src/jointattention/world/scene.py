"""Scenes drawn at random: the caregiver (identity, place, gaze) and the salient objects.

A :class:`SceneState` is a complete, immutable description of one scene; the simulator shows
it, the fast projection projects it, and ground truth (the caregiver's target) lives in it.
Identities are :mod:`.identity`'s (``Caregiver`` and ``sample_caregiver`` are named here too);
the light's colour, the room's and the robot's image effects are :mod:`.look`'s.
"""

from __future__ import annotations

import colorsys
from dataclasses import dataclass, replace

import numpy as np

from .identity import Caregiver, head_turn_fraction, pose_noise_deg, sample_caregiver
from .look import Look, sample_look
from .options import N_OBJECTS, WorldConfig
from .placement import sample_objects

__all__ = [
    "Caregiver",
    "SceneState",
    "gaze_angles",
    "sample_caregiver",
    "sample_scene",
    "scene_with",
    "shuffle_target",
    "with_new_distractors",
    "with_target",
]


@dataclass(frozen=True)
class SceneState:
    """One scene: caregiver, its gaze, the objects, the light. Only the world sees it."""

    caregiver: Caregiver
    head_pos_m: np.ndarray  # (3,) centre of the caregiver's head
    head_yaw_pitch_rad: np.ndarray  # (2,) head rotation; positive yaw turns to its left
    eye_yaw_pitch_rad: np.ndarray  # (2,) eyes' rotation relative to the head
    object_pos_m: np.ndarray  # (n, 3)
    object_radius_m: np.ndarray  # (n,)
    object_rgb: np.ndarray  # (n, 3) in [0, 1]
    target_index: int  # the object the caregiver attends to
    light_pos_m: np.ndarray  # (3,)
    light_intensity: float
    look: Look = Look()  # light colour and direction, ambient, room, image effects

    @property
    def n_objects(self) -> int:
        """How many objects the scene holds."""
        return len(self.object_radius_m)

    @property
    def target_pos_m(self) -> np.ndarray:
        """Where the caregiver's target is."""
        return self.object_pos_m[self.target_index]

    @property
    def face_radius_m(self) -> float:
        """Half the apparent height of the head (the face window is cropped from it)."""
        return self.caregiver.face_radius_m


def gaze_angles(from_m, to_m) -> np.ndarray:
    """(yaw, pitch) that turn a face looking along -y toward ``to_m``; pitch > 0 looks down."""
    v = np.asarray(to_m, float) - np.asarray(from_m, float)
    v = v / np.linalg.norm(v)
    return np.array([np.arctan2(v[0], -v[1]), -np.arcsin(v[2])])


def sample_scene(
    world: WorldConfig,
    rng: np.random.Generator,
    caregiver: Caregiver | None = None,
    n_objects: int = N_OBJECTS,
) -> SceneState:
    """A random scene of ``n_objects`` objects; ``caregiver`` fixes the identity (else drawn)."""
    cg = world.caregiver
    n = n_objects
    caregiver = caregiver if caregiver is not None else sample_caregiver(world, rng)
    # Her own place: offsets of exactly 0 leave the default world's numbers as they were.
    place = [0.0, cg.distance_m + caregiver.distance_offset_m,
             cg.height_m + caregiver.height_offset_m]
    head_pos = np.array(place) + rng.normal(0, cg.position_noise_m, 3)
    face_radius = caregiver.face_radius_m
    obj_pos, obj_rad = sample_objects(world, head_pos, face_radius, rng, n)
    rgb = _object_colours(n, rng)
    target = int(rng.integers(n))
    gaze = gaze_angles(head_pos, obj_pos[target])
    head = (head_turn_fraction(world, caregiver) * gaze
            + rng.normal(0, np.deg2rad(pose_noise_deg(world, caregiver)), 2))
    light = _light(world, rng)
    return SceneState(
        caregiver=caregiver,
        head_pos_m=head_pos,
        head_yaw_pitch_rad=head,
        eye_yaw_pitch_rad=gaze - head,
        object_pos_m=obj_pos,
        object_radius_m=obj_rad,
        object_rgb=rgb,
        target_index=target,
        **light,
        look=sample_look(world, rng),  # after the light: its draws come last
    )


def _object_colours(n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, 3) bright colours (HSV saturation and value 0.85-1), hues spread around the circle."""
    hues = (rng.uniform() + np.arange(n) / n + rng.uniform(-0.3, 0.3, n) / n) % 1.0
    rgb = [colorsys.hsv_to_rgb(h, rng.uniform(0.85, 1.0), rng.uniform(0.85, 1.0)) for h in hues]
    return np.array(rgb).reshape(n, 3)


def _light(world: WorldConfig, rng: np.random.Generator) -> dict:
    """The key light's position and intensity."""
    jitter = rng.normal(0, world.lighting.position_jitter_m, 3)
    return {"light_pos_m": np.array([0.3, 0.2, 1.6]) + jitter,
            "light_intensity": float(rng.uniform(*world.lighting.intensity_range))}


def scene_with(world: WorldConfig, caregiver: Caregiver, head_pos_m, object_pos_m,
               object_radius_m, target_index: int, rng: np.random.Generator) -> SceneState:
    """A scene of given geometry, the caregiver looking at the target.

    The geometry is a trial's objects and the caregiver's head where a data set has it; the
    caregiver looks without pose noise; ``rng`` draws the objects' colours, the light and the
    look.
    """
    head_pos_m = np.asarray(head_pos_m, float)
    object_pos_m = np.asarray(object_pos_m, float)
    head, eyes = _look_at(world, caregiver, head_pos_m, object_pos_m[target_index])
    colours = _object_colours(len(object_pos_m), rng)
    light = _light(world, rng)
    return SceneState(caregiver, head_pos_m, head, eyes, object_pos_m,
                      np.asarray(object_radius_m, float), colours, int(target_index), **light,
                      look=sample_look(world, rng))


def with_target(state: SceneState, world: WorldConfig, target_pos_m) -> SceneState:
    """``state`` with its target moved to ``target_pos_m``.

    The caregiver looks at it without pose noise (for pictures and held-out caregiver poses).
    """
    pos = state.object_pos_m.copy()
    pos[state.target_index] = target_pos_m
    head, eyes = _look_at(world, state.caregiver, state.head_pos_m, target_pos_m)
    return replace(state, object_pos_m=pos, head_yaw_pitch_rad=head, eye_yaw_pitch_rad=eyes)


def _look_at(world: WorldConfig, caregiver: Caregiver, head_pos_m,
             target_m) -> tuple[np.ndarray, np.ndarray]:
    """(head, eyes) rotations of ``caregiver`` looking at ``target_m`` without pose noise."""
    gaze = gaze_angles(head_pos_m, target_m)
    head = head_turn_fraction(world, caregiver) * gaze
    return head, gaze - head


def shuffle_target(pos_m: np.ndarray, radius_m: np.ndarray, rng: np.random.Generator):
    """The objects in random order, the target (first) among them: (pos, radius, target)."""
    order = rng.permutation(len(radius_m))
    return pos_m[order], radius_m[order], int(np.flatnonzero(order == 0)[0])


def with_new_distractors(state: SceneState, world: WorldConfig,
                         rng: np.random.Generator) -> SceneState:
    """``state`` with every object but the target drawn anew, in a new order.

    The caregiver, its gaze and the target stay (a recorded data set in a new scene).
    """
    n, t = state.n_objects, state.target_index
    pos, rad = sample_objects(world, state.head_pos_m, state.face_radius_m, rng, n,
                               [state.target_pos_m], [state.object_radius_m[t]])
    pos, rad, target = shuffle_target(pos, rad, rng)
    return replace(state, object_pos_m=pos, object_radius_m=rad, target_index=target)
