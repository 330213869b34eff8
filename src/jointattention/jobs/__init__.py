"""Whole jobs: each runs experiments, then analyses and draws what they give.

The paper's figures and tables (:mod:`.reproduce`), sweeps (:mod:`.sweep`), what the module
learned (:mod:`.learned`: ``jointattention gaze``), the detectors' parity (:mod:`.parity`),
the closed loop through images (:mod:`.closed_loop`), the face finders compared
(:mod:`.face_finders`), the speed benchmark (:mod:`.bench`) and the presets' wall times
(:mod:`.estimates`).

Layer 9: it may import everything below it (figures, analysis, the environments, the runner,
deployment, the configuration, the world, the models and the robot); only the command line
imports it.
"""
