"""The memory module's compiled kernels: a trial's recall, its steps, what it leaves out and keeps.

:class:`~.module.MemoryModule` (the step-by-step agent) and the compiled engine's loop call
the same kernels on the same arrays (:class:`MemoryArrays`), so both engines keep and recall
the same bits. :data:`KERNELS` are its part of a trial
(:class:`~jointattention.agent.protocol.ModuleKernels`): the compiled loop is handed them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..._jit import jit
from ...agent.moves import place_step, places_into, random_step
from ...agent.protocol import ModuleKernels
from ._left_out import (
    drop_left_out_from,
    empty_arrival,
    leave_out,
    left_out_into,
    passed_over_into,
)
from .episodic import face_code_into, memory_recall, memory_store

__all__ = ["EVIDENCE", "KERNELS", "RECALLED", "SUPPORT", "MemoryArrays", "memory_begin",
           "memory_command", "memory_direction", "memory_learn", "memory_observe",
           "memory_passed_over"]

RECALLED, EVIDENCE, SUPPORT = range(3)  # the entries of MemoryArrays.trial


class MemoryArrays(NamedTuple):
    """The memory's options, kept trials, the trial's recall and scratch, as the kernels take them.

    The arrays are the memory's own (changed in place); ``counters`` are its trials kept,
    codes in use, places left out (see :class:`~.episodic.EpisodicMemory`) and the face's
    places left out now (see :meth:`~.module.MemoryModule.compiled_state`).
    """

    projection: np.ndarray  # the face code
    lo_rad: np.ndarray
    cell_rad: float
    k: int
    radius_rad: float
    in_view: bool  # keep every object in view, not only the attended one
    codes: np.ndarray  # the kept trials (models/memory/_recall.py)
    counts: np.ndarray
    links: np.ndarray
    aims: np.ndarray
    base: np.ndarray
    leave_out_empty: bool  # leave out a recalled place found empty (models/memory/_left_out.py)
    left_codes: np.ndarray
    left_aims: np.ndarray
    pass_over: bool  # visual attention passes over objects at places left out
    drop_left_out: bool  # nor does the memory keep their places
    recall_again: bool  # a place left out, the face's next place is recalled at once
    saccade_rad: float  # the longest move to a recalled place (memory.saccade); 0: one step
    counters: np.ndarray  # trials kept, codes in use, places left out, the face's left out
    code: np.ndarray  # the trial's face code
    aim: np.ndarray  # (2,): the place recalled for it
    trial: np.ndarray  # (3,): whether a place was recalled, its evidence and support
    mine: np.ndarray  # (len(left_aims), 2): the face's places left out, the first counters[3]
    places: np.ndarray  # (MAX_PLACES, 2): the places of a trial, scratch
    recalled_ids: np.ndarray  # per face id (frozen): 0 not yet, 1 recalled, 2 nothing
    recalled_of: np.ndarray  # per face id (frozen): its aim, evidence and support
    coded: np.ndarray  # per face id (learning): whether its code is kept
    code_of: np.ndarray  # per face id (learning): its code


@jit
def _recall(s) -> float:
    """Recall the place for the trial's face code, the face's places left out not winning.

    Into ``s.aim`` and ``s.trial``; returns the evidence.
    """
    support, evidence = memory_recall(s.code, s.codes, s.counts, s.links, s.aims, s.base,
                                      s.counters[0], s.counters[1], s.lo_rad, s.cell_rad, s.k,
                                      s.radius_rad, s.mine[:s.counters[3]], s.aim)
    s.trial[RECALLED], s.trial[EVIDENCE], s.trial[SUPPORT] = support >= 0, evidence, support
    return evidence


@jit
def memory_begin(s, face, face_id, pan, tilt, learning) -> float:
    """The trial starts: the face's code, and the place recalled for it; returns its evidence.

    A frozen memory recalls a face alike each time: what it recalled for a face id is kept
    (``recalled_ids``). Learning, a face id's code is kept (``coded``). Either only if the
    state was made for the run's faces (``compiled_state(n_faces)``).
    """
    if 0 <= face_id < len(s.recalled_ids) and s.recalled_ids[face_id]:
        s.aim[0], s.aim[1] = s.recalled_of[face_id, 0], s.recalled_of[face_id, 1]
        s.trial[RECALLED] = s.recalled_ids[face_id] == 1
        s.trial[EVIDENCE], s.trial[SUPPORT] = s.recalled_of[face_id, 2], s.recalled_of[face_id, 3]
        s.counters[3] = 0  # frozen, it leaves nothing out
        return s.trial[EVIDENCE]
    if 0 <= face_id < len(s.coded) and s.coded[face_id]:
        s.code[:] = s.code_of[face_id]
    else:
        face_code_into(face, s.projection, s.code)
        if 0 <= face_id < len(s.coded):
            s.code_of[face_id], s.coded[face_id] = s.code, True
    s.counters[3] = left_out_into(s.code, s.left_codes, s.left_aims, s.counters[2], s.mine)
    evidence = _recall(s)
    if 0 <= face_id < len(s.recalled_ids):
        s.recalled_ids[face_id] = 1 if s.trial[RECALLED] else 2
        s.recalled_of[face_id, 0], s.recalled_of[face_id, 1] = s.aim[0], s.aim[1]
        s.recalled_of[face_id, 2], s.recalled_of[face_id, 3] = evidence, s.trial[SUPPORT]
    return evidence


@jit(inline=True)  # into the compiled loop: its arrays not counted in and out
def memory_observe(s, pan, tilt, step_rad, centre, cx, cy, gain_rad_per_px, learning) -> float:
    """Leave the recalled place out if the head found it empty; returns the evidence now.

    While learning, with ``leave_out_empty`` (:mod:`._left_out`): the trial then has no
    recalled place and no evidence, or with ``recall_again`` the face's next place and its
    evidence.
    """
    if (s.leave_out_empty and learning and s.trial[RECALLED] > 0
            and empty_arrival(s.aim[0], s.aim[1], pan, tilt, step_rad, centre, cx, cy,
                              s.radius_rad / gain_rad_per_px)):
        s.counters[2] = leave_out(s.code, s.aim[0], s.aim[1], s.left_codes, s.left_aims,
                                  s.counters[2])
        s.counters[3] = left_out_into(s.code, s.left_codes, s.left_aims, s.counters[2],
                                      s.mine)
        if s.recall_again:  # the next place, the one left out no longer winning
            _recall(s)
        else:
            s.trial[RECALLED], s.trial[EVIDENCE], s.trial[SUPPORT] = 0.0, 0.0, -1.0
    return s.trial[EVIDENCE]


@jit(inline=True)
def memory_passed_over(s, pan, tilt, centre, cx, cy, gain_rad_per_px, learning,
                       passed) -> bool:
    """With ``pass_over``, learning: flag in ``passed`` the objects at places left out."""
    if not (s.pass_over and learning):
        return False
    passed_over_into(centre, cx, cy, gain_rad_per_px, pan, tilt, s.mine[:s.counters[3]],
                     s.radius_rad, passed)
    return True


@jit(inline=True)
def memory_direction(s, pan, tilt, step_rad) -> tuple[float, float]:
    """A move toward the recalled place (``saccade_rad``: its longest); none without one."""
    if s.trial[RECALLED] == 0:
        return 0.0, 0.0
    return place_step(s.aim[0] - pan, s.aim[1] - tilt, step_rad, s.saccade_rad)


@jit(inline=True)
def memory_command(s, pan, tilt, step_rad, rng) -> tuple[float, float]:
    """:func:`memory_direction`; a random step from ``rng`` while nothing is recalled."""
    if s.trial[RECALLED] == 0:
        return random_step(rng, step_rad)
    return memory_direction(s, pan, tilt, step_rad)


@jit
def memory_learn(s, place, centre, seen, pan, tilt, cx, cy, gain_rad_per_px, face, thetas,
                 steps, rng) -> int:
    """Keep the trial's places with its face code; returns how many.

    ``place``, then (``in_view``) every other object's in the last image
    (:func:`~jointattention.agent.moves.places_into`); with ``drop_left_out`` none at a place
    left out of the face's recalls.
    """
    n = places_into(place, centre, seen, s.in_view, pan, tilt, cx, cy, gain_rad_per_px,
                    s.places)
    if s.drop_left_out:
        n = drop_left_out_from(s.places, n, s.mine[:s.counters[3]], s.radius_rad)
    for i in range(n):
        s.counters[1] = memory_store(s.code, s.places[i, 0], s.places[i, 1], s.codes, s.counts,
                                     s.links, s.aims, s.base, s.counters[0], s.counters[1],
                                     s.lo_rad, s.cell_rad, s.radius_rad)
        s.counters[0] += 1
    return n


KERNELS = ModuleKernels(memory_begin, memory_command, memory_direction, memory_learn,
                        memory_observe, memory_passed_over)
