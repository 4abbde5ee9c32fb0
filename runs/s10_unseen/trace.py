"""Every loop of one sweep record's default diagnosis, round by round (the show functions
are runs/s9_bench200/trace.py's).

PYTHONPATH=. python runs/s10_unseen/trace.py ID [DIAGNOSE_KEYWORDS_JSON]
"""
import json
import sys
import time
from pathlib import Path

import liquidamp.analysis.measured.diagnosis as D

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sweep  # noqa: E402


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


D._loop = _loop
rid = sys.argv[1]
kw = json.loads(sys.argv[2]) if len(sys.argv) > 2 else {}
cal, val = sweep.records(rid)
t0 = time.perf_counter()
d = D.diagnose([cal], [val], **kw)
print(f"{rid}: {time.perf_counter() - t0:.1f} s, added {list(d.added)}")
print("truth", sweep.truth(*rid.split("_", 1)))
print("noise nrmse", d.noise_nrmse)
print(d.summary())
for w in d.warnings:
    print("warning:", w[:400])
