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

try:
    import fcntl
except ImportError:  # not POSIX: runs are not locked
    fcntl = None

__all__ = ["LOCK_NAME", "atomic_path", "check_writable", "folder_lock", "remove_stale_tmp",
           "save_json", "save_npz", "write_text"]

LOCK_NAME = ".jointattention.lock"  # the empty file a run folder is locked by


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


@contextmanager
def folder_lock(out: str | Path) -> Iterator[Path]:
    """Hold the folder ``out`` for one run: any other run into it is refused while held.

    An advisory ``flock`` on ``out/.jointattention.lock``, which stays (empty); it holds
    across processes and across calls in one process, and ends with the process, however it
    ends. ``out`` is made if missing: call this after every check.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fd = os.open(out / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        if fcntl is not None:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                raise FileError(f"{out}: another run is writing into this folder now; expected "
                                "one run per folder (wait for it, or choose another --out)"
                                ) from None
        yield out
    finally:
        os.close(fd)  # releases the lock


def remove_stale_tmp(folder: str | Path) -> None:
    """Remove the temporary files that a killed writer left in ``folder`` (:func:`atomic_path`).

    Only under :func:`folder_lock`: no other writer can be using them.
    """
    for stale in Path(folder).glob(".*.tmp"):
        stale.unlink(missing_ok=True)
