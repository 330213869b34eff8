"""The claims of the bootstrap model's neighbours, checked on a run (pure functions).

docs/neighbours.md. Each model's claim is checked against its twin: the condition
with the same objects and the same options the two models share. A claim names its condition
(and its twin's), since conditions of one reading may differ by their gate.

- **teacher at least bootstrap** (the supervised bound): the upper end of the paired 95%
  interval of (teacher - bootstrap) final success is at least zero (the data do not show the
  teacher worse).
- **developmental faster than teacher** (Nagai, Asada, Hosoda 2006: the adaptive evaluation
  speeds learning): the mean success over the whole learning time (the area under the success
  curve) beats the teacher twin's, paired lower 95% bound above zero.
- **visual development improves accuracy** (the same paper): the developmental model's final
  success beats its twin without the blur (``blur_start_px = 0``), paired lower 95% bound
  above zero.
- **horizontal before vertical** (the same paper), beyond what the geometry gives: a module
  that errs by the same small angle in every direction lands off the target mostly across the
  command, and the commands are mostly horizontal, so its horizontal error is only ``r`` times
  its vertical one, ``r`` = median |tilt command| / median |pan command| over the run's data
  sets (0.61 for the shipped ones). The claim holds when the learning module's horizontal
  error (``lm_pan_error_deg``) is below ``r`` times its vertical error (``lm_tilt_error_deg``)
  over the learning time: the paired 95% interval of (horizontal - r x vertical), averaged
  over the bins, lies below zero. Checked for the developmental model and the teacher, in
  runs whose cells hold the two errors.
- **gaze following emerges from the basic set** (Triesch, Teuscher, Deák, Carlson 2006; 2 or
  more objects): the reinforcement learner's final success beats chance (1 / objects) and its
  first bin, both with the lower 95% bound above zero.
"""

from __future__ import annotations

from dataclasses import fields, replace

import numpy as np

from ..config import Config, model_options
from ..experiment.cells import datasets_of
from ..models.bootstrap import BootstrapOptions
from ..models.developmental import DevelopmentalOptions
from ..models.registry import MODELS
from ..models.teacher import TeacherOptions
from .claim_record import PAIRED_RULE, Claim, finals_of, paired, paired_lower, reading_of
from .metrics import mean_interval

__all__ = ["AxisErrors", "geometry_ratio", "neighbour_claims"]

AxisErrors = dict[str, tuple[np.ndarray, np.ndarray]]
"""{condition: (horizontal, vertical) median errors, each (seeds, bins)}."""


def _twins(config: Config, options: dict, kind: type, of, n_objects: int) -> list:
    """The unshuffled conditions of model ``kind`` whose shared options equal ``of``'s."""
    twin = kind(**{f.name: getattr(of, f.name) for f in fields(kind)})
    return [c for c in config.experiment.conditions
            if c.n_objects == n_objects and not c.shuffle_faces
            and type(options[c.name]) is kind and options[c.name] == twin]


def geometry_ratio(config: Config) -> float:
    """Horizontal over vertical error of a module erring alike in every direction (small errors).

    An error of angle a turns the command c by a: the landing point is off by about a |c| across
    c, that is a |c_tilt| horizontally and a |c_pan| vertically.
    """
    command = np.abs(datasets_of(config).command_rad)
    return float(np.median(command[:, 1]) / np.median(command[:, 0]))


def neighbour_claims(config: Config, curves: dict,
                     axis_errors: AxisErrors | None = None) -> list[Claim]:
    """Every neighbour's claim the run's conditions allow (see the module docstring)."""
    options = {c.name: model_options(config, c) for c in config.experiment.conditions}
    axis_errors = axis_errors or {}
    ratio = geometry_ratio(config) if axis_errors else np.nan  # reads the data sets: once
    claims = []
    for c in config.experiment.conditions:
        o, kind = options[c.name], type(options[c.name])
        if c.shuffle_faces:
            continue
        reading, n = reading_of(c, config), c.n_objects
        if kind is TeacherOptions:
            for b in _twins(config, options, BootstrapOptions, o, n):
                ft, fb = finals_of(curves[c.name][1]), finals_of(curves[b.name][1])
                _, _, upper = mean_interval((ft - fb)[:, None])
                claims.append(Claim(
                    reading, f"{c.name}: teacher at least bootstrap ({b.name})",
                    bool(upper[0] >= 0),
                    f"final {ft.mean():.3f} against {fb.mean():.3f}; paired difference "
                    f"{(ft - fb).mean():+.3f}, 95% upper bound {upper[0]:+.3f}",
                    "final difference: paired 95% upper bound >= 0"))
        if kind is DevelopmentalOptions:
            for t in _twins(config, options, TeacherOptions, o, n):
                md, mt = curves[c.name][1].mean(axis=1), curves[t.name][1].mean(axis=1)
                holds, evidence = paired(md, mt)
                claims.append(Claim(reading, f"{c.name}: developmental faster than teacher "
                                    f"({t.name})", holds, "mean success over the learning "
                                    "time " + evidence.removeprefix("final "),
                                    "mean success difference: paired 95% lower bound > 0"))
            if o.blur_start_px > 0:
                sharp = replace(o, blur_start_px=0.0)
                for s in (s for s in config.experiment.conditions if not s.shuffle_faces
                          and s.n_objects == n and options[s.name] == sharp):
                    claims.append(Claim(
                        reading, f"{c.name}: visual development improves accuracy ({s.name})",
                        *paired(finals_of(curves[c.name][1]), finals_of(curves[s.name][1])),
                        PAIRED_RULE))
        if kind in (DevelopmentalOptions, TeacherOptions) and c.name in axis_errors:
            claims.append(_horizontal_first(c, reading, *axis_errors[c.name], ratio))
        if MODELS.name_of(o) == "rl" and n > 1:
            final, first = finals_of(curves[c.name][1]), curves[c.name][1][:, 0]
            chance = 1 / n
            above, rises = paired_lower(final, np.full_like(final, chance)), paired_lower(
                final, first)
            claims.append(Claim(
                reading, f"{c.name}: gaze following emerges from the basic set",
                above > 0 and rises > 0,
                f"final {final.mean():.3f}, chance {chance:.3f}, first bin {first.mean():.3f}; "
                f"95% lower bounds above chance {above:+.3f}, above the first bin {rises:+.3f}",
                "final - chance and final - first bin: paired 95% lower bounds > 0"))
    return [replace(c, source="neighbours") for c in claims]


def _horizontal_first(c, reading: str, pan: np.ndarray, tilt: np.ndarray,
                      ratio: float) -> Claim:
    """The claim "horizontal before vertical" for one condition's per-seed errors by bin."""
    h, v = pan.mean(axis=1), tilt.mean(axis=1)
    d = h - ratio * v
    _, _, upper = mean_interval(d[:, None])
    return Claim(
        reading, f"{c.name}: horizontal before vertical", bool(upper[0] < 0),
        f"error over the learning time {h.mean():.2f}° horizontal, {v.mean():.2f}° vertical "
        f"(geometry alone: horizontal = {ratio:.2f} x vertical); horizontal - {ratio:.2f} x "
        f"vertical {d.mean():+.2f}°, below 0 in {(d < 0).sum()} of {len(d)} seeds, 95% upper "
        f"bound {upper[0]:+.2f}°",
        "horizontal - geometry ratio x vertical error: 95% upper bound < 0")
