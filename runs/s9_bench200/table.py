"""Before/after table of the 200 Hz bench: before = runs/s9_bench200/before/EFFECT.json
(one.py on main 261aa68), after = a `liquidamp bench --json` file.

python runs/s9_bench200/table.py runs/s9_bench200/bench_after.json
"""
import json
import sys
from pathlib import Path

here = Path(__file__).parent


def find(js):
    if isinstance(js, dict):
        if any(k.startswith("seconds_") for k in js):
            return js
        for v in js.values():
            r = find(v)
            if r:
                return r
    return None


after = find(json.loads(Path(sys.argv[1]).read_text()))
print("| effect | before s | after s | added before | added after | param. rel. error before "
      "| after |")
print("|---|---|---|---|---|---|---|")
for key in [k for k in after if k.startswith("seconds_")]:
    e = key[len("seconds_"):]
    try:
        b = json.loads((here / "before" / f"{e}.json").read_text())
        bs, ba = f"{b['seconds']:.1f}", ",".join(s["effect"] for s in b["steps"])
        be = "-" if b["parameter_error"] is None else f"{b['parameter_error']:.3g}"
    except OSError:
        bs = ba = be = "?"
    ae = after.get(f"parameter_error_{e}")
    print(f"| {e} | {bs} | {after[key]:.1f} | {ba} | {','.join(after[f'added_{e}'])} | {be} | "
          + ("-" if ae is None else f"{ae:.3g}") + " |")
