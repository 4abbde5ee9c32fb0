"""Session 19: is the friction damper's residual a friction level that varies with the stroke?

Fits, on each record's sliding samples (|v| above 30 % of its peak), the residual of a saved
device against a + b y + c y^2 per sliding direction (and jointly, sign(v) (a + b y + c y^2)
plus d y + e y^2), y the stroke over its amplitude, and prints the share of the residual's
mean square each removes.  A position-dependent friction (a toggle linkage's lever arm)
would give coefficients that agree across the records; they do not (README).

Data: Coble, Huggins, Cao, Ricles, Downey (2022), Dataset-Friction-Damper-with-Backlash
(ARTS-Laboratory), CC BY-SA 4.0.

    PYTHONPATH=. python runs/s19_lead/fric_position.py DEV.toml [steady] [full]
"""
import sys
import warnings

import numpy as np

from liquidamp.analysis.measured.record_model import nrmse, simulate_record
from liquidamp.device.effects import with_effects
from liquidamp.device.models import get_model
from liquidamp.device.presets import load_device_file
from runs.s10_fric_where import records

warnings.filterwarnings("ignore")
dev = load_device_file(sys.argv[1])
model = with_effects(get_model("full"), *dev.effects)
for kind in sys.argv[2:] or ("steady",):
    for f, rec in records(kind).items():
        out = simulate_record(model, dev.params, rec)
        r = rec.force - out.force
        v, y = rec.velocity, rec.displacement
        A = float(np.max(np.abs(y - y.mean())))
        yn = (y - y.mean()) / A
        ms = np.sum(r ** 2)
        line = [f"{kind} {f} NRMSE {nrmse(out.force, rec.force):.4f}"]
        for s, nm in ((1, 'fwd'), (-1, 'rev')):
            m = s * v > 0.3 * np.abs(v).max()
            X = np.c_[np.ones(m.sum()), yn[m], yn[m] ** 2]
            c, *_ = np.linalg.lstsq(X, r[m], rcond=None)
            rem = np.sum((X @ c) ** 2)
            line.append(f"{nm}: c0 {c[0]:+5.0f} c1 {c[1]:+5.0f} c2 {c[2]:+5.0f} N "
                        f"removes {rem / ms:.2f}")
        # whole-record: sign(v) * (a + b yn + c yn^2) over sliding
        m = np.abs(v) > 0.3 * np.abs(v).max()
        sg = np.sign(v[m])
        X = np.c_[sg, sg * yn[m], sg * yn[m] ** 2, yn[m], yn[m]**2]
        c, *_ = np.linalg.lstsq(X, r[m], rcond=None)
        line.append(f"joint sign*(1,y,y2),(y,y2): {np.round(c).astype(int).tolist()} "
                    f"removes {np.sum((X @ c) ** 2) / ms:.2f}")
        print(' | '.join(line), flush=True)
