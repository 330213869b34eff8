"""The fast way to see: a trial's objects projected through the head's camera, no rendering.

Used by the experiments; the rendered mode renders the same objects and detects them in the
image. The detector's rule here: an object is seen when its centre lies in the image; its
bright-colour area is its image area times the part of it inside the image.
"""

from __future__ import annotations

import math

import numpy as np
from numba.np.random.generator_core import next_uint32
from numba.np.random.random_methods import (  # numpy's draws, in numba
    bounded_lemire_uint64,
    buffered_bounded_lemire_uint32,
    random_interval,
)

from .._arrays import floats
from .._jit import jit
from ..agent.detections import Detections
from ..errors import ConfigError
from .kinematics import (
    HeadKinematics,
    camera_point,
    pixel_px,
    rotation_matrix,
    sphere_area_px,
)
from .mjcf import HEAD_RADII_M
from .options import WorldConfig
from .placement import place_into, region_of

__all__ = ["FastScene", "detect_into", "draw_index", "draw_objects", "permutation"]


@jit
def draw_index(rng, n: int) -> int:
    """``rng.integers(n)`` for ``n`` >= 1, the same draws (numpy's), quicker to compile.

    numba's own ``integers`` checks its arguments with formatted messages: about 0.5 s of the
    first run's compile. This is what it runs for one draw below ``n``.
    """
    top = np.uint64(n - 1)
    if top == 0:
        return 0
    if top < 0xFFFFFFFF:
        return np.int64(buffered_bounded_lemire_uint32(rng.bit_generator, top))
    if top == 0xFFFFFFFF:
        return np.int64(next_uint32(rng.bit_generator))
    return np.int64(bounded_lemire_uint64(rng.bit_generator, top))


@jit
def permutation(rng, n: int) -> np.ndarray:
    """``rng.permutation(n)``, the same draws (numpy's shuffle), quicker for numba to compile.

    numba's own ``permutation`` shuffles arrays of any shape: compiling it took about 4 s of
    the first run's 22 (``jointattention bench``); this is the loop it runs for a range.
    """
    out = np.arange(n)
    for i in range(n - 1, 0, -1):
        j = np.int64(random_interval(rng.bit_generator, i))
        if i != j:
            out[i], out[j] = out[j], out[i]
    return out


@jit
def draw_objects(rng, target_m, face_m, face_radius_m, region, offset_m, limits_rad, pos, rad,
                 edge) -> int:
    """One trial's objects, into ``pos`` (n, 3), ``rad`` and ``edge``: the target's index.

    The target at ``target_m`` with a radius drawn from the region, the distractors placed
    apart from it, from each other and from the face (:func:`~.placement.place_into`), all in
    a random order, each with a texture drawn: :meth:`FastScene.sample`, the compiled engine's
    trials and the native vector environment draw their scenes with it, in this order. -1 if
    the objects cannot be placed.
    """
    # element by element: numba compiles these loops faster than slice assignments
    n = len(rad)
    for d in range(3):
        pos[0, d] = target_m[d]
    rad[0] = rng.uniform(region[6], region[7])
    if place_into(rng, pos, rad, 1, face_m, face_radius_m, region, offset_m, limits_rad) < n:
        return -1
    order = permutation(rng, n)
    was_pos, was_rad = pos.copy(), rad.copy()
    target = 0
    for a in range(n):
        for d in range(3):
            pos[a, d] = was_pos[order[a], d]
        rad[a] = was_rad[order[a]]
        if order[a] == 0:
            target = a
    for a in range(n):
        edge[a] = rng.uniform(0.0, 1.0)
    return target


@jit
def _inside_fraction(h: float) -> float:
    """Fraction of a disc inside a straight border at signed distance h (in radii)."""
    h = min(max(h, -1.0), 1.0)
    return 1.0 - (math.acos(h) - h * math.sqrt(1 - h * h)) / math.pi


@jit(inline=True)  # into the compiled loops' look: no arrays counted in and out per step
def detect_into(pos_m, radius_m, edge, rot, offset_m, focal_px, width_px, height_px,
                centre_out, area_out, edge_out, ids_out) -> int:
    """The fast detector: the objects whose centre lies in the image, written into ``*_out``.

    Returns how many. Each object is projected (:func:`~.kinematics.pixel_px`), and only
    those in the image are given their area (:func:`~.kinematics.sphere_area_px`).
    """
    w, h = float(width_px), float(height_px)
    m = 0
    for i in range(len(radius_m)):
        x, d, z = camera_point(pos_m[i], rot, offset_m)
        u, v = pixel_px(x, d, z, focal_px, (w - 1) / 2, (h - 1) / 2)
        if not (d > 0 and u >= -0.5 and u <= w - 0.5 and v >= -0.5 and v <= h - 0.5):
            continue
        a = sphere_area_px(x, d, z, radius_m[i], focal_px)
        r = math.sqrt(a / math.pi)  # equal_area_radius
        # distance of the centre to the nearest image border, in radii
        if min(min(u + 0.5, w - 0.5 - u), min(v + 0.5, h - 0.5 - v)) / r < 1.0:
            a = a * (_inside_fraction((u + 0.5) / r) * _inside_fraction((w - 0.5 - u) / r)
                     * _inside_fraction((v + 0.5) / r) * _inside_fraction((h - 0.5 - v) / r))
        centre_out[m, 0], centre_out[m, 1] = u, v
        area_out[m], edge_out[m], ids_out[m] = a, edge[i], i
        m += 1
    return m


class FastScene:
    """One trial's objects as the fast detector sees them (a :class:`~.protocol.Scene`).

    Args:
        kinematics: the head and camera.
        object_pos_m: (n, 3) object centres.
        object_radius_m: (n,) object radii.
        target_index: the caregiver's target among them.
        edge: (n,) each object's texture complexity (the paper's f_edge).

    :meth:`sample` draws one for an experiment's trial.
    """

    def __init__(self, kinematics: HeadKinematics, object_pos_m, object_radius_m,
                 target_index: int, edge):
        self.kinematics = kinematics
        self.object_radius_m = floats("object_radius_m", object_radius_m, (None,))
        n = len(self.object_radius_m)
        self.object_pos_m = floats("object_pos_m", object_pos_m, (n, 3))
        self.edge = floats("edge", edge, (n,))
        self.target_index = int(target_index)
        self.visible_ids = np.arange(0)
        # what every look needs of the camera, once
        self._camera = (np.asarray(kinematics.offset_m, dtype=float), float(kinematics.focal_px),
                        kinematics.width_px, kinematics.height_px)

    @classmethod
    def sample(cls, world: WorldConfig, kinematics: HeadKinematics, target_m, face_m,
               n_objects: int, rng: np.random.Generator) -> FastScene:
        """The caregiver's target at ``target_m`` plus random distractors.

        The distractors are kept clear of the face at ``face_m``; ``rng`` draws them, the target's
        size, the objects' order and every object's texture.
        """
        pos, rad, edge = np.empty((n_objects, 3)), np.empty(n_objects), np.empty(n_objects)
        target = draw_objects(rng, np.asarray(target_m, dtype=float),
                              np.asarray(face_m, dtype=float), HEAD_RADII_M[2],
                              *region_of(world), pos, rad, edge)
        if target < 0:
            raise ConfigError(
                f"objects: could not place {n_objects} objects apart within the object region; "
                "expected fewer objects, a wider region or smaller gaps")
        return cls(kinematics, pos, rad, target, edge)

    def observe(self, theta_rad) -> Detections:
        """What the robot's detector reports at head angle ``theta_rad``.

        The object ids of the detections are left in ``visible_ids``.
        """
        n = len(self.object_radius_m)
        centre, area, edge = np.empty((n, 2)), np.empty(n), np.empty(n)
        ids = np.empty(n, dtype=np.int64)
        offset_m, focal_px, width_px, height_px = self._camera
        m = detect_into(self.object_pos_m, self.object_radius_m, self.edge,
                        rotation_matrix(float(theta_rad[0]), float(theta_rad[1])), offset_m,
                        focal_px, width_px, height_px, centre, area, edge, ids)
        self.visible_ids = ids[:m]
        return Detections(centre[:m], area[:m], edge[:m], np.zeros(m), (width_px, height_px))
