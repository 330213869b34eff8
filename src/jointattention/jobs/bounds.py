"""The bench's bounds beside its rates: what a cell could reach if only its core cost time.

A rendered step renders the robot's view and detects in it; its bound is one view rendered
and detected alone (:func:`rendered_rows`). A learning cell of the memory, the population or
the reinforcement learner spends a step of the compiled loop on the world (scene, projection,
detection) and its trial's bookkeeping, and once per trial on the learning module: at the
trial's start the module reads the face (the memory's code and recall; the population code's
features and forward pass; the values of the face's shifts), and at the end of a trial the
evaluator fired on it learns (the memory keeps each place; the population code is taught,
with its replayed trials; the reinforcement learner updates at every trial's end). Both are
timed alone, in compiled loops, on the state the cell ended with, so the bench can print what
share of the cell's time the module's arithmetic is: the rest is the loop around it
(:func:`learner_cell_rows`).
"""

from __future__ import annotations

import copy
import dataclasses
import time

import numpy as np

from .._jit import jit
from ..agent.face_standardiser import standardise, welford_update
from ..agent.vision import ImageDetector
from ..config import WorldConfig
from ..models.memory.episodic import face_code_into, left_out_of, memory_recall, memory_store
from ..models.memory.module import MemoryModule
from ..models.population._trial import population_begin, population_learn
from ..models.rl import RLAgent
from ..models.rl._kernels import rl_choice_odds, rl_choose, rl_learn, rl_values_into

__all__ = ["RENDERED_ROW", "cell_rate", "learner_cell_rows", "rendered_rows"]

# the rate the rendered preset's estimate takes (bench.AGENT_RATE_ROWS)
RENDERED_ROW = ("agent steps, rendered mode + OpenCV, the rendered preset's view (FAST_CAMERA; "
                "quick n5-sigmoid)")


@jit
def _memory_starts(faces, projection, codes, counts, links, aims, base, n_stored, n_codes,
                   lo_rad, cell_rad, k_nearest, radius_rad, left_codes, left_aims,
                   n_left) -> float:
    """A trial's start, once per face: its code and the recall (MemoryModule.begin)."""
    code, out, total = np.empty(projection.shape[1]), np.empty(2), 0.0
    for i in range(len(faces)):
        face_code_into(faces[i], projection, code)
        left_out = left_out_of(code, left_codes, left_aims, n_left)
        support, _ = memory_recall(code, codes, counts, links, aims, base, n_stored, n_codes,
                                   lo_rad, cell_rad, k_nearest, radius_rad, left_out, out)
        total += support
    return total


@jit
def _memory_keeps(codes_in, places, codes, counts, links, aims, base, n_stored, n_codes,
                  lo_rad, cell_rad, radius_rad) -> int:
    """Each place kept with its face's code (MemoryModule.learn); the places kept."""
    for i in range(len(places)):
        n_codes = memory_store(codes_in[i], places[i, 0], places[i, 1], codes, counts, links,
                               aims, base, n_stored, n_codes, lo_rad, cell_rad, radius_rad)
        n_stored += 1
    return n_stored


@jit
def _population_trials(a, faces, thetas, places, replay_rng, learn: bool) -> float:
    """A trial's start for each face (PopulationModule.begin), and with ``learn`` its end."""
    total = 0.0
    for i in range(len(faces)):
        total += population_begin(a, faces[i], thetas[i, 0], thetas[i, 1], learn)
        if learn:
            population_learn(a, places[i:i + 1], faces[i], thetas[i, 0], thetas[i, 1],
                             replay_rng)
    return total


def _best_s(fn, state, repeats: int = 3) -> float:
    """Seconds of the fastest of ``repeats`` calls ``fn(copy of state)`` (copied untimed)."""
    best = np.inf
    for _ in range(repeats):
        own = copy.deepcopy(state)
        start = time.perf_counter()
        fn(own)
        best = min(best, time.perf_counter() - start)
    return best


def _memory_us(module, faces: np.ndarray) -> tuple[float, float]:
    """Microseconds of a trial's start and of keeping one place, on copies of ``module``."""
    memory = module.memory
    n = min(memory.n_stored_, len(memory.aims_), 4 * len(faces))
    codes = np.stack([memory.code(f) for f in faces[np.arange(n) % len(faces)]])
    places = memory.aims_[:n].copy()
    args = (memory.lo_rad, memory.cell_rad)

    def starts(m, faces=faces):
        _memory_starts(faces, m.projection, *m.kept_arrays(), *args, m.options.k_nearest,
                       m.radius_rad, *m.left_arrays())

    def keeps(m, n=n):
        _memory_keeps(codes[:n], places[:n], *m.kept_arrays(), *args, m.radius_rad)

    starts(memory, faces[:1])  # each loop compiled (or loaded) outside the timing
    keeps(copy.deepcopy(memory), 1)
    return _best_s(starts, memory) / len(faces) * 1e6, _best_s(keeps, memory) / n * 1e6


def _start_and_end_us(trials, state, faces) -> tuple[float, float]:
    """Microseconds of a trial's start and of its end, each face once.

    ``trials(copy of state, learn, faces)`` runs the starts alone, then starts and ends; the
    end's time is the difference.
    """
    trials(copy.deepcopy(state), True, faces[:1])  # compiled (or loaded) outside the timing
    start_s = _best_s(lambda s: trials(s, False, faces), state)
    both_s = _best_s(lambda s: trials(s, True, faces), state)
    return start_s / len(faces) * 1e6, (both_s - start_s) / len(faces) * 1e6


def _population_us(module, faces, thetas, places) -> tuple[float, float]:
    """Microseconds of a trial's start and of its end, on copies of ``module``."""

    def trials(m, learn, faces):
        _population_trials(m.arrays(), faces, thetas, places, np.random.default_rng(0), learn)

    return _start_and_end_us(trials, module, faces)


@jit
def _rl_starts(faces, s, choice_rng, xs, qs, shifts) -> None:
    """A trial's start for each face (``rl_begin``, frozen); its input, values and shift kept.

    ``s``: the agent's state (``RLAgent.compiled_state``).
    """
    for i in range(len(faces)):
        standardise(faces[i], s.mean, s.m2, s.faces_seen[0], s.min_std, xs[i])
        rl_values_into(xs[i], s.w, s.b, qs[i])
        rl_choice_odds(qs[i], s.q_stay, s.temperature, s.cdf, s.p_stay)
        shifts[i] = max(rl_choose(choice_rng.random(), s.p_stay[0], s.cdf), 0)


@jit
def _rl_ends(faces, xs, qs, shifts, places, s) -> None:
    """A learning trial's end for each face: the face's statistics and the updates.

    The evaluator fired at the face's target after one shift of 3 steps.
    """
    for i in range(len(faces)):
        s.faces_seen[0] += 1
        welford_update(faces[i], s.mean, s.m2, s.faces_seen[0])
        rl_learn(True, places[i, 0], places[i, 1], 0, shifts[i], 3, xs[i], qs[i], s.w, s.b,
                 s.q_stay, s.habituation, s.lo_rad, s.cell_rad, s.face_reward,
                 s.face_habituation, s.object_reward, s.place_habituation, s.place_recovery,
                 s.gamma, s.learning_rate_shift, s.learning_rate_stay)


def _rl_us(agent, faces, places) -> tuple[float, float]:
    """Microseconds of a trial's start and of its end, each timed alone on copies of ``agent``.

    Each is its own loop (not the difference of two timings, which noise can make negative):
    the ends learn from the inputs, values and shifts the starts computed.
    """
    n_dir = len(agent.steps_rad)
    xs, qs = np.empty_like(faces), np.empty((len(faces), n_dir))
    shifts = np.empty(len(faces), dtype=np.int64)

    def starts(a):
        _rl_starts(faces, a.compiled_state(faces.shape[1]), np.random.default_rng(0), xs, qs,
                   shifts)

    def ends(a):
        _rl_ends(faces, xs, qs, shifts, places, a.compiled_state(faces.shape[1]))

    starts(copy.deepcopy(agent))  # compiled (or loaded) outside the timing; fills the inputs
    ends(copy.deepcopy(agent))
    n = len(faces)
    return _best_s(starts, agent) / n * 1e6, _best_s(ends, agent) / n * 1e6


def learner_cell_rows(config, condition, n_steps: int | None = None
                      ) -> tuple[float, list[tuple[str, float, str]]]:
    """The cell's steps/s, and rows of its module's arithmetic and its share of the cell.

    ``condition`` of ``config`` learns ``n_steps`` (default: the configuration's) with the
    memory, the population or the reinforcement learner, in the compiled engine; its module is
    then timed alone (:func:`_memory_us`, :func:`_population_us` or :func:`_rl_us`) on the
    data sets' faces.
    """
    from ..experiment.cells import datasets_of, run_cell

    exp = dataclasses.replace(config.experiment, **({} if n_steps is None else
                                                    {"n_steps": n_steps}))
    config, ended = dataclasses.replace(config, experiment=exp), []
    start = time.perf_counter()
    records = run_cell(config, condition, 0, checkpoints=[exp.n_steps],
                       on_checkpoint=lambda t, agent: ended.append(agent))
    cell_s = time.perf_counter() - start
    agent, ds = ended[-1], datasets_of(config)
    faces = np.ascontiguousarray(ds.views.reshape(len(ds), -1), dtype=float)
    thetas = np.ascontiguousarray(ds.theta_face_rad, dtype=float)
    places = np.ascontiguousarray(thetas + ds.command_rad)
    n_trials, n_learned = len(records["end"]), int((records["end"] == 0).sum())
    if isinstance(agent, RLAgent):  # it learns at every trial's end, fired or not
        start_us, end_us = _rl_us(agent, faces, places)
        start, end, n_learned = "values of the face", "face statistics, updates", n_trials
    elif isinstance(agent.module, MemoryModule):
        memory = agent.module.memory
        start_us, keep_us = _memory_us(agent.module, faces)
        end_us = keep_us * memory.n_stored_ / max(n_learned, 1)  # its places, each kept
        start, end = "its code and recall", "each place kept"
    else:
        start_us, end_us = _population_us(agent.module, faces, thetas, places)
        start, end = "features, forward pass", "taught, and its replayed trials"
    module_s = (n_trials * start_us + n_learned * end_us) / 1e6
    return exp.n_steps / cell_s, [
        (f"  bound: the module alone, a trial's start ({start})", start_us, "us"),
        (f"  bound: the module alone, a learning trial's end ({end})", end_us, "us"),
        ("  the module's arithmetic (at the cell's end) / the cell's time", module_s / cell_s,
         "x")]


def cell_rate(config, condition, **experiment) -> float:
    """Agent steps per second of one cell of ``config`` with ``experiment``'s fields changed."""
    from ..experiment.cells import run_cell

    exp = dataclasses.replace(config.experiment, **experiment)
    start = time.perf_counter()
    run_cell(dataclasses.replace(config, experiment=exp), condition, 0)
    return exp.n_steps / (time.perf_counter() - start)


def rendered_rows(config, cond, n_steps: int) -> list[tuple[str, float, str]]:
    """The rendered agent's steps/s in ``cond`` of ``config`` for each view, and its bound.

    The views: the rendered preset's (``FAST_CAMERA``; the rate its estimate takes) and the
    world's (4 samples, 28 x 16 facets). Each rate is beside its bound, a view rendered and
    detected alone (:func:`_view_rate`), and their ratio.
    """
    from ..config import load_config

    views = ((RENDERED_ROW, load_config("rendered").world),
             ("agent steps, rendered mode, the world's view (4 samples; quick n5-sigmoid)",
              config.world))
    cell_rate(config, cond, n_steps=100, perception="rendered", engine="python")  # start GL
    rows = []
    for name, world in views:
        rate = cell_rate(dataclasses.replace(config, world=world), cond, n_steps=n_steps,
                         perception="rendered", engine="python")
        bound = _view_rate(world)
        rows += [(name, rate, "steps/s"),
                 ("  bound: one view rendered and detected alone", bound, "frames/s"),
                 ("  agent / bound", rate / bound, "x")]
    return rows


def _view_rate(world: WorldConfig, n_scenes: int = 20, n_views: int = 10) -> float:
    """Views per second of the rendered agent's perception alone: render one, detect in it.

    The bound of a rendered step (the agent's and the trial's Python cost nothing here). The
    views are a trial's: in each of ``n_scenes`` scenes of the 5-object world of ``world``,
    ``n_views`` head angles on the line from the caregiver's face to one of the objects (a
    view of walls alone, with nothing to detect, would cost less than the agent's).
    """
    from ..world.simulator import World

    rng, seconds = np.random.default_rng(0), []
    with World(world, seed=0) as view:
        detector = ImageDetector(focal_px=view.kinematics.focal_px)
        view.render()  # start the GL context outside the timing
        for _ in range(n_scenes):
            state = view.reset()
            face = view.face_angle_rad
            obj = view.kinematics.centring_angles(state.object_pos_m[rng.integers(
                state.n_objects)])
            detector.reset()
            for t in np.linspace(0.0, 1.0, n_views):
                theta = view.kinematics.clip(face + t * (obj - face))
                start = time.perf_counter()
                view.set_head_angle(theta)
                detector.detect(view.render())
                seconds.append(time.perf_counter() - start)
    return len(seconds) / sum(seconds)
