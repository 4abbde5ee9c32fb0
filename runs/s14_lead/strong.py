"""A held-out sweep at the shared set's effect sizes (20-60 x the force noise).

The session-12 sweep (runs/s12_indep/sweep.py) sized each effect at 5-10 x the noise, below
the shared independent records' 10-136 x (median about 40 x, their truth.json).  This adds
cases at the shared set's sizes, under conditions (frequency, amplitude, sampling) none of
the shared records or of the s12 cases use, for the effects the shared set does not hold
alone (leakage, Coulomb friction, freeplay, series spring, moving mass, force offset,
digressive valve) and three it does on the other design.  Same simulator, same protocol.

    PYTHONPATH=. python runs/s14_lead/strong.py gen RECDIR
    PYTHONPATH=. python runs/s14_lead/strong.py run RECDIR OUT [ID..]
    PYTHONPATH=. python runs/s14_lead/strong.py table RECDIR OUT
"""
from __future__ import annotations

import sys

from runs.s12_indep import sweep

STRONG = {
    "R_leakage40": ("reference", (3.0, 2.5e-3), (1.5, 4e-3), 500.0, "leakage", 40),
    "B_leakage40": ("device_b", (2.5, 3e-3), (5.0, 1.5e-3), 200.0, "leakage", 40),
    "R_relief40": ("reference", (3.0, 3.5e-3), (6.0, 1.5e-3), 500.0, "relief", 40),
    "B_coulomb40": ("device_b", (2.0, 3e-3), (6.0, 1.2e-3), 200.0, "coulomb", 40),
    "R_freeplay30": ("reference", (2.5, 3e-3), (4.5, 2e-3), 500.0, "freeplay", 30),
    "B_freeplay30": ("device_b", (3.0, 2.5e-3), (1.5, 4e-3), 1000.0, "freeplay", 30),
    "R_series30": ("reference", (3.0, 3e-3), (6.0, 1.5e-3), 500.0, "series", 30),
    "B_series30": ("device_b", (2.0, 3e-3), (5.0, 1.5e-3), 200.0, "series", 30),
    "R_mass20": ("reference", (6.0, 2e-3), (4.0, 2.5e-3), 1000.0, "mass", 20),
    "B_mass20": ("device_b", (7.0, 1.5e-3), (5.0, 2e-3), 500.0, "mass", 20),
    "R_offset30": ("reference", (2.0, 4e-3), (4.5, 2e-3), 200.0, "offset", 30),
    "B_digressive40": ("device_b", (2.5, 3.5e-3), (4.5, 2e-3), 500.0, "digressive", 40),
    "R_digressive40": ("reference", (4.5, 2e-3), (2.0, 4e-3), 200.0, "digressive", 40),
    "B_endstops60": ("device_b", (2.5, 3e-3), (5.0, 2.9e-3), 2000.0, "endstops", 60),
    "R_elastomer40": ("reference", (3.0, 2.5e-3), (1.5, 4e-3), 200.0, "elastomer", 40),
    "B_asym40": ("device_b", (5.0, 2e-3), (2.5, 3.5e-3), 200.0, "asym", 40),
    "R_null2": ("reference", (6.0, 1.5e-3), (2.0, 4e-3), 1000.0, "null", 0),
}
sweep.CASES.update(STRONG)

if __name__ == "__main__":
    sweep.main_with(STRONG, sys.argv)
