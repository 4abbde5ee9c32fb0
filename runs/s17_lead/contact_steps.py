"""RODAS4 steps per period against a floating freeplay's contact stiffness (session 17).

The friction start of the strong set's R_mass20 diagnosis (paper_initial at force x0.023:
chambers 4e-7 m^3, piston 1.6e-5 m^2; smooth friction 669 N) with a floating freeplay of
29 um, under 2 mm at 6 Hz; one period from rest on the fit preset with the step budget
lifted, so that the cost of each contact stiffness shows.

    PYTHONPATH=. python runs/s17_lead/contact_steps.py 4e8 4e9 1e10 2e10 4e10
"""
import sys
import time

from liquidamp.coupled.fast import march_cycles
from liquidamp.device import preset
from liquidamp.device.effects import make_effect, with_effects
from liquidamp.device.models import get_model
from liquidamp.options import PRESETS
from liquidamp.structure.testmachine import HarmonicStroke

p = preset("paper_initial").replace(V01=3.985e-7, V02=3.985e-7, A_p=1.594e-5,
                                    c1_factor=320.1, c2_factor=127.9, S_t_factor=13.42,
                                    inv_gamma1=0.06484, inv_gamma2=0.06484)
s = HarmonicStroke(0.002, 6.0)
opts = PRESETS["fit"].replace(min_cycles=1, max_cycles=1, max_steps=5_000_000)
for k in map(float, sys.argv[1:]):
    m = with_effects(get_model("full"),
                     make_effect("floating_freeplay", gap_m=2.94e-5, contact_stiffness_N_per_m=k),
                     make_effect("smooth_friction", force_N=668.6, stiffness_N_per_m=1.25e6))
    st = {}
    t = time.perf_counter()
    march_cycles(m, p, s, m.initial_state(p, 0.0), opts, stats=st)
    print(f"contact {k:.3g} N/m: {st['steps']} steps in one period, "
          f"{time.perf_counter() - t:.2f} s")
