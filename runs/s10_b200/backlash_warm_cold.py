"""The backlash refit of the 200 Hz Coulomb-friction bench record: its least-squares
objective at the solution warm (the fit's last orbits) against cold (from rest), with the
states at the first sample.

PYTHONPATH=. python runs/s10_b200/backlash_warm_cold.py
"""
import numpy as np
import scipy.optimize

import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.fit_objective import FitObjective

_ls = scipy.optimize.least_squares


def ls(fun, x0, *a, **k):
    s = _ls(fun, x0, *a, **k)
    if len(x0) == 7 and isinstance(fun, FitObjective):
        obj = fun
        warm = {i: v.copy() for i, v in obj.warm.items()}
        r_w = obj(s.x)
        print("warm at sol", float(np.sqrt(r_w @ r_w)), np.round(warm[0], 7))
        obj.warm.clear()
        r_c = obj(s.x)
        print("cold at sol", float(np.sqrt(r_c @ r_c)), np.round(obj.warm[0], 7))
        print("names", [p.name for p in obj.var], obj.model.state_names)
    return s


scipy.optimize.least_squares = ls
recs = real_rate_records("diagnosis_200hz_10_cycles", "coulomb_friction")
D.diagnose([recs[0]], [recs[1]], max_steps=1, candidates=["coulomb_friction", "backlash"])
