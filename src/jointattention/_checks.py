"""Checking single values: names, ranges, integers and types, each refusal one line.

Used by the configuration's sections (:mod:`._fields`) and by the API's argument checks.
"""

from __future__ import annotations

import functools
import math
import numbers
import os
import re
import types
import typing
from collections.abc import Mapping
from typing import Any

from .errors import ArgumentError, ConfigError

__all__ = ["MAX_INT", "NAME", "UNSAFE", "check_int", "check_name", "check_path",
           "check_type", "check_value", "scalar_types", "short_repr"]

# Names become file and folder names: letters, digits and a few marks, never a path.
_SAFE = "A-Za-z0-9_.,=+-"
NAME = re.compile(rf"[A-Za-z0-9][{_SAFE}]{{0,79}}")
UNSAFE = re.compile(rf"[^{_SAFE}]")  # a character that a name may not hold
MAX_INT = 2**63 - 1  # the compiled engine's integers; TOML's own limit too


def check_name(name: str, where: str) -> None:
    """Refuse a name that is not a safe file name (it names cells, folders and figures)."""
    if not isinstance(name, str) or not NAME.fullmatch(name):
        raise ConfigError(f"{where} = {name!r}: expected a name of 1-80 letters, digits and "
                          "_ . , = + - that starts with a letter or digit")


def _expected_range(lo: float | None, hi: float | None) -> str:
    if hi is None:
        return f"a value of at least {lo}"
    return f"a value of at most {hi}" if lo is None else f"a value in [{lo}, {hi}]"


def check_value(name: str, value: Any, meta: Mapping) -> None:
    """Refuse ``value`` (or an item of it) outside the field's choices or range, or not finite."""
    lo, hi, choices = meta.get("lo"), meta.get("hi"), meta.get("choices")
    for v in value if isinstance(value, tuple) else (value,):
        if v is None or (isinstance(v, str) and choices is None):
            continue
        if choices is not None:
            if v not in choices:
                raise ConfigError(f"{name} = {v!r}: expected one of "
                                  f"{', '.join(map(repr, choices))}")
            continue
        if isinstance(v, float) and not math.isfinite(v):
            raise ConfigError(f"{name} = {v!r}: expected a finite number")
        if (lo is not None and v < lo) or (hi is not None and v > hi):
            raise ConfigError(f"{name} = {v!r}: expected {_expected_range(lo, hi)}")


def check_int(name: str, value: Any, lo: int, hi: int, error: type = ConfigError) -> int:
    """``value`` as an int in [lo, hi], else one ``error`` naming the argument ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) \
            or not lo <= value <= hi:
        raise error(f"{name}={short_repr(value)}: expected an integer in [{lo}, {hi}]")
    return int(value)


def short_repr(value: Any) -> str:
    """``repr(value)`` on one line, cut to 80 characters."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 80 else text[:77] + "..."


_SCALARS = {int: numbers.Integral, float: numbers.Real, str: str, bool: bool}


@functools.cache
def scalar_types(cls: type) -> dict[str, type]:
    """Field name -> the Python type of its values, for the scalar fields of section ``cls``."""
    out = {}
    for name, hint in typing.get_type_hints(cls).items():
        if typing.get_origin(hint) in (typing.Union, types.UnionType):
            hint = next(a for a in typing.get_args(hint) if a is not type(None))
        args = typing.get_args(hint)
        if typing.get_origin(hint) is tuple and args and args[-1] is not Ellipsis:
            hint = args[0]
        if hint in _SCALARS:
            out[name] = hint
    return out


def check_type(name: str, value: Any, hint: type) -> None:
    """Refuse ``value`` (or an item of it) not of the scalar type ``hint`` (bool is not int)."""
    for v in value if isinstance(value, tuple) else (value,):
        wrong = v is not None and (not isinstance(v, _SCALARS[hint])
                                   or (hint is not bool and isinstance(v, bool)))
        if wrong:
            raise ConfigError(f"{name} = {short_repr(v)}: expected {hint.__name__}")


def check_path(value: Any, name: str) -> Any:
    """``value`` if it is a path (str or os.PathLike), else one ArgumentError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (str, os.PathLike)) or not str(value):
        raise ArgumentError(f"{name} {short_repr(value)}: expected a path (str or Path)")
    return value
