"""Caregiver data sets: the paper's recorded (face window, head angle, motor command) triples.

On-disk format: one NumPy ``.npz`` archive (no pickles) with

=================  ========  ===========  ==================================================
key                dtype     shape        meaning
=================  ========  ===========  ==================================================
``schema_version`` int       ()           ``2`` if the file has ``caregiver``, else ``1``
``face``           uint8     (N, H, W)    grayscale face window while the robot looks at the
                                          caregiver (paper: H = 25, W = 30)
``theta_face_rad`` float     (N, 2)       head angle (pan, tilt) at that moment; pan > 0
                                          turns right, tilt > 0 looks up
``command_rad``    float     (N, 2)       motor command from ``theta_face_rad`` to the head
                                          angle that centres the caregiver's target
``target_m``       float     (N, 3)       optional: the target's position in the robot's
                                          frame (x right, y forward, z up, metres, origin at
                                          the pan/tilt axes); omit it if it was not measured
``caregiver``      int       (N,)         schema version 2 only (and required there): which
                                          caregiver (identity index >= 0) posed each data
                                          set, for data sets of several people
``eyes``           uint8     (N, h, w)    optional: grayscale eye window, cut around both
                                          eyes from a finer sensor (``[world.eye_window]``)
``meta``           str       ()           optional: JSON text, free provenance (camera, seed)
=================  ========  ===========  ==================================================

Schema version 1 (no ``caregiver`` field: one caregiver, or nobody said who) is still read, and
:func:`save` writes version 1 for data sets without the field, so files of one caregiver are
byte for byte what they were before version 2.

A robot records one row per caregiver pose: look at the caregiver, save the face window and
the head angle, then turn to the object the caregiver attends to and save the difference of
head angles. Angles must lie in [-pi, pi].
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ._checks import check_path
from ._files import save_npz
from ._readers import loads_json, read_npz, shipped_path
from .errors import DatasetError, FileError

__all__ = ["MAX_TARGET_M", "SCHEMA_VERSION", "CaregiverDatasets", "default_datasets", "load",
           "save", "scenes_sha256", "shipped_file", "views_of", "window_mismatch"]

SCHEMA_VERSION = 2  # the newest; version 1 is version 2 without ``caregiver``
MAX_TARGET_M = 100.0  # a target farther than this from the robot is not a scene it can see
_REQUIRED = ("schema_version", "face", "theta_face_rad", "command_rad")
_OPTIONAL = ("target_m", "meta", "eyes")
_VERSION_FIELDS = {1: (), 2: ("caregiver",)}  # the fields each version adds, all required


@dataclass(frozen=True)
class CaregiverDatasets:
    """N recorded data sets (see the module docstring for the fields)."""

    face: np.ndarray
    theta_face_rad: np.ndarray
    command_rad: np.ndarray
    target_m: np.ndarray | None = None
    meta: dict = field(default_factory=dict)
    caregiver: np.ndarray | None = None
    eyes: np.ndarray | None = None

    def __post_init__(self) -> None:
        _validate(self, "data sets")

    def __len__(self) -> int:
        return len(self.face)

    def subset(self, keep) -> CaregiverDatasets:
        """The data sets at ``keep`` (indices, a slice or a mask), every field cut alike."""
        def cut(a):
            return None if a is None else a[keep]
        return CaregiverDatasets(self.face[keep], self.theta_face_rad[keep],
                                 self.command_rad[keep], cut(self.target_m), self.meta,
                                 cut(self.caregiver), cut(self.eyes))

    @property
    def window_size_px(self) -> tuple[int, int]:
        """(width, height) of the face windows."""
        return self.face.shape[2], self.face.shape[1]

    @property
    def eye_window_size_px(self) -> tuple[int, int] | None:
        """(width, height) of the eye windows, or None without them."""
        return None if self.eyes is None else (self.eyes.shape[2], self.eyes.shape[1])

    @property
    def views(self) -> np.ndarray:
        """What the robot kept of each look: the face windows, and the eye windows if kept.

        The face windows (N, H, W) as they are; with eye windows, each face window's grey
        levels then its eye window's, flat: (N, H * W + h * w).
        """
        return views_of(self.face, self.eyes)

    def view(self, k: int) -> np.ndarray:
        """Data set ``k``'s view (:attr:`views`)."""
        return views_of(self.face[k], None if self.eyes is None else self.eyes[k])

    @property
    def n_caregivers(self) -> int | None:
        """How many distinct caregivers the ``caregiver`` field names (None without it)."""
        return None if self.caregiver is None else len(np.unique(self.caregiver))


def window_mismatch(ds: CaregiverDatasets, face_px, eye_px) -> str | None:
    """How ``ds``'s windows differ from a model's (face ``face_px``, eyes ``eye_px`` or None).

    None if they are the same size; else what differs, as an error message says it.
    """
    def said(size):
        return "none" if size is None else f"{size[0]}x{size[1]} px"

    face_px, eye_px = tuple(face_px), None if eye_px is None else tuple(eye_px)
    if ds.window_size_px != face_px:
        return f"face windows of {said(ds.window_size_px)}; expected the model's {said(face_px)}"
    if ds.eye_window_size_px != eye_px:
        return (f"eye windows {said(ds.eye_window_size_px)}; expected the model's: "
                f"{said(eye_px)}")
    return None


def views_of(face: np.ndarray, eyes: np.ndarray | None) -> np.ndarray:
    """What the robot kept of each look (:attr:`CaregiverDatasets.views`).

    Face windows (..., H, W) as they are; with eye windows (..., h, w), each face's grey
    levels then its eyes', flat: (..., H * W + h * w).
    """
    if eyes is None:
        return face
    lead = face.shape[:-2]
    return np.concatenate([face.reshape(*lead, -1), eyes.reshape(*lead, -1)], axis=-1)


def _fail(where: str, key: str, expected: str, got: str) -> None:
    raise DatasetError(f"{where}: field '{key}': expected {expected}, got {got}")


def _describe(a: np.ndarray) -> str:
    return f"{a.dtype} array of shape {a.shape}"


def _validate(ds, where: str) -> None:
    face = np.asarray(ds.face)
    if face.dtype != np.uint8 or face.ndim != 3 or min(face.shape[1:], default=0) < 4:
        _fail(where, "face", "uint8 array of shape (N, H, W) with H, W >= 4", _describe(face))
    n = len(face)
    if n == 0:
        _fail(where, "face", "at least one data set", "none")
    for key, width in (("theta_face_rad", 2), ("command_rad", 2), ("target_m", 3)):
        a = getattr(ds, key)
        if a is None and key == "target_m":
            continue
        a = np.asarray(a)
        if a.dtype.kind != "f" or a.shape != (n, width):
            _fail(where, key, f"float array of shape ({n}, {width})", _describe(a))
        if not np.all(np.isfinite(a)):
            _fail(where, key, "finite values", f"{np.count_nonzero(~np.isfinite(a))} non-finite")
        if key.endswith("_rad") and np.max(np.abs(a)) > np.pi:
            _fail(
                where,
                key,
                "angles in radians within [-pi, pi]",
                f"a value of {np.max(np.abs(a)):.4g}",
            )
        if key == "target_m" and np.max(np.abs(a)) > MAX_TARGET_M:  # a room, not the sky
            _fail(where, key, f"positions in metres within ±{MAX_TARGET_M:g} of the robot",
                  f"a coordinate of {np.max(np.abs(a)):.4g}")
    eyes = getattr(ds, "eyes", None)
    if eyes is not None:
        a = np.asarray(eyes)
        if a.dtype != np.uint8 or a.ndim != 3 or len(a) != n or min(a.shape[1:]) < 4:
            _fail(where, "eyes", f"uint8 array of shape ({n}, h, w) with h, w >= 4",
                  _describe(a))
    caregiver = getattr(ds, "caregiver", None)
    if caregiver is not None:
        a = np.asarray(caregiver)
        if a.dtype.kind not in "iu" or a.shape != (n,):
            _fail(where, "caregiver", f"integer array of shape ({n},)", _describe(a))
        if np.any(a < 0):
            _fail(where, "caregiver", "identity indices >= 0", f"{int(a.min())}")


SCENE_DECIMALS = 6  # radians and metres kept to 1e-6 in scenes_sha256: far above float noise


def scenes_sha256(datasets: CaregiverDatasets) -> str:
    """SHA-256 of the scenes the data sets hold, not of their images: it holds across machines.

    The head angles, commands, targets and caregivers, each rounded to ``SCENE_DECIMALS``
    (radians, metres), and the windows' shape. A recording made again on another machine gives
    the same scenes, while its rendered windows and its file's bytes may differ in a few grey
    levels (another OpenGL), so a model is bound to the scenes it learned from by this.
    """
    h = hashlib.sha256(np.array(datasets.face.shape, "<i8").tobytes())
    if datasets.eyes is not None:
        h.update(b"eyes" + np.array(datasets.eyes.shape, "<i8").tobytes())
    for a in (datasets.theta_face_rad, datasets.command_rad, datasets.target_m):
        if a is not None:  # + 0.0: -0.0 rounds to the bytes of 0.0
            h.update((np.round(np.asarray(a, float), SCENE_DECIMALS) + 0.0).astype("<f8").tobytes())
    if datasets.caregiver is not None:
        h.update(np.asarray(datasets.caregiver).astype("<i8").tobytes())
    return h.hexdigest()


def save(datasets: CaregiverDatasets, path: str | Path) -> Path:
    """Write ``datasets`` to ``path`` (an ``.npz``) atomically: all of it or nothing.

    Schema version 2 if they name their caregivers, else version 1 (as before version 2).
    """
    path = Path(path)
    if path.suffix != ".npz":
        raise DatasetError(f"{path}: expected a file name ending in .npz")
    arrays = {
        "schema_version": np.array(1 if datasets.caregiver is None else 2),
        "face": datasets.face,
        "theta_face_rad": datasets.theta_face_rad,
        "command_rad": datasets.command_rad,
        "meta": np.array(json.dumps(datasets.meta, sort_keys=True)),
    }
    if datasets.target_m is not None:
        arrays["target_m"] = datasets.target_m
    if datasets.caregiver is not None:
        arrays["caregiver"] = datasets.caregiver
    if datasets.eyes is not None:
        arrays["eyes"] = datasets.eyes
    return save_npz(path, arrays)


def load(path: str | Path) -> CaregiverDatasets:
    """Read and validate data sets; any problem is one :class:`DatasetError` naming the field."""
    path = Path(check_path(path, "path"))
    where = str(path)
    try:
        archive = read_npz(path, "a data-set .npz file (jointattention datasets make)")
    except FileError as err:
        raise DatasetError(str(err)) from None
    keys = set(archive)
    for key in _REQUIRED:
        if key not in keys:
            raise DatasetError(
                f"{where}: field '{key}' is missing; expected the fields "
                f"{', '.join(_REQUIRED)} (and optionally target_m, meta, eyes)"
            )
    version = archive["schema_version"]
    if version.shape != () or version.dtype.kind not in "iu":
        _fail(where, "schema_version", "an integer", _describe(version))
    version = int(version)
    if version not in _VERSION_FIELDS:
        _fail(where, "schema_version", " or ".join(map(str, _VERSION_FIELDS)), f"{version}")
    added = _VERSION_FIELDS[version]
    for key in added:
        if key not in keys:
            raise DatasetError(f"{where}: field '{key}' is missing; schema version {version} "
                               f"files have it (version 1 files have no {key})")
    unknown = sorted(keys - set(_REQUIRED) - set(_OPTIONAL) - set(added))
    if unknown:
        newer = [v for v, extra in _VERSION_FIELDS.items() if unknown[0] in extra]
        hint = f" (it is a field of version {newer[0]})" if newer else ""
        raise DatasetError(
            f"{where}: field '{unknown[0]}' is not part of schema version {version}{hint}"
        )
    meta = {}
    if "meta" in keys:
        try:
            meta = loads_json(str(archive["meta"]))
        except ValueError:
            meta = None
        if not isinstance(meta, dict) or archive["meta"].shape != ():
            _fail(where, "meta", "JSON text of an object", repr(str(archive["meta"]))[:60])
    fields = dict(face=archive["face"], theta_face_rad=archive["theta_face_rad"],
                  command_rad=archive["command_rad"], target_m=archive.get("target_m"),
                  meta=meta, caregiver=archive.get("caregiver"), eyes=archive.get("eyes"))
    _validate(SimpleNamespace(**fields), where)  # errors name the file, not "data sets"
    return CaregiverDatasets(**fields)


def shipped_file() -> Path:
    """The file of the 125 data sets shipped with the package."""
    return shipped_path("caregiver_125.npz")  # its sum checked: a damaged one is one line


def default_datasets() -> CaregiverDatasets:
    """The 125 data sets shipped with the package (made by ``jointattention datasets make``)."""
    return load(shipped_file())
