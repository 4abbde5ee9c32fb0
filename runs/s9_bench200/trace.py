"""Every loop of one 200 Hz bench effect's default diagnosis, round by round (the chosen
start's loop and each alternative start's), with the candidates' evidence.

PYTHONPATH=. python runs/s9_bench200/trace.py EFFECT [CASE] [DIAGNOSE_KEYWORDS_JSON]
"""
import json
import sys
import time

import liquidamp.analysis.measured.diagnosis as D
from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records


def show_round(tag, ranked):
    print(f"  {tag}")
    for c in ranked:
        if c.note.startswith("not applicable"):
            continue
        if c.score <= 0 and not c.refitted:
            continue
        print(f"    {c.effect:20s} score {c.score:.3g} "
              + (f"cal {c.nrmse_calibration:.4g} val {c.nrmse_validation:.4g} "
                 f"dBIC {c.delta_bic:.4g} acc {c.accepted} " if c.refitted
                 and c.nrmse_calibration is not None else "")
              + (f"est {c.estimate} " if c.estimate else "")
              + f"| {c.note[:160]}")


def show_run(label, run):
    b = run["baseline"]
    print(f"== {label}: baseline cal {b.nrmse_calibration:.4g} val {b.nrmse_validation:.4g} "
          f"mult { {k: round(v, 4) for k, v in b.values.items()} }")
    for s in run["device_steps"]:
        show_round(f"device {s.effect} {s.parameters} cal {s.nrmse_calibration:.4g} "
                   f"val {s.nrmse_validation:.4g}", s.candidates)
    for i, s in enumerate(run["steps"]):
        show_round(f"step {i + 1}: + {s.effect} cal {s.nrmse_calibration:.4g} "
                   f"val {s.nrmse_validation:.4g} {s.parameters}", s.candidates)
    if run["last_round"]:
        show_round("last round (rejected)", run["last_round"])
    print("  stop:", run["stop"])
    print("  final mult", {k: round(v, 4) for k, v in run["current"].values.items()})


_orig_loop = D._loop


def _loop(*a, **k):
    run = _orig_loop(*a, **k)
    show_run("loop", run)
    return run


def traced(fn, *a, **k):
    """``fn(*a, **k)`` with every diagnosis loop printed round by round."""
    D._loop = _loop
    try:
        return fn(*a, **k)
    finally:
        D._loop = _orig_loop


def report(d):
    print("noise nrmse", d.noise_nrmse)
    print(d.summary())
    for w in d.warnings:
        print("warning:", w[:400])


if __name__ == "__main__":
    effect = sys.argv[1]
    name = sys.argv[2] if len(sys.argv) > 2 and sys.argv[2] else "diagnosis_200hz_10_cycles"
    kw = json.loads(sys.argv[3]) if len(sys.argv) > 3 else {}
    warm = real_rate_records(name, effect, warm=True)
    D.diagnose(warm, warm, max_steps=1, max_nfev=2, top=1)
    recs = real_rate_records(name, effect)
    t0 = time.perf_counter()
    d = traced(D.diagnose, [recs[0]], [recs[1]], **kw)
    print(f"{effect}: {time.perf_counter() - t0:.1f} s, added {list(d.added)}")
    print("truth", REAL_RATE_RECORDS[name][-1][effect])
    report(d)
