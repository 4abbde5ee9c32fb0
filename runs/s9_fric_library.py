"""Session 9 (s9-fric): refits of the catalogue's friction-damper model on the 0.5 Hz record.

Starts from a device file written by the default diagnosis of the steady records
(``liquidamp diagnose ... --save-device DEV.toml``: smooth friction at the piston behind a
dead band, the friction start's fluid on the rod) and refits the friction's parameters and
the gap on the 0.5 Hz steady record (conditioned as the diagnosis conditions it), reporting
the held-out NRMSE of the 1 Hz and 0.25 Hz records:

* ``fluid L:S ...``: with the fluid's losses (c1, c2) scaled by L and its channel
  inertance S_t by S [-] (the share of the rod force the friction start's fluid carries);
* ``band H:K ...``: with the calibration record conditioned to keep H harmonics (30: the
  default, 60: a 30 Hz anti-alias cut-off at 0.5 Hz) and K = ``b`` (force, stiffness,
  reverse ratio) or ``x`` (also the static ratio, Stribeck velocity, transition exponent).

Data: Coble, Huggins, Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash
(ARTS-Laboratory), CC BY-SA 4.0 (``$LIQUIDAMP_SHARED/data/friction-damper-backlash``).

Usage: ``python runs/s9_fric_library.py DEV.toml fluid 1:1 1:0.01 0.1:0.01``
"""

from __future__ import annotations

import os
import sys
import time
import warnings

from liquidamp.analysis.measured.calibration import calibrate
from liquidamp.analysis.measured.conditioning import condition
from liquidamp.analysis.measured.fit_spec import FitSpec, scale_effect_bounds
from liquidamp.analysis.measured.records import read_record
from liquidamp.device.presets import load_device_file

BASE = ("force_N", "stiffness_N_per_m", "reverse_ratio")
EXTRA = ("static_ratio", "stribeck_velocity_m_per_s", "transition_exponent")


def main(argv) -> None:
    """Command line (module docstring)."""
    warnings.filterwarnings("ignore")
    dev = load_device_file(argv[0])
    mode = argv[1]
    shared = os.environ.get("LIQUIDAMP_SHARED", os.path.join(
        os.path.dirname(__file__), "..", "..", "shared"))
    d = os.path.join(shared, "data", "friction-damper-backlash")
    raw = {f: read_record(os.path.join(d, f"brfd30_{f}_0.5in_steady.csv"))
           for f in ("0.5Hz", "1Hz", "0.25Hz")}
    val = [condition(raw[f])[0] for f in ("1Hz", "0.25Hz")]
    sf = next(e for e in dev.effects if e.name == "smooth_friction")
    fp = next(e for e in dev.effects if e.name == "freeplay")
    for arg in argv[2:]:
        a, b = arg.split(":")
        params, keys, h = dev.params, BASE, 30.0
        if mode == "fluid":
            params = dev.params.scaled(c1=float(a), c2=float(a), S_t=float(b))
        else:
            h, keys = float(a), BASE + (EXTRA if b == "x" else ())
        cal = [condition(raw["0.5Hz"], harmonics=h)[0]]
        spec = FitSpec(()).with_effect(sf, keys=keys).with_effect(fp, keys=("gap_m",))
        spec = scale_effect_bounds(spec, cal)
        if "smooth_friction.static_ratio" in spec.names:
            spec = spec.with_values({"smooth_friction.static_ratio": 1.2})
        t0 = time.time()
        r = calibrate(cal, model="full", params=params, effects=dev.effects, spec=spec,
                      validate=val, start="spec", sizing="preset", warn=False, max_nfev=120)
        der = r.params.derived()
        print(f"{mode} {arg}: c_L {der['c_L [N s/m]']:.4g} N s/m, b_L {der['b_L [kg]']:.4g} kg; "
              + ", ".join(f"{e.label} {e.nrmse:.4f}" for e in r.record_errors)
              + f"; {r.status} {time.time() - t0:.0f} s; "
              + ", ".join(f"{k.split('.')[-1]} {v:.4g}" for k, v in r.values.items()),
              flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
