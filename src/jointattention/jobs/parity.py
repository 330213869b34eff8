"""Do the two ways of seeing agree? Rendered images through OpenCV against the projection.

The OpenCV detector on rendered images against the fast projection, over many random scenes
and head angles (docs/images.md).

A case is one random scene seen from one head angle: aimed at a random object (or, one time in
four, at the caregiver's face) plus a random turn, as the head looks during trials. A case
agrees when both detectors pick the same object as most interesting (Eq. 1 with the
configured weights) and every object seen by both has its two centres within ``tol_px``.
An object seen by one detector only also agrees if its projected centre lies within
``tol_px`` of the image border, where the fast detector's rule (seen if the centre is in the
image) is sharp and the image detector's estimate of a cut object's centre is not.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..agent.attention import most_interesting
from ..agent.detections import equal_area_radius
from ..agent.vision import ImageDetector
from ..analysis.tables import Table
from ..config import Config
from ..world.options import N_OBJECTS
from ..world.rendered import object_ids
from ..world.simulator import World

__all__ = ["CAUSES", "ParityResult", "measure_parity", "parity_table"]

CAUSES = {
    "overlap": "two objects overlap in the image (one hides part of the other, or their "
               "regions merge)",
    "border": "an object cut by the image border: its centre is estimated from a short arc",
    "tie": "the two largest objects' areas are within 5%: pixel counts order them otherwise",
    "other": "none of the above",
}


@dataclass(frozen=True)
class ParityResult:
    """Per case, whether the detectors agree, and the errors of their centres.

    Per case: ``same_choice``, ``centres_agree``, ``max_error_px`` (over objects seen by both; 0 if
    none) and ``cause`` (of a disagreement, else ""); ``errors_px`` over every object seen by both
    in every case.
    """

    same_choice: np.ndarray
    centres_agree: np.ndarray
    max_error_px: np.ndarray
    errors_px: np.ndarray
    causes: tuple[str, ...]

    @property
    def agree(self) -> np.ndarray:
        """Per case: the same choice and the centres within the tolerance."""
        return self.same_choice & self.centres_agree

    def summary(self) -> dict:
        """The figures: rates, centre errors (percentiles, px) and counts of causes."""
        n = len(self.agree)
        e = self.errors_px
        return {
            "cases": n,
            "agree": float(self.agree.mean()),
            "same_choice": float(self.same_choice.mean()),
            "centres_within_tol": float(self.centres_agree.mean()),
            "objects_compared": len(e),
            "error_px_median": float(np.median(e)) if len(e) else 0.0,
            "error_px_p99": float(np.percentile(e, 99)) if len(e) else 0.0,
            "error_px_max": float(e.max()) if len(e) else 0.0,
            "causes": dict(Counter(c for c in self.causes if c)),
        }


def _overlaps(uv: np.ndarray, radius_px: np.ndarray, ids) -> bool:
    ids = [i for i in ids if i >= 0]
    for i in ids:
        d = np.hypot(*(uv - uv[i]).T) - radius_px - radius_px[i]
        d[i] = np.inf
        if np.nanmin(d) < 1:
            return True
    return False


def measure_parity(config: Config, n_cases: int, seed: int = 0, tol_px: float = 2.0,
                   progress: Callable[[int], None] | None = None, *,
                   n_objects: int = N_OBJECTS) -> ParityResult:
    """Compare the two detectors over ``n_cases`` random cases of ``n_objects`` objects."""
    rng = np.random.default_rng(seed)
    weights = config.agent.interest_weights
    same, agree, worst, errors, causes = [], [], [], [], []
    with World(config.world, seed=seed, n_objects=n_objects) as world:
        kin = world.kinematics
        detector = ImageDetector(config.detector, kin.focal_px)
        w, h = kin.width_px, kin.height_px
        for case in range(n_cases):
            s = world.reset(new_identity=case % 25 == 0)
            aim = s.head_pos_m if rng.random() < 0.25 else s.object_pos_m[
                rng.integers(s.n_objects)]
            theta = kin.clip(kin.centring_angles(aim) + rng.normal(0, 0.2, 2))
            world.set_head_angle(theta)
            fast = world.fast_scene()
            f = fast.observe(theta)
            detector.reset()
            d = detector.detect(world.render())
            uv, _, area = kin.project_spheres(s.object_pos_m, s.object_radius_m, theta)
            radius = equal_area_radius(area)
            img_ids = object_ids(d.centre_px, uv, radius)
            fast_ids = fast.visible_ids
            cf, ci = most_interesting(f, weights), most_interesting(d, weights)
            choice_ok = (None if cf is None else int(fast_ids[cf])) == (
                None if ci is None else int(img_ids[ci]))
            errs, lonely = [], []
            for obj in set(fast_ids) | {i for i in img_ids if i >= 0}:
                in_fast, hits = obj in fast_ids, np.flatnonzero(img_ids == obj)
                if in_fast and len(hits):
                    errs.append(np.min(np.hypot(*(d.centre_px[hits] - uv[obj]).T)))
                else:
                    lonely.append(obj)
            stray = int(np.sum(img_ids < 0))
            near_border = [min(uv[o][0] + 0.5, w - 0.5 - uv[o][0], uv[o][1] + 0.5,
                               h - 0.5 - uv[o][1]) for o in lonely]
            centres_ok = (all(e < tol_px for e in errs) and stray == 0
                          and all(abs(b) < tol_px for b in near_border))
            cause = ""
            if not (choice_ok and centres_ok):
                top = np.sort(f.colour_area_px)[-2:]
                if _overlaps(uv, radius, list(fast_ids) + list(img_ids)):
                    cause = "overlap"
                elif lonely or any(min(uv[o][0], w - uv[o][0], uv[o][1], h - uv[o][1])
                                   < radius[o] for o in fast_ids):
                    cause = "border"
                elif not choice_ok and len(top) == 2 and top[0] > 0.95 * top[1]:
                    cause = "tie"
                else:
                    cause = "other"
            same.append(choice_ok)
            agree.append(centres_ok)
            worst.append(max(errs, default=0.0))
            errors += errs
            causes.append(cause)
            if progress is not None:
                progress(case + 1)
    return ParityResult(np.array(same), np.array(agree), np.array(worst), np.array(errors),
                        tuple(causes))



def parity_table(results: dict[int, ParityResult]) -> Table:
    """One row per object count: the rates, centre errors and disagreements by cause."""
    rows = []
    for n, r in results.items():
        s = r.summary()
        causes = ", ".join(f"{k} {v}" for k, v in sorted(s["causes"].items())) or "none"
        rows.append((n, s["cases"], f"{s['agree']:.3f}", f"{s['same_choice']:.3f}",
                     f"{s['centres_within_tol']:.3f}", f"{s['error_px_median']:.2f}",
                     f"{s['error_px_p99']:.2f}", f"{s['error_px_max']:.2f}", causes))
    return Table(("objects", "cases", "agree", "same choice", "centres within 2 px",
                  "median error px", "99th pct px", "max px", "disagreements by cause"), rows)
