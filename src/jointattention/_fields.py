"""The machinery behind configuration sections: typed fields with help text and ranges."""

from __future__ import annotations

import dataclasses
import types
import typing
from typing import Any

from .errors import ConfigError

__all__ = ["check_section", "from_mapping", "param", "to_mapping"]


def param(
    default: Any,
    help: str,
    *,
    lo: float | None = None,
    hi: float | None = None,
    choices: tuple | None = None,
) -> Any:
    """A configuration field: its default, its help text and the range it must lie in."""
    meta = {"help": help, "lo": lo, "hi": hi, "choices": choices}
    if isinstance(default, (list, dict)):
        raise TypeError("use tuples for sequence defaults")
    return dataclasses.field(default=default, metadata=meta)


def _check_value(name: str, value: Any, meta: dict) -> None:
    lo, hi, choices = meta.get("lo"), meta.get("hi"), meta.get("choices")
    values = value if isinstance(value, tuple) else (value,)
    for v in values:
        if v is None:
            continue
        if choices is not None and v not in choices:
            raise ConfigError(f"{name} = {v!r}: expected one of {', '.join(map(repr, choices))}")
        if (lo is not None and v < lo) or (hi is not None and v > hi):
            raise ConfigError(f"{name} = {v!r}: expected a value in [{lo}, {hi}]")


def check_section(section: Any, prefix: str = "") -> None:
    """Check every field of a section against its declared range; raise one ConfigError."""
    for f in dataclasses.fields(section):
        value = getattr(section, f.name)
        name = f"{prefix}{f.name}"
        if dataclasses.is_dataclass(value):
            check_section(value, prefix=f"{name}.")
        elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
            for i, item in enumerate(value):
                check_section(item, prefix=f"{name}[{i}].")
        else:
            _check_value(name, value, f.metadata)


def _coerce(name: str, value: Any, hint: Any) -> Any:
    origin = typing.get_origin(hint)
    if dataclasses.is_dataclass(hint):
        if not isinstance(value, dict):
            raise ConfigError(f"{name}: expected a table of settings, got {value!r}")
        return from_mapping(hint, value, prefix=f"{name}.")
    if origin is tuple and typing.get_args(hint)[-1] is Ellipsis:
        if not isinstance(value, (list, tuple)):
            raise ConfigError(f"{name} = {value!r}: expected a list")
        item = typing.get_args(hint)[0]
        return tuple(_coerce(f"{name}[{i}]", v, item) for i, v in enumerate(value))
    if origin is tuple:
        args = typing.get_args(hint)
        if not isinstance(value, (list, tuple)) or len(value) != len(args):
            raise ConfigError(f"{name} = {value!r}: expected a list of {len(args)} numbers")
        return tuple(_coerce(name, v, a) for v, a in zip(value, args, strict=True))
    if origin in (typing.Union, types.UnionType):
        if value is None:
            return None
        hint = next(a for a in typing.get_args(hint) if a is not type(None))
        return _coerce(name, value, hint)
    if hint is float and isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    if hint is int and isinstance(value, int) and not isinstance(value, bool):
        return value
    if hint is bool and isinstance(value, bool):
        return value
    if hint is str and isinstance(value, str):
        return value
    raise ConfigError(f"{name} = {value!r}: expected {getattr(hint, '__name__', hint)}")


def from_mapping(cls: type, data: dict, prefix: str = "") -> Any:
    """Build section ``cls`` from a (TOML) mapping; unknown keys and wrong types are errors."""
    hints = typing.get_type_hints(cls)
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(set(data) - names)
    if unknown:
        raise ConfigError(
            f"{prefix}{unknown[0]}: unknown setting; expected one of {', '.join(sorted(names))}"
        )
    kwargs = {k: _coerce(f"{prefix}{k}", v, hints[k]) for k, v in data.items()}
    return dataclasses.replace(cls(), **kwargs)


def to_mapping(section: Any) -> dict:
    """The section as a plain, TOML-ready mapping (tuples become lists, None is dropped)."""
    out = {}
    for f in dataclasses.fields(section):
        value = getattr(section, f.name)
        if dataclasses.is_dataclass(value):
            out[f.name] = to_mapping(value)
        elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
            out[f.name] = [to_mapping(v) for v in value]
        elif value is not None:
            out[f.name] = list(value) if isinstance(value, tuple) else value
    return out
