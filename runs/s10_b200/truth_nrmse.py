"""NRMSE of the truth model (paper_calibrated with the hidden effect at its truth) and of
nearby points on the conditioned 200 Hz bench records.

PYTHONPATH=. python runs/s10_b200/truth_nrmse.py EFFECT [JSON of {multiplier: value}]
"""
import json
import sys

from liquidamp.analysis.bench_diagnosis import REAL_RATE_RECORDS, real_rate_records
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.diagnosis_options import march_options
from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model

name = "diagnosis_200hz_10_cycles"
eff = sys.argv[1]
truth = REAL_RATE_RECORDS[name][-1][eff]
extra = json.loads(sys.argv[2]) if len(sys.argv) > 2 else {}
recs = real_rate_records(name, eff)
conds = [condition(r)[0] for r in recs]
opts = march_options(None, conds)
model = with_effects(get_model("full"), make_effect(eff, **{**truth, **extra.get(eff, {})}))
p = preset("paper_calibrated")
if extra.get("scale"):
    p = p.scaled(**extra["scale"])
for routes in ("auto", "march"):
    out = []
    for _r, c in zip(recs, conds, strict=True):
        f = simulate_record(model, p, c, options=opts, route=routes).force
        out.append(nrmse(f, c.force))
    print(routes, [round(x, 6) for x in out])
