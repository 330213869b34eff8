"""What only the experimenter knows: the scene, the caregiver, the objects, ground truth.

The robot's side (:mod:`jointattention.agent`) never imports this package.
"""
