"""Cost history of every least-squares fit of one 200 Hz bench diagnosis:
python runs/s18_lead/fit_history.py EFFECT."""
import sys

import numpy as np
import scipy.optimize as so

from liquidamp.analysis.bench_diagnosis import real_rate_records
from liquidamp.analysis.measured.diagnosis import diagnose

name = "diagnosis_200hz_10_cycles"
effect = sys.argv[1]
warm = real_rate_records(name, effect, warm=True)[0]
diagnose([warm], [warm], max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
orig = so.least_squares


def ls(fun, x0, **kw):
    hist = []

    def f(x):
        r = fun(x)
        hist.append(float(np.asarray(r) @ np.asarray(r)))
        return r
    sol = orig(f, x0, **kw)
    best = np.minimum.accumulate(hist)
    final = best[-1]
    # first evaluation within 1e-3 / 1e-2 of the final cost
    i3 = int(np.argmax(best <= final * (1 + 1e-3)))
    i2 = int(np.argmax(best <= final * (1 + 1e-2)))
    print(f"k={len(x0)} nfev {sol.nfev} njev {sol.njev} status {sol.status} ftol {kw.get('ftol')}"
          f" cost0 {hist[0]:.4g} final {final:.4g}  evals to 1%: {i2 + 1}  to 0.1%: {i3 + 1}"
          f" of {len(hist)}")
    return sol


so.least_squares = ls
d = diagnose([recs[0]], [recs[1]])
print(d.added)
