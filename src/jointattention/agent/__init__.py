"""The robot's parts: what the robot has and knows.

Its detectors and face finders, the eye windows it cuts from its frames, the socket patches it
keeps of them and the network that finds the sockets, visual attention (Eq. 1, 2), the internal
evaluator's radius (Eq. 3), the faces' running statistics (:mod:`.face_standardiser`), the
gates, the head's moves, the agent protocol and the robot's options. The learners, each with
its kernels, are folders of :mod:`jointattention.models` (``models/network/``,
``models/memory/``, ``models/population/``).

Layer 2 of ``docs/architecture.md``: it may import only the plumbing (the package's top-level
private modules, ``errors``, ``rng``, ``datasets``). Nothing here imports
:mod:`jointattention.world`: the robot learns without knowing what only the experimenter
knows (``tests/test_boundary.py`` and ``tests/test_layers.py`` guard it).
"""
