"""The paper's network learner (``learner = "backprop"``): its kernels, its command and module.

:mod:`.learner` (the three-layer network trained by back-propagation,
:class:`~.learner.LearningModule`, the door to the compiled kernels of :mod:`._backprop`),
:mod:`.command` (its command at a head angle, one face or a batch), :mod:`._trial` (its part
of a trial as compiled kernels, which both engines call), :mod:`.module` (the learning module
that the bootstrap agent composes, :class:`~.module.NetworkModule`) and
:mod:`.state` (what a model file keeps of it). Its options are the bootstrap model's own
fields (``[model]``: ``learning_rate``, ``n_hidden``, ...), so it has no options module.

Part of layer 3 (``models/``): it may import the robot's parts (:mod:`jointattention.agent`:
the face statistics and the head's moves among them) and the plumbing; no other learner's
folder, and not the models that compose it (``tests/test_layers.py``).
"""
