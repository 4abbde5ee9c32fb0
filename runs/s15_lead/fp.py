"""Held-out freeplay records (floating piston) and nulls from the independent simulator.

The s12/s14 sweeps' freeplay records (runs/s12_indep/simulator.py: the piston, 0.05 kg,
floats in the dead band under the fluid force and meets the rod through a 2e7 N/m, 600 N s/m
contact) were missed by the catalogue's seal-held freeplay; session 15 added
``floating_freeplay``.  These cases are new conditions (frequencies, amplitudes, sampling,
sizes 10-60 x the force noise) that the effect was not developed on, and two nulls to check
it is not added where there is nothing.  Same simulator, same protocol.

    PYTHONPATH=. python runs/s15_lead/fp.py gen RECDIR
    PYTHONPATH=. python runs/s15_lead/fp.py run RECDIR OUT [ID..]
    PYTHONPATH=. python runs/s15_lead/fp.py table RECDIR OUT
"""
from __future__ import annotations

import sys

from runs.s12_indep import sweep

FP = {
    "R_fp12": ("reference", (2.0, 3.5e-3), (4.0, 2e-3), 500.0, "freeplay", 12),
    "R_fp60": ("reference", (4.0, 2e-3), (2.5, 3e-3), 1000.0, "freeplay", 60),
    "B_fp10": ("device_b", (4.0, 2e-3), (2.0, 3.5e-3), 500.0, "freeplay", 10),
    "B_fp20": ("device_b", (2.5, 3e-3), (5.0, 1.5e-3), 200.0, "freeplay", 20),
    "R_fpnull": ("reference", (3.5, 2.5e-3), (1.5, 4e-3), 500.0, "null", 0),
    "B_fpnull": ("device_b", (3.0, 2e-3), (6.0, 1.2e-3), 500.0, "null", 0),
}
sweep.CASES.update(FP)
sweep.KEYS["freeplay"] = (("floating_freeplay", "freeplay", "backlash"), "gap_m", "gap")

if __name__ == "__main__":
    argv = list(sys.argv)
    if argv[1] in ("gen", "run", "table") and len(argv) <= (3 if argv[1] == "gen" else 4):
        argv += list(FP)
    sweep.main(argv)
