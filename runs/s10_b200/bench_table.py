"""Side-by-side table of two `liquidamp bench --cases diagnosis_200hz_10_cycles` JSONs.

python runs/s10_b200/bench_table.py BEFORE.json AFTER.json
"""
import json
import sys


def case(path):
    js = json.load(open(path))
    return js["cases"]["diagnosis_200hz_10_cycles"], js["load_average"]


(a, la), (b, lb) = case(sys.argv[1]), case(sys.argv[2])
print(f"load at start: before {la[0]:.2f}, after {lb[0]:.2f}")
print("| effect | before s | after s | added before | added after | param. error before | after "
      "| stop after |")
print("|---|---|---|---|---|---|---|---|")
for key in [k for k in a if k.startswith("seconds_")]:
    e = key[len("seconds_"):]

    def err(d, e=e):
        v = d.get(f"parameter_error_{e}")
        return "-" if v is None else f"{v:.3g}"
    print(f"| {e} | {a[key]:.1f} | {b.get(key, float('nan')):.1f} | {','.join(a[f'added_{e}'])} "
          f"| {','.join(b.get(f'added_{e}', []))} | {err(a)} | {err(b)} "
          f"| {b.get(f'stop_reason_{e}', '')[:60]} |")
