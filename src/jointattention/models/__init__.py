"""The whole learner models and their registry (:data:`.registry.MODELS`).

The paper's bootstrap model (:mod:`.bootstrap`) composes a learning module: the paper's
network (:mod:`.network`), the episodic memory (the folder :mod:`.memory`) or the population
code (the folder :mod:`.population`); a learner with options and kernels of its own is one
folder (options, kernels, module). The teacher (:mod:`.teacher`), the developmental model
(:mod:`.developmental`) and the reinforcement learner (:mod:`.rl`) are one module each. A new
model is one module (or folder) and one line in the registry.

Layer 3 (beside the world, which it never imports): it may import the robot's parts
(:mod:`jointattention.agent`) and the plumbing.
"""
