"""The environments' speeds: one environment in each mode, and vectorised (``bench``)."""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable

import numpy as np

from .._jit import jit
from ..agent.attention import attended_index
from ..config import Config, WorldConfig
from ..experiment.trial import end_after_look, move_head
from ..world.fast import FastScene, detect_into
from ..world.kinematics import HeadKinematics, rotation_into

__all__ = ["CARTPOLE_AIMS", "cartpole_rows", "run_env_benchmark", "step_bound", "with_camera"]


def with_camera(world: WorldConfig, **fields) -> WorldConfig:
    """``world`` with these fields of its camera changed (e.g. ``antialias_samples=0``)."""
    return dataclasses.replace(world, camera=dataclasses.replace(world.camera, **fields))


@jit
def _kernel_steps(dtheta, pos, rad, edge, offset_m, focal_px, width_px, height_px, d_th_px,
                  limits_rad, centre, area, seen_edge, ids) -> int:
    """The arithmetic of ``len(dtheta)`` environment steps: move, project, evaluate, end."""
    pan = tilt = 0.0
    cx, cy = (width_px - 1) / 2, (height_px - 1) / 2
    ended, rot = 0, np.empty((3, 3))
    for i in range(len(dtheta)):
        pan, tilt, hit = move_head(pan, tilt, dtheta[i, 0], dtheta[i, 1], limits_rad[0],
                                   limits_rad[1], limits_rad[2], limits_rad[3])
        rotation_into(pan, tilt, rot)
        m = detect_into(pos, rad, edge, rot, offset_m, focal_px, width_px, height_px, centre,
                        area, seen_edge, ids)
        seen = attended_index(centre[:m], cx, cy, d_th_px)
        ended += end_after_look(seen, hit, i % 40, 40) >= 0
    return ended


def step_bound(n_steps: int = 200_000) -> float:
    """Steps per second of one environment step's kernels alone, in one compiled loop.

    Moving the head, projecting a 5-object scene and evaluating the image (Eq. 3): the bound
    of an environment without images, whatever the Python around it.
    """
    config = Config()
    world, kin = config.world, HeadKinematics.from_config(config.world)
    rng = np.random.default_rng(0)
    scene = FastScene.sample(world, kin, [0.1, 0.6, 0.0], [0.0, 1.2, 0.3], 5, rng)
    n = len(scene.object_radius_m)
    dtheta = rng.uniform(-0.02, 0.02, (n_steps, 2))
    limits = np.array([*kin.pan_limits_rad, *kin.tilt_limits_rad])
    arrays = np.empty((n, 2)), np.empty(n), np.empty(n), np.empty(n, dtype=np.int64)
    args = (scene.object_pos_m, scene.object_radius_m, scene.edge,
            np.asarray(kin.offset_m, float), float(kin.focal_px), kin.width_px, kin.height_px,
            config.agent.d_th_px(kin.width_px), limits, *arrays)  # Eq. 3's radius
    _kernel_steps(dtheta[:10], *args)
    best = np.inf
    for _ in range(3):
        start = time.perf_counter()
        _kernel_steps(dtheta, *args)
        best = min(best, time.perf_counter() - start)
    return n_steps / best


def _timed_steps(envs, n_steps: int) -> Callable[[], float]:
    """A function that runs ``n_steps`` steps of ``envs`` under random actions; its seconds.

    One environment or a vector. The actions are drawn, and the kernels loaded by a few steps,
    before: the figure is the environment's own. Each run starts from the same seeded reset,
    so runs step the same episodes (resets included).
    """
    envs.action_space.seed(0)
    actions = [envs.action_space.sample() for _ in range(n_steps)]
    single = not hasattr(envs, "num_envs")

    def steps(some) -> None:
        for action in some:
            *_, terminated, truncated, _ = envs.step(action)
            if single and (terminated or truncated):
                envs.reset()

    def run() -> float:
        envs.reset(seed=0)
        start = time.perf_counter()
        steps(actions)
        return time.perf_counter() - start

    envs.reset(seed=0)
    steps(actions[:20])
    return run


def _env_rate(envs, n_steps: int, rounds: int = 3) -> float:
    """Environment steps per second of ``envs`` (one or a vector): the best of ``rounds`` runs.

    The best, as the machine is shared: many short runs for the fast forms, so that one of them
    falls in a quiet moment.
    """
    run = _timed_steps(envs, n_steps)
    best = min(run() for _ in range(rounds))
    envs.close()
    return n_steps * getattr(envs, "num_envs", 1) / best


def _paired_rates(ours, anchor, n_steps: int, rounds: int = 9) -> tuple[float, float]:
    """Steps per second of ``ours`` and of ``anchor``, timed in turns: the best round of each.

    Turns, so that both see the same moments of a shared machine; their ratio is the figure.
    """
    runs = [_timed_steps(envs, n_steps) for envs in (ours, anchor)]
    best = [float("inf")] * 2
    for _ in range(rounds):
        for j, run in enumerate(runs):
            best[j] = min(best[j], run())
    rates = [n_steps * getattr(envs, "num_envs", 1) / t
             for envs, t in zip((ours, anchor), best, strict=True)]
    for envs in (ours, anchor):
        envs.close()
    return rates[0], rates[1]


# Issue 60's aims: against Gymnasium's CartPole-v1, measured in the same run.
CARTPOLE_AIMS = {"one": 0.5, "x64": 1.0}


def cartpole_rows(n_steps: int = 600) -> list[tuple[str, float, str]]:
    """JointAttentionFace-v2 beside CartPole-v1 in the same run, and the two ratios.

    One environment each as ``gymnasium.make`` gives it (its wrappers included, as a user
    gets it), and 64 in each one's native vector environment (``vectorization_mode=
    "vector_entry_point"``), random actions; each pair timed in turns (:func:`_paired_rates`).
    """
    import gymnasium as gym

    import jointattention.env  # noqa: F401 (registers the ids)

    face = "JointAttentionFace-v2"
    one, cartpole = _paired_rates(gym.make(face), gym.make("CartPole-v1"), 5 * n_steps,
                                  rounds=15)
    native = {"vectorization_mode": "vector_entry_point"}
    x64, cartpole64 = _paired_rates(gym.make_vec(face, num_envs=64, **native),
                                    gym.make_vec("CartPole-v1", num_envs=64, **native),
                                    3 * n_steps * 8 // 64, rounds=25)
    return [(f"{face} steps, one env (gym.make)", one, "steps/s"),
            ("CartPole-v1 steps, one env (gym.make), same run", cartpole, "steps/s"),
            (f"one env / CartPole-v1 (aim: {CARTPOLE_AIMS['one']:g})", one / cartpole, "x"),
            (f"{face} x64, native vector, beside CartPole", x64, "steps/s"),
            ("CartPole-v1 x64, Gymnasium's native vector, same run", cartpole64, "steps/s"),
            (f"x64 native / CartPole-v1 x64 native (aim: {CARTPOLE_AIMS['x64']:g})",
             x64 / cartpole64, "x")]


def run_env_benchmark(n_steps: int = 600) -> list[tuple[str, float, str]]:
    """Steps per second of the environment in each observation mode, single and vectorised.

    The current ids (v2; v3 for fast images), each single one as registered but without
    ``gym.make``'s wrappers. Random actions, resets included; vector environments count the
    steps of all their sub-environments (async: 2 processes, started with spawn). Beside them,
    their bound: the kernels of one step alone (:func:`step_bound`), and how far each is from
    it; and JointAttentionFace-v2 against CartPole-v1 (:func:`cartpole_rows`). Empty if
    Gymnasium is not installed.
    """
    try:
        import gymnasium as gym

        from ..env import JointAttentionEnv
    except ImportError:
        return []
    def current(env_id: str, **kwargs) -> JointAttentionEnv:
        """The environment of the registered ``env_id``, without gym.make's wrappers."""
        return JointAttentionEnv(**{**gym.spec(env_id).kwargs, **kwargs})

    plain = Config()
    jagged = dataclasses.replace(plain, world=with_camera(plain.world, antialias_samples=0))
    rows = [("JointAttention-v2 steps, image (rendered)",
             _env_rate(current("JointAttention-v2"), n_steps), "steps/s"),
            ("JointAttention-v2 steps, image, antialias_samples = 0",
             _env_rate(current("JointAttention-v2", config=jagged), n_steps), "steps/s"),
            ("JointAttention-v3 steps, image, render_quality = 'fast'",
             _env_rate(current("JointAttention-v3"), n_steps), "steps/s")]
    for name, mode in (("Face", "face"), ("Detections", "detections")):
        rows.append((f"JointAttention{name}-v2 steps, {mode} (no rendering)",
                     _env_rate(current(f"JointAttention{name}-v2"), 5 * n_steps, 9),
                     "steps/s"))
    fast = "JointAttentionFace-v2"
    for n_envs in (8, 64):
        for mode in ("sync", "vector_entry_point"):
            envs = gym.make_vec(fast, num_envs=n_envs, vectorization_mode=mode)
            name = "native vector" if mode == "vector_entry_point" else "sync vector"
            rows.append((f"{fast} x{n_envs}, {name}",
                         _env_rate(envs, 3 * n_steps * 8 // n_envs, 9), "steps/s"))
    for env_id, steps in ((fast, 5 * n_steps), ("JointAttention-v2", n_steps // 2)):
        envs = gym.make_vec(env_id, num_envs=2, vectorization_mode="async",
                            vector_kwargs={"context": "spawn"})
        rows.append((f"{env_id} x2, async vector (spawn)", _env_rate(envs, steps), "steps/s"))
    bound, rates = step_bound(), {name: rate for name, rate, _ in rows}
    rows += [("bound: one step's kernels alone (move, project, evaluate), compiled", bound,
              "steps/s"),
             ("bound / one env, face", bound / rates["JointAttentionFace-v2 steps, face (no "
                                                      "rendering)"], "x"),
             ("bound / x64 native vector", bound / rates[f"{fast} x64, native vector"], "x")]
    return rows + cartpole_rows(n_steps)
