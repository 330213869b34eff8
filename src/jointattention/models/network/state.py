"""What a model file keeps of an agent whose learning module is the paper's network.

The bootstrap agent and its kin (:mod:`..bootstrap`) inherit it; :mod:`.saved` writes, checks
and loads the members by name. It imports only numpy.
"""

from __future__ import annotations

import numpy as np

__all__ = ["NetworkState"]


class NetworkState:
    """The network's weights and the face statistics, as a model file's members.

    Expects ``self.learner`` (:class:`~.learner.LearningModule`), ``self.faces``
    (:class:`~jointattention.agent.face_standardiser.FaceStandardiser`) and ``self.body`` (its
    face window size).
    """

    def saved_arrays(self) -> dict[str, np.ndarray]:
        """What a model file keeps of the learned state, by member name (``deploy/saved.py``)."""
        net, faces = self.learner, self.faces
        return {"w1": net.w1_, "b1": net.b1_, "w2": net.w2_, "b2": net.b2_,
                "face_mean": faces.mean_, "face_m2": faces.m2_,
                "face_n_seen": np.array(faces.n_seen_)}

    def saved_shapes(self) -> dict[str, tuple[int, ...]]:
        """The shape of each member of :meth:`saved_arrays` for this agent's options."""
        net, n_pix = self.learner, self.body.view_size
        return {"w1": net.w1_.shape, "b1": net.b1_.shape, "w2": net.w2_.shape,
                "b2": net.b2_.shape, "face_mean": (n_pix,), "face_m2": (n_pix,),
                "face_n_seen": ()}

    def load_arrays(self, arrays: dict[str, np.ndarray]) -> None:
        """Set the learned state from checked members of a model file (:meth:`saved_arrays`)."""
        net, faces = self.learner, self.faces
        net.w1_, net.b1_, net.w2_, net.b2_ = (arrays[k].astype(float)
                                              for k in ("w1", "b1", "w2", "b2"))
        net.velocity_ = [np.zeros_like(p) for p in net._params()]
        faces.mean_ = arrays["face_mean"].astype(float)
        faces.m2_ = arrays["face_m2"].astype(float)
        faces.n_seen_ = int(arrays["face_n_seen"])
