"""Running the model: trials, cells, backends, run folders, the main job and sweeps.

The trial loop (:mod:`.trial`), the oracle (:mod:`.oracle`), cells and ceilings (:mod:`.cells`),
where cells run (:mod:`.backends`), run folders (:mod:`.results`), the main job (:mod:`.reproduce`)
and sweeps (:mod:`.sweep`).
"""
