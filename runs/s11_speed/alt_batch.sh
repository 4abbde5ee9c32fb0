#!/bin/bash
# usage: runs/s11_speed/alt_batch.sh OUTDIR ID...: alt_trace.py on sweep records (one at a time)
out=$1; shift; mkdir -p $out
for id in "$@"; do
  u=$(cut -d' ' -f1 /proc/loadavg); s=$(date +%s)
  if [[ $id == d* ]]; then
    c=$(ls ${LIQUIDAMP_SHARED:-/work/shared}/data/independent-records/${id}_*cal.csv); v=${c%_cal.csv}_val.csv
    PYTHONPATH=. timeout 900 python runs/s11_speed/alt_trace.py $c $v > $out/$id.txt 2>&1
  else
    PYTHONPATH=. timeout 900 python runs/s11_speed/alt_trace.py sweep $id > $out/$id.txt 2>&1
  fi
  echo "$id $(( $(date +%s)-s )) s load $u -> $(cut -d' ' -f1 /proc/loadavg)" >> $out/times.txt
done
