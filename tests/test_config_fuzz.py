"""Any TOML-like mapping is a valid configuration or one ConfigError line: nothing else."""

from __future__ import annotations

import dataclasses
import math
import typing

from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from jointattention.agent.gates import ConstantGate, EvidenceGate, PerformanceGate, SigmoidGate
from jointattention.config import ConditionConfig, Config, load_config, to_toml
from jointattention.errors import ConfigError
from jointattention.models.bootstrap import BootstrapOptions
from jointattention.models.memory.options import MemoryOptions


def _field_names(*classes) -> list[str]:
    names, todo = set(), list(classes)
    while todo:
        cls = todo.pop()
        for f in dataclasses.fields(cls):
            names.add(f.name)
            if dataclasses.is_dataclass(f.type) and isinstance(f.type, type):
                todo.append(f.type)
    return sorted(names)


# Keys the loader knows (so that the fuzz reaches deep into sections), old-style keys, and junk.
KEYS = st.sampled_from([
    *_field_names(Config, ConditionConfig, BootstrapOptions, SigmoidGate, ConstantGate,
                  PerformanceGate, EvidenceGate, MemoryOptions),
    "world", "camera", "head", "caregiver", "objects", "lighting", "face_window", "agent",
    "model", "detector", "experiment", "conditions", "kind", "gate", "memory", "gate_rate",
    "gate_midpoint_steps", "performance", "constant", "sigmoid", "bootstrap",
]) | st.text(max_size=8)
SCALARS = (st.booleans() | st.integers() | st.integers(-2**70, 2**70)
           | st.floats(allow_nan=True, allow_infinity=True) | st.text(max_size=12)
           | st.sampled_from(["fast", "rendered", "compiled", "python", "constant", "sigmoid",
                              "performance", "evidence", "memory", "backprop", "trial",
                              "step", "sweep",
                              "in_view", "n5", "../x", ""]))
VALUES = st.recursive(SCALARS, lambda inner: st.lists(inner, max_size=4)
                      | st.dictionaries(KEYS, inner, max_size=5), max_leaves=25)


def _shaped(cls: type) -> st.SearchStrategy:
    """Mappings shaped like section ``cls``: its own keys, each a fitting or a random value."""
    hints = typing.get_type_hints(cls)
    optional = {}
    for f in dataclasses.fields(cls):
        hint, registry = hints[f.name], f.metadata.get("registry")
        if registry is not None:
            kinds = [st.builds(lambda k, d: {"kind": k, **d}, st.sampled_from(list(registry)),
                               _shaped(registry[k])) for k in registry]
            optional[f.name] = st.one_of(*kinds) | st.sampled_from(list(registry)) | VALUES
        elif dataclasses.is_dataclass(hint):
            optional[f.name] = _shaped(hint) | VALUES
        elif typing.get_origin(hint) is tuple and dataclasses.is_dataclass(
                typing.get_args(hint)[0]):
            optional[f.name] = st.lists(_shaped(typing.get_args(hint)[0]), max_size=3) | VALUES
        elif f.name == "model":  # a condition's changes to the run's model
            optional[f.name] = _shaped(BootstrapOptions) | VALUES
        else:
            optional[f.name] = VALUES | st.just(getattr(cls(), f.name))
    return st.fixed_dictionaries({}, optional=optional)


MAPPINGS = _shaped(Config) | st.dictionaries(KEYS, VALUES, max_size=6)


@settings(max_examples=500, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=MAPPINGS)
def test_any_mapping_is_a_configuration_or_one_config_error_line(data):
    """The loader gives a valid configuration, or a ConfigError of one line; never another error."""
    try:
        config = load_config(data)
    except ConfigError as err:
        message = str(err)
        assert message and "\n" not in message and "Traceback" not in message
        event("refused")
        return
    event("valid")
    assert load_config(data) == config  # loading does not change the mapping it was given
    text = to_toml(config)
    assert all(math.isfinite(v) for v in _numbers(config))
    assert load_config(_parse(text)) == config


def _numbers(section) -> list[float]:
    out = []
    for f in dataclasses.fields(section):
        v = getattr(section, f.name)
        for x in v if isinstance(v, tuple) else (v,):
            if dataclasses.is_dataclass(x):
                out += _numbers(x)
            elif isinstance(x, float):
                out.append(x)
    return out


def _parse(text: str) -> dict:
    import tomllib

    return tomllib.loads(text)
