#!/bin/bash
# usage: bash runs/s13_valved/shared.sh OUT TAG... ; the shared cases one at a time (uptime beside each)
out=$1; shift
for t in "$@"; do
  echo "$t start $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/load.txt
  LIQUIDAMP_SHARED=/work/shared timeout 900 bash runs/run_case.sh $t $out
  echo "$t end $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/load.txt
done
