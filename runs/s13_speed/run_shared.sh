#!/bin/bash
# usage: bash runs/s13_speed/run_shared.sh OUTDIR TAG... ; one default diagnosis at a time,
# each under timeout 900, the 1-min load at start and end beside each case (OUTDIR/load.txt)
out=$1; shift; mkdir -p "$out"
for tag in "$@"; do
  a=$(cut -d' ' -f1 /proc/loadavg)
  LIQUIDAMP_SHARED=${LIQUIDAMP_SHARED:-/work/shared} timeout 900 bash runs/run_case.sh "$tag" "$out"
  b=$(cut -d' ' -f1 /proc/loadavg)
  echo "$tag $(cat "$out/$tag.time") $a $b" >> "$out/load.txt"
done
