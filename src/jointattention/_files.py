"""Writing files whole or not at all: every file the package writes goes through here.

Commands check their output places with :func:`check_writable` before any work, so that a
place that cannot be written is one error line, not a traceback after the computing, and hold
them with :func:`output_lock` (run folders: :func:`folder_lock`) while they write.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
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

__all__ = ["LOCK_NAME", "atomic_path", "check_writable", "folder_lock", "output_lock",
           "remove_stale_tmp", "save_json", "save_npz", "write_text"]

LOCK_NAME = ".jointattention.lock"  # the empty file a run folder is locked by


def _kind_of(mode: int) -> str:
    """What a file that is neither a regular file nor a folder is, in words."""
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a regular file"


def _probe(place: Path) -> None:
    """Create and remove a file in the folder ``place``; OSError if it cannot be written.

    The only sure test: ``os.access`` says yes to root everywhere, and to /proc's folders.
    """
    fd, tmp = tempfile.mkstemp(dir=place, prefix=".jointattention-probe-", suffix=".tmp")
    os.close(fd)
    os.unlink(tmp)


def check_writable(path: str | Path, kind: str = "folder", what: str = "--out") -> Path:
    """Refuse ``path`` unless a ``kind`` ("folder" or "file") can be made or written there.

    A file must be new or a regular file: a device, FIFO or socket is never replaced (files
    are written by rename). A symbolic link is followed: its target is what is written. The
    place is tried by creating (and removing) a file in it; nothing else is created.
    """
    text = os.fspath(path)
    if not text.strip():  # before Path(): Path("") is "."
        raise FileError(f"{what}: an empty path; expected a {kind}")
    path = Path(text)
    if len(path.name.encode()) > 255 or "\0" in text:
        raise FileError(f"{what} {text[:60]}...: not a possible file name; expected a "
                        f"{kind} name of at most 255 bytes without NUL")
    target = Path(os.path.realpath(path)) if os.path.islink(path) else path
    try:
        mode = os.stat(target).st_mode if os.path.lexists(target) else None
    except OSError as err:
        raise FileError(f"{what} {path}: cannot be reached ({(err.strerror or str(err)).lower()}"
                        f"); expected a {kind}") from None
    if mode is not None:
        if kind == "folder" and not stat.S_ISDIR(mode):
            got = "a file" if stat.S_ISREG(mode) else _kind_of(mode)
            raise FileError(f"{what} {path}: {got}; expected a folder")
        if kind == "file" and stat.S_ISDIR(mode):
            raise FileError(f"{what} {path}: a folder; expected a file name")
        if kind == "file" and not stat.S_ISREG(mode):
            raise FileError(f"{what} {path}: {_kind_of(mode)}; expected a regular file or a "
                            "new file name (it would be replaced)")
        place = target if kind == "folder" else target.parent
    else:
        place = target.parent
        while not os.path.lexists(place):
            place = place.parent
        if not os.path.isdir(place):
            raise FileError(f"{what} {path}: {place} is a file; expected a folder on the way")
    try:
        _probe(place)
    except OSError as err:
        reason = (err.strerror or str(err)).lower()
        raise FileError(f"{what} {path}: {place} cannot be written ({reason}); "
                        f"expected a writable place for a {kind}") from None
    return path


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; move it into place only if the block succeeds.

    The file gets the permissions a new file would get (``0o666`` less the umask): mkstemp
    makes private files, and results and data sets are not private.
    """
    path = Path(path)
    if path.is_symlink():  # the link stays; its target is what is written
        path = Path(os.path.realpath(path))
    try:
        mode = os.stat(path).st_mode
    except OSError:
        mode = stat.S_IFREG  # new: nothing to replace
    if not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)):  # /dev/full would become a file
        raise FileError(f"{path}: {_kind_of(mode)}; expected a regular file or a new file "
                        "name (it would be replaced)")
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


def _lock_file(path: Path) -> Path:
    """Where the lock of the output ``path`` lives: a per-user folder of the temporary folder.

    Outside the output, so that a refused or failed command leaves nothing beside it; named
    by the output's resolved path, so that two spellings of one place share a lock.
    """
    folder = Path(tempfile.gettempdir()) / f"jointattention-locks-{os.getuid()}"
    folder.mkdir(mode=0o700, exist_ok=True)
    key = hashlib.sha256(os.fsencode(os.path.realpath(path))).hexdigest()[:32]
    return folder / f"{key}.lock"


@contextmanager
def output_lock(path: str | Path, what: str = "--out") -> Iterator[Path]:
    """Hold the output ``path`` (a file or a folder) for one command; another is refused.

    An advisory ``flock``, as :func:`folder_lock`'s, on a file named by the path (see
    :func:`_lock_file`), removed when released. Nothing is created at ``path`` itself.
    """
    path = Path(path)
    if fcntl is None:
        yield path
        return
    lock = _lock_file(path)
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise FileError(f"{what} {path}: another command is writing it now; expected one "
                            f"command per output (wait for it, or choose another {what})"
                            ) from None
        try:  # the holder before may have removed the file after we opened it: open anew
            if os.stat(lock).st_ino == os.fstat(fd).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(fd)
    try:
        yield path
    finally:
        Path(lock).unlink(missing_ok=True)  # while held: no one else holds this file
        os.close(fd)


def remove_stale_tmp(folder: str | Path) -> None:
    """Remove the temporary files that a killed writer left in ``folder`` (:func:`atomic_path`).

    Only under :func:`folder_lock`: no other writer can be using them.
    """
    for stale in Path(folder).glob(".*.tmp"):
        stale.unlink(missing_ok=True)
