"""Caregiver data sets: the paper's recorded (face window, head angle, motor command) triples.

On-disk format, schema version 1: one NumPy ``.npz`` archive (no pickles) with

=================  ========  ===========  ==================================================
key                dtype     shape        meaning
=================  ========  ===========  ==================================================
``schema_version`` int       ()           ``1``
``face``           uint8     (N, H, W)    grayscale face window while the robot looks at the
                                          caregiver (paper: H = 25, W = 30)
``theta_face_rad`` float     (N, 2)       head angle (pan, tilt) at that moment; pan > 0
                                          turns right, tilt > 0 looks up
``command_rad``    float     (N, 2)       motor command from ``theta_face_rad`` to the head
                                          angle that centres the caregiver's target
``target_m``       float     (N, 3)       optional: the target's position in the robot's
                                          frame (x right, y forward, z up, metres, origin at
                                          the pan/tilt axes); omit it if it was not measured
``meta``           str       ()           optional: JSON text, free provenance (camera, seed)
=================  ========  ===========  ==================================================

A robot records one row per caregiver pose: look at the caregiver, save the face window and
the head angle, then turn to the object the caregiver attends to and save the difference of
head angles. Angles must lie in [-pi, pi].
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ._files import save_npz
from ._readers import read_npz
from .errors import DatasetError, FileError

__all__ = ["SCHEMA_VERSION", "CaregiverDatasets", "default_datasets", "load", "save"]

SCHEMA_VERSION = 1
_REQUIRED = ("schema_version", "face", "theta_face_rad", "command_rad")
_OPTIONAL = ("target_m", "meta")


@dataclass(frozen=True)
class CaregiverDatasets:
    """N recorded data sets (see the module docstring for the fields)."""

    face: np.ndarray
    theta_face_rad: np.ndarray
    command_rad: np.ndarray
    target_m: np.ndarray | None = None
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        _validate(self, "data sets")

    def __len__(self) -> int:
        return len(self.face)

    @property
    def window_size_px(self) -> tuple[int, int]:
        """(width, height) of the face windows."""
        return self.face.shape[2], self.face.shape[1]


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


def save(datasets: CaregiverDatasets, path: str | Path) -> Path:
    """Write ``datasets`` to ``path`` (an ``.npz``) atomically: all of it or nothing."""
    path = Path(path)
    if path.suffix != ".npz":
        raise DatasetError(f"{path}: expected a file name ending in .npz")
    arrays = {
        "schema_version": np.array(SCHEMA_VERSION),
        "face": datasets.face,
        "theta_face_rad": datasets.theta_face_rad,
        "command_rad": datasets.command_rad,
        "meta": np.array(json.dumps(datasets.meta, sort_keys=True)),
    }
    if datasets.target_m is not None:
        arrays["target_m"] = datasets.target_m
    return save_npz(path, arrays)


def load(path: str | Path) -> CaregiverDatasets:
    """Read and validate data sets; any problem is one :class:`DatasetError` naming the field."""
    path = Path(path)
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
                f"{', '.join(_REQUIRED)} (and optionally target_m, meta)"
            )
    unknown = sorted(keys - set(_REQUIRED) - set(_OPTIONAL))
    if unknown:
        raise DatasetError(
            f"{where}: field '{unknown[0]}' is not part of schema version {SCHEMA_VERSION}"
        )
    version = archive["schema_version"]
    if version.shape != () or version.dtype.kind not in "iu":
        _fail(where, "schema_version", "an integer", _describe(version))
    if int(version) != SCHEMA_VERSION:
        _fail(where, "schema_version", f"{SCHEMA_VERSION}", f"{int(version)}")
    meta = {}
    if "meta" in keys:
        try:
            meta = json.loads(str(archive["meta"]))
        except ValueError:
            meta = None
        if not isinstance(meta, dict) or archive["meta"].shape != ():
            _fail(where, "meta", "JSON text of an object", repr(str(archive["meta"]))[:60])
    fields = dict(face=archive["face"], theta_face_rad=archive["theta_face_rad"],
                  command_rad=archive["command_rad"], target_m=archive.get("target_m"),
                  meta=meta)
    _validate(SimpleNamespace(**fields), where)  # errors name the file, not "data sets"
    return CaregiverDatasets(**fields)


def default_datasets() -> CaregiverDatasets:
    """The 125 data sets shipped with the package (made by ``jointattention datasets make``)."""
    with resources.as_file(resources.files("jointattention.data") / "caregiver_125.npz") as p:
        return load(p)
