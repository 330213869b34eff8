"""The population-code learner (``learner = "population"``): its options, kernels and module.

:mod:`.options` (the ``[model.population]`` section), :mod:`.features` (what the robot
computes from a face window before it learns), :mod:`.code` (the network whose output is a
population code, :class:`~.code.PopulationCode`, over the compiled forward pass and readout
of :mod:`._forward` and the learning step of :mod:`._teaching`), :mod:`._trial` (the module's
compiled trial start and end, its batched commands and replay) and :mod:`.module` (the
learning module that the bootstrap agent composes, :class:`~.module.PopulationModule`).

Part of layer 3 (``models/``): it may import the robot's parts (:mod:`jointattention.agent`)
and the plumbing; no other learner's folder, and not the models that compose it
(``tests/test_layers.py``).
"""
