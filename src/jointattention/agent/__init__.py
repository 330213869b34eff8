"""What the robot has: detectors, controller, evaluator, learner, gate and the agent.

Nothing here imports :mod:`jointattention.world`: the robot learns without knowing what only
the experimenter knows (a test guards this).
"""
