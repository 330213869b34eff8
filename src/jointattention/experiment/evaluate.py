"""Frozen models on other data sets: what a learned model carries over to poses and people.

A number on the data sets a model learned from says how well it remembers. Here a learned
agent is frozen (it learns nothing, its face statistics and its learning time stand still) and
run on other data sets in the fast world, with the same scene sampler and trial rules as
learning (:func:`~.cells.random_scene`, :class:`~.trial.SceneTrial`): its success, that set's
oracle ceiling, and the learning module's angle error at the faces (:mod:`.probes`), overall
and per caregiver identity.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .._checks import check_int
from .._readers import loads_toml
from ..agent.protocol import freeze
from ..config import Config, WorldConfig, load_config
from ..datasets import CaregiverDatasets, window_mismatch
from ..errors import ConfigError, DatasetError, FileError
from ..rng import stream
from ..world.identity import Caregiver, caregiver_from_dict
from ..world.kinematics import HeadKinematics
from ..world.novelty import novelty
from .cells import evaluator, fast_world, oracle_wins, random_scene
from .compiled.cell import compiled_cell, unsupported
from .probes import angle_errors
from .trial import SceneTrial, run_trial

__all__ = ["AIM_DEG", "Evaluation", "data_sets_novelty", "evaluate_agent", "freeze",
           "frozen_success", "learned_from", "oracle_success", "who_posed"]

AIM_DEG = 10.0  # an identity whose median error is above this is not followed


@dataclass(frozen=True)
class Evaluation:
    """A frozen model on one data-set file (see the module docstring).

    Attributes:
        name: what the data sets are (``training``, ``new poses``, ``unseen caregivers``, a
            file name).
        n_sets: data sets; ``n_identities``: caregivers among them (1 if the file names none).
        n_objects: objects per trial; ``n_trials``: trials run, by the model and the oracle.
        success: the frozen model's share of trials ending on the caregiver's target.
        ceiling: the oracle gaze-line follower's share on the same kind of trials.
        median_error_deg, p90_error_deg: the learning module's angle error at the faces
            (NaN for a model without one).
        share_identities_over_10deg: the share of identities whose median error is above 10°.
    """

    name: str
    n_sets: int
    n_identities: int
    n_objects: int
    n_trials: int
    success: float
    ceiling: float
    median_error_deg: float
    p90_error_deg: float
    share_identities_over_10deg: float
    novelty_median: float = float("nan")
    novelty_max: float = float("nan")

    @property
    def fraction_of_ceiling(self) -> float:
        """Success as a fraction of the ceiling (NaN for a ceiling of 0)."""
        return self.success / self.ceiling if self.ceiling > 0 else float("nan")

    def as_dict(self) -> dict:
        """The fields and ``fraction_of_ceiling``, as plain numbers (for JSON and CSV)."""
        return {**dataclasses.asdict(self), "fraction_of_ceiling": self.fraction_of_ceiling}


def frozen_success(agent, ds: CaregiverDatasets, config: Config, n_objects: int,
                   n_trials: int, seed: int) -> float:
    """The share of ``n_trials`` trials on ``ds`` that the frozen ``agent`` ends on the target.

    The compiled engine runs the models it can (the same trials as step by step would be);
    the rest run step by step. ``seed`` names the trials' stream.
    """
    frozen = freeze(agent)
    rng = stream(seed, "evaluate", n_objects)
    kin = HeadKinematics.from_config(config.world)
    options = getattr(frozen, "options", None)
    if options is not None and unsupported(options) is None:
        cell = compiled_cell(frozen, fast_world(config, ds, n_objects), rng,
                             stream(seed, "evaluate-shuffle"), n_trials)
        cell.run_until(0)
        return float(np.mean(cell.records()["success"]))
    evaluate, wins = evaluator(config), 0
    for _ in range(n_trials):
        k, scene, _ = random_scene(config, ds, kin, n_objects, rng)
        trial = SceneTrial(scene, ds.theta_face_rad[k], kinematics=kin,
                           max_steps=config.agent.max_steps, evaluate=evaluate)
        wins += run_trial(trial, frozen, ds.view(k)).success
    return wins / n_trials


def oracle_success(ds: CaregiverDatasets, config: Config, n_objects: int, n_trials: int,
                   seed: int) -> float:
    """The oracle gaze-line follower's share of ``n_trials`` trials on ``ds`` (its ceiling)."""
    return oracle_wins(ds, config, n_objects, n_trials,
                       stream(seed, "evaluate-ceiling", n_objects)) / n_trials


def _errors(agent, ds: CaregiverDatasets,
            outputs: np.ndarray | None = None) -> tuple[float, float, float]:
    """Median and 90th percentile angle error, and the share of identities above AIM_DEG.

    ``outputs``: the module's outputs at ``ds``'s faces (N, 2), if already taken.
    """
    if not hasattr(agent, "lm_command"):
        return float("nan"), float("nan"), float("nan")
    e = angle_errors(agent, ds, outputs)
    who = np.zeros(len(ds), int) if ds.caregiver is None else ds.caregiver
    medians = np.array([np.median(e[who == i]) for i in np.unique(who)])
    return (float(np.median(e)), float(np.percentile(e, 90)),
            float(np.mean(medians > AIM_DEG)))


def data_sets_novelty(ds: CaregiverDatasets, world: WorldConfig,
                      known: Sequence[Caregiver] | None, known_world: WorldConfig) -> np.ndarray:
    """How new each caregiver who posed ``ds`` is to ``known`` (:func:`~.novelty.novelty`).

    ``world``: the world ``ds`` were recorded in, unless their ``meta`` names it. Empty if
    ``known`` is None or ``ds`` do not say who posed them.
    """
    if known is None:
        return np.empty(0)
    toml = ds.meta.get("world_config_toml")
    if isinstance(toml, str):
        with contextlib.suppress(ValueError):  # a file of another version: the given world
            world = load_config(loads_toml(toml)).world
    people = who_posed(ds, world)
    return np.empty(0) if people is None else novelty(people, world, known, known_world)


def who_posed(ds: CaregiverDatasets, world: WorldConfig) -> list[Caregiver] | None:
    """The caregivers who posed ``ds`` in ``world``; None if they do not say (a robot's).

    :func:`~jointattention.world.recording.caregivers_of`, its DatasetError as None.
    """
    from ..world.recording import caregivers_of  # its module loads OpenCV: only when asked

    try:
        return caregivers_of(ds, world)
    except DatasetError:
        return None


def evaluate_agent(agent, ds: CaregiverDatasets, config: Config, *, name: str = "",
                   n_objects: int = 5, n_trials: int = 2000, seed: int = 0,
                   ceiling: float | None = None,
                   known: Sequence[Caregiver] | None = None) -> Evaluation:
    """The frozen ``agent`` of a run of ``config`` on the data sets ``ds`` (an Evaluation).

    ``ceiling``: the set's oracle ceiling if known (it depends on the set, the object count,
    the trials and the seed, not on the model), else measured here on ``n_trials`` trials.
    ``known``: the caregivers it learned from, in ``config``'s world (for the novelty).
    """
    check_int("n_objects", n_objects, 1, 20)
    check_int("n_trials", n_trials, 1, 10**7)
    check_int("seed", seed, 0, 2**63 - 1)
    if not isinstance(ds, CaregiverDatasets):
        raise ConfigError(f"datasets {ds!r}: expected CaregiverDatasets (jointattention."
                          "load_datasets)")
    wrong = window_mismatch(ds, agent.body.face_size_px, getattr(agent.body, "eye_size_px", None))
    if wrong is not None:
        raise ConfigError(f"{name or 'data sets'}: {wrong}")
    if ceiling is None:
        ceiling = oracle_success(ds, config, n_objects, n_trials, seed)
    success = frozen_success(agent, ds, config, n_objects, n_trials, seed)
    median, p90, share = _errors(freeze(agent), ds)
    new = data_sets_novelty(ds, config.world, known, config.world)
    new = new[np.isfinite(new)]
    return Evaluation(name, len(ds), ds.n_caregivers or 1, n_objects, n_trials, success,
                      float(ceiling), median, p90, share,
                      *((float(np.median(new)), float(new.max())) if len(new) else ()))


def evaluate(model, datasets, *, name: str = "", n_objects: int = 5, n_trials: int = 2000,
             seed: int = 0) -> Evaluation:
    """A saved model, frozen, on data sets: :func:`evaluate_agent` for files.

    ``model``: a :class:`~jointattention.deploy.saved.LearnedModel` or a model file's path;
    ``datasets``: :class:`~jointattention.datasets.CaregiverDatasets` or a data-set file's
    path. ``name`` labels the result (default: the file's name).
    """
    from pathlib import Path

    from ..datasets import load
    from ..deploy.saved import LearnedModel, load_model

    where = str(model) if isinstance(model, (str, Path)) else "model"
    if isinstance(model, (str, Path)):
        model = load_model(model)
    elif not isinstance(model, LearnedModel):
        raise ConfigError(f"model {model!r}: expected a LearnedModel or a model file's path")
    if isinstance(datasets, (str, Path)):
        name = name or Path(datasets).name
        datasets = load(datasets)
    return evaluate_agent(model.agent, datasets, model.config, name=name, n_objects=n_objects,
                          n_trials=n_trials, seed=seed, known=learned_from(model, where))


def learned_from(model, where: str = "model") -> list[Caregiver] | None:
    """The caregivers a saved model learned from (its file's ``meta.caregivers``), if it says.

    One :class:`~jointattention.errors.FileError`, naming ``where`` (the model file), if one of
    them is not an identity.
    """
    if model.caregivers is None:
        return None
    out = []
    for i, person in enumerate(model.caregivers):
        try:
            out.append(caregiver_from_dict(person))
        except ValueError as err:
            raise FileError(f"{where}: field 'meta.caregivers[{i}]': {err}") from None
    return out
