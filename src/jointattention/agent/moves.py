"""The bootstrap agent's compiled kernels: its moves, its inputs and its learning samples.

Shared by :class:`~.bootstrap.BootstrapAgent` (step by step) and the compiled engine
(:mod:`jointattention.experiment.compiled._loop`), so that both compute the same numbers.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit
from .attention import visual_feedback_rad

__all__ = ["MAX_PLACES", "capped_step", "learning_samples", "line_capture", "place_step",
           "places_into", "random_step", "scale_angle_into", "unit_step"]

MAX_PLACES = 20  # places a learning module keeps of one trial at most (objects in a scene: 20)


@jit
def unit_step(out_0: float, out_1: float, step_rad: float) -> tuple[float, float]:
    """The learning module's command: the direction of its output, one step long."""
    norm = max(math.hypot(out_0, out_1), 1e-12)
    return step_rad * out_0 / norm, step_rad * out_1 / norm


@jit
def capped_step(d_pan: float, d_tilt: float, max_rad: float) -> tuple[float, float]:
    """The move (d_pan, d_tilt) to a known place, at most ``max_rad`` long (shorter at the end)."""
    f = min(1.0, max_rad / max(math.hypot(d_pan, d_tilt), 1e-12))
    return d_pan * f, d_tilt * f


@jit
def place_step(d_pan: float, d_tilt: float, step_rad: float,
               saccade_rad: float) -> tuple[float, float]:
    """A move toward a place (d_pan, d_tilt) away: one step long, or the whole way there.

    With ``saccade_rad`` > 0 (``memory.saccade``) the move is at most that long.
    """
    if saccade_rad > 0:
        return capped_step(d_pan, d_tilt, saccade_rad)
    return unit_step(d_pan, d_tilt, step_rad)


@jit
def line_capture(centre_px, cx_px, cy_px, gain_rad_per_px, pan, tilt, start_pan, start_tilt,
                 u_pan, u_tilt, capture_rad) -> int:
    """The first object in view along a line, within ``capture_rad`` of it; -1 if none.

    The line runs from the trial's start (``start_pan``, ``start_tilt``) in the direction
    (``u_pan``, ``u_tilt``). Each object's place is the head angle now plus Eq. 2's command
    to it; of those ahead of the start and no farther than ``capture_rad`` from the line, the
    nearest the start along it. Following a line, the eyes land on the first thing on it.
    """
    norm = math.hypot(u_pan, u_tilt)
    if norm <= 0.0:
        return -1
    u0, u1 = u_pan / norm, u_tilt / norm
    best, best_i = np.inf, -1
    for i in range(centre_px.shape[0]):
        v_pan, v_tilt = visual_feedback_rad(centre_px[i, 0], centre_px[i, 1], cx_px, cy_px,
                                            gain_rad_per_px)
        d_pan, d_tilt = pan + v_pan - start_pan, tilt + v_tilt - start_tilt
        along = d_pan * u0 + d_tilt * u1
        if along > 0.0 and abs(d_pan * u1 - d_tilt * u0) <= capture_rad and along < best:
            best, best_i = along, i
    return best_i


@jit
def random_step(rng: np.random.Generator, step_rad: float) -> tuple[float, float]:
    """One step in a direction drawn from ``rng``."""
    angle = rng.uniform(0.0, 2 * math.pi)
    return step_rad * math.cos(angle), step_rad * math.sin(angle)


@jit
def scale_angle_into(pan_rad, tilt_rad, theta_mid_rad, theta_half_rad, out, first) -> None:
    """The head angle scaled to [-1, 1] by the joint ranges (the learning module's input).

    Written into ``out[first]`` and ``out[first + 1]``.
    """
    out[first] = (pan_rad - theta_mid_rad[0]) / theta_half_rad[0]
    out[first + 1] = (tilt_rad - theta_mid_rad[1]) / theta_half_rad[1]


@jit
def learning_samples(thetas_rad, steps_rad, aim_rad, executed: bool, y_out) -> np.ndarray:
    """Teaching signals of a successful trial: unit vectors in ``y_out``, and which to keep.

    Each step is taught the unit direction from where the head was to ``aim_rad``, or, if
    ``executed``, of the step it made; steps of no length are not kept.
    """
    keep = np.empty(len(thetas_rad), dtype=np.bool_)
    for i in range(len(thetas_rad)):
        if executed:
            d0, d1 = steps_rad[i, 0], steps_rad[i, 1]
        else:
            d0, d1 = aim_rad[0] - thetas_rad[i, 0], aim_rad[1] - thetas_rad[i, 1]
        norm = max(math.hypot(d0, d1), 1e-12)
        keep[i] = norm > 1e-9
        y_out[i, 0], y_out[i, 1] = d0 / norm, d1 / norm
    return keep


@jit
def places_into(place, centre, seen, in_view, pan, tilt, cx, cy, gain_rad_per_px,
                places) -> int:
    """``place``, then (``in_view``) every other object of the last image but ``seen``.

    Into ``places``, as ``BootstrapAgent.place_of`` finds them; returns how many.
    """
    places[0, 0], places[0, 1], n = place[0], place[1], 1
    for i in range(len(centre) if in_view else 0):
        if i != seen and n < len(places):
            v_pan, v_tilt = visual_feedback_rad(centre[i, 0], centre[i, 1], cx, cy,
                                                gain_rad_per_px)
            places[n, 0], places[n, 1] = pan + v_pan, tilt + v_tilt
            n += 1
    return n
