"""The cavitating device's periodic orbit (steady_state) against a long march from rest."""
import sys
import time

import numpy as np

from liquidamp.analysis.measured.record_model import integrate
from liquidamp.coupled.testrig import steady_state
from liquidamp.device import preset
from liquidamp.device.effects import with_effects
from liquidamp.device.effects_fluid import Cavitation
from liquidamp.device.models import get_model
from liquidamp.structure.testmachine import HarmonicStroke

pv, f, Y = (float(a) for a in sys.argv[1:4])
p = preset("paper_calibrated")
m = with_effects(get_model(sys.argv[4] if len(sys.argv) > 4 else "full"), Cavitation(pv))
st = HarmonicStroke(Y, f)
t0 = time.perf_counter()
o = steady_state(m, p, st)
print(f"steady_state {time.perf_counter() - t0:.2f} s:", o.message if hasattr(o, "message")
      else "", getattr(o, "stats", ""))
x0 = o.states[:, 0]
T = 1 / f
X = integrate(m, p, st, np.linspace(0, T, 201), x0, rtol=1e-10, atol_scale=1e-12)
sc = np.asarray(m.state_scales(p))
print("x(T)-x(0) / scale:", np.abs((X[:, -1] - x0) / sc).max())
x = m.initial_state(p, 0.0)
for c in range(int(sys.argv[5]) if len(sys.argv) > 5 else 100):
    x = integrate(m, p, st, np.array([c * T, (c + 1) * T]), x, rtol=1e-10,
                  atol_scale=1e-12)[:, -1]
print("march from rest, cycles", c + 1, "vs orbit:", np.abs((x - x0) / sc).max())
Fo = m.force(0, o.states, st(np.arange(o.states.shape[1]) * T / o.states.shape[1]), p)
print("orbit force swing", np.ptp(Fo))
