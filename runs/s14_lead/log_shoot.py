"""Run a liquidamp command with every periodic shooting logged (one JSON line each).

    python runs/s14_lead/log_shoot.py LOG.jsonl diagnose CAL --validate VAL --json OUT

Each line: ok, wall seconds, one-period runs, iterations, Newton steps, marched periods, final
residual, accepted (below ShootingOptions.accept; absent before session 14), or the error.
"""

import json
import sys
import time

import liquidamp.coupled.periodic as periodic
from liquidamp.cli import main

_shoot = periodic._shoot
LOG = open(sys.argv[1], "w")  # noqa: SIM115 (kept open for the whole run)


def logged(rig, engine, x, target, options, shooting, out_grid=None):
    t0 = time.perf_counter()
    try:
        r = _shoot(rig, engine, x, target, options, shooting, out_grid)
    except Exception as exc:
        row = dict(ok=False, s=time.perf_counter() - t0, err=str(exc)[:300], n=len(x))
        LOG.write(json.dumps(row) + "\n")
        LOG.flush()
        raise
    row = dict(ok=True, s=time.perf_counter() - t0, runs=r[1], it=r[2], newton=r[3],
               marched=r[4], res=r[5], n=len(x), accepted=bool(r[7]) if len(r) > 7 else None)
    LOG.write(json.dumps(row) + "\n")
    LOG.flush()
    return r


periodic._shoot = logged
sys.exit(main(sys.argv[2:]))
