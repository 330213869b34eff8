"""The Gymnasium adapter: ``JointAttention-v0``, registered when this package is imported.

Needs the ``gym`` extra (``pip install "jointattention[gym]"``). The environment's manual is
:class:`JointAttentionEnv`'s docstring; :class:`FaceWindowObservation` adds the caregiver's
face window to the observation, and :class:`EnvTrial` runs an agent of the trial loop
through the environment.
"""

try:
    import gymnasium as gym
except ImportError:  # pragma: no cover - depends on the installed extras
    raise ImportError('jointattention.env needs Gymnasium; expected it installed: '
                      'pip install "jointattention[gym]"') from None

from .joint_attention import JointAttentionEnv
from .trial import EnvTrial
from .wrappers import FaceWindowObservation

__all__ = ["ENV_ID", "EnvTrial", "FaceWindowObservation", "JointAttentionEnv"]

ENV_ID = "JointAttention-v0"

if ENV_ID not in gym.registry:
    gym.register(id=ENV_ID, entry_point="jointattention.env:JointAttentionEnv")
