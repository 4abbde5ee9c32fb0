"""Table of the default diagnose / calibrate runs of runs/s12_outside/run.sh.

Usage: ``python runs/s12_outside/tabulate.py DIR [DIR_BEFORE]`` (markdown on stdout).
"""

from __future__ import annotations

import glob
import json
import os
import sys


def _refs(d):
    out = {}
    for name, ref in (d.get("reference_models") or {}).items():
        out[name] = [r["nrmse"] for r in ref.get("records", []) if r["role"] == "validation"]
    return out


def _physics(d, cmd):
    if cmd == "diagnose":
        h = d.get("heldout") or {}
        return list(h.values()) if isinstance(h, dict) else h
    recs = d.get("records") or []
    return [r.get("nrmse") for r in recs if r.get("role") == "validation"]


def _fmt(xs):
    return ",".join(f"{x:.3g}" for x in xs if x is not None) or "-"


def row(path_json, tag, cmd):
    base = path_json[: -len(".json")]
    t = open(base + ".time").read().split() if os.path.exists(base + ".time") else ["?"] * 3
    rc = open(base + ".rc").read().strip() if os.path.exists(base + ".rc") else "?"
    if not os.path.exists(path_json):
        err = open(base + ".err").read().strip().splitlines() if os.path.exists(
            base + ".err") else []
        last = next((x for x in reversed(err) if "compiling" not in x), "")
        return (f"| {tag} | {cmd} | rc {rc} | - | - | - | - | {last[:200]} | - | "
                f"{t[0]} ({t[1]}-{t[2]}) |")
    d = json.load(open(path_json))
    refs = _refs(d)
    summ = d.get("summary", "")
    first = (summ if isinstance(summ, str) else str(summ)).splitlines()[0] if summ else ""
    if cmd == "diagnose":
        added = ",".join(s.get("effect", "?") for s in d.get("steps", [])) or "-"
        cls = (d.get("baseline") or {}).get("device_class", "?")
        if isinstance(cls, dict):
            cls = cls.get("chosen", "?")
    else:
        added = "(fit only)"
        cls = d.get("device_class", "?")
        if isinstance(cls, dict):
            cls = cls.get("chosen", "?")
    flags = [f.get("kind", "?") for f in d.get("plausibility", []) or []]
    if cmd == "diagnose":
        fin = d.get("final") or {}
        flags += [f.get("kind", "?") for f in fin.get("plausibility", []) or []]
    return (f"| {tag} | {cmd} | {cls} | {added} | {_fmt(_physics(d, cmd))} | "
            f"{_fmt(refs.get('line', []))} | {_fmt(refs.get('two_slope', []))} | "
            f"{first[:260]} | {','.join(flags) or '-'} | {t[0]} ({t[1]}-{t[2]}) |")


def main(dirname):
    print("| record | command | class | added | physics held-out | line | two-slope | "
          "summary first line (260 chars) | plausibility flags | wall s (load start-end) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    tags = sorted({os.path.basename(p).split(".")[0] for p in glob.glob(f"{dirname}/*.rc")})
    for tag in tags:
        for cmd in ("diagnose", "calibrate"):
            if os.path.exists(f"{dirname}/{tag}.{cmd}.rc"):
                print(row(f"{dirname}/{tag}.{cmd}.json", tag, cmd))


if __name__ == "__main__":
    main(sys.argv[1])
