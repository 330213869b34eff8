"""Analysis: pure functions of saved results.

Success curves and intervals (:mod:`.metrics`, :mod:`.curves`), tables (:mod:`.tables`), the paper's
claims (:mod:`.claims`), the parity of the two detectors (:mod:`.parity`) and what the learning
module learned (:mod:`.learned`).
"""
