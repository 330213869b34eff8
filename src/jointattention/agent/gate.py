"""The gate: how often the learning module's command is chosen (paper, III-E and Fig. 4b)."""

from __future__ import annotations

import numpy as np

__all__ = ["constant_rate", "sigmoid_rate"]


def sigmoid_rate(learning_time_steps, midpoint_steps: float, width_steps: float):
    """Rate of choosing LM dtheta: 1 / (1 + exp(-(t - midpoint) / width))."""
    t = np.asarray(learning_time_steps, dtype=float)
    return 1.0 / (1.0 + np.exp(-(t - midpoint_steps) / width_steps))


def constant_rate(learning_time_steps, rate: float):
    """A constant rate of choosing LM dtheta (the paper compares 0.7, 0.9 and 1.0)."""
    return np.full(np.shape(learning_time_steps), float(rate))
