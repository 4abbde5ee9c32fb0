#!/bin/bash
# 200 Hz bench, two codes alternated (A B A B), one process at a time (session 16).
# usage: bench_ab.sh DIR_A DIR_B OUT  (each DIR a source tree; its liquidamp imported via PYTHONPATH)
A=$1; B=$2; out=$3; mkdir -p $out
for rep in 1 2; do
  for tag in A B; do
    d=$A; [ $tag = B ] && d=$B
    l0=$(cut -d' ' -f1 /proc/loadavg)
    (cd $d && PYTHONPATH=$d python -m liquidamp bench --cases diagnosis_200hz_10_cycles \
        --json $out/${tag}_$rep.json > /dev/null 2>&1)
    echo "$tag $rep load $l0 -> $(cut -d' ' -f1 /proc/loadavg)"
  done
done
python - "$out" <<'PY'
import json, sys, glob, statistics, os
out = sys.argv[1]
rows = {}
for f in sorted(glob.glob(os.path.join(out, "*_*.json"))):
    tag = os.path.basename(f).split("_")[0]
    c = json.load(open(f))["cases"]["diagnosis_200hz_10_cycles"]
    for k, v in c.items():
        if k.startswith("seconds_"):
            rows.setdefault(k[8:], {}).setdefault(tag, []).append(v)
print("effect | A median | B median | B/A")
for e, d in rows.items():
    a, b = statistics.median(d["A"]), statistics.median(d["B"])
    print(f"{e} | {a:.2f} | {b:.2f} | {b / a:.3f}")
print("max |", round(max(statistics.median(d['A']) for d in rows.values()), 2), "|",
      round(max(statistics.median(d['B']) for d in rows.values()), 2))
PY
