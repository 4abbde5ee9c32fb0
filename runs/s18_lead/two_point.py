"""Score at the probe against score at the probe's linearized estimate (one more run), per
candidate of the first screen of each 200 Hz bench record:
python runs/s18_lead/two_point.py [EFFECT ...]."""
import math
import sys
from dataclasses import replace

import numpy as np

import liquidamp.analysis.measured.diagnosis as dg
from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured import diagnosis_evidence as ev
from liquidamp.analysis.measured.fit_objective import predict
from liquidamp.device.effects import EFFECTS

name = "diagnosis_200hz_10_cycles"
effects = sys.argv[1:] or list(REAL_RATE_RECORDS[name][5])
orig = dg._screen
done = []


def drop_of(change, result, options, preroll):
    Fp = predict(result.model, change.params or result.params, change.effects,
                 result.calibration, options=options, preroll=preroll)
    meas = np.concatenate([r.force for r in result.calibration])
    scale = float(np.sqrt(np.mean((meas - meas.mean()) ** 2))) * math.sqrt(meas.size)
    r = (np.concatenate(result.predictions_calibration) - meas) / scale
    s = (np.concatenate(Fp) - np.concatenate(result.predictions_calibration)) / scale
    J, P = ev._free_projector(result, r)
    sp = s - J @ (P @ s) if J.size else s
    ss = float(sp @ sp)
    return (float(sp @ r) ** 2 / ss) / float(r @ r), -float(sp @ r) / ss


def screen(names, current, options, bud, sel, route="auto"):
    out = orig(names, current, options, bud, sel, route)
    if done:
        return out
    done.append(1)
    ranked, probes = out[0], out[1]
    rows = []
    for c in ranked:
        if c.score <= 0 or c.effect not in probes:
            continue
        ch = probes[c.effect]
        eff, key = ch.lead
        if eff not in EFFECTS or eff != ch.added:
            rows.append((c.effect, c.score, None, None))
            continue
        d1, beta = drop_of(ch, current, options, bud.preroll)
        est = ch.estimate(beta)
        lo, hi = EFFECTS[eff].bounds[key]
        est = min(max(est, lo), hi)
        e2 = tuple(e.replace(**{key: est}) if e.name == eff else e for e in ch.effects)
        try:
            d2, beta2 = drop_of(replace(ch, effects=e2, probe=est), current, options,
                                bud.preroll)
        except Exception as exc:  # noqa: BLE001
            d2, beta2 = float("nan"), str(exc)[:40]
        rows.append((c.effect, c.score, d2, f"{ch.probe:.3g}->{est:.3g} beta2 {beta2}"))
    rows.sort(key=lambda r: -(r[2] if r[2] is not None and r[2] == r[2] else r[1]))
    for r in rows[:7]:
        at = r[2] if r[2] is None else round(r[2], 4)
        print(f"   {r[0]:20s} score {r[1]:.4f}  at estimate {at}  {r[3]}")
    return out


dg._screen = screen
for effect in effects:
    done.clear()
    print("==", effect)
    recs = real_rate_records(name, effect)
    dg.diagnose([recs[0]], [recs[1]], max_steps=1, max_nfev=2, top=1)
