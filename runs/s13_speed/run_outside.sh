#!/bin/bash
# usage: bash runs/s13_speed/run_outside.sh OUTDIR TAG... ; the default diagnose of each record
# of runs/s12_outside/make.py (/tmp/s12_outside), one at a time under timeout 600, from the
# current directory's liquidamp; OUTDIR/TAG.{json,out,err,rc} and OUTDIR/load.txt (wall s, rc,
# 1-min load at start and end)
out=$1; shift; mkdir -p "$out"; O=/tmp/s12_outside
for tag in "$@"; do
  a=$(cut -d' ' -f1 /proc/loadavg); s=$(date +%s.%N)
  timeout 600 python -m liquidamp diagnose $O/${tag}_cal.csv --validate $O/${tag}_val.csv \
    --json "$out/$tag.json" > "$out/$tag.out" 2> "$out/$tag.err"
  rc=$?; e=$(date +%s.%N); b=$(cut -d' ' -f1 /proc/loadavg)
  echo "$tag $(python -c "print(round($e-$s, 1))") rc $rc load $a $b" >> "$out/load.txt"
done
