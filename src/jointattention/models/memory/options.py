"""The episodic memory's options: the ``[model.memory]`` section (``learner = "memory"``)."""

from __future__ import annotations

from dataclasses import dataclass

from ..._fields import Section, param
from ...errors import ConfigError

__all__ = ["MemoryOptions"]


@dataclass(frozen=True)
class MemoryOptions(Section):
    """The episodic learning module's options (``[model.memory]``, with ``learner = "memory"``)."""

    code_dims: int = param(
        32, "length of the face code: a random projection of the face window that the robot "
        "draws once (it keeps distances between faces)", lo=1, hi=4096)
    k_nearest: int = param(
        64, "trials recalled for a face: those whose faces are the k nearest (ties included)",
        lo=1, hi=100_000)
    radius_deg: float = param(
        2.0, "places closer than this count as one place when the recalled trials vote",
        lo=0.01, hi=90)
    keep: str = param(
        "in_view", "places kept when the evaluator fires: the attended object's, or every "
        "object's in view then (the target is often in view when a distractor is attended)",
        choices=("attended", "in_view"))
    capacity: int = param(
        20_000, "trials kept; the oldest is forgotten when it is full", lo=1, hi=10_000_000)
    leave_out_empty: bool = param(
        False, "leave a place out of a face's recalls once the head reached it (within a step) "
        "with no object near the view's centre: a data set's target does not move")
    pass_over_left_out: bool = param(
        False, "visual attention passes over an object at a place left out of the face's "
        "recalls (it is not the target); needs leave_out_empty")
    drop_left_out: bool = param(
        False, "keep no place found at a trial's end that lies at a place left out of the "
        "face's recalls (it is a distractor's); needs leave_out_empty")
    recall_again: bool = param(
        False, "once a place is left out, recall the face's next place at once: the trial goes "
        "on toward it, with its evidence for the gate; needs leave_out_empty")
    saccade: bool = param(False, "move to the recalled place in one move, no longer than visual "
                          "feedback's longest (Eq. 2 at an image corner), not lm_step_deg a step")

    def __post_init__(self) -> None:
        super().__post_init__()
        for name in ("pass_over_left_out", "drop_left_out", "recall_again"):
            if getattr(self, name) and not self.leave_out_empty:
                raise ConfigError(f"memory.{name} = true: expected memory.leave_out_empty = "
                                  "true (it acts on the places left out)")
