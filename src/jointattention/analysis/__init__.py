"""Analysis: pure functions of saved results.

Success curves and intervals (:mod:`.metrics`, :mod:`.curves`), tables (:mod:`.tables`), the
paper's claims (:mod:`.claims`, :mod:`.claim_record`, :mod:`.neighbours`), the held-out measures'
table (:mod:`.held_out`) and the diagnostics (:mod:`.diagnostics`).

Layer 7 (beside the environments, which it never imports): it may import the runner's results
and everything below it. It trains nothing and renders nothing: whole jobs that do are in
:mod:`jointattention.jobs`.
"""
