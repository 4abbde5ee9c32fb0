"""A fresh held-out draw (session 19): conditions drawn at random, not chosen.

Every earlier sweep (runs/s12_indep, runs/s14_lead/strong.py) fixed its conditions by hand,
and the selection rules have since been checked on them.  This draws, with a fixed seed
(19, the session) and before any run, one case per effect kind of the independent
simulator (runs/s12_indep/simulator.py, NOT liquidamp's code) plus a null: base design
(Table 3 reference or Device B), calibration and held-out frequency (1-8 Hz, at least a
factor 1.4 apart), amplitudes (1-5 mm, capped so that the
peak rate stays within 60 mm/s, as in the earlier sweeps), sampling rate (200 Hz - 2 kHz)
and the effect's size (12-45 x the force noise).  Protocol and classes as runs/s12_indep/sweep.py.

    PYTHONPATH=. python runs/s19_lead/fresh.py gen RECDIR
    PYTHONPATH=. python runs/s19_lead/fresh.py run RECDIR OUT [ID..]
    PYTHONPATH=. python runs/s19_lead/fresh.py table RECDIR OUT

``FRESH_SEED=N`` draws another set (ids suffixed ``_sN``); seed 19 is the session's draw.
"""
from __future__ import annotations

import math
import os
import sys

import numpy as np

from runs.s12_indep import sweep

KINDS = ("coulomb", "leakage", "relief", "freeplay", "series", "mass", "offset", "asym",
         "elastomer", "endstops", "digressive", "null")


def draw(seed: int = 19) -> dict:
    """The cases: id -> (base, (f, Y) cal, (f, Y) val, fs, kind, target)."""
    rng = np.random.default_rng(seed)
    out = {}
    for kind in KINDS:
        base = ("reference", "device_b")[int(rng.integers(2))]
        while True:
            fc, fv = (float(np.round(rng.uniform(1.0, 8.0), 1)) for _ in range(2))
            if max(fc, fv) / min(fc, fv) >= 1.4:
                break
        pair = []
        for f in (fc, fv):
            ymax = min(5e-3, 0.060 / (2 * math.pi * f))  # peak rate 60 mm/s at most
            pair.append((f, float(np.round(rng.uniform(1e-3, max(1.2e-3, ymax)), 4))))
        fs = float((200.0, 500.0, 1000.0, 2000.0)[int(rng.integers(4))])
        target = 0 if kind == "null" else int(rng.integers(12, 46))
        tag = "" if seed == 19 else f"_s{seed}"
        out[f"{'R' if base == 'reference' else 'B'}_F{kind}{tag}"] = (
            base, pair[0], pair[1], fs, kind, target)
    return out


FRESH = draw(int(os.environ.get("FRESH_SEED", "19")))
sweep.CASES.update(FRESH)

if __name__ == "__main__":
    sweep.main_with(FRESH, sys.argv)
