"""The reinforcement-learning model (``kind = "rl"``): the basic set of Triesch et al. (2006).

:mod:`.agent` (the model, :class:`~.agent.RLAgent`, and its options, :class:`~.agent.RLOptions`),
:mod:`._kernels` (its equations, compiled) and :mod:`._trial` (its whole part of a trial as
compiled kernels over its own state, a :class:`~jointattention.agent.protocol.TrialKernels`,
which the step-by-step agent and the compiled engine both call).

Part of layer 3 (``models/``): it may import the robot's parts (:mod:`jointattention.agent`:
the face statistics and the trial protocol among them), the models' registry and the
plumbing; no learner's folder, and the compiled engine may not import it
(``tests/test_layers.py``).
"""

from .agent import STAY, RLAgent, RLOptions

__all__ = ["STAY", "RLAgent", "RLOptions"]
