"""The native vector environment's fixed kernel arguments, packed as one numba StructRef.

numba types and unboxes each argument of a compiled call anew; at 64 sub-environments the
thirty-odd arguments of a step (:func:`~._vector_kernels.start_step_all`), the typed list of
generators most, cost about as much as the step's arithmetic. Packed once per list of
generators (:func:`pack`), a step passes one struct and its own arrays (:func:`step_packed`).
This module imports numba: the vector environment imports it at its first step.
"""

from __future__ import annotations

from numba.core import types
from numba.experimental import structref

from .._jit import jit
from ._vector_kernels import start_step_all

__all__ = ["FIELDS", "StepArgs", "pack", "step_packed"]

# start_step_all's arguments that no step changes, in its order (starts, then and actions aside)
FIELDS = ("rngs", "targets_m", "faces_m", "face_radius_m", "region", "offset_m", "limits_rad",
          "theta_face_rad", "clip", "moves", "cam", "max_steps", "pos", "radius", "edge",
          "state", "theta", "looks", "faces", "bounds", "scaled", "with_rows")


@structref.register
class StepArgsType(types.StructRef):
    """numba's type of :class:`StepArgs`: its fields typed as they were packed."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class StepArgs(structref.StructRefProxy):
    """The packed arguments, as Python holds them (made by :func:`pack`)."""


structref.define_proxy(StepArgs, StepArgsType, list(FIELDS))


@jit
def pack(rngs, targets_m, faces_m, face_radius_m, region, offset_m, limits_rad, theta_face_rad,
         clip, moves, cam, max_steps, pos, radius, edge, state, theta, looks, faces, bounds,
         scaled, with_rows):
    """:data:`FIELDS` as one :class:`StepArgs` (compiled, so its constructor is cached too)."""
    return StepArgs(rngs, targets_m, faces_m, face_radius_m, region, offset_m, limits_rad,
                    theta_face_rad, clip, moves, cam, max_steps, pos, radius, edge, state, theta,
                    looks, faces, bounds, scaled, with_rows)


@jit
def step_packed(a, starts, then, actions, head_out, face_out, rows_out, centre_out, det_out,
                ints_out, flags_out, floats_out) -> int:
    """:func:`~._vector_kernels.start_step_all` with its fixed arguments packed in ``a``."""
    return start_step_all(a.rngs, a.targets_m, a.faces_m, a.face_radius_m, a.region, a.offset_m,
                          a.limits_rad, a.theta_face_rad, starts, then, actions, a.clip,
                          a.moves, a.cam, a.max_steps, a.pos, a.radius, a.edge, a.state,
                          a.theta, a.looks, a.faces, a.bounds, a.scaled, a.with_rows, head_out,
                          face_out, rows_out, centre_out, det_out, ints_out, flags_out,
                          floats_out)
