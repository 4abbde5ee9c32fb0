"""One sweep record's default diagnosis under an experiment on files this helper does not
own (the library is not changed; module attributes are set in this process only).

PYTHONPATH=. python runs/s10_unseen/variant.py ID OUTDIR [reach=R] [air=A] [preset=NAME] [airfree=1]

reach: class_revisit.CHANNEL_REACH (2 on main); air: class_revisit._AIR (1e-3 on main: the
least air ratio of a design "with air"); preset: the device given to diagnose (``params``;
by default none: paper_initial).
"""
import json
import sys
import time
from pathlib import Path

import liquidamp.analysis.measured.class_revisit as CR
from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.device import preset

sys.path.insert(0, str(Path(__file__).resolve().parent))
import sweep  # noqa: E402

rid, out = sys.argv[1], Path(sys.argv[2])
opts = dict(a.split("=", 1) for a in sys.argv[3:])
if "reach" in opts:
    CR.CHANNEL_REACH = float(opts["reach"])
if "air" in opts:
    CR._AIR = float(opts["air"])
if opts.get("airfree"):
    # the family's air-free designs (air ratio below _AIR: the inerter) as starts too, with
    # their own air and channel (what the report proposes for fluid_alternatives)
    from liquidamp.device import preset_names

    _orig = CR.fluid_alternatives

    def _with_airfree(baseline, run, noise_level, params, sizing="auto"):
        out = _orig(baseline, run, noise_level, params, sizing)
        if not out and (run["current"].nrmse_calibration <= noise_level or params is None):
            return out
        for name in preset_names():
            q = preset(name)
            if min(q.inv_gamma1, q.inv_gamma2) < CR._AIR and q.S_t > 0:
                out.append((f"fluid ({name} design: air-free, channel S_t {q.S_t:.3g})",
                            {"params": params.replace(S_t=q.S_t, inv_gamma1=q.inv_gamma1,
                                                      inv_gamma2=q.inv_gamma2,
                                                      name=f"{params.name} as {name}"),
                             "sizing": "preset", "device_class": "fluid"}))
        return out

    CR.fluid_alternatives = _with_airfree
kw = {"params": preset(opts["preset"])} if "preset" in opts else {}
out.mkdir(parents=True, exist_ok=True)
cal, val = sweep.records(rid)
t0 = time.perf_counter()
d = diagnose([cal], [val], **kw)
sec = time.perf_counter() - t0
j = d.as_dict()
j["sweep"] = {"id": rid, "truth": sweep.truth(*rid.split("_", 1)), "seconds": sec,
              "effect_rms_N": None if rid.endswith("_null") else float("nan"),
              "noise_N": sweep.CONDITIONS[rid[0]][5], "stop_reason": d.stop_reason,
              "summary_first": d.summary().splitlines()[0], "variant": opts}
(out / f"{rid}.json").write_text(json.dumps(j, indent=1, default=str))
(out / f"{rid}.time").write_text(f"{sec:.1f}\n")
print(f"{rid} {opts}: {sec:.1f} s")
print(d.summary())
