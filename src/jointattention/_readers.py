"""Reading files guardedly: every file the package reads goes through here.

Each reader names the file and what was expected in one :class:`~.errors.FileError` line,
whatever is wrong with it: missing, a folder, unreadable, too large, not UTF-8, not TOML or
JSON, a truncated or corrupt archive, a header claiming more data than the file holds.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import stat
import sys
import tomllib
import warnings
import zipfile
from contextlib import contextmanager
from importlib import resources
from pathlib import Path

import numpy as np

from ._checks import short_repr
from .errors import FileError

__all__ = ["MAX_IMAGE_PIXELS", "MAX_NESTING", "MAX_NPZ_BYTES", "MAX_NPZ_MEMBERS", "MAX_TEXT_BYTES",
           "check_nesting", "loads_json", "loads_toml", "quiet_stderr", "read_bytes", "read_image",
           "read_json", "read_npz", "read_text", "read_toml", "sha256_of", "shipped_path"]

MAX_TEXT_BYTES = 16 * 2**20  # configurations, specs and run files are kilobytes
MAX_IMAGE_PIXELS = 100_000_000  # a 100-megapixel photograph; larger headers are refused
MAX_NESTING = 32  # tables, arrays and objects within each other; the package uses 4
MAX_NPZ_BYTES = 2**30  # an archive's arrays, in total, as its directory declares them
MAX_NPZ_MEMBERS = 1024  # the package writes at most a few dozen arrays per archive


def _open_error(path: Path, err: OSError, what: str) -> FileError:
    reason = "is a folder" if os.path.isdir(path) else (err.strerror or str(err)).lower()
    return FileError(f"{path}: cannot read it ({reason}); expected {what}")


def _regular_size(path: Path, what: str) -> int:
    """The size of ``path`` if it is a regular file (not a folder, FIFO or device)."""
    st = path.stat()
    if stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(21, "is a folder")
    if not stat.S_ISREG(st.st_mode):  # /dev/zero or a FIFO would be read without end
        raise FileError(f"{path}: not a regular file (a device, FIFO or socket); expected {what}")
    return st.st_size


def read_bytes(path: str | Path, what: str, max_bytes: int) -> bytes:
    """The bytes of ``path`` (a regular file of at most ``max_bytes``); ``what`` it should be."""
    path = Path(path)
    try:
        size = _regular_size(path, what)
        if size > max_bytes:
            raise FileError(f"{path}: {size:,} bytes; expected {what} of at most "
                            f"{max_bytes:,} bytes")
        with open(path, "rb") as f:
            return f.read(max_bytes + 1)
    except OSError as err:
        raise _open_error(path, err, what) from None


def read_text(path: str | Path, what: str, max_bytes: int = MAX_TEXT_BYTES) -> str:
    """The UTF-8 text of ``path``."""
    data = read_bytes(path, what, max_bytes)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise FileError(f"{path}: not UTF-8 text (byte {err.start}); expected {what}") from None


def check_nesting(data, limit: int = MAX_NESTING) -> None:
    """Raise ValueError if ``data`` holds dicts and lists more than ``limit`` levels deep.

    Iterative, so that any depth is measured without recursion.
    """
    stack = [(data, 1)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, dict):
            item = list(item.values())
        elif not isinstance(item, (list, tuple)):
            continue
        if depth > limit:
            raise ValueError(f"nested more than {limit} levels deep (MAX_NESTING)")
        stack.extend((v, depth + 1) for v in item)


def _loads(parse, text: str):
    """``parse(text)``, at most :data:`MAX_NESTING` deep; else ValueError."""
    try:
        data = parse(text)
    except RecursionError:
        raise ValueError(f"nested more than {MAX_NESTING} levels deep (MAX_NESTING)") from None
    check_nesting(data)
    return data


def loads_toml(text: str):
    """TOML text as a mapping, at most :data:`MAX_NESTING` deep; else ValueError."""
    return _loads(tomllib.loads, text)


def loads_json(text: str):
    """JSON text as Python values, at most :data:`MAX_NESTING` deep; else ValueError."""
    return _loads(json.loads, text)


def read_toml(path: str | Path, what: str) -> dict:
    """The TOML mapping in ``path``."""
    text = read_text(path, what)
    try:
        return loads_toml(text)
    except ValueError as err:  # TOMLDecodeError, or too deep
        raise FileError(f"{path}: not valid TOML ({err}); expected {what}") from None


def read_json(path: str | Path, what: str) -> dict:
    """The JSON object in ``path``."""
    text = read_text(path, what)
    try:
        data = loads_json(text)
    except ValueError as err:  # JSONDecodeError; numbers too long to convert; too deep
        raise FileError(f"{path}: not valid JSON ({err}); expected {what}") from None
    if not isinstance(data, dict):
        raise FileError(f"{path}: JSON {type(data).__name__}, not an object; expected {what}")
    return data


def _read_member(z: zipfile.ZipFile, info: zipfile.ZipInfo, max_bytes: int) -> np.ndarray:
    fmt = np.lib.format
    with z.open(info) as f:
        version = fmt.read_magic(f)
        header = {(1, 0): fmt.read_array_header_1_0, (2, 0): fmt.read_array_header_2_0}
        if version not in header:
            raise ValueError(f".npy format version {version}; expected 1.0 or 2.0")
        shape, fortran, dtype = header[version](f)
        if dtype.hasobject:
            raise ValueError("holds Python objects (a pickle), which are never loaded")
        n_bytes = int(np.prod(shape, dtype=object)) * dtype.itemsize
        if n_bytes > min(info.file_size, max_bytes):
            raise ValueError(f"its header claims {n_bytes:,} bytes of data, the file holds "
                             f"{info.file_size:,}")
        data = f.read(n_bytes)
    if len(data) != n_bytes:
        raise ValueError(f"{len(data):,} bytes of data, its header claims {n_bytes:,}")
    order = "F" if fortran else "C"
    return np.frombuffer(data, dtype=dtype).reshape(shape, order=order).copy(order="K")


def _check_directory(z: zipfile.ZipFile, max_bytes: int) -> None:
    """Refuse an archive by its directory alone, before any member is read."""
    infos = z.infolist()
    if len(infos) > MAX_NPZ_MEMBERS:
        raise ValueError(f"{len(infos):,} members; expected at most {MAX_NPZ_MEMBERS:,}")
    names = [i.filename for i in infos]
    for name in names:
        if not name.endswith(".npy"):
            raise ValueError(f"member {short_repr(name)} is not a NumPy array (.npy)")
    if len(set(names)) != len(names):
        raise ValueError("a member name occurs twice")
    total = sum(i.file_size for i in infos)
    if total > max_bytes:
        raise ValueError(f"its members unpack to {total:,} bytes; expected at most "
                         f"{max_bytes:,} (MAX_NPZ_BYTES)")


def read_npz(path: str | Path, what: str, max_bytes: int = MAX_NPZ_BYTES) -> dict[str, np.ndarray]:
    """The arrays of the NumPy ``.npz`` archive ``path``, each fully read and checked.

    The archive's directory is checked first (a regular file; at most :data:`MAX_NPZ_MEMBERS`
    members, all ``.npy``, named once, unpacking to at most ``max_bytes`` in total); a member
    whose header claims more bytes than it holds is refused before anything is allocated;
    object arrays (pickles) are never loaded.
    """
    path = Path(path)
    arrays, member = {}, ""
    try:
        _regular_size(path, what)
        with zipfile.ZipFile(path) as z:
            try:
                _check_directory(z, max_bytes)
            except ValueError as err:
                raise FileError(f"{path}: {err}; expected {what}") from None
            for info in z.infolist():
                member = info.filename
                arrays[member.removesuffix(".npy")] = _read_member(z, info, max_bytes)
    except FileError:
        raise
    except zipfile.BadZipFile as err:
        raise FileError(f"{path}: not a readable .npz archive ({err}); expected {what}") from None
    except OSError as err:
        raise _open_error(path, err, what) from None
    except (ValueError, EOFError, zipfile.LargeZipFile, NotImplementedError) as err:
        raise FileError(f"{path}: member {member!r} cannot be read ({err}); "
                        f"expected {what}") from None
    return arrays


@contextmanager
def quiet_stderr():
    """Silence the process's stderr (file descriptor 2, where C libraries write) for a block.

    libtiff, libjpeg and FFmpeg print their own lines about a broken file; the program's one
    error line says it instead.
    """
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def read_image(path: str | Path) -> np.ndarray:
    """An image file as RGB uint8 (H, W, 3); its size is read from the header first."""
    import cv2
    from PIL import Image

    path = Path(path)
    what = "a PNG, JPEG, BMP or TIFF image"
    data = read_bytes(path, what, 2**30)
    try:  # Pillow reads the header, and checks the file whole (CRCs, length) without decoding
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # bombs are judged below; corrupt EXIF is noise
            with Image.open(io.BytesIO(data)) as im:
                w, h = im.size
                if w * h == 0:
                    raise ValueError(f"its header claims {w}x{h} pixels")
                if w * h <= MAX_IMAGE_PIXELS:
                    im.verify()
    except Image.DecompressionBombError:
        w, h = MAX_IMAGE_PIXELS, 2  # Pillow refused it as too large: so do we
    except Image.UnidentifiedImageError:
        if data.startswith((b"\x89PNG\r\n\x1a\n", b"\xff\xd8\xff")):  # PNG or JPEG, broken
            raise FileError(f"{path}: a corrupt image (its header is broken); expected {what}"
                            ) from None
        w, h = 0, 0  # a format Pillow does not know: OpenCV may still read it
    except Exception as err:  # Pillow raises many kinds for a corrupt file
        raise FileError(f"{path}: a corrupt image ({short_repr(str(err))}); expected {what}"
                        ) from None
    if w * h > MAX_IMAGE_PIXELS:
        raise FileError(f"{path}: its header claims {w}x{h} pixels; expected {what} of at "
                        f"most {MAX_IMAGE_PIXELS:,} pixels")
    try:
        with quiet_stderr():
            image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR) if data else None
    except cv2.error:
        image = None
    if image is None:
        raise FileError(f"{path}: not an image OpenCV can read; expected {what}")
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


def sha256_of(path: str | Path) -> str:
    """The SHA-256 of a file's content, in hex."""
    digest = hashlib.sha256()
    try:
        _regular_size(Path(path), "a readable file")
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(2**20), b""):
                digest.update(block)
    except OSError as err:
        raise _open_error(Path(path), err, "a readable file") from None
    return digest.hexdigest()



_CHECKED: dict[str, tuple] = {}  # shipped file -> (path, size, mtime) when its sum was right


def shipped_path(name: str) -> Path:
    """The package data file ``name``, its SHA-256 checked against the one recorded.

    Checked when first used in a process (and again if the file changed since), not at
    import. A missing or damaged file is one :class:`~.errors.FileError` naming it and saying
    to reinstall.
    """
    from . import data
    from ._version import __version__

    with resources.as_file(resources.files(data) / name) as p:
        path = Path(p)  # an installed package is a folder: the path stays valid
    try:
        st = path.stat()
        key = (str(path), st.st_size, st.st_mtime_ns)
        if _CHECKED.get(name) == key:
            return path
        digest = sha256_of(path)
    except (OSError, FileError):
        reason = "missing or unreadable"
    else:
        if digest == data.SHA256[name]:
            _CHECKED[name] = key
            return path
        reason = f"its SHA-256 {digest[:12]}... is not the {data.SHA256[name][:12]}... shipped"
    raise FileError(f"{path}: a damaged installation of jointattention ({reason}); expected "
                    f"the file jointattention {__version__} ships: reinstall the package (pip "
                    "install --force-reinstall jointattention)")
