"""Deployment: learned models in files, and following a caregiver's gaze in camera images.

Model files (:mod:`.saved`), the gaze follower (:mod:`.follower`) and its overlay
(:mod:`.overlay`).

Layer 5 (with the data sets a robot records, :mod:`jointattention.head_recording`): it may import
the configuration, the models, the robot's parts and the plumbing; never the world.
"""
