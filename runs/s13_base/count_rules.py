"""Run the default diagnose in-process on shared cases (or sweep records), counting how often
each of this session's rules acts and what it costs.

    PYTHONPATH=. python runs/s13_base/count_rules.py d01 d03 fd_steady B_cavitation

* ``air_refit``: the air continuation's refits (calibration._air_continued with a bound to
  lower), ``air_kept`` those kept, ``air_s`` their wall time;
* ``force``: the device's-credit tests of a chosen effect (diagnosis_credit.effect_force),
  ``negligible`` those that found its force hidden by the noise, ``force_s`` their time.

A sweep id is read from /tmp/s13_base/records (``sweep.py gen``).
"""
from __future__ import annotations

import glob
import os
import sys
import time
import warnings

import liquidamp.analysis.measured.calibration as cal_mod
import liquidamp.analysis.measured.diagnosis_credit as credit_mod
from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.records import read_record

SHARED = "/work/shared/data"
RECORDS = "/tmp/s13_base/records"
COUNT = {}


def _air(orig):
    def air(res, refit):
        def counted(spec):
            COUNT["air_refit"] += 1
            t = time.time()
            r = refit(spec)
            COUNT["air_s"] += time.time() - t
            return r
        out = orig(res, counted)
        COUNT["air_kept"] += out is not res
        return out
    return air


def _force(orig):
    def force(*a, **k):
        t = time.time()
        r = orig(*a, **k)
        COUNT["force_s"] += time.time() - t
        COUNT["force"] += 1
        COUNT["negligible"] += bool(r is not None and r.negligible)
        return r
    return force


def _records(tag):
    fd = f"{SHARED}/friction-damper-backlash"
    if tag.startswith("fd_"):
        return ([read_record(f"{fd}/brfd30_0.5Hz_0.5in_steady.csv")],
                [read_record(f"{fd}/brfd30_{f}_0.5in_steady.csv") for f in ("1Hz", "0.25Hz")])
    if os.path.exists(f"{RECORDS}/{tag}_cal.csv"):
        return ([read_record(f"{RECORDS}/{tag}_cal.csv")],
                [read_record(f"{RECORDS}/{tag}_val.csv")])
    c = glob.glob(f"{SHARED}/independent-records/{tag}_*cal.csv")[0]
    return [read_record(c)], [read_record(c.replace("_cal.csv", "_val.csv"))]


def main(tags):
    warnings.simplefilter("ignore")
    cal_mod._air_continued = _air(cal_mod._air_continued)
    credit_mod.effect_force = _force(credit_mod.effect_force)
    for tag in tags:
        COUNT.update(air_refit=0, air_kept=0, air_s=0.0, force=0, negligible=0, force_s=0.0)
        cal, val = _records(tag)
        load = os.getloadavg()[0]
        t = time.time()
        d = diagnose(cal, val)
        print(tag, d.added, f"{time.time() - t:.1f} s (load {load:.2f})",
              {k: round(v, 2) for k, v in COUNT.items()}, flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
