"""Writing files whole or not at all: every file the package writes goes through here.

Commands check their output places with :func:`check_writable` before any work, so that a
place that cannot be written is one error line, not a traceback after the computing.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .errors import FileError

__all__ = ["atomic_path", "check_writable", "save_json", "save_npz", "write_text"]


def check_writable(path: str | Path, kind: str = "folder", what: str = "--out") -> Path:
    """Refuse ``path`` unless a ``kind`` ("folder" or "file") can be made or written there.

    Nothing is created: the nearest existing ancestor must be a writable folder.
    """
    path = Path(path)
    if not str(path).strip():
        raise FileError(f"{what}: an empty path; expected a {kind}")
    if len(path.name.encode()) > 255 or "\0" in str(path):
        raise FileError(f"{what} {str(path)[:60]}...: not a possible file name; expected a "
                        f"{kind} name of at most 255 bytes without NUL")
    if os.path.lexists(path):
        if kind == "folder" and not os.path.isdir(path):
            raise FileError(f"{what} {path}: a file; expected a folder")
        if kind == "file" and os.path.isdir(path):
            raise FileError(f"{what} {path}: a folder; expected a file name")
        place = path if os.path.isdir(path) else path.parent
    else:
        place = path.parent
        while not os.path.lexists(place):
            place = place.parent
        if not os.path.isdir(place):
            raise FileError(f"{what} {path}: {place} is a file; expected a folder on the way")
    if not os.access(place, os.W_OK | os.X_OK):
        raise FileError(f"{what} {path}: {place} cannot be written (permission denied); "
                        f"expected a writable place for a {kind}")
    return path


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it into place only if the block succeeds.

    The file gets the permissions a new file would get (``0o666`` less the umask): mkstemp
    makes private files, and results and data sets are not private.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        yield Path(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    finally:
        Path(tmp).unlink(missing_ok=True)


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def save_npz(path: str | Path, arrays: dict) -> Path:
    """Write ``arrays`` as a compressed NumPy ``.npz`` archive to ``path`` atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez_compressed(f, **arrays)
    return Path(path)


def save_json(data: dict, path: str | Path) -> Path:
    """Write ``data`` as indented, key-sorted JSON to ``path`` atomically."""
    return write_text(path, json.dumps(data, indent=2, sort_keys=True) + "\n")
