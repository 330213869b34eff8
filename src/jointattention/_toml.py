"""Writing TOML (the standard library only reads it): enough for configuration mappings."""

from __future__ import annotations

from typing import Any

__all__ = ["dumps"]


def _string(s: str) -> str:
    out = []
    for ch in s:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:  # control characters must be escaped
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _key(k: str) -> str:
    bare = k and all(c.isascii() and (c.isalnum() or c in "-_") for c in k)
    return k if bare else _string(k)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return repr(v)


def _is_tables(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def dumps(mapping: dict, prefix: str = "") -> str:
    """TOML text of ``mapping``.

    Tables become ``[headers]``, lists of tables ``[[headers]]`` whose nested tables are written
    inline.
    """
    lines = [f"{_key(k)} = {_value(v)}" for k, v in mapping.items()
             if not isinstance(v, dict) and not _is_tables(v)]
    for k, v in mapping.items():
        name = f"{prefix}{_key(k)}"
        if isinstance(v, dict):
            inner = dumps(v, prefix=f"{name}.").strip()
            has_keys = any(not isinstance(x, dict) and not _is_tables(x) for x in v.values())
            lines += ["", f"[{name}]", inner] if has_keys or not v else ["", inner]
        elif _is_tables(v):
            for item in v:
                lines += ["", f"[[{name}]]"]
                lines += [f"{_key(kk)} = {_value(x)}" for kk, x in item.items()]
    return "\n".join(lines).strip() + "\n"
