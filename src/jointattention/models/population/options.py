"""The population code's options: ``[model.population]`` (with ``learner = "population"``)."""

from __future__ import annotations

from dataclasses import dataclass

from ..._fields import Section, param

__all__ = ["READOUTS", "PopulationOptions"]

READOUTS = ("excess", "ratio", "mode")


@dataclass(frozen=True)
class PopulationOptions(Section):
    """The population code's options (``[model.population]``, with ``learner = "population"``)."""

    n_bins: int = param(72, "output units: directions around the face, evenly on the circle",
                        lo=8, hi=720)
    n_hidden: int = param(128, "hidden units (tanh) between the face features and the output",
                          lo=1, hi=1024)
    learning_rate: float = param(0.02, "step size of the cross-entropy gradient, per place "
                                 "taught", lo=0, hi=10)
    label_width_deg: float = param(
        5.0, "s.d. of the von Mises kernel that spreads a taught direction over nearby units",
        lo=0.1, hi=90)
    features: str = param(
        "pixels+hog", "the face's features: its contrast-normalised grey levels, a histogram "
        "of its gradient orientations, or both", choices=("pixels+hog", "pixels", "hog"))
    cell_px: int = param(5, "side of a cell of the gradient-orientation histogram (pixels)",
                         lo=2, hi=64)
    n_orientations: int = param(12, "signed orientation bins per histogram cell", lo=2, hi=36)
    standardise: bool = param(
        False, "centre and scale each feature by its running mean and s.d. over the faces "
        "seen (the histogram's features are all positive: uncentred inputs slow learning)")
    readout: str = param(
        "excess", "how the direction is read out: where p(direction | face) most exceeds "
        "p(direction | the average face) (excess), where its log does (ratio), or the plain "
        "mode of p(direction | face) (mode: no base rate)", choices=READOUTS)
    average_rate: float = param(
        0.002, "rate of the running average of the weights, per trial taught, that the "
        "readout uses (Polyak averaging: the noise of the last steps averaged out; 0: the "
        "weights themselves)", lo=0, hi=1)
    hidden_rate: float = param(0.01, "rate of the running mean of the hidden units over the "
                               "faces taught (the average face of the readout)", lo=0, hi=1)
    keep: str = param(
        "in_view", "places taught when the evaluator fires: the attended object's, or every "
        "object's in view then (the target is often in view when a distractor is attended)",
        choices=("attended", "in_view"))
    replay: int = param(8, "updates on trials drawn from the replay memory after each trial "
                        "taught (0: none)", lo=0, hi=100)
    belief: float = param(
        0.0, "how far each place taught is weighted by the network's own belief in it, each "
        "time it is taught: 0, every place alike; 1, in proportion to p(direction | face) / "
        "p(direction | the average face) there (self-training: a distractor lies anywhere for "
        "any face, the target where she looks, so the network's belief picks it out as it "
        "learns)", lo=0, hi=1)
    unfound: bool = param(
        False, "a trial that the module drove and that ended with nothing found (the "
        "evaluator never fired: a joint or the step limit) teaches a direction drawn from the "
        "network's own p(direction | face) with the line it followed left out (within three "
        "label widths): a line into empty space is otherwise never taught against, and a "
        "face whose line leads there stays wrong (docs/generalisation.md)")
    replay_capacity: int = param(20_000, "trials the replay memory keeps (the oldest is "
                                 "forgotten); each keeps its face's features, 8.9 kB with "
                                 "the default features (178 MB when full)", lo=1,
                                 hi=10_000_000)
