"""Session 20: R_Ffreeplay_s21 (fresh draw, seed 21) ends 55 x its calibration floor with the
right effect.  Does liquidamp's floating_freeplay at the simulator's truth reproduce the
records (model form) or does the fit stop in another basin?

usage: python runs/s20_lead/freeplay_truth.py RECDIR
"""
import json
import sys

import numpy as np

from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.analysis.measured.records import read_record
from liquidamp.device.effects import EFFECTS, with_effects
from liquidamp.device.presets import preset
from liquidamp.options import PRESETS

d = sys.argv[1]
truth = json.load(open(f"{d}/truth.json"))["R_Ffreeplay_s21"]
mult = truth["device"]["multipliers"]
p = preset("reference").scaled(**mult)
gap = truth["simulator_settings"]["gap"]
for role in ("cal", "val"):
    rec, cond = condition(read_record(f"{d}/R_Ffreeplay_s21_{role}.csv"))
    for k in (2e6, 2e7, 2e8):
        m = with_effects("full", EFFECTS["floating_freeplay"](gap_m=gap,
                                                             contact_stiffness_N_per_m=k))
        r = simulate_record(m, p, rec, options=PRESETS["fit"])
        res = rec.force - r.force
        print(role, f"contact {k:.0e}", "NRMSE",
              round(float(np.sqrt(np.mean(res ** 2)) / np.std(rec.force)), 5),
              "floor", round(cond.noise.nrmse, 5), flush=True)
