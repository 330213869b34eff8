"""The population module's compiled kernels: its input, commands, replay, trial start and end.

:class:`~.module.PopulationModule` (the step-by-step agent) and the compiled engine's
loop call the same kernels on the same arrays (:class:`PopulationArrays`), so both engines
learn the same bits. :data:`KERNELS` are its part of a trial
(:class:`~jointattention.agent.protocol.ModuleKernels`): the compiled loop is handed them.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..._jit import jit
from ...agent.face_standardiser import standardise, welford_update
from ...agent.moves import places_into, scale_angle_into, unit_step
from ...agent.protocol import ModuleKernels
from .code import (
    EXCESS,
    average_face_into,
    average_into,
    population_activate,
    population_hidden_into,
    population_readout,
    population_scores_into,
    population_teach_rows,
    scores_of_output_into,
)
from .features import face_features_into, n_window_features

__all__ = ["KERNELS", "InputSpec", "PopulationArrays", "commands_into", "line_step",
           "population_begin", "population_learn", "replay_rows_into", "trial_begin",
           "trial_command", "trial_direction", "trial_learn"]


class InputSpec(NamedTuple):
    """How the module's input is made from a view and a head angle (for the kernels).

    A view is the face window's grey levels (``height`` x ``width``), then the eye window's
    (``eye_height`` x ``eye_width``, 0 x 0 without one): each window gives its features.
    """

    height: int
    width: int
    eye_height: int
    eye_width: int
    cell_px: int
    n_orientations: int
    pixels: bool
    hog: bool
    min_std: float  # of the features' standardiser
    theta_mid_rad: np.ndarray
    theta_half_rad: np.ndarray


@jit
def features_into(face, spec, out) -> None:
    """The features ``spec`` asks for of one view: the face window's, then the eye window's.

    Each window's are :func:`face_features_into`'s.
    """
    n_face = spec.height * spec.width
    m_face = n_window_features(spec.height, spec.width, spec.cell_px, spec.n_orientations,
                               spec.pixels, spec.hog)
    face_features_into(face[:n_face], spec.height, spec.width, spec.cell_px,
                       spec.n_orientations, spec.pixels, spec.hog, out[:m_face])
    if spec.eye_height > 0:
        face_features_into(face[n_face:], spec.eye_height, spec.eye_width, spec.cell_px,
                           spec.n_orientations, spec.pixels, spec.hog, out[m_face:])


@jit
def input_of_features_into(features, pan, tilt, spec, mean, m2, n_seen, x) -> None:
    """The module's input ``x``: a window's ``features``, then the scaled head angle.

    The features are standardised by ``mean``, ``m2`` of ``n_seen`` faces if ``n_seen`` > 0
    (pass 0 to leave them as they are).
    """
    n = len(features)
    if n_seen > 0:
        standardise(features, mean, m2, n_seen, spec.min_std, x[:n])
    else:
        x[:n] = features
    scale_angle_into(pan, tilt, spec.theta_mid_rad, spec.theta_half_rad, x, n)


_BATCH = 32  # faces whose hidden units are summed in one pass over the input weights


@jit
def commands_into(faces, thetas, spec, mean, m2, n_seen, w1, b1, w2, b2, hidden_mean,
                  readout, step_rad, out) -> None:
    """The first step from each face (K, pixels) at its head angle (K, 2): ``out`` (K, 2).

    A batch of faces at a time shares each pass over ``w1`` (:func:`population_hidden_into`:
    the same bits as one face at a time). A face the same as the one before (a blank face at
    many head angles) reuses its features and its hidden units' sums over them: the head
    angle's two inputs come last, so adding theirs to those sums gives the whole sums' bits.
    """
    n_face = len(w1) - 2  # the inputs before the head angle's
    X, G = np.empty((_BATCH, len(w1))), np.empty((_BATCH, len(b1)))  # each face's input, sums
    group = np.empty(_BATCH, np.int64)  # each row's face among the batch's faces
    features, angle = np.empty(n_face), np.empty(2)
    h, p, z, score = np.empty(len(b1)), np.empty(len(b2)), np.empty(len(b2)), np.empty(len(b2))
    if readout == EXCESS:
        average_face_into(hidden_mean, w2, b2, z)
    for k0 in range(0, len(faces), _BATCH):
        n, m = min(_BATCH, len(faces) - k0), 0
        for k in range(k0, k0 + n):
            new = k == 0 or not np.array_equal(faces[k], faces[k - 1])
            if new:  # e.g. not the blank face again
                features_into(faces[k], spec, features)
            if new or k == k0:
                input_of_features_into(features, thetas[k, 0], thetas[k, 1], spec, mean, m2,
                                       n_seen, X[m])
                m += 1
            group[k - k0] = m - 1
        population_hidden_into(X[:m, :n_face], w1[:n_face], b1, G[:m])
        for k in range(k0, k0 + n):  # the sums go on from the face's, over the angle's two
            scale_angle_into(thetas[k, 0], thetas[k, 1], spec.theta_mid_rad, spec.theta_half_rad,
                             angle, 0)
            population_hidden_into(angle.reshape((1, 2)), w1[n_face:], G[group[k - k0]],
                                   h.reshape((1, len(h))))
            population_activate(h, w2, b2, p)
            scores_of_output_into(h, p, w2, hidden_mean, readout, z, score)
            psi, _ = population_readout(score)
            out[k, 0], out[k, 1] = step_rad * math.cos(psi), step_rad * math.sin(psi)


@jit
def replay_rows_into(drawn, features, thetas, directions, counts, spec, mean, m2, n_seen, X,
                     taught_rad, n_taught) -> None:
    """The inputs and places of the kept trials ``drawn`` (replay memory rows), into rows.

    Each row keeps its face's features, not standardised, so the input is the same as from
    the face (:func:`features_into`, then :func:`input_of_features_into`), without computing
    them again.
    """
    for r in range(len(drawn)):
        i = drawn[r]
        input_of_features_into(features[i], thetas[i, 0], thetas[i, 1], spec, mean, m2,
                               n_seen, X[r])
        taught_rad[r, : counts[i]] = directions[i, : counts[i]]
        n_taught[r] = counts[i]


class PopulationArrays(NamedTuple):
    """The module's options, learned arrays, replay memory and scratch, as the kernels take them.

    The arrays are the module's own (changed in place); ``counters`` are its trials kept,
    places taught and faces whose features were standardised (see
    :meth:`~.module.PopulationModule.arrays`).
    """

    spec: InputSpec
    kappa: float
    learning_rate: float
    hidden_rate: float
    average_rate: float
    readout: int
    standardise: bool
    in_view: bool  # keep every object in view, not only the attended one
    replay: int
    belief: float  # how far each place taught is weighted by the network's belief in it
    w1: np.ndarray
    b1: np.ndarray
    w2: np.ndarray
    b2: np.ndarray
    averaged_w1: np.ndarray
    averaged_b1: np.ndarray
    averaged_w2: np.ndarray
    averaged_b2: np.ndarray
    readout_w1: np.ndarray  # the averages, or the weights themselves (average_rate 0)
    readout_b1: np.ndarray
    readout_w2: np.ndarray
    readout_b2: np.ndarray
    hidden_mean: np.ndarray
    feature_mean: np.ndarray
    feature_m2: np.ndarray
    replay_features: np.ndarray  # each kept face's features, not standardised
    replay_thetas: np.ndarray
    replay_directions: np.ndarray
    replay_counts: np.ndarray
    x: np.ndarray  # the trial's input, from its start to its end
    features: np.ndarray  # its face's features, not standardised, likewise
    h: np.ndarray
    p: np.ndarray
    grad_h: np.ndarray
    taught: np.ndarray
    z: np.ndarray
    score: np.ndarray
    counters: np.ndarray  # trials kept, places taught, faces standardised by
    trial: np.ndarray  # (3,): the direction read out, the head angle at the trial's start
    places: np.ndarray  # (MAX_PLACES, 2): the places of a trial, scratch


@jit
def population_begin(a, face, pan, tilt, fit) -> float:
    """A trial's start (``PopulationModule.begin``): its input ``a.x``; the direction read out.

    With ``standardise``, ``fit`` adds this face's features to their running statistics
    first.
    """
    features_into(face, a.spec, a.features)
    if fit and a.standardise:
        a.counters[2] += 1
        welford_update(a.features, a.feature_mean, a.feature_m2, a.counters[2])
    n_seen = a.counters[2] if a.standardise else 0
    input_of_features_into(a.features, pan, tilt, a.spec, a.feature_mean, a.feature_m2,
                           n_seen, a.x)
    population_scores_into(a.x, a.readout_w1, a.readout_b1, a.readout_w2, a.readout_b2,
                           a.hidden_mean, a.readout, a.h, a.p, a.z, a.score)
    psi, _ = population_readout(a.score)
    return psi


@jit
def population_learn(a, places, face, start_pan, start_tilt, replay_rng) -> int:
    """A trial's end (``PopulationModule.learn``): teach the directions of ``places`` (n, 2).

    Their directions from the trial's start are taught for its input ``a.x``; the trial is
    kept in the replay memory (the oldest forgotten when it is full), ``a.replay`` kept
    trials drawn from ``replay_rng`` are taught again, and the running averages move once.
    Returns the places of this trial.
    """
    n = len(places)
    rows = 1 + a.replay  # the trial, then the replayed ones: taught in one pass each
    X, taught_rad = np.empty((rows, len(a.x))), np.empty((rows, a.replay_directions.shape[1]))
    n_taught = np.empty(rows, np.int64)
    X[0], n_taught[0] = a.x, n
    for i in range(n):
        taught_rad[0, i] = math.atan2(places[i, 1] - start_tilt, places[i, 0] - start_pan)
    slot, kept, whole = a.counters[0] % len(a.replay_counts), np.empty(len(face)), True
    for j in range(len(face)):  # kept as an image keeps it: whole grey levels, 0 to 255
        kept[j] = float(np.uint8(min(max(np.rint(face[j]), 0.0), 255.0)))
        whole = whole and kept[j] == face[j]
    if whole:  # the trial's features are those of the face kept
        a.replay_features[slot, :] = a.features
    else:
        features_into(kept, a.spec, a.replay_features[slot])
    a.replay_thetas[slot, 0], a.replay_thetas[slot, 1] = start_pan, start_tilt
    a.replay_directions[slot, :n] = taught_rad[0, :n]
    a.replay_counts[slot] = n
    a.counters[0] += 1
    drawn = replay_rng.integers(0, min(a.counters[0], len(a.replay_counts)), size=a.replay)
    n_seen = a.counters[2] if a.standardise else 0
    replay_rows_into(drawn, a.replay_features, a.replay_thetas, a.replay_directions,
                     a.replay_counts, a.spec, a.feature_mean, a.feature_m2, n_seen, X[1:],
                     taught_rad[1:], n_taught[1:])
    a.counters[1] += population_teach_rows(
        X, taught_rad, n_taught, a.kappa, a.w1, a.b1, a.w2, a.b2, a.learning_rate,
        a.hidden_mean, a.hidden_rate, a.h, a.p, a.grad_h, a.taught, a.belief, a.z,
        a.averaged_w1, a.average_rate)  # the last update's pass moves averaged_w1
    average_into(a.averaged_b1, a.b1, a.average_rate)
    average_into(a.averaged_w2.reshape(-1), a.w2.reshape(-1), a.average_rate)
    average_into(a.averaged_b2, a.b2, a.average_rate)
    return n


@jit
def line_step(start_pan, start_tilt, psi_rad, pan, tilt, step_rad) -> tuple[float, float]:
    """One step along the line from ``start`` in direction ``psi_rad``, from the head angle now.

    It aims one step beyond the head's projection on the line (never behind the start), so
    a head on the line moves along it and a head off it turns back toward it.
    """
    u0, u1 = math.cos(psi_rad), math.sin(psi_rad)
    s = max((pan - start_pan) * u0 + (tilt - start_tilt) * u1, 0.0) + step_rad
    return unit_step(start_pan + s * u0 - pan, start_tilt + s * u1 - tilt, step_rad)


@jit
def trial_begin(a, face, face_id, pan, tilt, learning) -> float:
    """The trial starts: :func:`population_begin`, its direction and start kept in ``a.trial``.

    It keeps nothing by ``face_id``, and no evidence: 0.0.
    """
    a.trial[0] = population_begin(a, face, pan, tilt, learning)
    a.trial[1], a.trial[2] = pan, tilt
    return 0.0


@jit(inline=True)  # into the compiled loop: its arrays not counted in and out
def trial_direction(a, pan, tilt, step_rad) -> tuple[float, float]:
    """The step along the line from the trial's start in the direction read out."""
    return line_step(a.trial[1], a.trial[2], a.trial[0], pan, tilt, step_rad)


@jit(inline=True)
def trial_command(a, pan, tilt, step_rad, rng) -> tuple[float, float]:
    """The module's step: :func:`trial_direction` (it draws nothing from ``rng``)."""
    return trial_direction(a, pan, tilt, step_rad)


@jit
def trial_learn(a, place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px, face, thetas,
                steps, rng) -> int:
    """The trial's end: :func:`population_learn` of ``place`` (and ``in_view``, the others').

    The places are :func:`~jointattention.agent.moves.places_into`'s, from the last image
    (``thetas`` and ``steps``, the trial's, teach nothing); with ``seen`` -1 (a trial the
    module drove that found nothing, with ``unfound``), :func:`unfound_learn`'s.
    """
    if seen < 0:  # the module drove and found nothing (``unfound``; BootstrapAgent.end_trial)
        return unfound_learn(a, face, rng)
    n = places_into(place, centre, seen, a.in_view, pan, tilt, cx, cy, gain_rad_per_px,
                    a.places)
    return population_learn(a, a.places[:n], face, a.trial[1], a.trial[2], rng)


@jit
def unfound_learn(a, face, rng) -> int:
    """A trial whose line found nothing: teach a direction the network believed in besides.

    The evaluator never fired along the line read out (``a.trial[0]``), so that direction is
    not taught again: one is drawn from ``rng`` by the network's p(direction | face) at the
    trial's start (``a.p``, as :func:`population_begin` left it) with the directions within
    three label widths of the line left out, and taught as a place found is
    (:func:`population_learn`). Returns the places taught: 1, or 0 where the network believes
    in no other direction.
    """
    n = len(a.p)
    away_rad = 3.0 / math.sqrt(a.kappa)  # three label widths: kappa is 1 / width^2
    q, total = np.empty(n), 0.0
    for b in range(n):
        d = 2.0 * math.pi * b / n - a.trial[0]
        q[b] = a.p[b] if abs(math.atan2(math.sin(d), math.cos(d))) > away_rad else 0.0
        total += q[b]
    if total <= 0.0:
        return 0
    u, b = rng.random() * total, 0
    while b < n - 1 and u >= q[b]:
        u -= q[b]
        b += 1
    psi = 2.0 * math.pi * b / n  # unit b's direction (von_mises_into)
    a.places[0, 0], a.places[0, 1] = a.trial[1] + math.cos(psi), a.trial[2] + math.sin(psi)
    return population_learn(a, a.places[:1], face, a.trial[1], a.trial[2], rng)


KERNELS = ModuleKernels(trial_begin, trial_command, trial_direction, trial_learn)
