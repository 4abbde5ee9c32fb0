"""Backlash at its refit's point on the 200 Hz Coulomb-friction bench record: the orbit from
rest against the orbit warm-started from a small-gap point's (the fit's path), and the
latter marched on (is it a slow transient the march accepted?).

PYTHONPATH=. python runs/s10_b200/backlash_warm.py
"""
import dataclasses

import numpy as np

from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.diagnosis_options import march_options
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model

rec = condition(real_rate_records("diagnosis_200hz_10_cycles", "coulomb_friction")[0])[0]
opts = march_options(None, [rec])
p = preset("paper_initial").scaled(inv_gamma1=0.75023, inv_gamma2=1.21979, c1=3.57751,
                                   c2=4.03462)


def model(gap, k=1.666e9):
    return with_effects(get_model("full"),
                        make_effect("smooth_friction", force_N=30.0586, stiffness_N_per_m=k,
                                    location="piston"),
                        make_effect("freeplay", gap_m=gap, drives="friction"))


m = model(1.7496e-3)
cold = simulate_record(m, p, rec, options=opts)
print("cold", nrmse(cold.force, rec.force), cold.solver_stats["march_cycles"])
x = None
for gap in (5e-7, 1e-5, 1e-4, 5e-4, 1e-3, 1.5e-3, 1.7496e-3):
    r = simulate_record(model(gap), p, rec, options=opts, x0=x)
    x = np.array(r.states[:, 0])
    print(f"path gap {gap:.3g}: NRMSE {nrmse(r.force, rec.force):.5f}, cycles "
          f"{r.solver_stats['march_cycles']}, state {np.round(x[5:], 7)}")
print("cold state", np.round(cold.states[5:, 0], 7))
tight = dataclasses.replace(opts, steady_tol=opts.steady_tol * 1e-3, min_cycles=40)
r = simulate_record(m, p, rec, options=tight, x0=x, route="march")
print("warm marched >= 40 cycles", nrmse(r.force, rec.force), r.solver_stats["march_cycles"],
      np.round(r.states[5:, 0], 7))
