"""Where one bench effect's default diagnosis spends its time: wall time, model runs
(simulate_record), least-squares fits and integrator steps per stage (innermost stage wins).

PYTHONPATH=. python runs/s8_speed/stages_one.py CASE EFFECT
"""
import collections
import functools
import sys
import time

import scipy.optimize as LS

import liquidamp.analysis.measured.class_revisit as CR
import liquidamp.analysis.measured.diagnosis as D
import liquidamp.analysis.measured.diagnosis_fits as DF
import liquidamp.analysis.measured.record_model as RM
import liquidamp.coupled.fast as F
import liquidamp.coupled.periodic as PER
from liquidamp.analysis.bench_diagnosis import real_rate_records

STACK = ["other"]
T = collections.Counter()
N = collections.Counter()


def stage(mod, name, label=None):
    f = getattr(mod, name)
    lab = label or name

    @functools.wraps(f)
    def w(*a, **k):
        STACK.append(lab)
        t = time.perf_counter()
        try:
            return f(*a, **k)
        finally:
            dt = time.perf_counter() - t
            STACK.pop()
            T[lab + ":wall_incl"] += dt
    setattr(mod, name, w)


def counter(mod, name, what):
    f = getattr(mod, name)

    @functools.wraps(f)
    def w(*a, **k):
        N[STACK[-1] + ":" + what] += 1
        return f(*a, **k)
    setattr(mod, name, w)


for n in ("_prepare", "_screen", "_fit_round", "_device_round", "_reduce", "reference_models"):
    stage(D, n)
stage(D, "revisit_starts", "revisit_starts")
stage(CR, "_alternative_loop", "alt_loop")
for n in ("_refit", "_restart", "_converge"):
    stage(DF, n)
    setattr(D, n, getattr(DF, n)) if hasattr(D, n) else None
counter(RM, "simulate_record", "model_runs")
counter(LS, "least_squares", "lsq_fits")
counter(PER, "_shoot", "shootings")
_orig_run = F._run


def _run(options, args, out, info):
    x, rr = _orig_run(options, args, out, info)
    N[STACK[-1] + ":steps"] += int(info[3])
    return x, rr


F._run = _run
name, effect = sys.argv[1], sys.argv[2]
warm = real_rate_records(name, effect, warm=True)  # compile or load the kernels first
D.diagnose(warm, warm, max_steps=1, max_nfev=2, top=1)
recs = real_rate_records(name, effect)
T.clear()
N.clear()
t0 = time.perf_counter()
d = D.diagnose([recs[0]], [recs[1]])
print(f"{name} {effect}: {time.perf_counter() - t0:.1f} s, added {list(d.added)}")
for s in d.steps:
    print("  ", s.effect, {k: f"{v:.6g}" for k, v in s.parameters.items()})
for key in sorted(T):
    print(f"  {key} {T[key]:.1f}")
for key in sorted(N):
    print(f"  {key} {N[key]}")
