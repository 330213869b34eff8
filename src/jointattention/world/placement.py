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

__all__ = ["all_reachable", "place_into", "place_objects", "region_of", "sample_objects"]

_MAX_TRIES = 4000
_REACHABLE = 10  # the region's entry that says every point of it is reachable (region_of)


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
    range, least gap, face clearance, and whether all of it is reachable (:func:`region_of`);
    ``limits_rad`` the pan and tilt joint ranges. Returns the
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
            if region[_REACHABLE] == 0.0:  # else every candidate is (region_of)
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
    """``place_into``'s region, camera offset and joint limits for ``world``.

    The region's last entry is 1.0 if every point of it is reachable (:func:`all_reachable`),
    and ``place_into`` then skips the check: about a tenth of a scene draw's time.
    """
    o = world.objects
    offset = np.asarray(world.camera.offset_m, dtype=float)
    limits = np.deg2rad([*world.head.pan_limits_deg, *world.head.tilt_limits_deg])
    region = np.array([*o.pan_range_deg, *o.tilt_range_deg, *o.distance_range_m,
                       *o.radius_range_m, o.min_gap_deg, o.face_clearance_deg, 0.0], dtype=float)
    region[_REACHABLE] = float(all_reachable(region, offset, limits))
    return region, offset, limits


_DEPTH_MARGIN_M = 1e-9  # by how much all_reachable's distances must clear the camera's offsets


def all_reachable(region: np.ndarray, offset_m: np.ndarray, limits_rad: np.ndarray,
                  margin_rad: float = 1e-6) -> bool:
    """Whether every point of the object region can be centred within the joint limits.

    A point at distance d lies off the optical axis that centres it by at most
    delta = asin(|offset across the axis| / d) (the camera's offset along its axis moves no
    direction), so the centring tilt is within delta of the point's own elevation, and the
    pan within asin(sin delta / cos(elevation)) of its azimuth (a spherical cap's half width in
    longitude). If the region grown by these stays inside the limits (with ``margin_rad`` for
    rounding), and its nearest points are far enough for a centring angle to exist in front,
    :func:`~.kinematics.centring_angles` would accept every candidate. False when unsure.
    """
    ox, oy, oz = (float(v) for v in offset_m)
    pan_deg, tilt_deg, d_min = region[0:2], region[2:4], float(region[4])
    across = math.hypot(ox, oz)
    if not d_min > 2 * across or max(abs(tilt_deg)) >= 80.0:
        return False
    delta = math.asin(across / d_min)
    elevation = math.radians(max(abs(tilt_deg)))
    # a point a rounding error past an offset may land inside it or behind the camera
    if not (d_min * math.cos(elevation) > abs(ox) + _DEPTH_MARGIN_M
            and d_min * math.cos(delta) > oy + _DEPTH_MARGIN_M
            and math.sin(delta) < math.cos(elevation)):
        return False
    spread = math.asin(math.sin(delta) / math.cos(elevation))
    pan, tilt = np.radians(pan_deg), np.radians(tilt_deg)
    return bool(limits_rad[0] + margin_rad <= pan[0] - spread
                and pan[1] + spread <= limits_rad[1] - margin_rad
                and limits_rad[2] + margin_rad <= tilt[0] - delta
                and tilt[1] + delta <= limits_rad[3] - margin_rad)


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
