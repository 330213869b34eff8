"""Benchmarks: figures printed, never asserted (machines here are shared and noisy)."""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .._jit import jit
from ..agent.vision import ImageDetector
from ..config import WorldConfig
from ..models.network.learner import LearningModule, sgd_rows, sgd_update
from ..world.options import FAST_CAMERA
from .bounds import RENDERED_ROW, cell_rate, learner_cell_rows, rendered_rows
from .env_bench import run_env_benchmark, with_camera

__all__ = ["AGENT_RATE_ROWS", "compile_times", "run_agent_benchmark",
           "run_env_benchmark", "run_follow_benchmark", "run_world_benchmarks", "write_bench"]

AGENT_RATE_ROWS = {  # each kind of cell the preset estimates know, and its row
    "compiled": "agent steps, compiled engine, learning (quick n5-sigmoid)",
    "python": "agent steps, python engine, learning (same cell)",
    "rendered": RENDERED_ROW,
    "memory": "agent steps, compiled engine, memory learner (beyond memory-n5)",
    "rl": "agent steps, compiled engine, RL learner (models rl-n5, 1e5 steps)",
    "population": "agent steps, compiled engine, population learner (quick n5, 1e5 steps)"}


def _rate(fn: Callable[[int], object], n: int, repeats: int = 3) -> float:
    """Best of ``repeats`` runs of ``n`` calls, in calls per second."""
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        for i in range(n):
            fn(i)
        best = min(best, time.perf_counter() - start)
    return n / best


def run_world_benchmarks(
    config: WorldConfig | None = None, n_frames: int = 200, n_projections: int = 20000
) -> list[tuple[str, float, str]]:
    """(name, value, unit) rows for rendering and fast projection at ``config``'s size."""
    from ..world.simulator import World

    config = config if config is not None else WorldConfig()
    rows = []
    with World(config, seed=0) as world:
        rng = np.random.default_rng(0)
        thetas = world.kinematics.clip(rng.uniform(-1, 1, (max(n_frames, n_projections), 2)))
        world.render()  # start the GL context outside the timing

        def render(i: int) -> None:
            world.set_head_angle(thetas[i])
            world.render()

        size = f"{config.camera.width_px}x{config.camera.height_px}"
        rows.append(
            (
                f"render robot view ({size}, {world.state.n_objects} objects)",
                _rate(render, n_frames),
                "frames/s",
            )
        )
        scene = world.fast_scene()
        rows.append(
            (
                "fast projection (all objects, one head angle)",
                _rate(lambda i: scene.observe(thetas[i]), n_projections),
                "projections/s",
            )
        )
        rows.append(("new scene (sample + show)", _rate(lambda i: world.reset(), 200), "scenes/s"))
        views = [(world.set_head_angle(t), world.render())[1] for t in thetas[:20]]
        detector = ImageDetector(focal_px=world.kinematics.focal_px)
        rows.append((f"detect objects in one view (OpenCV, {size})",
                     _rate(lambda i: detector.detect(views[i % 20]), n_frames), "frames/s"))
    for name, camera in (("antialias_samples = 0", {"antialias_samples": 0}),
                         ("FAST_CAMERA: 0 samples, 16 x 8 facets", FAST_CAMERA)):
        with World(with_camera(config, **camera), seed=0) as world:
            world.render()
            rows.append((f"render robot view, {name} ({size})",
                         _rate(lambda i, w=world: (w.set_head_angle(thetas[i]), w.render()),
                               n_frames), "frames/s"))
    return rows


def run_follow_benchmark(n_frames: int = 30) -> list[tuple[str, float, str]]:
    """Frames per second of gaze following: find the face, cut its window, the command.

    BlazeFace (the default) on a rendered view of the caregiver enlarged to 640x480, and on
    matplotlib's photograph; the template on the rendered view; Haar on the photograph. With an
    untrained model whose face statistics are the shipped data sets' (speed only).
    """
    import cv2

    from ..config import load_config
    from ..datasets import default_datasets
    from ..deploy.follower import GazeFollower
    from ..deploy.saved import LearnedModel
    from ..experiment.cells import make_agent
    from ..world.simulator import World
    from .face_finders import hopper_photo

    config = load_config()
    ds = default_datasets()
    agent = make_agent(config, config.experiment.conditions[0], 0, ds)
    agent.faces.partial_fit(ds.face.reshape(len(ds), -1))
    model = LearnedModel(agent, config, config.experiment.conditions[0].name)
    with World(config.world, seed=0) as world:
        world.set_head_angle(world.face_angle_rad)
        view = world.render()
    photo, rows = hopper_photo(), []
    camera = cv2.resize(view, (640, 480), interpolation=cv2.INTER_LINEAR)
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)  # one core, as a robot's control loop would have it
    try:
        for face, image in (("blazeface", camera), ("blazeface", photo), ("template", view),
                            ("haar", photo)):
            follower = GazeFollower(model, face)
            h, w = image.shape[:2]
            rows.append((f"follow frames (face, window, command), one core: {face}, {w}x{h}",
                         _rate(lambda i, f=follower, im=image: f.look(im, np.zeros(2)),
                               n_frames), "frames/s"))
    finally:
        cv2.setNumThreads(threads)
    return rows


def run_agent_benchmark(rendered_steps: int = 2000) -> list[tuple[str, float, str]]:
    """Agent-steps per second of learning: both engines, rendered mode, memory and RL learners.

    The quick preset's 5-object sigmoid cell in both engines, and its first ``rendered_steps``
    steps in rendered mode (MuJoCo render + OpenCV detection each step) with two views,
    each beside its bound (:func:`.bounds.rendered_rows`); the beyond preset's 5-object memory
    cell at the paper's scale (its recall grows with the distinct faces kept); the models
    preset's 5-object reinforcement learner (compiled) for 1e5 steps; the population learner
    for 1e5 steps compiled and 5x10^4 step by step; each of these three learners' arithmetic
    alone, and its share of the cell (:func:`.bounds.learner_cell_rows`).
    Then one compiled step's time against its bound: one forward and backward pass of the
    learning module alone, in compiled code; and one update as a trial's updates run (10 that
    share the face).
    """
    from ..config import load_config

    config = load_config("quick")
    cond = next(c for c in config.experiment.conditions if c.name == "n5-sigmoid")
    cell_rate(config, cond, n_steps=100)  # load (or compile) the engine outside the timing
    compiled = cell_rate(config, cond, engine="compiled")
    python = cell_rate(config, cond, engine="python")
    rendered = rendered_rows(config, cond, rendered_steps)
    beyond, models = load_config("beyond"), load_config("models")
    memory_cell = next(c for c in beyond.experiment.conditions if c.name == "memory-n5")
    rl_cell = next(c for c in models.experiment.conditions if c.name == "rl-n5")
    population_cell = dataclasses.replace(cond, model={"learner": "population",
                                                       "vf_fallback": "sweep"})
    for warm_config, warm_cell in ((beyond, memory_cell), (models, rl_cell),
                                   (config, population_cell)):  # each loop loaded outside
        cell_rate(warm_config, warm_cell, n_steps=100)
    memory, memory_rows = learner_cell_rows(beyond, memory_cell)
    rl, rl_rows = learner_cell_rows(models, rl_cell, 100_000)
    population, population_rows = learner_cell_rows(config, population_cell, 100_000)
    population_python = cell_rate(config, population_cell, n_steps=50_000, engine="python")
    step_us, bound_us, trial_us = 1e6 / compiled, _update_us(), _update_us(trial_rows=10)
    named = AGENT_RATE_ROWS
    return [(named["compiled"], compiled, "steps/s"), (named["python"], python, "steps/s"),
            (named["memory"], memory, "steps/s"), *memory_rows, (named["rl"], rl, "steps/s"),
            *rl_rows,
            (named["population"], population, "steps/s"), *population_rows,
            ("agent steps, python engine, population learner (same cell, 5e4 steps)",
             population_python, "steps/s"),
            ("population learner: compiled / python engine", population / population_python,
             "x"),
            ("compiled / python engine", compiled / python, "x"),
            ("compiled, paper's learner / memory learner (the recall's cost)", compiled / memory,
             "x"),
            ("compiled / rendered (the rendered preset's view)",
             compiled / rendered[0][1], "x"),
            ("one compiled step (mean over the cell)", step_us, "us"),
            ("bound: one forward + backward pass, 752-7-2, compiled", bound_us, "us"),
            ("one update of a trial's 10 (the face shared, summed in closed form)", trial_us,
             "us"),
            ("step / bound", step_us / bound_us, "x")] + rendered


def _update_us(trial_rows: int = 1, n: int = 20000) -> float:
    """Microseconds of one back-propagation step (forward and backward) of a 752-7-2 network.

    Alone (``trial_rows`` 1), or as one of a trial's ``trial_rows`` updates, which share the
    face (750 inputs) and are summed in closed form (:func:`~.models.network.learner.sgd_rows`).
    """
    net = LearningModule(752, 7, 2, rng=np.random.default_rng(0))
    x, y = np.random.default_rng(1).normal(size=(n, 752)), np.tile([0.6, 0.8], (n, 1))
    angles = np.ascontiguousarray(x[:, 750:])
    net.partial_fit(x[:10], y[:10])
    best = np.inf
    for _ in range(3):
        start = time.perf_counter()
        _updates(x, angles, y, trial_rows, *net._params(), *net.velocity_)
        best = min(best, time.perf_counter() - start)
    return best / n * 1e6


@jit
def _updates(x, angles, y, trial_rows, w1, b1, w2, b2, v1, vb1, v2, vb2) -> None:
    """The updates, in one compiled loop (no call overhead).

    One :func:`~.models.network.learner.sgd_update` per row, or with ``trial_rows`` above 1 one
    :func:`~.models.network.learner.sgd_rows` call per block of rows, the block's first face
    (``x[:, :750]``) shared by its rows (``angles``: ``x[:, 750:]``).
    """
    if trial_rows == 1:
        for i in range(len(x)):
            sgd_update(x[i], y[i], w1, b1, w2, b2, v1, vb1, v2, vb2, 0.0003, 0.5)
        return
    for start in range(0, len(x), trial_rows):
        end = min(start + trial_rows, len(x))
        sgd_rows(x[start, :750], angles[start:end], y[start:end], w1, b1, w2, b2, v1, vb1, v2,
                 vb2, 0.0003, 0.5)


def compile_times() -> list[tuple[str, float, str]]:
    """Seconds of a first run on a new machine (empty kernel cache) and of a second run.

    Each in a new process: import, load or compile the kernels, learn a 100-step cell.
    """
    import os
    import subprocess
    import sys
    import tempfile

    script = ("import dataclasses\n"
              "from jointattention import load_config, run_cell\n"
              "c = load_config('quick')\n"
              "c = dataclasses.replace(c, experiment=dataclasses.replace(c.experiment, "
              "n_steps=100))\n"
              "run_cell(c, c.experiment.conditions[0], 0)\n")
    rows = []
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        for name in ("first run, empty kernel cache (compiles)", "second run (cache loaded)"):
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", script], env=env, check=True)
            rows.append((name, time.perf_counter() - start, "s"))
    return rows


def write_bench(folder, rows: list[tuple[str, float, str]],
                env_rows: list[tuple[str, float, str]], command: str) -> list[Path]:
    """Write ``bench.csv`` (every row) and, if measured, ``environments.md`` into ``folder``.

    ``environments.md`` is the environments' table, which docs/gymnasium.md and docs/speed.md
    include (the docs quote no figure of their own); ``command`` is what measured them.
    """
    import csv
    import io
    import os

    from .._files import write_text

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(["figure", "value", "unit"])
    writer.writerows((name, f"{value:.6g}", unit) for name, value, unit in rows)
    written = [write_text(folder / "bench.csv", text.getvalue())]
    if env_rows:
        lines = ["| environment (random actions, resets included) | value |", "|---|---:|"]
        lines += [f"| {name} | {value:,.2f}x |" if unit == "x" else
                  f"| {name} | {value:,.0f} {unit} |" for name, value, unit in env_rows]
        lines += ["", f"(`{command}`, {time.strftime('%d %B %Y, %H:%M UTC', time.gmtime())}, "
                      f"{os.cpu_count()} cores, shared: compare within one run.)"]
        written.append(write_text(folder / "environments.md", "\n".join(lines) + "\n"))
    return written
