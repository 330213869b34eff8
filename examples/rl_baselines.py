"""Baselines of every algorithm family: SB3's PPO, A2C, SAC, TD3 and DQN with their defaults.

One command, one table. Each algorithm learns ``JointAttentionFace-N{n}-v2`` (DQN its discrete
twin, ``JointAttentionFace-N{n}-Discrete-v2``: DQN takes only a ``Discrete`` action) with
Stable-Baselines3's default hyperparameters and ``MultiInputPolicy``, on 8 environments for
the on-policy PPO and A2C (the docs' first recipe) and on one for the off-policy SAC, TD3 and
DQN (their usual form: one gradient step per environment step, or per 4 for DQN). Beside them
are the floor (uniform random actions, on both ids), the project's own reinforcement learner
(``kind = "rl"``, learning from its own evaluator) and the bootstrap model (the ``paper``
preset's), each learning for as many steps in the same fast world. Where the defaults fail,
a row with one documented change (:data:`TUNED`) follows: A2C with ``learning_rate=2e-4``,
DQN with ``gamma=0.9``, TD3 with Gaussian action noise of s.d. 0.1, and that TD3 with
``learning_rate=1e-4`` as well.

Each learned policy is then frozen and measured on new episodes of the three splits
(``caregivers="training" | "new-poses" | "unseen"``), both with actions drawn as in learning
(``predict(deterministic=False)``: PPO's and A2C's Gaussian, SAC's squashed Gaussian, DQN's
epsilon-greedy with its final epsilon; TD3's actor has no noise there) and with the policy's
deterministic action (the Gaussian's mean, DQN's greedy move). The runner's learners are
measured by the runner's held-out measure, their own way of acting.

    pip install "jointattention[rl]"
    python examples/rl_baselines.py                        # 2.5e5 steps x 3 seeds: hours
    python examples/rl_baselines.py --algos dqn --steps 100000 --out runs/dqn

writes ``baselines.md`` (the table), and ``baselines_runs.json``, every finished run (a
re-run with the same arguments resumes from it). An off-policy run (SAC, TD3: about 30 steps
a second on one core, two and a half hours a seed) also saves its model and replay buffer in
``checkpoints/`` every ``--checkpoint-every`` steps; stopped, the same command continues it
from there, and a finished run deletes them. ``--finished-only`` trains nothing and writes the
table from the runs that have finished, each row naming its seeds. ``--merge FOLDER ...``
first adds the finished runs of other output folders, so that seeds run in parallel, each
with its own ``--out``, make one table. ``--quick`` runs a few hundred steps of each, one
seed, 10 episodes per measure (the test suite runs it; its numbers mean nothing).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import shutil
import time
from pathlib import Path

import gymnasium as gym
import numpy as np

import jointattention.env  # noqa: F401  (registers the environments)
from jointattention._files import atomic_path, check_writable, write_text  # no half file
from jointattention.cli._common import int_in  # argparse's one error line out of range
from jointattention.errors import FileError

ALGOS = ("ppo", "a2c", "sac", "td3", "dqn")
# Where the defaults fail, a documented setting: {name: (algorithm, its non-default arguments)}.
# DQN, gamma 0.9: stay, and a move followed by its opposite, come back to the same observation;
# with the default 0.99 such loops are worth nearly as much as a move towards the object, and
# the greedy policy circles. 0.9 costs a wasted step a tenth; a success a few moves away keeps
# most of its value.
# A2C, learning rate 2e-4 (default 7e-4): with the default, two seeds of three rose to 0.4
# and then collapsed to nothing within 5x10^4 steps (its Gaussian's s.d. unchanged); gamma 0.9
# did not stop it (docs/reinforcement-learning.md).
# TD3, action noise of s.d. 0.1 (the TD3 paper's; SB3's default is none): with none, its
# actor acts deterministically after the first 100 random steps and never found the object
# (no success on seed 0 in 2.5x10^5 steps). The noise is named by its s.d. here and made for
# the env's action space in train().
# TD3, that noise and learning rate 1e-4 (default 1e-3): with the noise alone (and 2.5x10^4
# random steps first) its actor's tanh had saturated 2.5x10^4 steps into learning, every action
# at a corner of the box, where no gradient reaches the actor's weights (docs/lab-notes.md,
# "Why TD3 fails on the face ids"); with the smaller rate it learned (seed 0, to 5x10^4).
TUNED = {"a2c-lr-2e-4": ("a2c", {"learning_rate": 2e-4}),
         "dqn-gamma-0.9": ("dqn", {"gamma": 0.9}),
         "td3-noise-0.1": ("td3", {"action_noise": 0.1}),
         "td3-noise-0.1-lr-1e-4": ("td3", {"action_noise": 0.1, "learning_rate": 1e-4})}
LEARNERS = ("own-rl", "bootstrap")  # the runner's: the project's RL model, the paper's model
SPLITS = ("training", "new-poses", "unseen")
_KINDS = {"training": "training", "new-poses": "new poses", "unseen": "unseen caregivers"}
OFF_POLICY = ("sac", "td3", "dqn")  # one gradient step per 1 (4) steps: hours on a CPU
ON_POLICY_ENVS, QUICK = 8, {"steps": 600, "episodes": 10}


def env_id(algo: str, n_objects: int) -> str:
    """The id an algorithm learns: the discrete twin for DQN, else the continuous v2 id."""
    dqn = TUNED.get(algo, (algo,))[0] == "dqn"
    return f"JointAttentionFace-N{n_objects}-{'Discrete-' if dqn else ''}v2"


def train(algo: str, n_objects: int, steps: int, seed: int, quick: bool,
          checkpoint: Path | None = None, every: int = 0):
    """SB3's ``algo`` with its defaults (or a :data:`TUNED` setting).

    Returns the model, the steps at which episodes ended, whether each succeeded, and the
    seconds spent learning (over every process that continued the run).

    With a ``checkpoint`` folder, the model, its replay buffer and the episodes so far are saved
    there every ``every`` steps, and a run that finds them continues from the last: SAC and TD3
    take hours per seed on a CPU. A continued run's environments start new episodes from a seed
    of their own, so it is not bitwise the run that would not have stopped; its policy, replay
    buffer, optimiser state and step count are.
    """
    import stable_baselines3 as sb3
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.env_util import make_vec_env

    from jointattention.env.sb3 import EpisodeLog

    algo, tuned = TUNED.get(algo, (algo, {}))
    n_envs = ON_POLICY_ENVS if algo in ("ppo", "a2c") else 1
    kind = getattr(sb3, algo.upper())
    log, start = EpisodeLog(), time.perf_counter()
    saved = checkpoint is not None and (checkpoint / "log.json").exists()
    state = json.loads((checkpoint / "log.json").read_text()) if saved else {}
    done_steps, before_s = state.get("steps", 0), state.get("seconds", 0.0)
    # a continued run's environments must not replay the first episodes: a seed per restart
    envs = make_vec_env(env_id(algo, n_objects), n_envs,
                        seed=seed + 1_000_003 * (done_steps // max(every, 1)))
    if saved:
        folder = checkpoint / state.get("folder", ".")
        model = kind.load(folder / "model.zip", env=envs, device="cpu")
        if hasattr(model, "replay_buffer"):
            _load_buffer(model.replay_buffer, folder / "replay.npz")
        log.ends, log.wins = state["ends"], state["wins"]
        print(f"  continuing from {done_steps:,} steps ({checkpoint})", flush=True)
    else:
        # --quick: PPO's default rollout (2,048 x 8 steps) would be longer than the whole run,
        # and the off-policy ones learn from the last 100 steps only (seconds, not a minute)
        short = ({} if not quick else {"n_steps": 64} if algo == "ppo" else {} if algo == "a2c"
                 else {"learning_starts": steps - 100})
        if "action_noise" in tuned:  # an s.d.: Gaussian noise on each action dimension
            from stable_baselines3.common.noise import NormalActionNoise
            shape = envs.action_space.shape
            tuned = {**tuned, "action_noise": NormalActionNoise(
                np.zeros(shape), np.full(shape, tuned["action_noise"]))}
        model = kind("MultiInputPolicy", envs, seed=seed, device="cpu", verbose=0, **tuned,
                     **short)

    class Saver(BaseCallback):
        """Save a checkpoint every ``every`` steps but the last."""

        def _on_step(self) -> bool:
            return True

        def _on_rollout_end(self) -> None:
            # here, not in _on_step: there the step's transition is not yet in the buffer
            nonlocal done_steps
            n = self.model.num_timesteps
            if n // every > done_steps // every and n < steps:
                _save(self.model, log, checkpoint, before_s + time.perf_counter() - start)
                done_steps = n
                print(f"  {n:,} of {steps:,} steps, saved", flush=True)

    callbacks = [log] if checkpoint is None else [log, Saver()]
    model.learn(steps - model.num_timesteps, callback=callbacks, reset_num_timesteps=not saved)
    envs.close()
    return model, np.array(log.ends), np.array(log.wins, float), \
        before_s + time.perf_counter() - start


def _save(model, log, checkpoint: Path, seconds: float) -> None:
    """Write the model, its replay buffer and the episodes so far.

    The model and buffer go to a folder of their own, and ``log.json`` names it last: a run
    stopped while saving continues from the checkpoint before, whole.
    """
    folder = checkpoint / f"at-{model.num_timesteps}"
    folder.mkdir(parents=True, exist_ok=True)
    # a replay buffer is a gigabyte: never offered to git, wherever the output folder is
    write_text(checkpoint.parent / ".gitignore", "*\n")
    model.save(folder / "model.zip")
    if hasattr(model, "replay_buffer"):
        _save_buffer(model.replay_buffer, folder / "replay.npz")
    write_text(checkpoint / "log.json",
               json.dumps({"steps": model.num_timesteps, "seconds": seconds,
                           "folder": folder.name, "ends": log.ends,
                           "wins": [bool(w) for w in log.wins]}))
    for old in checkpoint.glob("at-*"):
        if old != folder:
            shutil.rmtree(old, ignore_errors=True)


def frozen(model, env: str, episodes: int, seed: int) -> dict[str, dict[str, float]]:
    """{"sampled" | "deterministic": {split: success}} of the frozen ``model`` on ``env``."""
    from jointattention.env.sb3 import success_rate

    return {mode: {split: success_rate(model, gym.make(env, caregivers=split), episodes, seed,
                                       deterministic=mode == "deterministic")
                   for split in SPLITS}
            for mode in ("sampled", "deterministic")}


def _buffer_arrays(buffer) -> dict[str, np.ndarray]:
    """The replay buffer's per-transition arrays by name (dict observations flattened)."""
    arrays = {}
    for name, value in vars(buffer).items():
        for key, array in (value.items() if isinstance(value, dict) else [("", value)]):
            if isinstance(array, np.ndarray) and array.shape[:1] == (buffer.buffer_size,):
                arrays[f"{name}.{key}" if key else name] = array
    return arrays


def _save_buffer(buffer, path: Path) -> None:
    """Only the filled rows: SB3's own pickle writes all 10^6 rows (6 GB for this env)."""
    n = buffer.buffer_size if buffer.full else buffer.pos
    # uncompressed: zlib on a gigabyte would cost each checkpoint minutes
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, pos=buffer.pos, full=buffer.full,
                 **{name: array[:n] for name, array in _buffer_arrays(buffer).items()})


def _load_buffer(buffer, path: Path) -> None:
    """Fill a fresh buffer's rows from :func:`_save_buffer`'s file."""
    with np.load(path) as saved:
        buffer.pos, buffer.full = int(saved["pos"]), bool(saved["full"])
        for name, array in _buffer_arrays(buffer).items():
            array[:len(saved[name])] = saved[name]


def final(times: np.ndarray, success: np.ndarray, steps: int) -> float:
    """Success of the episodes that ended in the last tenth of learning (NaN if none)."""
    last = success[times > 0.9 * steps]
    return float(last.mean()) if len(last) else float("nan")


def sb3_record(algo: str, n_objects: int, steps: int, seed: int, episodes: int,
               quick: bool, checkpoint: Path | None = None, every: int = 0) -> dict:
    """One SB3 run: learning's final success, the frozen measures, wall minutes."""
    model, ends, wins, seconds = train(algo, n_objects, steps, seed, quick, checkpoint, every)
    t = time.perf_counter()
    measured = frozen(model, env_id(algo, n_objects), episodes, 10_000 + seed)
    return {"final": final(ends, wins, steps), "frozen": measured,
            "minutes": (seconds + time.perf_counter() - t) / 60}


def runner_record(learner: str, n_objects: int, steps: int, seed: int, episodes: int) -> dict:
    """One run of the runner's ``learner``: final success, held-out success, wall minutes."""
    from jointattention import ConditionConfig, load_config
    from jointattention.experiment.held_out import final_held_out, run_cell_measured

    t = time.perf_counter()
    base = load_config({"model": {"kind": "rl"}, "experiment": {"engine": "python"}}
                       if learner == "own-rl" else "paper")
    experiment = dataclasses.replace(
        base.experiment, n_steps=steps, bin_steps=min(steps, base.experiment.bin_steps),
        held_out=dataclasses.replace(base.experiment.held_out, n_trials=episodes,
                                     n_checkpoints=1))
    config = dataclasses.replace(base, experiment=experiment)
    rec = run_cell_measured(config, ConditionConfig(name=f"{learner}-n{n_objects}",
                                                    n_objects=n_objects), seed)
    held = final_held_out(rec)
    return {"final": final(rec["learning_time"].astype(float), rec["success"].astype(float),
                           steps),
            "frozen": {"sampled": {s: held[_KINDS[s]]["success"] for s in SPLITS},
                       "deterministic": None},
            "minutes": (time.perf_counter() - t) / 60}


def floor(env: str, episodes: int) -> dict[str, float]:
    """Uniform random actions' success on each split of ``env``."""
    from jointattention.env.sb3 import success_rate

    return {split: success_rate(None, gym.make(env, caregivers=split), episodes, 0)
            for split in SPLITS}


def main() -> None:
    """Train every algorithm and learner on every seed, measure, write the table."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=float, default=250_000,
                        help="environment steps of learning per run (default 2.5e5)")
    parser.add_argument("--seeds", type=int_in(0, 10**6), nargs="+", default=[0, 1, 2],
                        help="seeds (default 0 1 2)")
    parser.add_argument("--algos", nargs="+", default=[*ALGOS, *TUNED, *LEARNERS],
                        choices=[*ALGOS, *TUNED, *LEARNERS], help="what learns (default: all)")
    parser.add_argument("--n-objects", type=int, default=1, choices=_object_counts(),
                        help="objects (default 1)")
    parser.add_argument("--episodes", type=int_in(1, 10**6), default=1000,
                        help="episodes per frozen measure (default 1000)")
    parser.add_argument("--out", default="runs/baselines", help="output folder")
    parser.add_argument("--checkpoint-every", type=float, default=25_000,
                        help="save an off-policy run (SAC, TD3, DQN) every this many steps, "
                             "to continue it if stopped (default 2.5e4; 0: never)")
    parser.add_argument("--finished-only", action="store_true",
                        help="train nothing: write the table from the runs that have finished "
                             "(each row names the seeds it holds; a run still under way is "
                             "left out)")
    parser.add_argument("--merge", nargs="+", default=[], metavar="FOLDER",
                        help="first add the finished runs of these output folders (seeds run "
                             "in parallel, each with its own --out); a run this folder "
                             "already holds is kept")
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK['steps']} steps, the first seed, {QUICK['episodes']} "
                             "episodes per measure (a smoke test)")
    args = parser.parse_args()
    _check(parser, args)
    steps, episodes, seeds = int(args.steps), args.episodes, args.seeds
    if args.quick:
        steps, episodes, seeds = QUICK["steps"], QUICK["episodes"], seeds[:1]
    out = Path(args.out)
    done_path = out / "baselines_runs.json"  # every finished run: a re-run resumes
    done = _finished_runs(out) if done_path.exists() else {}
    if isinstance(done, str):
        parser.error(f"--out {out}: {done}")
    merged = {}
    for folder in args.merge:  # all read before anything is written
        runs = _finished_runs(Path(folder))
        if isinstance(runs, str):
            parser.error(f"--merge {folder}: {runs}")
        merged |= runs
    out.mkdir(parents=True, exist_ok=True)
    if merged:
        done = merged | done
        write_text(done_path, json.dumps(done, indent=1))
    rows = []
    for algo in args.algos:
        records = []
        for seed in seeds:
            key = f"{algo} | N{args.n_objects} | {steps} | seed {seed} | {episodes}"
            if key not in done and args.finished_only:
                continue
            if key not in done:
                every = int(args.checkpoint_every)
                checkpoint = (out / "checkpoints" / key.replace(" | ", "_").replace(" ", "")
                              if every and TUNED.get(algo, (algo,))[0] in OFF_POLICY else None)
                done[key] = (runner_record(algo, args.n_objects, steps, seed, episodes)
                             if algo in LEARNERS else
                             sb3_record(algo, args.n_objects, steps, seed, episodes, args.quick,
                                        checkpoint, every))
                write_text(done_path, json.dumps(done, indent=1))
                if checkpoint is not None:
                    shutil.rmtree(checkpoint, ignore_errors=True)
            records.append(done[key] | {"seed": seed})
            print(algo, f"seed {seed}", f"final {done[key]['final']:.3f}", flush=True)
        rows.append((algo, records))
    floors = {env_id(a, args.n_objects): floor(env_id(a, args.n_objects), episodes)
              for a in ("ppo", "dqn")}
    algos = ("" if args.algos == [*ALGOS, *TUNED, *LEARNERS] else
             f" --algos {' '.join(args.algos)}")
    lines = _table(rows, floors, args.n_objects, steps, seeds, episodes, args.quick,
                   algos + " --finished-only" * args.finished_only)
    write_text(out / "baselines.md", "\n".join(lines) + "\n")
    print("\n".join(lines))


def _object_counts() -> list[int]:
    """The object counts with an id to learn: those of the registered ``env_id``s."""
    return sorted(n for name, spec in gym.registry.items()
                  if (n := spec.kwargs.get("n_objects")) and name == env_id("ppo", n))


def _check(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """One error line (argparse's) for an argument its type cannot check, before anything runs."""
    if args.steps < 1 or args.steps != int(args.steps):
        parser.error(f"--steps {args.steps:g}: expected a whole number of steps, at least 1")
    if args.checkpoint_every < 0:
        parser.error(f"--checkpoint-every {args.checkpoint_every:g}: expected 0 (never) or "
                     "more steps")
    try:  # a file there, or a place that cannot be written
        check_writable(args.out, "folder", "--out")
    except FileError as error:
        parser.error(str(error))


def _finished_runs(folder: Path) -> dict | str:
    """The finished runs another output folder holds, or what is wrong with it."""
    path = folder / "baselines_runs.json"
    if not path.is_file():
        return f"no {path.name} there; expected the --out folder of a finished run"
    try:
        runs = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        return f"{path.name} is not readable JSON ({error})"
    ok = isinstance(runs, dict) and all(
        isinstance(run, dict) and {"final", "frozen", "minutes"} <= run.keys()
        for run in runs.values())
    return runs if ok else f"{path.name} does not hold this command's runs"


_NAMES = {"ppo": "PPO", "a2c": "A2C", "sac": "SAC", "td3": "TD3", "dqn": "DQN",
          "own-rl": "own RL model (kind rl), runner",
          "bootstrap": "bootstrap model (paper), runner"}


def _name(algo: str) -> str:
    """A row's label: the algorithm, then the arguments its tuned setting changes."""
    if algo not in TUNED:
        return _NAMES[algo]
    base, tuned = TUNED[algo]
    return ", ".join([_NAMES[base], *(f"{arg}={_value(arg, v)}" for arg, v in tuned.items())])


def _value(arg: str, value: float) -> str:
    """An argument as the label writes it: 2e-4, not 0.0002; the noise as its Gaussian."""
    if arg == "action_noise":
        return f"N(0, {value:g})"
    mantissa, exponent = f"{value:e}".split("e")
    return f"{value:g}" if value >= 1e-2 else f"{float(mantissa):g}e{int(exponent)}"


def _fmt(values) -> str:
    """Mean (lowest-highest) of the seeds' values; '-' where there are none."""
    values = np.array([np.nan if v is None else v for v in values], float)
    if len(values) == 0 or np.all(np.isnan(values)):
        return "-"
    text = f"{np.nanmean(values):.3f}"
    return text if len(values) == 1 else \
        f"{text} ({np.nanmin(values):.2f}-{np.nanmax(values):.2f})"


def _table(rows, floors, n_objects, steps, seeds, episodes, quick, algos) -> list[str]:
    lines = ["| learner | environment | final, learning | sampled: training | sampled: new "
             "poses | sampled: unseen | deterministic: training | deterministic: new poses | "
             "deterministic: unseen | minutes per seed | seeds |", "|---" * 11 + "|"]
    for algo, records in rows:
        if not records:  # --finished-only, and none of its runs has finished
            lines.append(f"| {_name(algo)} | {env_id(algo, n_objects)} | not yet run"
                         + " | -" * 7 + " | none |")
            continue
        env = env_id(algo, n_objects) if algo not in LEARNERS else \
            f"runner, {n_objects} object" + "s" * (n_objects > 1)
        cells = [_fmt([r["final"] for r in records])]
        for mode in ("sampled", "deterministic"):
            cells += [_fmt([None if r["frozen"][mode] is None else r["frozen"][mode][s]
                            for r in records]) for s in SPLITS]
        minutes = np.mean([r["minutes"] for r in records])
        ran = " ".join(str(r["seed"]) for r in records)
        lines.append(f"| {_name(algo)} | {env} | {' | '.join(cells)} | {minutes:.1f} | {ran} |")
    for env, values in floors.items():
        lines.append(f"| random actions | {env} | - | "
                     + " | ".join(f"{values[s]:.3f}" for s in SPLITS) + " | - | - | - | - | - |")
    command = "python examples/rl_baselines.py" + algos + (" --quick" if quick else (
        f" --steps {steps} --seeds {' '.join(map(str, seeds))} --n-objects {n_objects}"
        f" --episodes {episodes}"))
    lines += ["", f"(Seeds {' '.join(map(str, seeds))}: mean (lowest-highest) of those a row's "
              "last column names; "
              f"{steps:,} environment steps of learning; SB3's defaults (PPO, A2C: 8 "
              "environments; SAC, TD3, DQN: one), but for the arguments a row names; final: "
              "the episodes ending in the last tenth of learning; frozen: "
              f"{episodes:,} new episodes per split from seed 10,000 + seed, actions sampled "
              "as in learning or deterministic; the runner's learners "
              f"act their own way. Command: `{command}`.)"]
    return lines


if __name__ == "__main__":
    main()
