import sys, time, json
import liquidamp.coupled.periodic as P
from liquidamp.errors import ConvergenceError
orig = P._shoot
LOG = open(sys.argv[1], "w")
def wrapped(rig, engine, x, target, options, shooting, out_grid=None):
    t0 = time.perf_counter()
    try:
        r = orig(rig, engine, x, target, options, shooting, out_grid)
        LOG.write(json.dumps(dict(ok=True, s=time.perf_counter()-t0, runs=r[1], it=r[2], newton=r[3], marched=r[4], res=r[5], n=len(x)))+"\n")
        LOG.flush()
        return r
    except Exception as e:
        LOG.write(json.dumps(dict(ok=False, s=time.perf_counter()-t0, err=str(e)[:300], n=len(x)))+"\n"); LOG.flush()
        raise
P._shoot = wrapped
from liquidamp.cli import main
sys.exit(main(sys.argv[2:]))
