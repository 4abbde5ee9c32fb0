"""Session 19: read diagnosis JSONs (``liquidamp diagnose --json``) of a sweep, no model run.

    python runs/s19_lead/read_jsons.py floors DIR..    # final calibration vs the noise level,
                                                       # each held-out NRMSE vs its own floor
    python runs/s19_lead/read_jsons.py ties DIR..      # steps where, among the candidates
                                                       # tied on held-out data (10 %), the
                                                       # lowest delta BIC is another effect
    python runs/s19_lead/read_jsons.py bic-first DIR.. # steps where the best held out of the
                                                       # candidates within 10 of the lowest
                                                       # delta BIC is another effect

``ties`` and ``bic-first`` are what-ifs of two tie rules on the recorded evidence: each names
the first step a rule would change (the loop after it is not replayed).
"""
from __future__ import annotations

import glob
import json
import os
import sys


def _jsons(dirs):
    for d in dirs:
        for f in sorted(glob.glob(os.path.join(d, "*.json"))):
            try:
                j = json.load(open(f))
            except (OSError, ValueError):
                continue
            if "steps" in j and "conditioning" in j:
                yield f"{os.path.basename(d)}/{os.path.basename(f)[:-5]}", j


def floors(dirs) -> None:
    """Final calibration NRMSE over the noise floor, worst held-out NRMSE over its floor."""
    for name, j in _jsons(dirs):
        fl = {c["source"]: c["noise_floor"]["nrmse"] for c in j["conditioning"]
              if c.get("noise_floor")}
        ratio = max((v / fl[k] for k, v in j["heldout"].items() if k in fl), default=None)
        cal = j["final"]["nrmse"]["calibration"] / j["noise_floor_nrmse"]
        flag = "at the noise, held out far" if cal <= 1.5 and (ratio or 0) > 2 else ""
        print(f"{name:36s} cal/floor {cal:6.2f}  held-out/floor "
              f"{ratio if ratio is not None else float('nan'):7.2f}  {flag:26s} "
              f"{[s['effect'] for s in j['steps']]}")


def _changed(dirs, pick) -> None:
    for name, j in _jsons(dirs):
        for i, s in enumerate(j["steps"]):
            passed = [c for c in s.get("evidence") or () if c.get("accepted")]
            if not passed:
                continue
            w = pick(passed)
            if w["effect"] != s["effect"]:
                ch = next((c for c in passed if c["effect"] == s["effect"]), None)
                was = (f"held-out ratio {1 - ch['relative_reduction']:.3f}, dBIC "
                       f"{ch['delta_bic']:.1f}" if ch else "not among the passed")
                print(f"{name} step {i + 1}: {s['effect']} ({was}) -> {w['effect']} "
                      f"(held-out ratio {1 - w['relative_reduction']:.3f}, dBIC "
                      f"{w['delta_bic']:.1f})")
                break


def _ties(passed, tol=0.10):
    best = min(1 - c["relative_reduction"] for c in passed)
    tied = [c for c in passed if 1 - c["relative_reduction"] <= (1 + tol) * best]
    return min(tied, key=lambda c: c["delta_bic"])


def _bic_first(passed, margin=10.0):
    b = min(c["delta_bic"] for c in passed)
    return min((c for c in passed if c["delta_bic"] <= b + margin),
               key=lambda c: 1 - c["relative_reduction"])


if __name__ == "__main__":
    cmd, dirs = sys.argv[1], sys.argv[2:]
    if cmd == "floors":
        floors(dirs)
    else:
        _changed(dirs, {"ties": _ties, "bic-first": _bic_first}[cmd])
