"""Session 20: does slip weakening, refitted beside the default's final friction model,
predict the friction damper's held-out records better?  Records: Coble, Huggins, Cao, Ricles,
Downey (2022), Dataset-Friction-Damper-with-Backlash (ARTS-Laboratory), CC BY-SA 4.0.

usage: python runs/s20_lead/sw_probe.py DEVICE.toml [steady|full] [D_mm ...]
"""
import sys
import time

from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.fit_spec import FitSpec, Parameter
from liquidamp.analysis.measured.records import read_record
from liquidamp.device.effects import EFFECTS
from liquidamp.device.presets import load_device_file

D = "/work/shared/data/friction-damper-backlash"
kind = sys.argv[2] if len(sys.argv) > 2 else "steady"
dists = [float(x) * 1e-3 for x in sys.argv[3:]] or [1e-3, 2e-3, 4e-3, 8e-3]
recs = [condition(read_record(f"{D}/brfd30_{f}_0.5in_{kind}.csv"))[0]
        for f in ("0.5Hz", "1Hz", "0.25Hz")]
dev = load_device_file(sys.argv[1])
print(dev)
sf, fp = dev.effects
free = [("smooth_friction.force_N", sf.force_N, 1e3, 1e5, True),
        ("smooth_friction.stiffness_N_per_m", sf.stiffness_N_per_m, 1e5, 1e9, True),
        ("smooth_friction.reverse_ratio", sf.reverse_ratio, 0.1, 10, True),
        ("smooth_friction.transition_exponent", sf.transition_exponent, 1, 20, True),
        ("freeplay.gap_m", fp.gap_m, 1e-5, 1e-2, True)]
base = [Parameter(n, v, lo, hi, log=lg) for n, v, lo, hi, lg in free]
for c in ("c1", "c2", "inv_gamma1", "inv_gamma2"):
    base.append(Parameter(c, 1.0, 0.05, 20.0, vary=False))
t0 = time.time()
r0 = calibrate(recs[:1], params=dev.params, effects=dev.effects, spec=FitSpec(tuple(base)),
               validate=recs[1:], start="spec", sizing="preset", max_nfev=60)
print("without", r0.nrmse_calibration, r0.heldout_records(), f"{time.time()-t0:.0f}s", flush=True)
for Dm in dists:
    t0 = time.time()
    sw = EFFECTS["slip_weakening"](ratio=0.1, distance_m=Dm)
    spec = FitSpec(tuple(base) + (Parameter("slip_weakening.ratio", 0.1, 0.0, 5.0, log=False),
                                  Parameter("slip_weakening.distance_m", Dm, 1e-5, 0.1, log=True)))
    r = calibrate(recs[:1], params=dev.params, effects=dev.effects + (sw,), spec=spec,
                  validate=recs[1:], start="spec", sizing="preset", max_nfev=60)
    print(f"D0={Dm*1e3:g}mm", r.nrmse_calibration, r.heldout_records(),
          {k: r.values[k] for k in r.varying if "slip" in k or "friction" in k},
          f"{time.time()-t0:.0f}s", flush=True)
