"""What only the experimenter knows: the scene, the caregiver, the objects, ground truth.

The MuJoCo world and its renderer, the fast world, the head's kinematics, object placement,
caregivers and their faces, recording data sets, and the world's options
(:mod:`.options`, :mod:`.variation`).

Layer 3 (beside the models, which it never imports): it may import the robot's parts (its
rendered scenes detect with the robot's detectors) and the plumbing. The robot's side
(:mod:`jointattention.agent`, :mod:`jointattention.models`) never imports this package.
"""
