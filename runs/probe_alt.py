"""Print both loops of the class revisit for one case: python runs/probe_alt.py CASE."""
import sys
import time
import warnings

import importlib

dg = importlib.import_module("liquidamp.analysis.measured.diagnosis")
from liquidamp.analysis.measured.records import read_record

I = "/work/shared/data/independent-records/"
orig = dg.revisit


def spy(run, run2, chosen, alt, sel):
    for tag, r in ((chosen, run), (alt, run2)):
        print(f"== {tag}: baseline cal {r['baseline'].nrmse_calibration:.4g} val "
              f"{r['baseline'].nrmse_validation:.4g}")
        for s in r["steps"]:
            print("  +", s.effect, {k: f"{v:.4g}" for k, v in s.parameters.items()
                                    if isinstance(v, float)},
                  f"cal {s.nrmse_calibration:.4g} val {s.nrmse_validation:.4g}")
        print("  final effects", r["current"].effects)
        print("  mult", r["current"].parameters_dict()["multipliers"])
        print("  stop", r["stop"][:300])
    return orig(run, run2, chosen, alt, sel)


dg.revisit = spy
c = sys.argv[1]
t = time.time()
with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    d = dg.diagnose([read_record(I + c + "_cal.csv")], [read_record(I + c + "_val.csv")])
print(d.summary())
print(time.time() - t)
