"""The claims of the bootstrap model's neighbours, checked on a run (pure functions).

README, *The models side by side*. Each model's claim is checked against its twin: the condition
with the same objects and the same options the two models share.

- **teacher at least bootstrap** (the supervised bound): the upper end of the paired 95%
  interval of (teacher - bootstrap) final success is at least zero (the data do not show the
  teacher worse).
- **developmental faster than teacher** (Nagai, Asada, Hosoda 2006: the adaptive evaluation
  speeds learning): the mean success over the whole learning time (the area under the success
  curve) beats the teacher twin's, paired lower 95% bound above zero.
- **horizontal before vertical** (the same paper): each seed's learning module halves its
  horizontal error (``lm_pan_error_deg``, from its first bin) in an earlier bin than its
  vertical error (a seed that never halves one counts the run's end); the paired 95% interval
  of (horizontal - vertical) halving time lies below zero. Checked for the developmental model
  and the teacher, in runs whose cells hold the two errors.
- **gaze following emerges from the basic set** (Triesch, Teuscher, Deák, Carlson 2006; 2 or
  more objects): the reinforcement learner's final success beats chance (1 / objects) and its
  first bin, both with the lower 95% bound above zero.
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from ..agent.bootstrap import BootstrapOptions
from ..agent.developmental import DevelopmentalOptions
from ..agent.models import MODELS
from ..agent.teacher import TeacherOptions
from ..config import Config, model_options
from .claims import Claim, _finals, _paired, _paired_lower, reading_of
from .metrics import mean_interval

__all__ = ["AxisErrors", "halving_bins", "neighbour_claims"]

AxisErrors = dict[str, tuple[np.ndarray, np.ndarray]]
"""{condition: (horizontal, vertical) median errors, each (seeds, bins)}."""


def _twins(config: Config, options: dict, kind: type, of, n_objects: int) -> list:
    """The unshuffled conditions of model ``kind`` whose shared options equal ``of``'s."""
    twin = kind(**{f.name: getattr(of, f.name) for f in fields(kind)})
    return [c for c in config.experiment.conditions
            if c.n_objects == n_objects and not c.shuffle_faces
            and type(options[c.name]) is kind and options[c.name] == twin]


def halving_bins(errors: np.ndarray) -> np.ndarray:
    """Per seed, the first bin whose error is at most half the first bin's (bins if none)."""
    errors = np.atleast_2d(errors)
    halved = errors <= errors[:, :1] / 2
    return np.where(halved.any(axis=1), halved.argmax(axis=1), errors.shape[1])


def neighbour_claims(config: Config, curves: dict,
                     axis_errors: AxisErrors | None = None) -> list[Claim]:
    """Every neighbour's claim the run's conditions allow (see the module docstring)."""
    options = {c.name: model_options(config, c) for c in config.experiment.conditions}
    claims = []
    for c in config.experiment.conditions:
        o, kind = options[c.name], type(options[c.name])
        if c.shuffle_faces:
            continue
        reading, n = reading_of(c, config), c.n_objects
        if kind is TeacherOptions:
            for b in _twins(config, options, BootstrapOptions, o, n):
                ft, fb = _finals(curves[c.name][1]), _finals(curves[b.name][1])
                _, _, upper = mean_interval((ft - fb)[:, None])
                claims.append(Claim(
                    reading, f"{n} objects: teacher at least bootstrap", bool(upper[0] >= 0),
                    f"final {ft.mean():.3f} against {fb.mean():.3f}; paired difference "
                    f"{(ft - fb).mean():+.3f}, 95% upper bound {upper[0]:+.3f}"))
        if kind is DevelopmentalOptions:
            for t in _twins(config, options, TeacherOptions, o, n):
                md, mt = curves[c.name][1].mean(axis=1), curves[t.name][1].mean(axis=1)
                holds, evidence = _paired(md, mt)
                claims.append(Claim(reading, f"{n} objects: developmental faster than teacher",
                                    holds, "mean success over the learning time "
                                    + evidence.removeprefix("final ")))
        if kind in (DevelopmentalOptions, TeacherOptions) and c.name in (axis_errors or {}):
            claims.append(_horizontal_first(c, reading, *axis_errors[c.name],
                                            config.experiment.bin_steps))
        if MODELS.name_of(o) == "rl" and n > 1:
            final, first = _finals(curves[c.name][1]), curves[c.name][1][:, 0]
            chance = 1 / n
            above, rises = _paired_lower(final, np.full_like(final, chance)), _paired_lower(
                final, first)
            claims.append(Claim(
                reading, f"{n} objects: gaze following emerges from the basic set",
                above > 0 and rises > 0,
                f"final {final.mean():.3f}, chance {chance:.3f}, first bin {first.mean():.3f}; "
                f"95% lower bounds above chance {above:+.3f}, above the first bin {rises:+.3f}"))
    return claims


def _horizontal_first(c, reading: str, pan: np.ndarray, tilt: np.ndarray,
                      bin_steps: int) -> Claim:
    """The claim "horizontal before vertical" for one condition's per-seed errors."""
    hp, ht = halving_bins(pan), halving_bins(tilt)
    _, _, upper = mean_interval((hp - ht)[:, None].astype(float))
    return Claim(
        reading, f"{c.n_objects} objects: horizontal before vertical", bool(upper[0] < 0),
        f"error halved at {(hp.mean() + 1) * bin_steps:,.0f} (horizontal) and "
        f"{(ht.mean() + 1) * bin_steps:,.0f} steps (vertical), means over seeds; horizontal "
        f"first in {(hp < ht).sum()}, second in {(hp > ht).sum()}, same bin in "
        f"{(hp == ht).sum()} seeds; paired 95% upper bound {upper[0] * bin_steps:+,.0f} steps")
