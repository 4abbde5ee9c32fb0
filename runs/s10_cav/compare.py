"""Side-by-side of two `liquidamp bench --json` files of the 200 Hz case (before, after).

python runs/s10_cav/compare.py runs/s9_bench/b_200.json runs/s10_cav/b_200.json
"""
import json
import sys
from pathlib import Path

CASE = "diagnosis_200hz_10_cycles"
b, a = (json.loads(Path(f).read_text())["cases"][CASE] for f in sys.argv[1:3])
print("| effect | s before | s after | added before | added after | param. error before | after "
      "| stop after |")
print("|---|---|---|---|---|---|---|---|")
for key in [k for k in a if k.startswith("seconds_")]:
    e = key[len("seconds_"):]

    def f(d, k, e=e):
        v = d.get(f"{k}_{e}")
        return f"{v:.3g}" if isinstance(v, float) else str(v)
    print(f"| {e} | {f(b, 'seconds')} | {f(a, 'seconds')} | {f(b, 'added')} | {f(a, 'added')} "
          f"| {f(b, 'parameter_error')} | {f(a, 'parameter_error')} "
          f"| {str(a.get('stop_reason_' + e))[:60]} |")
