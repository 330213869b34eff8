"""The episodic memory learner (``learner = "memory"``): its options, kernels and module.

:mod:`.options` (the ``[model.memory]`` section), :mod:`.episodic` (the face code, the store
and the recall, compiled, with :class:`~.episodic.EpisodicMemory` their wrapper; its costly
parts are :mod:`._recall`, :mod:`._agreement` and :mod:`._left_out`), :mod:`._trial` (its part
of a trial as compiled kernels, which both engines call: the recall, ``saccade``, the places
left out and kept) and :mod:`.module` (the learning module that the bootstrap agent composes,
:class:`~.module.MemoryModule`).

Part of layer 3 (``models/``): it may import the robot's parts (:mod:`jointattention.agent`)
and the plumbing; no other learner's folder, and not the models that compose it
(``tests/test_layers.py``).
"""
