"""Log the integrator steps of every compiled march (session 17 measurement).

    LIQ_STEPLOG=LOG PYTHONPATH=.:runs/s17_lead/hook python -m liquidamp diagnose ...

Each line of LOG: the kind (``mc`` a periodic march, ``m`` one span), the model, its steps,
the periods it covered (-1 where it raised; 0 for a span of a stroke without a period), the
seconds and the error.  Summary: runs/s17_lead/steps_hist.py.
"""
import json
import os
import time

LOG = os.environ.get("LIQ_STEPLOG")
if LOG:
    import liquidamp.coupled.fast as fast

    _mc, _m = fast.march_cycles, fast.march

    def _log(kind, model, st, cycles, dt, err=""):
        with open(LOG, "a") as f:
            f.write(json.dumps({"kind": kind, "model": model.name, "steps": st.get("steps", 0),
                                "cycles": cycles, "s": round(dt, 4), "err": err}) + "\n")

    def _call(kind, fn, model, cyc, stats, *a, **kw):
        st = {}
        t = time.perf_counter()
        try:
            out = fn(*a, stats=st, **kw)
        except Exception as e:
            _log(kind, model, st, -1, time.perf_counter() - t, type(e).__name__ + str(e)[:80])
            raise
        finally:
            if stats is not None:
                stats.update(st)
        _log(kind, model, st, cyc(out), time.perf_counter() - t)
        return out

    def march_cycles(model, params, stroke, x0, options, *, stats=None, grid=None):
        return _call("mc", _mc, model, lambda o: o[1], stats, model, params, stroke, x0,
                     options, grid=grid)

    def march(model, params, stroke, x0, t0, t1, t_eval, options, max_step, *, h0=0.0,
              stats=None, max_steps=None):
        T = getattr(stroke, "period", 0.0) or 0.0
        return _call("m", _m, model, lambda o: (t1 - t0) / T if T else 0.0, stats, model,
                     params, stroke, x0, t0, t1, t_eval, options, max_step, h0=h0,
                     max_steps=max_steps)

    fast.march_cycles, fast.march = march_cycles, march
