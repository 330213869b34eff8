"""The record of one checked claim, its reading, and the paired statistics every claim uses.

:mod:`.claims` (the paper's claims), :mod:`.neighbours` (the neighbouring models' claims) and
:mod:`.held_out` (generalisation) build on it; it imports none of them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..config import Config, model_options
from ..models.registry import MODELS
from .metrics import final_success, mean_interval

__all__ = ["PAIRED_RULE", "SOURCES", "Claim", "finals_of", "paired", "paired_lower", "reading_of"]


SOURCES = {  # a claim's source: the heading its claims are shown under
    "paper": "The paper's claims",
    "neighbours": "The neighbouring models' claims (their papers)",
    "project": "This project's own targets, beyond the paper",
}


@dataclass(frozen=True)
class Claim:
    """One checked claim: its reading, what was claimed, whether it held, numbers and rule.

    ``source`` says whose claim it is (:data:`SOURCES`): the paper's, a neighbouring model's
    paper's, or a target of this project beyond the paper (generalisation, the performance
    gate), so that a reader does not take a missed target of ours for a failure of the paper.
    """

    reading: str
    claim: str
    holds: bool
    evidence: str
    rule: str = ""
    source: str = "paper"


def reading_of(condition, config: Config) -> str:
    """The condition's reading, e.g. ``gate_per=step, vf_fallback=lm, learning_target=...``.

    Preceded by ``model=<kind>`` for models other than the bootstrap model, and by
    ``learner=<kind>`` for a learning module other than the paper's.
    """
    options = model_options(config, condition)
    kind = MODELS.name_of(options)
    parts = [f"{k}={getattr(options, k)}" for k in options.readings]
    if getattr(options, "learner", "backprop") != "backprop":
        parts.insert(0, f"learner={options.learner}")
    return ", ".join(parts if kind == "bootstrap" else [f"model={kind}", *parts])


def paired_lower(a: np.ndarray, b: np.ndarray) -> float:
    """Lower end of the 95% interval of mean(a - b) over seeds (paired)."""
    return float(mean_interval((a - b)[:, None])[1][0])


PAIRED_RULE = "final difference: paired 95% lower bound > 0"  # the rule :func:`paired` checks


def paired(a: np.ndarray, b: np.ndarray) -> tuple[bool, str]:
    """Whether finals ``a`` beat ``b`` (paired 95% lower bound above zero), and the numbers."""
    lower = paired_lower(a, b)
    return lower > 0, (f"final {a.mean():.3f} against {b.mean():.3f}; paired difference "
                       f"{(a - b).mean():+.3f}, 95% lower bound {lower:+.3f}")


def finals_of(per_seed: np.ndarray) -> np.ndarray:
    """Each seed's final success (the mean of its curve's last 10% of bins)."""
    return np.array([final_success(s) for s in per_seed])
