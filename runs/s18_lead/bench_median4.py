"""Medians of the 200 Hz bench over several A/B alternations (runs/s16_lead/bench_ab.sh):
python runs/s18_lead/bench_median4.py DIR [DIR ...]  (each holding A_1.json, B_1.json, ...)."""
import glob
import json
import os
import statistics
import sys

rows: dict = {}
for d in sys.argv[1:]:
    for f in sorted(glob.glob(os.path.join(d, "*_*.json"))):
        tag = os.path.basename(f).split("_")[0]
        c = json.load(open(f))["cases"]["diagnosis_200hz_10_cycles"]
        for k, v in c.items():
            if k.startswith("seconds_"):
                e = k[len("seconds_"):]
                rows.setdefault(e, {}).setdefault(tag, []).append(v)
                rows[e].setdefault(tag + "_added", set()).add(tuple(c[f"added_{e}"]))
print("| effect | A median (n) | B median (n) | B/A | added (A; B) |")
print("|---|---|---|---|---|")
for e, d in rows.items():
    a, b = statistics.median(d["A"]), statistics.median(d["B"])
    print(f"| {e} | {a:.2f} ({len(d['A'])}) | {b:.2f} ({len(d['B'])}) | {b / a:.3f} | "
          f"{sorted(d['A_added'])}; {sorted(d['B_added'])} |")
print(f"| max | {max(statistics.median(d['A']) for d in rows.values()):.2f} | "
      f"{max(statistics.median(d['B']) for d in rows.values()):.2f} | | |")
