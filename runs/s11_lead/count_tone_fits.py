"""How often, and how long, the default diagnosis of the tapered friction-damper records asks
for a stroke's line-spectrum fit (session 11: 2264 calls, 95 of 182 s before the fit was
made once per distinct stroke; 1 s after).

    python runs/s11_lead/count_tone_fits.py

Data: Coble, Huggins, Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash,
CC BY-SA 4.0 (read from ../shared/data/friction-damper-backlash, or LIQUIDAMP_SHARED).
"""
import os
import time
from pathlib import Path

import liquidamp.analysis.measured.records as R
from liquidamp.analysis.measured.diagnosis import diagnose

_fit = R.tone_fit
stats = {"calls": 0, "seconds": 0.0}


def counted(t, y, *args, **kwargs):
    t0 = time.time()
    out = _fit(t, y, *args, **kwargs)
    stats["calls"] += 1
    stats["seconds"] += time.time() - t0
    return out


R.tone_fit = counted
shared = Path(os.environ.get("LIQUIDAMP_SHARED",
                             Path(__file__).resolve().parents[3] / "shared"))
d = shared / "data" / "friction-damper-backlash"
cal = R.read_record(d / "brfd30_0.5Hz_0.5in_full.csv")
val = [R.read_record(d / f) for f in ("brfd30_1Hz_0.5in_full.csv",
                                      "brfd30_0.25Hz_0.5in_full.csv")]
t0 = time.time()
diagnose([cal], val)
print(f"diagnose {time.time() - t0:.1f} s; tone_fit {stats['calls']} calls, "
      f"{stats['seconds']:.2f} s; load {os.getloadavg()}")
