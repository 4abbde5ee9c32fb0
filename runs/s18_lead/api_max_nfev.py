"""diagnose() of one record pair at a given max_nfev:
python runs/s18_lead/api_max_nfev.py CAL VAL MAX_NFEV."""
import sys

from liquidamp.analysis.measured.diagnosis import diagnose
from liquidamp.analysis.measured.records import read_record

d = diagnose([read_record(sys.argv[1])], [read_record(sys.argv[2])], max_nfev=int(sys.argv[3]))
print("ADDED", d.added, d.heldout)
