"""The whole learner models, one module each, and their registry (:data:`.registry.MODELS`).

The paper's bootstrap model (:mod:`.bootstrap`; its memory and population learners,
:mod:`.memory` and :mod:`.population`), the teacher (:mod:`.teacher`), the developmental
model (:mod:`.developmental`) and the reinforcement learner (:mod:`.rl`). A new model is one
module and one line in the registry.

Layer 3 (beside the world, which it never imports): it may import the robot's parts
(:mod:`jointattention.agent`) and the plumbing.
"""
