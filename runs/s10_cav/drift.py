"""March the cavitating paper_calibrated device from rest; print per-cycle invariants."""
import sys
import time

import numpy as np

from liquidamp.analysis.measured.record_model import integrate
from liquidamp.coupled.periodic import _chamber_density
from liquidamp.device import preset
from liquidamp.device.effects import with_effects
from liquidamp.device.effects_fluid import Cavitation
from liquidamp.device.models import get_model
from liquidamp.structure.testmachine import HarmonicStroke

pv = float(sys.argv[1]) if len(sys.argv) > 1 else 40e3
f, Y = (4.0, 0.002) if len(sys.argv) < 3 else (float(sys.argv[2]), float(sys.argv[3]))
p = preset("paper_calibrated")
base = get_model("full")
m = with_effects(base, Cavitation(pv))
print(m.state_names if hasattr(m, "state_names") else "", p.p0)
st = HarmonicStroke(Y, f)
T = 1 / f
x = m.initial_state(p, 0.0)
t0 = time.time()
for c in range(int(sys.argv[4]) if len(sys.argv) > 4 else 60):
    t = np.linspace(c * T, (c + 1) * T, 201)
    X = integrate(m, p, st, t, x, rtol=1e-9, atol_scale=1e-10)
    F = m.force(t, X, st(t), p)
    x = X[:, -1]
    V1, V2 = p.V01, p.V02
    inv = []
    for k, (ip, ir) in enumerate(((0, 1), (2, 3))):
        r, _ = _chamber_density(x[ip], k + 1, p)
        V = V1 if k == 0 else V2
        inv.append(x[ir] / r - 1)
        inv.append(x[ir] * V / (r * (V - x[5 + k])) - 1)
    if c < 10 or c % 10 == 0:
        print(c, f"swing {np.ptp(F):.2f}", " ".join(f"{v:+.3e}" for v in inv),
              f"Vc {x[5]:.2e} {x[6]:.2e} maxVc {X[5].max():.2e} {X[6].max():.2e}", flush=True)
print("time", time.time() - t0)
