import time, sys, json
import numpy as np
from liquidamp.coupled.engines import TestRig, engine_for
from liquidamp.coupled.periodic import periodic_state, ShootingOptions
from liquidamp.device import preset
from liquidamp.device.models import get_model
from liquidamp.options import SolverOptions
from liquidamp.structure.testmachine import HarmonicStroke
cases = [("full","spring",1e-6,4.0),("full","device_a",2e-3,5.0),("full","device_b",2e-3,1.0),
         ("full","inerter",1e-3,3.0),("full","device_a",1e-3,1.0),("full","damper",3e-3,7.0)]
out = {}
for mname, pname, Y, f in cases:
    for opt in (SolverOptions(engine="compiled"), SolverOptions.preset("fit")):
        m, p = get_model(mname), preset(pname)
        rig = TestRig(m, p, HarmonicStroke(Y, f))
        eng = engine_for(rig, opt)
        x0 = m.initial_state(p, 0.0)
        try:
            periodic_state(rig, eng, x0, opt, route="shooting")
        except Exception as e:
            pass
        t0 = time.perf_counter()
        try:
            s = periodic_state(rig, eng, x0, opt, route="shooting")
            dt = time.perf_counter() - t0
            out[f"{pname} {Y} {f} rtol{opt.rtol}"] = dict(s=dt, runs=s.stats.get("shooting_runs"), it=s.stats.get("newton_iterations"), res=s.residual, x=s.states[:, 0].tolist())
            print(pname, Y, f, opt.rtol, f"{dt:.3f}s", s.stats.get("shooting_runs"), s.stats.get("newton_iterations"), f"{s.residual:.2e}", flush=True)
        except Exception as e:
            print(pname, Y, f, opt.rtol, "FAIL", str(e)[:200], flush=True)
json.dump(out, open(sys.argv[1], "w"))
