"""Success curves, intervals over seeds, and summary numbers (pure functions of records)."""

from __future__ import annotations

import numpy as np

__all__ = ["T975", "bin_index", "final_success", "mean_interval", "success_by_bin",
           "time_to_fraction"]

# Two-sided 95% Student t quantiles for 1..30 degrees of freedom; beyond, the normal's.
T975 = (12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179,
         2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
         2.060, 2.056, 2.052, 2.048, 2.045, 2.042)


def bin_index(learning_time: np.ndarray, bin_steps: int, n_steps: int) -> np.ndarray:
    """The learning-time bin of each trial (by its start); the last bin takes any overrun."""
    n_bins = int(np.ceil(n_steps / bin_steps))
    return np.minimum(np.asarray(learning_time) // bin_steps, n_bins - 1).astype(int)


def success_by_bin(learning_time: np.ndarray, success: np.ndarray, bin_steps: int,
                   n_steps: int) -> np.ndarray:
    """Success rate of the trials starting in each learning-time bin (NaN for empty bins)."""
    n_bins = int(np.ceil(n_steps / bin_steps))
    idx = bin_index(learning_time, bin_steps, n_steps)
    count = np.bincount(idx, minlength=n_bins)
    wins = np.bincount(idx, weights=np.asarray(success, float), minlength=n_bins)
    with np.errstate(invalid="ignore"):
        return wins / count


def mean_interval(per_seed: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mean over seeds (axis 0) and its 95% t interval; one seed gives a zero-width interval."""
    per_seed = np.atleast_2d(per_seed)
    n = per_seed.shape[0]
    mean = np.nanmean(per_seed, axis=0)
    if n < 2:
        return mean, mean, mean
    sem = np.nanstd(per_seed, axis=0, ddof=1) / np.sqrt(n)
    t = T975[n - 2] if n - 1 <= len(T975) else 1.96
    return mean, mean - t * sem, mean + t * sem


def final_success(curve: np.ndarray, fraction: float = 0.1) -> float:
    """Mean of the last ``fraction`` of a success curve's bins."""
    k = max(1, int(round(len(curve) * fraction)))
    return float(np.nanmean(curve[-k:]))


def time_to_fraction(curve: np.ndarray, bin_ends_steps: np.ndarray,
                     fraction: float = 0.9) -> float:
    """Learning time at which the curve reaches ``fraction`` of its final value.

    The end of the first bin that does (``bin_ends_steps``: each bin's end, the last at
    ``n_steps``); NaN if none does.
    """
    reached = np.flatnonzero(curve >= fraction * final_success(curve))
    return float(bin_ends_steps[reached[0]]) if len(reached) else float("nan")
