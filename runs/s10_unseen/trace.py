"""Every loop of one sweep record's default diagnosis, round by round (the tracing of
runs/s9_bench200/trace.py).

PYTHONPATH=. python runs/s10_unseen/trace.py ID [DIAGNOSE_KEYWORDS_JSON]
"""
import importlib.util
import json
import sys
import time
from pathlib import Path

import liquidamp.analysis.measured.diagnosis as D

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import sweep  # noqa: E402

_spec = importlib.util.spec_from_file_location("s9_trace", HERE.parent / "s9_bench200" / "trace.py")
_s9 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_s9)
report, traced = _s9.report, _s9.traced

rid = sys.argv[1]
kw = json.loads(sys.argv[2]) if len(sys.argv) > 2 else {}
cal, val = sweep.records(rid)
t0 = time.perf_counter()
d = traced(D.diagnose, [cal], [val], **kw)
print(f"{rid}: {time.perf_counter() - t0:.1f} s, added {list(d.added)}")
print("truth", sweep.truth(*rid.split("_", 1)))
report(d)
