"""The runner: trials, cells, engines, run folders, training and held-out measures.

The trial loop (:mod:`.trial`), the oracle (:mod:`.oracle`), cells and ceilings (:mod:`.cells`),
the compiled engine (:mod:`.compiled`, a folder of its own), where cells run (:mod:`.backends`),
run folders (:mod:`.results`), training (:mod:`.training`), frozen models measured on other data
sets (:mod:`.evaluate`, :mod:`.held_out`) and the checks before a run writes
(:mod:`.preflight`).

Layer 6: it may import deployment, the data sets, the configuration, the world, the models,
the robot and the plumbing; never the analysis, the figures or the jobs (which sit above it).
"""
