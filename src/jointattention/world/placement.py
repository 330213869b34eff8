"""Where a scene's objects go: at random, apart from each other and from the caregiver's face.

:func:`place_into` is the compiled kernel (the compiled engine calls it for every trial);
:func:`place_objects` and :func:`sample_objects` call it for the step-by-step world.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from ..errors import ConfigError
from .kinematics import CENTRED, centring_angles, forward_axis
from .mjcf import HEAD_RADII_M
from .options import WorldConfig

__all__ = ["place_into", "place_objects", "region_of", "sample_objects"]

_MAX_TRIES = 4000


@jit
def _norm(a: np.ndarray) -> float:
    """The length of vector ``a`` (3,)."""
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@jit
def _angle(a: np.ndarray, b: np.ndarray, norm_a: float, norm_b: float) -> float:
    """Angle (rad) between vectors ``a`` and ``b`` (3,) of lengths ``norm_a``, ``norm_b``."""
    dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    return math.acos(min(max(dot / (norm_a * norm_b), -1.0), 1.0))


@jit
def place_into(rng, pos, rad, n_fixed, head_pos_m, face_radius_m, region, offset_m,
               limits_rad) -> int:
    """Fill ``pos`` (n, 3) and ``rad`` (n,) after their ``n_fixed`` first rows with objects.

    The objects are drawn at random, apart from each other and from the face, all reachable.
    ``region`` holds, in degrees and metres: pan range, tilt range, distance range, radius
    range, least gap, face clearance; ``limits_rad`` the pan and tilt joint ranges. Returns the
    number of rows filled (fewer than n if ``_MAX_TRIES`` draws did not suffice).

    Candidates are drawn in batches and accepted in order, which is the same as drawing them
    one by one and rejecting the ones that break a rule.
    """
    n = len(rad)
    head_norm = _norm(head_pos_m)
    face_half = math.asin(face_radius_m / head_norm)
    gap, clearance = np.deg2rad(region[8]), np.deg2rad(region[9])
    half, norm = np.empty(n), np.empty(n)  # each placed object's angular radius and distance
    for i in range(n_fixed):
        norm[i] = _norm(pos[i])
        half[i] = math.asin(rad[i] / norm[i])
    placed, drawn = n_fixed, 0
    cand = np.empty(3)
    while placed < n and drawn < _MAX_TRIES:
        batch = 8 * (n - placed)
        drawn += batch
        pan = np.deg2rad(rng.uniform(region[0], region[1], batch))
        tilt = np.deg2rad(rng.uniform(region[2], region[3], batch))
        dist = rng.uniform(region[4], region[5], batch)
        radius = rng.uniform(region[6], region[7], batch)
        for j in range(batch):
            if placed == n:
                break
            f0, f1, f2 = forward_axis(pan[j], tilt[j])  # the direction at that head angle
            cand[0], cand[1], cand[2] = dist[j] * f0, dist[j] * f1, dist[j] * f2
            cand_half, cand_norm = math.asin(radius[j] / dist[j]), _norm(cand)
            if not (_angle(cand, head_pos_m, cand_norm, head_norm) - cand_half - face_half
                    >= clearance):
                continue
            apart = True
            for i in range(placed):
                if _angle(pos[i], cand, norm[i], cand_norm) - half[i] - cand_half < gap:
                    apart = False
                    break
            if not apart:
                continue
            p, t, status = centring_angles(cand, offset_m)
            if status != CENTRED or not (limits_rad[0] <= p <= limits_rad[1]
                                         and limits_rad[2] <= t <= limits_rad[3]):
                continue
            for d in range(3):  # element by element: quicker for numba to compile
                pos[placed, d] = cand[d]
            rad[placed], half[placed], norm[placed] = radius[j], cand_half, cand_norm
            placed += 1
    return placed


def region_of(world: WorldConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``place_into``'s region, camera offset and joint limits for ``world``."""
    o = world.objects
    region = np.array([*o.pan_range_deg, *o.tilt_range_deg, *o.distance_range_m,
                       *o.radius_range_m, o.min_gap_deg, o.face_clearance_deg], dtype=float)
    limits = np.deg2rad([*world.head.pan_limits_deg, *world.head.tilt_limits_deg])
    return region, np.asarray(world.camera.offset_m, dtype=float), limits


def sample_objects(world: WorldConfig, head_pos: np.ndarray, face_radius: float,
                    rng: np.random.Generator, n: int, fixed_pos=(), fixed_rad=()):
    """Objects at random, apart from each other and from the face, all reachable.

    The ``fixed`` objects (already placed) come first and count toward ``n``.
    """
    pos, rad = np.zeros((n, 3)), np.zeros(n)
    k = len(fixed_rad)
    pos[:k], rad[:k] = np.reshape(fixed_pos, (k, 3)), fixed_rad
    if place_into(rng, pos, rad, k, np.asarray(head_pos, dtype=float), float(face_radius),
                  *region_of(world)) < n:
        raise ConfigError(
            f"objects: could not place {n} objects apart within the object region after "
            f"{_MAX_TRIES} draws; expected fewer objects, a wider region or smaller gaps")
    return pos, rad


def place_objects(world: WorldConfig, head_pos_m, rng: np.random.Generator, n: int,
                  fixed_pos=(), fixed_rad=()) -> tuple[np.ndarray, np.ndarray]:
    """Positions (n, 3) and radii (n,) of ``n`` objects, the ``fixed`` ones first."""
    return sample_objects(world, np.asarray(head_pos_m, float), HEAD_RADII_M[2], rng, n,
                           fixed_pos, fixed_rad)
