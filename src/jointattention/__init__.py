"""jointattention: the bootstrap learning model for joint attention (Nagai, Hosoda, Asada).

A robot with a pan/tilt camera head learns, with no teacher, to look where a caregiver looks.

The public API is importable from here; each name is loaded from its module on first use, so
that importing the robot's side (:mod:`jointattention.agent`) loads no world and no MuJoCo.
The layout is described in ``docs/architecture.md``.
"""

import importlib

from . import _moved
from ._version import __version__

_moved.install()  # the module paths of version 0.3 keep working, with a warning

_EXPORTS = {
    "Agent": "jointattention.agent.protocol:Agent",
    "AgentKernels": "jointattention.agent.protocol:AgentKernels",
    "Body": "jointattention.agent.protocol:Body",
    "BootstrapAgent": "jointattention.models.bootstrap:BootstrapAgent",
    "BootstrapOptions": "jointattention.models.bootstrap:BootstrapOptions",
    "CaregiverDatasets": "jointattention.datasets:CaregiverDatasets",
    "ConditionConfig": "jointattention.config:ConditionConfig",
    "Config": "jointattention.config:Config",
    "ConfigError": "jointattention.errors:ConfigError",
    "DatasetError": "jointattention.errors:DatasetError",
    "Detections": "jointattention.agent.detections:Detections",
    "FastScene": "jointattention.world.fast:FastScene",
    "GATES": "jointattention.agent.gates:GATES",
    "Gate": "jointattention.agent.gates:Gate",
    "GazeFollower": "jointattention.deploy.follower:GazeFollower",
    "JointAttentionError": "jointattention.errors:JointAttentionError",
    "LearnedModel": "jointattention.deploy.saved:LearnedModel",
    "MODELS": "jointattention.models.registry:MODELS",
    "ModelOptions": "jointattention.models.registry:ModelOptions",
    "ModuleKernels": "jointattention.agent.protocol:ModuleKernels",
    "Outcome": "jointattention.agent.protocol:Outcome",
    "Robot": "jointattention.deploy.saved:Robot",
    "RunResult": "jointattention.jobs.reproduce:RunResult",
    "Scene": "jointattention.world.protocol:Scene",
    "SceneTrial": "jointattention.experiment.trial:SceneTrial",
    "TrialResult": "jointattention.experiment.trial:TrialResult",
    "World": "jointattention.world.simulator:World",
    "default_datasets": "jointattention.datasets:default_datasets",
    "Evaluation": "jointattention.experiment.evaluate:Evaluation",
    "evaluate": "jointattention.experiment.evaluate:evaluate",
    "import_recording": "jointattention.head_recording:import_recording",
    "load_config": "jointattention.config:load_config",
    "load_datasets": "jointattention.datasets:load",
    "load_model": "jointattention.deploy.saved:load_model",
    "measure_ceiling": "jointattention.experiment.cells:measure_ceiling",
    "param": "jointattention.config:param",
    "reproduce": "jointattention.jobs.reproduce:reproduce",
    "run_cell": "jointattention.experiment.cells:run_cell",
    "run_experiment": "jointattention.jobs.reproduce:run_experiment",
    "run_trial": "jointattention.experiment.trial:run_trial",
    "save_model": "jointattention.deploy.saved:save_model",
    "train": "jointattention.experiment.training:train",
    "write_report": "jointattention.figures.report:write_report",
}

__all__ = [
    "GATES",
    "MODELS",
    "Agent",
    "AgentKernels",
    "Body",
    "BootstrapAgent",
    "BootstrapOptions",
    "CaregiverDatasets",
    "ConditionConfig",
    "Config",
    "ConfigError",
    "DatasetError",
    "Detections",
    "Evaluation",
    "FastScene",
    "Gate",
    "GazeFollower",
    "JointAttentionError",
    "LearnedModel",
    "ModelOptions",
    "ModuleKernels",
    "Outcome",
    "Robot",
    "RunResult",
    "Scene",
    "SceneTrial",
    "TrialResult",
    "World",
    "__version__",
    "default_datasets",
    "evaluate",
    "import_recording",
    "load_config",
    "load_datasets",
    "load_model",
    "measure_ceiling",
    "param",
    "reproduce",
    "run_cell",
    "run_experiment",
    "run_trial",
    "save_model",
    "train",
    "write_report",
]


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'jointattention' has no attribute {name!r}")
    module, attribute = _EXPORTS[name].split(":")
    value = getattr(importlib.import_module(module), attribute)
    globals()[name] = value  # later lookups skip this function
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_EXPORTS})
