"""A shared case's default `liquidamp diagnose` (as runs/run_case.sh runs it) with
class_revisit.CHANNEL_REACH set in this process (an experiment; the library is not changed).

LIQUIDAMP_SHARED=/work/shared PYTHONPATH=. python runs/s10_unseen/shared_variant.py TAG OUTDIR R
"""
import glob
import os
import sys
import time
from pathlib import Path

import liquidamp.analysis.measured.class_revisit as CR
from liquidamp.cli import main

tag, out, reach = sys.argv[1], Path(sys.argv[2]), float(sys.argv[3])
CR.CHANNEL_REACH = reach
out.mkdir(parents=True, exist_ok=True)
d = Path(os.environ.get("LIQUIDAMP_SHARED", "/work/shared")) / "data" / "independent-records"
cal = glob.glob(str(d / f"{tag}_*cal.csv"))[0]
val = cal[:-len("_cal.csv")] + "_val.csv"
t0 = time.time()
sys.stdout = open(out / f"{tag}.out", "w")
rc = main(["diagnose", cal, "--validate", val, "--json", str(out / f"{tag}.json")])
(out / f"{tag}.time").write_text(f"{time.time() - t0:.1f}\n")
(out / f"{tag}.rc").write_text(f"{rc}\n")
