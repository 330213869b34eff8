"""Figures and the report.

The paper's Fig. 4 and 5 (:mod:`.paper`), Fig. 6 and 7 (:mod:`.learned`), pictures of the
world (:mod:`.world`), detections drawn on photographs (:mod:`.detect`), the held-out and
diagnostics figures and the HTML report of a run folder (:mod:`.report`). Figures are made
without pyplot, so the library never touches matplotlib's backend.

Layer 8: it may import the analysis and everything below it; never the jobs or the command
line.
"""
