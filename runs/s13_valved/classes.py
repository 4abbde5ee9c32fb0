"""Print each case's class-choice outcomes.

Usage: ``PYTHONPATH=. python runs/s13_valved/classes.py DIR``.
"""
import glob
import json
import sys


def starts(d):
    b = d.get("baseline", d)
    for k in ("start", "device_class"):
        x = b.get(k)
        if isinstance(x, dict):
            v = x.get("classes") or x.get("starts")
            if v:
                return v
    return []


for f in sorted(glob.glob(f"{sys.argv[1]}/*.json")):
    try:
        d = json.load(open(f))
    except ValueError:
        continue
    print(f.split("/")[-1], "; ".join(
        f"{c['name']} {c['nrmse_calibration'] or 0:.4g}/{c['nrmse_validation'] or 0:.4g} "
        f"bic {c['bic'] or 0:.1f}{' ADM' if c['admissible'] else ''}"
        f"{' CHOSEN' if c['chosen'] else ''}{' cont' if c.get('continued') else ''}"
        f"{' ERR ' + c['error'][:60] if c.get('error') else ''}" for c in starts(d)))
    for w in d.get("warnings", []):
        if "revisit" in w:
            print("   ", w[:300])
