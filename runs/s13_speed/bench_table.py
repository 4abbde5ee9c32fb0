"""Side-by-side 200 Hz bench: ``python runs/s13_speed/bench_table.py A.json B.json``."""

import json
import sys

if __name__ == "__main__":
    runs = [json.load(open(p)) for p in sys.argv[1:]]
    cases = [r["cases"]["diagnosis_200hz_10_cycles"] for r in runs]
    keys = [k for k in cases[0] if k.startswith("seconds_")]
    print("| record | " + " | ".join(f"{p} s" for p in sys.argv[1:]) + " | added same |")
    print("|---|" + "---|" * (len(runs) + 1))
    for k in keys:
        e = k[len("seconds_"):]
        same = len({str(c.get(f"added_{e}")) for c in cases}) == 1
        print(f"| {e} | " + " | ".join(f"{c.get(k, float('nan')):.2f}" for c in cases)
              + f" | {same} |")
    print("| max | " + " | ".join(f"{max(c[k] for k in keys):.2f}" for c in cases) + " | |")
    print("| load (1, 5, 15 min) | " + " | ".join(
        ", ".join(f"{x:.1f}" for x in r["load_average"]) for r in runs) + " | |")
