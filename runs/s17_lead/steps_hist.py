"""Integrator steps per period of the compiled marches logged by runs/s17_lead/hook.

    LIQ_STEPLOG=LOG PYTHONPATH=.:runs/s17_lead/hook python -m liquidamp diagnose ...
    python runs/s17_lead/steps_hist.py LOG

Periodic marches (march_cycles, and one-period runs under a periodic stroke) count steps per
period; whole-record runs (no period) are listed apart.
"""
import json
import sys

import numpy as np

rows = [json.loads(line) for line in open(sys.argv[1])]
per = np.array([r["steps"] / r["cycles"] for r in rows if r["cycles"] > 0])
whole = np.array([r["steps"] for r in rows if r["cycles"] == 0])
failed = [r for r in rows if r["err"]]
print(f"{len(rows)} compiled runs; {per.size} periodic: steps per period median "
      f"{np.median(per):.0f}, 99 % {np.percentile(per, 99):.0f}, 99.9 % "
      f"{np.percentile(per, 99.9):.0f}, most {per.max():.0f}")
if whole.size:
    print(f"{whole.size} whole-record runs: steps median {np.median(whole):.0f}, most "
          f"{whole.max():.0f}")
print(f"{len(failed)} failed:", sorted({r['err'][:60] for r in failed}))
