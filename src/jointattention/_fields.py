"""The machinery behind configuration sections: typed fields with help text and ranges.

A section is a frozen dataclass of :func:`param` fields; building one checks every field.
A *tagged* field holds one of several kinds of a part (a model, a gate), looked up by name
in a :class:`Registry`; in TOML it is a table whose ``kind`` names the kind.
"""

from __future__ import annotations

import dataclasses
import importlib
import types
import typing
from collections.abc import Iterator, Mapping
from typing import Any

from ._checks import MAX_INT, NAME, check_type, check_value, scalar_types
from .errors import ConfigError

__all__ = ["FrozenTable", "Registry", "Section", "from_mapping", "merge", "merge_tagged", "param",
           "to_mapping"]



def param(
    default: Any = dataclasses.MISSING,
    help: str = "",
    *,
    lo: float | None = None,
    hi: float | None = None,
    choices: Any = None,
    factory: Any = None,
    registry: Registry | None = None,
) -> Any:
    """A configuration field: its default, its help text and the range it must lie in.

    ``choices`` is a tuple of the allowed values. ``registry`` makes a tagged field (one of
    the registry's kinds), whose default comes from ``factory``.
    """
    meta = {"help": help, "lo": lo, "hi": hi, "choices": choices, "registry": registry}
    if isinstance(default, (list, dict)):
        raise TypeError("use tuples for sequence defaults")
    if factory is not None:
        return dataclasses.field(default_factory=factory, metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


class Registry:
    """The named kinds of one part of the model (the models, the gates).

    Each kind is an options section (a :class:`Section`) that builds its part. Built-in kinds
    may be given as ``"module:attribute"`` strings, imported on first use, so that a registry
    can name kinds whose modules import the configuration.
    """

    def __init__(self, part: str, kinds: Mapping[str, str | type]):
        self.part = part
        self._kinds = dict(kinds)

    def register(self, name: str, options: type) -> type:
        """Add the kind ``name``, whose options section is ``options``; returns ``options``."""
        if not (isinstance(options, type) and issubclass(options, Section)):
            raise TypeError(f"{self.part} {name!r}: expected a Section subclass")
        if name in self._kinds and self[name] is not options:
            raise ValueError(f"{self.part} {name!r} is registered already")
        self._kinds[name] = options
        return options

    def unregister(self, name: str) -> None:
        """Remove the kind ``name``."""
        del self._kinds[name]

    def __getitem__(self, name: str) -> type:
        if name not in self._kinds:
            raise ConfigError(f"{self.part} {name!r}: unknown; expected one of {', '.join(self)}")
        kind = self._kinds[name]
        if isinstance(kind, str):
            module, attribute = kind.split(":")
            kind = self._kinds[name] = getattr(importlib.import_module(module), attribute)
        return kind

    def __contains__(self, name: object) -> bool:
        return name in self._kinds

    def __iter__(self) -> Iterator[str]:
        return iter(list(self._kinds))

    def name_of(self, options: Any) -> str:
        """The name under which the kind of ``options`` is registered."""
        for name in self:
            if type(options) is self[name]:
                return name
        raise KeyError(f"{type(options).__name__} is not a registered {self.part}")


class FrozenTable(Mapping):
    """An immutable, hashable mapping: a partial table of settings kept as given."""

    def __init__(self, data: Mapping | None = None):
        def freeze(v):
            if isinstance(v, Mapping):
                return FrozenTable(v)
            return tuple(freeze(x) for x in v) if isinstance(v, (list, tuple)) else v

        self._data = {k: freeze(v) for k, v in dict(data or {}).items()}

    def __getitem__(self, key: str) -> Any:
        return self._data[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def __hash__(self) -> int:
        return hash(tuple(sorted(self._data.items(), key=lambda kv: kv[0])))

    def __repr__(self) -> str:
        return f"FrozenTable({self.to_dict()!r})"

    def to_dict(self) -> dict:
        """A plain (nested) dict."""
        return {k: v.to_dict() if isinstance(v, FrozenTable) else v for k, v in self.items()}


class Section:
    """Base of configuration sections: every field is checked when a section is built."""

    def __post_init__(self) -> None:
        types_of = scalar_types(type(self))
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.name in types_of:
                check_type(f.name, value, types_of[f.name])
            if not dataclasses.is_dataclass(value) and not (
                    isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0])):
                check_value(f.name, value, f.metadata)


def _coerce(name: str, value: Any, hint: Any) -> Any:
    origin = typing.get_origin(hint)
    if dataclasses.is_dataclass(hint):
        return from_mapping(hint, value, prefix=f"{name}.")
    if hint is FrozenTable:
        if not isinstance(value, Mapping):
            raise ConfigError(f"{name} = {value!r}: expected a table of settings")
        return FrozenTable(value)
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
        if abs(value) > MAX_INT:
            raise ConfigError(f"{name} = {value}: expected an integer of at most {MAX_INT}")
        return value
    if hint is bool and isinstance(value, bool):
        return value
    if hint is str and isinstance(value, str):
        return value
    raise ConfigError(f"{name} = {value!r}: expected {getattr(hint, '__name__', hint)}")


def merge_tagged(registry: Registry, current: Any, value: Any, name: str) -> Any:
    """``current`` (of some kind) changed by ``value``.

    ``value`` is a table, or just a kind's name. A new kind starts from its defaults and keeps the
    fields it shares with the old one.
    """
    if isinstance(value, str):
        value = {"kind": value}
    if not isinstance(value, Mapping):
        raise ConfigError(f"{name} = {value!r}: expected a table with a kind and its settings")
    kind = value.get("kind", registry.name_of(current))
    if not isinstance(kind, str) or kind not in registry:
        raise ConfigError(f"{name}.kind = {kind!r}: expected one of "
                          f"{', '.join(map(repr, registry))}")
    cls = registry[kind]
    base = current
    if type(current) is not cls:
        shared = ({f.name for f in dataclasses.fields(cls)}
                  & {f.name for f in dataclasses.fields(current)})
        base = dataclasses.replace(cls(), **{k: getattr(current, k) for k in shared})
    return merge(base, {k: v for k, v in value.items() if k != "kind"}, prefix=f"{name}.")


def merge(section: Any, changes: Mapping, prefix: str = "") -> Any:
    """``section`` with ``changes`` (a partial mapping, as TOML gives) applied.

    Nested sections change field by field; unknown keys, wrong types and values out of range
    are one :class:`ConfigError` naming the field.
    """
    cls = type(section)
    if not isinstance(changes, Mapping):
        raise ConfigError(f"{prefix.rstrip('.')}: expected a table of settings, got "
                          f"{changes!r}")
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(set(changes) - set(fields))
    if unknown:
        key = unknown[0] if NAME.fullmatch(str(unknown[0])) else repr(unknown[0])
        raise ConfigError(f"{prefix}{key}: unknown setting; expected one of "
                          f"{', '.join(sorted(fields))}")
    hints = typing.get_type_hints(cls)
    kwargs = {}
    for key, value in changes.items():
        current, registry = getattr(section, key), fields[key].metadata.get("registry")
        if registry is not None:
            kwargs[key] = merge_tagged(registry, current, value, f"{prefix}{key}")
        elif dataclasses.is_dataclass(current) and isinstance(value, Mapping):
            kwargs[key] = merge(current, value, prefix=f"{prefix}{key}.")
        else:
            kwargs[key] = _coerce(f"{prefix}{key}", value, hints[key])
    try:
        return dataclasses.replace(section, **kwargs)
    except ConfigError as err:  # the section's own checks name fields without the prefix
        raise ConfigError(f"{prefix}{err}") from None


def from_mapping(cls: type, data: Mapping, prefix: str = "") -> Any:
    """Build section ``cls`` from a (TOML) mapping over its defaults."""
    if not isinstance(data, Mapping):
        raise ConfigError(f"{prefix.rstrip('.')}: expected a table of settings, got {data!r}")
    return merge(cls(), data, prefix)


def to_mapping(section: Any) -> dict:
    """The section as a plain, TOML-ready mapping (tuples become lists, None is dropped)."""
    out = {}
    for f in dataclasses.fields(section):
        value, registry = getattr(section, f.name), f.metadata.get("registry")
        if registry is not None:
            out[f.name] = {"kind": registry.name_of(value), **to_mapping(value)}
        elif dataclasses.is_dataclass(value):
            out[f.name] = to_mapping(value)
        elif isinstance(value, tuple) and value and dataclasses.is_dataclass(value[0]):
            out[f.name] = [to_mapping(v) for v in value]
        elif isinstance(value, FrozenTable):
            if value:
                out[f.name] = value.to_dict()
        elif value is not None:
            out[f.name] = list(value) if isinstance(value, tuple) else value
    return out
