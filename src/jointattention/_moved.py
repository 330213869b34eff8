"""Module paths that shipped in version 0.3.0 and moved since: each warns and gives the new.

The policy (CHANGELOG.md): a public module path that shipped in a release keeps working for
one minor version after it moved; ``import`` of it goes through :class:`MovedFinder`
(installed by the package's ``__init__``), which issues a :class:`DeprecationWarning` naming
the new path, and the module it gives holds the new module's names (the same objects); a
path split in two gives the names of both.
Paths that never shipped in a release (they were moved before one) and private modules (a
leading underscore) get no shim. Version 0.5 removes this table.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings

__all__ = ["MOVED", "MovedFinder", "install", "new_paths"]

_TOP = __name__.rpartition(".")[0]

# old path (as version 0.3.0 shipped it) -> new path, or the new paths of a module split in
# two, relative to the package
MOVED = {
    "config.agent": "agent.options",
    "config.world": "world.options",
    "config.variation": "world.variation",
    "agent.bootstrap": "models.bootstrap",
    "agent.episodic": "models._compat",
    "agent.population_agent": "models._compat",
    "agent.rl": "models.rl",
    "agent.teacher": "models.teacher",
    "agent.developmental": "models.developmental",
    "agent.models": "models.registry",
    "agent.saved": "deploy.saved",
    "agent.follower": "deploy.follower",
    "figures.follow": "deploy.overlay",
    "experiment.reproduce": "jobs.reproduce",
    "experiment.sweep": "jobs.sweep",
    "experiment.closed_loop": "jobs.closed_loop",
    "analysis.parity": "jobs.parity",
    "analysis.learned": "jobs.learned",
    "bench": "jobs.bench",
    # one folder per learner, and names that say what they hold
    "agent.memory": "models.memory.episodic",
    "agent.population": "models.population.code",
    "agent.face_features": "models.population.features",
    "experiment.recorded": "experiment.dataset_cache",
    "recordings": "head_recording",
    "agent.learner": ("models.network.learner", "agent.face_standardiser"),
}


def new_paths(old: str) -> tuple[str, ...]:
    """The new path or paths of the old path ``old`` (both relative to the package)."""
    new = MOVED[old]
    return (new,) if isinstance(new, str) else new


class MovedFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds the old paths of :data:`MOVED`; loading one warns and copies the new module."""

    def find_spec(self, fullname, path=None, target=None):
        """A spec for an old path of this package; None for every other name."""
        old = fullname.removeprefix(f"{_TOP}.")
        if old == fullname or old not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec):
        """The default module object."""
        return None

    def exec_module(self, module):
        """Fill the old module with the new modules' names, after one DeprecationWarning."""
        new = [f"{_TOP}.{path}" for path in new_paths(module.__name__.removeprefix(f"{_TOP}."))]
        warnings.warn(f"{module.__name__} moved to {' and '.join(new)}; the old path goes in "
                      "version 0.5", DeprecationWarning, stacklevel=2)
        module.__all__ = []
        for name in new:
            real = importlib.import_module(name)
            module.__dict__.update({k: v for k, v in vars(real).items()
                                    if not (k.startswith("__") and k.endswith("__"))})
            module.__all__ += list(getattr(real, "__all__", ()))
        module.__doc__ = f"Moved to {' and '.join(f':mod:`{n}`' for n in new)} (version 0.4)."


def install() -> None:
    """Put one :class:`MovedFinder` on ``sys.meta_path`` (again: nothing)."""
    if not any(isinstance(f, MovedFinder) for f in sys.meta_path):
        sys.meta_path.append(MovedFinder())
