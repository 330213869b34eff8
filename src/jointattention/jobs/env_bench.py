"""The environments' speeds: one environment in each mode, and vectorised (``bench``)."""

from __future__ import annotations

import time

__all__ = ["run_env_benchmark"]


def _env_rate(envs, n_steps: int) -> float:
    """Environment steps per second of ``envs`` (one or a vector) under random actions.

    The actions are drawn, and the kernels loaded by a few steps, before the clock starts:
    the figure is the environment's own; the best of three runs of the same episodes.
    """
    envs.action_space.seed(0)
    actions = [envs.action_space.sample() for _ in range(n_steps)]
    single = not hasattr(envs, "num_envs")

    def steps(some) -> None:
        for action in some:
            *_, terminated, truncated, _ = envs.step(action)
            if single and (terminated or truncated):
                envs.reset()

    envs.reset(seed=0)
    steps(actions[:20])
    best = float("inf")
    for _ in range(3):  # the best of three: the machine is shared
        envs.reset(seed=0)
        start = time.perf_counter()
        steps(actions)
        best = min(best, time.perf_counter() - start)
    rate = n_steps * getattr(envs, "num_envs", 1) / best
    envs.close()
    return rate


def run_env_benchmark(n_steps: int = 600) -> list[tuple[str, float, str]]:
    """Steps per second of the environment in each observation mode, single and vectorised.

    Random actions, resets included; vector environments count the steps of all their
    sub-environments (async: 2 processes, started with spawn). Empty if Gymnasium is not
    installed.
    """
    try:
        import gymnasium as gym

        from ..env import JointAttentionEnv
    except ImportError:
        return []
    rows = [("JointAttention-v1 steps, image (rendered)",
             _env_rate(JointAttentionEnv(), n_steps), "steps/s")]
    for mode in ("face", "detections"):
        rows.append((f"JointAttention-v1 steps, {mode} (no rendering)",
                     _env_rate(JointAttentionEnv(obs_mode=mode), 20 * n_steps), "steps/s"))
    fast = "JointAttentionFace-v1"
    for n_envs in (8, 64):
        for mode in ("sync", "vector_entry_point"):
            envs = gym.make_vec(fast, num_envs=n_envs, vectorization_mode=mode)
            name = "native vector" if mode == "vector_entry_point" else "sync vector"
            rows.append((f"{fast} x{n_envs}, {name}",
                         _env_rate(envs, 3 * n_steps * 8 // n_envs), "steps/s"))
    for env_id, steps in ((fast, 5 * n_steps), ("JointAttention-v1", n_steps // 2)):
        envs = gym.make_vec(env_id, num_envs=2, vectorization_mode="async",
                            vector_kwargs={"context": "spawn"})
        rows.append((f"{env_id} x2, async vector (spawn)", _env_rate(envs, steps), "steps/s"))
    return rows
