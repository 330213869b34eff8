"""A head's recording (a real or simulated robot's folder) imported as caregiver data sets.

A recording is a folder a robot's script writes: camera images, and ``recording.csv`` with
one row per image, taken while the head looked at the caregiver:

=====================  ========================================================================
column                 meaning
=====================  ========================================================================
``image``              the image file, relative to the folder (PNG, JPEG, BMP or TIFF)
``pan_rad``            the head's pan when the image was taken (> 0 turns right)
``tilt_rad``           its tilt (> 0 looks up)
``command_pan_rad``    the pan change that then centred the object the caregiver looked at
``command_tilt_rad``   the tilt change
``target_x_m`` ...     optional, all three or none: ``target_x_m``, ``target_y_m``,
                       ``target_z_m``, the target in the robot's frame (x right, y forward,
                       z up, metres, origin at the pan/tilt axes)
``caregiver``          optional: who the caregiver is, an integer >= 0 (for recordings of
                       several people; the data sets' ``caregiver`` field)
=====================  ========================================================================

The caregiver's face is found in each image and its window cut by
:func:`~jointattention.agent.faces.window_of`, the function ``follow`` uses on live images.
Rows whose face is not found are reported (:class:`Missed`), never silently dropped.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import math
import numbers
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._arrays import floats
from ._checks import check_path, short_repr
from ._readers import read_image, read_text
from ._version import __version__
from .agent.faces import face_template, window_of
from .agent.finders import DEFAULT_FACE, check_finder, finder_for
from .config import FaceWindowConfig
from .datasets import CaregiverDatasets, default_datasets
from .errors import ArgumentError, DatasetError, FileError

__all__ = ["COLUMNS", "CSV_NAME", "MAX_ROWS", "Missed", "import_recording"]

CSV_NAME = "recording.csv"
COLUMNS = ("image", "pan_rad", "tilt_rad", "command_pan_rad", "command_tilt_rad")
_TARGET = ("target_x_m", "target_y_m", "target_z_m")
_OPTIONAL = (*_TARGET, "caregiver")
MAX_ROWS = 1_000_000
_WINDOW_FIELDS = {f.name: f for f in dataclasses.fields(FaceWindowConfig)}


@dataclass(frozen=True)
class Missed:
    """A row of the recording whose caregiver's face was not found."""

    row: int  # 1-based, the header not counted
    image: str


def _rows(folder: Path) -> tuple[list[dict], list[str]]:
    """The CSV's rows, every value checked; and which optional columns it has."""
    where = folder / CSV_NAME
    text = read_text(where, f"the recording's table ({', '.join(COLUMNS)})")
    reader = csv.DictReader(io.StringIO(text))
    try:
        return _read_rows(reader, where, folder)
    except csv.Error as err:  # e.g. a field longer than csv's limit
        raise DatasetError(f"{where}: not a readable CSV table ({err}); expected one row per "
                           "image") from None


def _read_rows(reader: csv.DictReader, where: Path, folder: Path) -> tuple[list[dict], list[str]]:
    header = reader.fieldnames or []
    if len(set(header)) != len(header):
        twice = next(c for c in header if header.count(c) > 1)
        raise DatasetError(f"{where}: column {twice!r} is named twice; expected each column "
                           "once")
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        raise DatasetError(f"{where}: column '{missing[0]}' is missing; expected the columns "
                           f"{', '.join(COLUMNS)} (and optionally {', '.join(_OPTIONAL)})")
    unknown = [c for c in header if c not in (*COLUMNS, *_OPTIONAL)]
    if unknown:
        raise DatasetError(f"{where}: column {unknown[0]!r} is unknown; expected "
                           f"{', '.join(COLUMNS)} (and optionally {', '.join(_OPTIONAL)})")
    targets = [c for c in _TARGET if c in header]
    if targets and len(targets) != 3:
        raise DatasetError(f"{where}: column '{targets[0]}' without the others; expected all "
                           f"of {', '.join(_TARGET)} or none")
    rows = []
    for i, row in enumerate(reader, start=1):
        if i > MAX_ROWS:
            raise DatasetError(f"{where}: more than {MAX_ROWS:,} rows; expected at most that")
        if None in row or None in row.values():
            raise DatasetError(f"{where}: row {i}: expected {len(header)} values, like the "
                               "header")
        rows.append(_checked(row, i, where, folder))
    if not rows:
        raise DatasetError(f"{where}: no rows; expected one row per image")
    return rows, [c for c in _OPTIONAL if c in header]


def _checked(row: dict, i: int, where: Path, folder: Path) -> dict:
    out = {"image": row["image"].strip()}
    image = Path(out["image"])
    if not out["image"] or image.is_absolute() or ".." in image.parts:
        raise DatasetError(f"{where}: row {i}: column 'image' {out['image']!r}: expected a "
                           "file name relative to the folder, inside it")
    for key in (*COLUMNS[1:], *_TARGET):
        if key not in row:
            continue
        try:
            value = float(row[key])
        except ValueError:
            value = math.nan
        if not math.isfinite(value) or (key.endswith("_rad") and abs(value) > math.pi):
            limits = " in [-pi, pi]" if key.endswith("_rad") else ""
            raise DatasetError(f"{where}: row {i}: column '{key}' {row[key]!r}: expected a "
                               f"finite number{limits}")
        out[key] = value
    if "caregiver" in row:
        text = row["caregiver"].strip()
        if not text.isdigit() or int(text) > 2**31 - 1:
            raise DatasetError(f"{where}: row {i}: column 'caregiver' {row['caregiver']!r}: "
                               "expected an integer >= 0")
        out["caregiver"] = int(text)
    if not (folder / image).is_file():
        raise DatasetError(f"{where}: row {i}: image {out['image']!r} is not a file in {folder}")
    return out


def _window_size(value) -> tuple[int, int]:
    """``face_size_px`` as (width, height) in world.face_window's range, else one ArgumentError."""
    lo, hi = (_WINDOW_FIELDS["width_px"].metadata[k] for k in ("lo", "hi"))
    pair = isinstance(value, (tuple, list)) and len(value) == 2
    if not pair or not all(not isinstance(v, bool) and isinstance(v, numbers.Integral)
                           and lo <= v <= hi for v in value):
        raise ArgumentError(f"face_size_px={short_repr(value)}: expected (width, height), two "
                            f"integers in [{lo}, {hi}] (world.face_window's range)")
    return int(value[0]), int(value[1])


def _template(value) -> np.ndarray:
    """A face template: grey levels (h, w) of at least 4 x 4, as uint8; else one ArgumentError."""
    a = floats("template", value, (None, None), what="grey levels from 0 to 255")
    if min(a.shape) < 4 or a.min() < 0 or a.max() > 255:
        raise ArgumentError(f"template: shape {a.shape}, values {a.min():g} to {a.max():g}; "
                            "expected at least 4 x 4 grey levels from 0 to 255")
    return np.rint(a).astype(np.uint8)


def import_recording(folder: str | Path, *, face: str = DEFAULT_FACE,
                     template: np.ndarray | None = None, face_size_px: tuple[int, int] = (30, 25),
                     min_score: float | None = None,
                     progress: Callable[[int], None] | None = None
                     ) -> tuple[CaregiverDatasets, list[Missed]]:
    """The data sets of a recorded folder, and the rows whose face was not found.

    ``face``: ``"blazeface"`` (the shipped neural detector), ``"template"`` (normalised
    correlation with ``template``, by default the mean face window of the shipped data sets:
    the simulated caregiver) or ``"haar"`` (OpenCV's cascade); ``min_score``: the least score
    of a face (default: the finder's own). ``face_size_px``: the windows' (width, height).
    Every row and image is checked before the data sets are built; nothing is written here.
    """
    check_path(folder, "folder")
    check_finder(face, min_score)
    face_size_px = _window_size(face_size_px)
    if template is not None:
        template = _template(template)
    folder = Path(folder)
    if not folder.is_dir():
        raise FileError(f"{folder}: not a folder; expected a recording folder with "
                        f"{CSV_NAME} and its images")
    rows, optional = _rows(folder)
    if face == "template" and template is None:
        template = face_template(default_datasets().face)
    finder = finder_for(face, template, min_score)
    kept, faces, missed = [], [], []
    for i, row in enumerate(rows, start=1):
        image = read_image(folder / row["image"])
        found = finder.find(image)
        if found:
            kept.append(row)
            faces.append(window_of(image, found[0], face_size_px))
        else:
            missed.append(Missed(i, row["image"]))
        if progress is not None:
            progress(i)
    if not kept:
        raise DatasetError(f"{folder}: no face found in any of the {len(rows)} images; expected "
                           f"the caregiver's face in them (face finder: {face})")

    def column(*keys):
        return np.array([[r[k] for k in keys] for r in kept], dtype=float)

    meta = {"generator": f"jointattention {__version__}", "imported_from": str(folder),
            "face_finder": face, "rows": len(rows), "rows_without_face": [m.row for m in missed]}
    caregiver = (np.array([r["caregiver"] for r in kept], dtype=np.int64)
                 if "caregiver" in optional else None)
    ds = CaregiverDatasets(np.stack(faces).astype(np.uint8), column("pan_rad", "tilt_rad"),
                           column("command_pan_rad", "command_tilt_rad"),
                           column(*_TARGET) if "target_x_m" in optional else None, meta,
                           caregiver)
    return ds, missed
