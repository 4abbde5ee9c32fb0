"""Compare two `liquidamp bench --cases diagnosis_200hz_10_cycles` JSON files effect by effect.

    python runs/s11_speed/compare_bench.py BEFORE.json AFTER.json
"""
import json
import sys

a, b = (json.load(open(p))["cases"]["diagnosis_200hz_10_cycles"] for p in sys.argv[1:3])
print("| effect | s before | s after | added before | added after | param. error before | after |")
print("|---|---|---|---|---|---|---|")
for k in sorted(k[len("seconds_"):] for k in a if k.startswith("seconds_")):
    print(f"| {k} | {a['seconds_' + k]:.2f} | {b.get('seconds_' + k, float('nan')):.2f} | "
          f"{','.join(a.get('added_' + k, []))} | {','.join(b.get('added_' + k, []))} | "
          f"{a.get('parameter_error_' + k)} | {b.get('parameter_error_' + k)} |")
