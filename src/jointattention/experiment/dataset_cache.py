"""The cache of data sets a run records itself, so that each is recorded once per machine.

A configuration may record its training sets (``[recording]``: K caregivers of the run's
world) instead of naming a file, and runs record their held-out sets
(:mod:`.held_out`). Recording renders every data set (off-screen OpenGL); the result depends
only on the world's configuration, the counts, the seed, the stream and the package version
(and, where the robot finds the eye sockets with its network, that network's SHA-256: a
network fitted again records other patches), so it is kept under a name made from them:
``$JOINTATTENTION_CACHE`` (default ``~/.cache/jointattention``) ``/datasets/<hash>.npz``,
written atomically (two processes recording the same file both write whole files). A run
records them in its own process before its cells (:func:`~.held_out.held_out_sets`), so that
worker processes only read them: a process forked after its parent rendered cannot render.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from collections.abc import Callable, Sequence
from pathlib import Path

from .._fields import to_mapping
from .._version import __version__
from ..agent.socket_net import NET_FILE
from ..config import Config, WorldConfig
from ..data import SHA256
from ..datasets import save

__all__ = ["cache_dir", "recorded_file", "recorded_path", "training_file"]


def cache_dir() -> Path:
    """Where recorded data sets are kept."""
    base = os.environ.get("JOINTATTENTION_CACHE") or Path(
        os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "jointattention"
    return Path(base) / "datasets"


def recorded_path(world: WorldConfig, n: int, seed: int, *, caregivers: int = 1,
                  stream: str = "world", identities: Sequence | None = None) -> Path:
    """Where :func:`recorded_file` keeps these data sets, whether or not they are recorded yet."""
    people = None if identities is None else [dataclasses.asdict(c) for c in identities]
    fields = {"world": to_mapping(world), "n": n, "seed": seed, "caregivers": caregivers,
              "stream": stream, "identities": people, "version": __version__}
    ew = world.eye_window
    if ew.enabled and ew.socket_patch_px and ew.socket_finder == "net":
        fields["socket_net"] = SHA256[NET_FILE]  # only then: other keys stay as they were
    key = json.dumps(fields, sort_keys=True)
    return cache_dir() / f"{hashlib.sha256(key.encode()).hexdigest()[:24]}.npz"


def recorded_file(world: WorldConfig, n: int, seed: int, *, caregivers: int = 1,
                  stream: str = "world", identities: Sequence | None = None,
                  progress: Callable[[int], None] | None = None) -> Path:
    """The file of ``make_datasets(world, n, seed, ...)``'s data sets: from the cache, or made.

    See :func:`jointattention.world.recording.make_datasets` for the arguments.
    """
    path = recorded_path(world, n, seed, caregivers=caregivers, stream=stream,
                         identities=identities)
    if not path.is_file():
        from ..world.recording import make_datasets  # rendering: only when recording

        ds = make_datasets(world, n, seed, progress, caregivers=caregivers if identities is None
                           else 1, stream=stream, identities=identities)
        path.parent.mkdir(parents=True, exist_ok=True)
        save(ds, path)
    return path


def training_file(config: Config, progress: Callable[[int], None] | None = None) -> Path | None:
    """The file of the run's recorded training sets (``[recording]``), None if it records none.

    ``progress`` is called with the data sets recorded so far, if they are recorded now.
    """
    r = config.recording
    if not r.caregivers:
        return None
    return recorded_file(config.world, r.caregivers * r.poses_per_caregiver, r.seed,
                         caregivers=r.caregivers, progress=progress)

