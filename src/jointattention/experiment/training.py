"""Learning one cell and keeping what it learned (``train``, ``reproduce --save-models``)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .._readers import sha256_of
from ..config import ConditionConfig, Config, check_config, condition_named
from ..datasets import CaregiverDatasets, scenes_sha256
from ..deploy.saved import LearnedModel, check_savable, save_model
from ..errors import FileError
from .cells import datasets_file, datasets_of
from .dataset_cache import training_file
from .evaluate import who_posed
from .held_out import final_held_out, run_cell_measured
from .preflight import check_memory
from .results import datasets_sha256

__all__ = ["model_datasets", "model_path", "provenance", "run_cell_saving_model", "train"]


def _learn(config: Config, condition: ConditionConfig, seed_index: int,
           progress: Callable[[int], None] | None = None):
    """The cell's records (with its held-out measures) and its agent at the end of learning."""
    learned = []
    records = run_cell_measured(config, condition, seed_index, progress, on_end=learned.append)
    return records, learned[-1]


def train(config: Config, condition: str, seed_index: int = 0,
          progress: Callable[[int], None] | None = None) -> LearnedModel:
    """Learn one cell (``experiment.n_steps`` steps) and return its learned model.

    Only the bootstrap model, the teacher and the developmental model, with the
    back-propagation or the population learner, are saved (checked first). The model's
    ``held_out`` holds its held-out measures at the end of learning (:mod:`.held_out`).
    """
    cond = condition_named(check_config(config), condition)
    check_savable(config, condition)  # before learning, not after
    check_memory(config, [condition])  # an in-range capacity may not fit this machine
    records, agent = _learn(config, cond, seed_index, progress)
    return LearnedModel(agent, config, condition, held_out=final_held_out(records),
                        **provenance(config))


def provenance(config: Config) -> dict:
    """What a model file keeps of its run's training sets: file and scene SHA-256s, who posed them.

    The caregivers as the file keeps them (JSON tables), None if the sets do not say.
    """
    ds = datasets_of(config)
    people = who_posed(ds, config.world)
    return {"datasets_sha256": datasets_sha256(config), "scenes_sha256": scenes_sha256(ds),
            "caregivers": None if people is None else tuple(
                {k: list(v) if isinstance(v, tuple) else v  # as JSON gives them back
                 for k, v in dataclasses.asdict(c).items()} for c in people)}


def model_path(models_dir: Path, condition: str, seed_index: int) -> Path:
    """Where ``reproduce --save-models`` keeps a cell's learned model."""
    return Path(models_dir) / condition / f"seed_{seed_index:03d}.npz"


def run_cell_saving_model(config: Config, condition: ConditionConfig, seed_index: int, *,
                          models_dir: Path) -> dict[str, np.ndarray]:
    """:func:`~.cells.run_cell`, saving the learned model (in the worker) before it returns.

    A cell's file is written only after its model, so a finished cell has its model.
    """
    records, agent = _learn(config, condition, seed_index)
    save_model(agent, model_path(models_dir, condition.name, seed_index), config=config,
               condition=condition.name, **provenance(config))
    return records


def model_datasets(model: LearnedModel, model_file: str | Path | None = None,
                   progress: Callable[[int], None] | None = None) -> CaregiverDatasets:
    """The data sets ``model`` learned from, checked against the SHA-256 it recorded.

    A relative ``datasets`` path of its configuration is looked for beside ``model_file``
    first, then in the current folder. A model that recorded its data sets' scenes
    (``scenes_sha256``) takes the same scenes recorded on any machine (another OpenGL renders
    a few grey levels apart); a model of before, the same file to the byte. Data sets of other
    content are refused in one line: what a model did on them says nothing of what it learned.
    Recorded training sets not yet in this machine's cache are recorded first (``progress``:
    called with the data sets recorded so far).
    """
    config = model.config
    if config.datasets and not Path(config.datasets).is_absolute() and model_file is not None:
        beside = Path(model_file).parent / config.datasets
        if beside.is_file():
            config = dataclasses.replace(config, datasets=str(beside))
    if not config.datasets:
        training_file(config, progress)  # recorded here, with progress, if not yet kept
    path = datasets_file(config)
    if model.scenes_sha256 is not None:
        ds = datasets_of(config)
        found = scenes_sha256(ds)
        if found != model.scenes_sha256:
            raise FileError(f"{path}: data sets of other scenes (sha256 {found[:12]}...) than "
                            f"the model learned from ({model.scenes_sha256[:12]}...); expected "
                            "the model's own data sets")
        return ds
    found = sha256_of(path) if model.datasets_sha256 is not None else None
    if found != model.datasets_sha256:
        raise FileError(f"{path}: data sets of other content (sha256 {found[:12]}...) than the "
                        f"model learned from ({model.datasets_sha256[:12]}...); expected the "
                        "model's own data sets")
    return datasets_of(config)
