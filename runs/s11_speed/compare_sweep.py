"""Sweep records before (runs/s10_lead/sweep) and after (OUTDIR): added effects, final effect
parameters, held-out NRMSE, seconds, and the screen's stops.

    python runs/s11_speed/compare_sweep.py OUTDIR
"""
import json
import sys
from pathlib import Path

out = Path(sys.argv[1])
print("| record | added before -> after | effect parameters equal | held-out before -> after "
      "| diagnose s before -> after (load) | design starts stopped by the screen |")
print("|---|---|---|---|---|---|")
for p in sorted(out.glob("*.json")):
    b = json.loads((Path("runs/s10_lead/sweep") / p.name).read_text())
    a = json.loads(p.read_text())
    ea, eb = a["final"]["parameters"].get("effects"), b["final"]["parameters"].get("effects")
    ha, hb = max(a["heldout"].values()), max(b["heldout"].values())
    load = (out / (p.stem + ".time")).read_text().split("(", 1)[-1].rstrip(")\n")
    stops = sum("is not diagnosed: neither" in w for w in a["warnings"])
    print(f"| {p.stem} | {','.join(s['effect'] for s in b['steps']) or '-'} -> "
          f"{','.join(s['effect'] for s in a['steps']) or '-'} | {ea == eb} | {hb:.4g} -> "
          f"{ha:.4g} | {b['sweep']['seconds']:.0f} -> {a['sweep']['seconds']:.0f} ({load}) | "
          f"{stops} |")
