"""Figures and the report.

The paper's Fig. 4 and 5 (:mod:`.paper`), Fig. 6 and 7 (:mod:`.learned`), pictures of the world
(:mod:`.world`), detections drawn on photographs (:mod:`.detect`) and the HTML report of a run
folder (:mod:`.report`). Figures are made without pyplot, so the library never touches matplotlib's
backend.
"""
