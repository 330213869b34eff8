"""The compiled engine: whole cells run in one compiled loop, byte-identical to step by step.

:mod:`.cell` is its door (:class:`~.cell.CompiledCell`, :func:`~.cell.compiled_cell`, and
:func:`~.cell.unsupported`, why a configuration cannot run compiled); :mod:`.rl_cell` packs
the reinforcement learner's cell; :mod:`.inputs` holds the named tuples the loops take, and
:mod:`.steps` a trial's draw, look and record (the oracle's loop calls them too). The loops
are private: :mod:`._loop` (the bootstrap family's trials, which calls the learning module's
kernels: :class:`~jointattention.agent.protocol.ModuleKernels`) and :mod:`._rl_loop` (the
trials of an agent whose whole trial is its own kernels,
:class:`~jointattention.agent.protocol.TrialKernels`: the reinforcement learner's). Neither
names a model's options: they are in the state the model hands with its kernels.

Part of layer 6 (``experiment/``): it may import the models and their kernels, the world,
the configuration, the robot, the plumbing, and of the runner only the trial's kernels
(:mod:`..trial`); the rest of the runner reaches it through its public modules, never its
private loops (``tests/test_layers.py``). Its names of version 0.3.0
(``experiment.compiled.CompiledCell``, ``pack_world``, ``unsupported``) import from here.
"""

from .cell import CompiledCell, pack_world, unsupported

__all__ = ["CompiledCell", "pack_world", "unsupported"]
