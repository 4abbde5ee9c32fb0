"""Session 20: where in frequency the default's final friction model misses the friction
damper's records: the residual's power per band of stroke harmonics, and the NRMSE each
record would have were it judged only below a given frequency.  Records: Coble, Huggins,
Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash (ARTS-Laboratory),
CC BY-SA 4.0.

usage: python runs/s20_lead/fd_spectrum.py DEVICE.toml [steady|full]
"""
import sys

import numpy as np

from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.record_model import simulate_record
from liquidamp.analysis.measured.records import read_record
from liquidamp.device.effects import with_effects
from liquidamp.device.presets import load_device_file
from liquidamp.options import PRESETS

D = "/work/shared/data/friction-damper-backlash"
kind = sys.argv[2] if len(sys.argv) > 2 else "steady"
dev = load_device_file(sys.argv[1])
model = with_effects("full", *dev.effects)
for f in ("0.5Hz", "1Hz", "0.25Hz"):
    raw = read_record(f"{D}/brfd30_{f}_0.5in_{kind}.csv")
    rec, cond = condition(raw)
    resp = simulate_record(model, dev.params, rec, options=PRESETS["fit"])
    F, P = rec.force, resp.force
    r = F - P
    n = len(r)
    fs = 1.0 / np.median(np.diff(rec.time))
    spec_r = np.abs(np.fft.rfft(r - r.mean())) ** 2
    spec_F = np.abs(np.fft.rfft(F - F.mean())) ** 2
    fr = np.fft.rfftfreq(n, 1 / fs)
    tot = spec_r.sum()
    print(f"{f} {kind}: fs {fs:.1f} Hz, kept to {cond.anti_alias_cutoff:.1f} Hz, NRMSE "
          f"{np.sqrt(np.mean(r**2))/np.std(F):.4f}")
    for lo, hi in ((0, 2.5), (2.5, 5), (5, 7.6), (7.6, 10), (10, 15.2), (15.2, 20), (20, 31.5),
                   (31.5, 60)):
        m = (fr >= lo) & (fr < hi)
        print(f"   {lo:5.1f}-{hi:5.1f} Hz: residual share {spec_r[m].sum()/tot:6.3f}"
              f"   force share {spec_F[m].sum()/spec_F.sum():6.4f}")
    for fc in (7.6, 15.2, 31.5):
        m = fr < fc
        print(f"   judged below {fc} Hz: NRMSE {np.sqrt(spec_r[m].sum()/spec_F[m].sum()):.4f}")
