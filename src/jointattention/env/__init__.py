"""The Gymnasium adapter: ``JointAttention-v2`` and its variants (and v1), registered on import.

Needs the ``gym`` extra (``pip install "jointattention[gym]"``). The environment's manual is
:class:`JointAttentionEnv`'s docstring; :class:`FaceWindowObservation` adds the caregiver's
face window to the ``"image"`` observation, and :class:`EnvTrial` runs an agent of the trial
loop through the environment.

Registered ids (:data:`ENV_IDS`), each with ``max_episode_steps=40`` and, but for the
``-Discrete`` ones, actions in [-1, 1] (``normalize_actions=True``; :class:`EnvTrial`
converts an agent's radians):

- ``JointAttention-v2``: ``obs_mode="image"`` (rendered);
- ``JointAttentionFace-v2`` and ``JointAttentionDetections-v2``: the modes without rendering;
- ``JointAttention{Mode}-N{n}-v2`` for n = 1, 3, 5, 10 objects (``Mode`` empty, ``Face`` or
  ``Detections``), and ``JointAttentionFace-N{n}-Intrinsic-v2`` with the intrinsic reward;
- ``JointAttention{Mode}-Discrete-v2`` and ``JointAttention{Mode}-N{n}-Discrete-v2`` (``Mode``
  ``Face`` or ``Detections``): the v2 id with a ``Discrete(9)`` action, head moves of 4° and
  12° (:mod:`jointattention.env.discrete`), for DQN and its kin.

v2 observations are scaled (``scaled_obs=True``: the face in [-0.5, 0.5], the head angle and
the detections near [-1, 1]), so that an RL library's default network learns from them; each
v2 id has a v1 twin with the raw observations (uint8 grey levels, radians, pixels). The ids
with images also have a v3: v2 rendered with ``render_quality="fast"`` (no multisampling,
coarser spheres; about 2.5x the steps on a CPU).

Every v2 and v3 spec has a ``reward_threshold`` (:data:`REWARD_THRESHOLDS`): an episode's return
is 0 or 1, and an id is solved at a mean return of 0.9 times the oracle gaze-line follower's at
its object count (5 where the id names none) and reward, as
``python scripts/reward_thresholds.py`` measured them (10^5 trials each, in
``reward_thresholds.json`` beside this module). ``caregivers="new-poses"`` or ``"unseen"``
makes an id's held-out split (:class:`JointAttentionEnv`'s **Caregivers**).

Other arguments go to :func:`gymnasium.make` as keywords, as usual. The ids without images
have a ``vector_entry_point``: ``gymnasium.make_vec(id, num_envs=N,
vectorization_mode="vector_entry_point")`` steps all N in one compiled kernel
(:class:`~jointattention.env.vector.JointAttentionVectorEnv`);
:class:`jointattention.env.sb3.NativeVecEnv` hands it to Stable-Baselines3 (the ``rl`` extra).

Layer 7 (beside the analysis, which it never imports): it may import the runner and everything
below it.
"""

import warnings
from pathlib import Path

try:
    import gymnasium as gym
except ImportError:  # pragma: no cover - depends on the installed extras
    raise ImportError('jointattention.env needs Gymnasium; expected it installed: '
                      'pip install "jointattention[gym]"') from None

from .._readers import read_json
from ..world.options import N_OBJECTS
from ._observation import DETECTION_COLUMNS, MAX_DETECTIONS, detections_of
from .joint_attention import JointAttentionEnv
from .trial import EnvTrial
from .wrappers import FaceWindowObservation

__all__ = ["DETECTION_COLUMNS", "ENV_ID", "ENV_IDS", "MAX_DETECTIONS", "REWARD_THRESHOLDS",
           "EnvTrial", "FaceWindowObservation", "JointAttentionEnv", "detections_of"]

ENV_ID = "JointAttention-v1"
_MODES = {"": "image", "Face": "face", "Detections": "detections"}


def _variants() -> dict[str, dict]:
    """Every registered id and its keyword arguments (v2: ``scaled_obs``; v3: fast images)."""
    ids = {}
    for name, mode in _MODES.items():
        ids[f"JointAttention{name}"] = {"obs_mode": mode}
        for n in (1, 3, 5, 10):
            ids[f"JointAttention{name}-N{n}"] = {"obs_mode": mode, "n_objects": n}
    for n in (1, 3, 5, 10):
        ids[f"JointAttentionFace-N{n}-Intrinsic"] = {"obs_mode": "face", "n_objects": n,
                                                    "reward": "intrinsic"}
    made = {f"{i}-v{v}": {**kwargs, "normalize_actions": True, "scaled_obs": v == 2}
            for v in (1, 2) for i, kwargs in ids.items()}
    fast = {f"{i}-v3": {**kwargs, "normalize_actions": True, "scaled_obs": True,
                        "render_quality": "fast"}
            for i, kwargs in ids.items() if kwargs["obs_mode"] == "image"}
    return {**made, **fast, **_discrete_variants(ids)}


def _discrete_variants(ids: dict[str, dict]) -> dict[str, dict]:
    """The v2 ids without images or intrinsic reward, with discrete moves: ``...-Discrete-v2``."""
    return {f"{i}-Discrete-v2": {**kwargs, "scaled_obs": True} for i, kwargs in ids.items()
            if kwargs["obs_mode"] != "image" and "reward" not in kwargs}


ENV_IDS = tuple(_variants())


def _thresholds() -> dict[str, float]:
    """Each v2 and v3 id's reward threshold: ``fraction`` x the oracle's ceiling (the file's)."""
    data = read_json(Path(__file__).with_name("reward_thresholds.json"),
                     "the oracle's ceilings (python scripts/reward_thresholds.py)")
    ceiling = data["ceiling"]
    return {i: round(data["fraction"] * ceiling[kwargs.get("reward", "external")][
        str(kwargs.get("n_objects", N_OBJECTS))], 4)
        for i, kwargs in _variants().items() if not i.endswith("-v1")}


REWARD_THRESHOLDS = _thresholds()

for _id, _kwargs in _variants().items():
    if _id not in gym.registry:
        fast = _kwargs["obs_mode"] != "image"
        if _id.endswith("-Discrete-v2"):
            entry = "jointattention.env.discrete:DiscreteJointAttentionEnv"
            vector = "jointattention.env.discrete:DiscreteJointAttentionVectorEnv"
        else:
            entry = "jointattention.env:JointAttentionEnv"
            vector = "jointattention.env.vector:JointAttentionVectorEnv" if fast else None
        gym.register(id=_id, entry_point=entry, vector_entry_point=vector,
                     max_episode_steps=40, kwargs=_kwargs,
                     reward_threshold=REWARD_THRESHOLDS.get(_id))

# v2 stays current: v3 is v2 rendered faster, not its successor, so Gymnasium's "out of date"
# warning (it warns of any lower version) would be noise before every make of a v2 id that
# has a v3. v1 still warns: v2 replaces it.
warnings.filterwarnings("ignore", message=r".*The environment JointAttention(-N\d+)?-v2 is out "
                        "of date", category=DeprecationWarning)
