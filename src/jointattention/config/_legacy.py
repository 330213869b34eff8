"""Reading configurations written before the ``[model]`` section and the compiled engine.

In version 0.1.0 and its run folders, the learning module's and the gate's settings lived in
``[agent]`` and in each condition. They are moved where they live now. A configuration of
rendered perception written before ``experiment.engine`` existed runs the python engine, the
only one that renders.
"""

from __future__ import annotations

import warnings
from typing import Any

__all__ = ["upgrade"]

_MODEL_KEYS = ("n_hidden", "learning_rate", "momentum", "init_scale", "gate_per",
               "vf_fallback", "learning_target")
# Old gate key -> (gate kind it belongs to, its name there); "gate" was the kind.
_GATE_KEYS = {"gate_rate": ("constant", "rate"),
              "gate_midpoint_steps": ("sigmoid", "midpoint_steps"),
              "gate_width_steps": ("sigmoid", "width_steps")}


def _gate(kind: str, values: dict) -> dict:
    """The gate table of ``kind`` from old-style ``values`` (only its own parameters)."""
    return {"kind": kind, **{name: values[key] for key, (owner, name) in _GATE_KEYS.items()
                             if owner == kind and key in values}}


def _pop_old(section: dict) -> tuple[dict, dict]:
    model = {k: section.pop(k) for k in _MODEL_KEYS if k in section}
    gate = {k: section.pop(k) for k in ("gate", *_GATE_KEYS) if k in section}
    return model, gate


def upgrade(data: dict[str, Any]) -> dict[str, Any]:
    """``data`` (a parsed configuration) with old-style keys moved to ``[model]``.

    ``[world.objects] n_objects`` (version 0.3; every saved run's config.toml has it) is
    dropped: the conditions hold the run's counts. A value other than 5 warns, since an
    environment or a command took it as its count.
    """
    world = data.get("world")
    objects = world.get("objects") if isinstance(world, dict) else None
    if isinstance(objects, dict) and "n_objects" in objects:
        count = objects.pop("n_objects")
        if count != 5:
            warnings.warn(f"world.objects.n_objects = {count!r} is no longer read (the world "
                          "holds no object count); expected n_objects in each condition, or "
                          "passed to the environment or the command", DeprecationWarning,
                          stacklevel=4)
    experiment = data.get("experiment")
    if isinstance(experiment, dict) and experiment.get("perception") == "rendered":
        experiment.setdefault("engine", "python")
    agent = data.get("agent")
    if not isinstance(agent, dict) or isinstance(data.get("model"), dict):
        return data  # new style (or nothing to move)
    model, run_gate = _pop_old(agent)
    run_kind = run_gate.get("gate", "sigmoid")
    if run_gate:
        model["gate"] = _gate(run_kind, run_gate)
    if model:
        data["model"] = model
    conditions = experiment.get("conditions") if isinstance(experiment, dict) else None
    for c in conditions if isinstance(conditions, list) else ():
        if not isinstance(c, dict) or "model" in c:
            continue
        changes, gate = _pop_old(c)
        if gate:  # the condition's gate: its kind, its values or else the run's
            changes["gate"] = _gate(gate.get("gate", run_kind), {**run_gate, **gate})
        if changes:
            c["model"] = changes
    return data
