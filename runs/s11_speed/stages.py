"""Where the default diagnosis of one CAL/VAL pair spends its time (s11-speed).

    PYTHONPATH=. python runs/s11_speed/stages.py CAL.csv VAL.csv
    PYTHONPATH=. python runs/s11_speed/stages.py sweep RECORD_ID    # runs/s10_unseen/sweep.py
    S11_NO_SCREEN=1 PYTHONPATH=. python runs/s11_speed/stages.py ...  # main's behaviour

With ``S11_NO_SCREEN=1`` the design starts' screen (class_revisit.screened) never stops a
start: the diagnosis then runs as on main (5a8f4e4), for before/after counts on one tree.

The library form of ``liquidamp diagnose CAL --validate VAL`` (``diagnose([cal], [val])``
on the records as read), with wall time, model runs (simulate_record), least-squares fits,
integrator steps and the phases each model run needs, per stage (innermost stage wins), and
per alternative start (time from the previous start's end to its verdict).
"""
import collections
import functools
import os
import sys
import time

import scipy.optimize as LS

import liquidamp.analysis.measured.class_revisit as CR
import liquidamp.analysis.measured.diagnosis as D
import liquidamp.analysis.measured.diagnosis_fits as DF
import liquidamp.analysis.measured.record_model as RM
import liquidamp.coupled.fast as F
from liquidamp.analysis.measured.records import read_record

STACK = ["other"]
T = collections.Counter()
N = collections.Counter()
ALT = []
MARK = [0.0]


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
            T[lab] += time.perf_counter() - t
            STACK.pop()
    setattr(mod, name, w)
    return w


for n in ("_prepare", "_screen", "_fit_round", "_device_round", "_reduce",
          "_bounded_reductions", "_profile_step", "reference_models", "_loop"):
    stage(D, n)
for n in ("_refit", "_restart", "_converge"):
    w = stage(DF, n)
    if hasattr(D, n):
        setattr(D, n, w)
stage(CR, "_alternative_loop", "alt_loop")
_orig_rs = CR.revisit_starts


def _rs(*a, **k):
    MARK[0] = time.perf_counter()
    STACK.append("revisit")
    try:
        return _orig_rs(*a, **k)
    finally:
        STACK.pop()


D.revisit_starts = _rs
_orig_rev = CR.revisit


def _rev(run, alt_run, chosen, alt, sel, cls=""):
    now = time.perf_counter()
    ALT.append((alt, now - MARK[0], N["runs_total"], ", ".join(s.effect for s in
                                                               alt_run["steps"])))
    MARK[0] = now
    return _orig_rev(run, alt_run, chosen, alt, sel, cls)


CR.revisit = _rev
_orig_screened = CR.screened


def _screened(run, base2, first, sel):
    if os.environ.get("S11_NO_SCREEN") == "1":
        return ""
    t = time.perf_counter()
    n0 = N["runs_total"]
    why = _orig_screened(run, base2, first, sel)
    ALT.append(("screen of " + base2.start_params.name + (": stopped" if why else ": passed"),
                time.perf_counter() - t, N["runs_total"] - n0, ""))
    return why


CR.screened = _screened
_orig_sim = RM.simulate_record


def _sim(*a, **k):
    N[STACK[-1] + ":runs"] += 1
    N["runs_total"] += 1
    return _orig_sim(*a, **k)


RM.simulate_record = _sim
for mod in (D, DF):
    if hasattr(mod, "simulate_record"):
        mod.simulate_record = _sim
import liquidamp.analysis.measured.fit_objective as FO  # noqa: E402

if hasattr(FO, "simulate_record"):
    FO.simulate_record = _sim
_orig_lsq = LS.least_squares
_orig_run = F._run


def _run(options, args, out, info):
    x, rr = _orig_run(options, args, out, info)
    N[STACK[-1] + ":steps"] += int(info[3])
    N[STACK[-1] + ":integrations"] += 1
    return x, rr


F._run = _run
_orig_phases = RM._phases


def _phases(record, cond, t, rig_stroke, origin):
    out = _orig_phases(record, cond, t, rig_stroke, origin)
    N[STACK[-1] + ":phases"] += out[1].size
    return out


RM._phases = _phases

if __name__ == "__main__":
    if sys.argv[1] == "sweep":
        sys.path.insert(0, "runs/s10_unseen")
        from sweep import records

        cal, val = records(sys.argv[2])
    else:
        cal, val = read_record(sys.argv[1]), read_record(sys.argv[2])
    print(f"cal {cal.time.size} samples at {cal.sampling_rate:.6g} Hz, f {cal.frequency:.6g};"
          f" val {val.time.size} at {val.sampling_rate:.6g} Hz, f {val.frequency:.6g}",
          flush=True)
    t0 = time.perf_counter()
    d = D.diagnose([cal], [val])
    wall = time.perf_counter() - t0
    print(f"wall {wall:.1f} s; added {list(d.added)}; held-out {d.final.nrmse_validation:.4g};"
          f" stop {d.stop_reason}")
    print(d.summary().splitlines()[0][:300])
    for c in d.conditioning:
        print(" ", c.describe()[:300])
    print("stage wall (inclusive, s):")
    for k, v in sorted(T.items(), key=lambda kv: -kv[1]):
        print(f"  {k:22s} {v:8.1f}")
    print("counts (innermost stage):")
    for k, v in sorted(N.items()):
        print(f"  {k:34s} {v}")
    print("alternative starts (s since the previous one, model runs so far, added; "
          "screens: s, model runs of the screen):")
    for a in ALT:
        print(f"  {a[1]:7.1f}  {a[2]:6d}  {a[0]}  [{a[3]}]")
