#!/bin/bash
# usage: runs/s11_speed/time_new.sh RECDIR OUTDIR NAME...: stages.py on RECDIR/NAME_{cal,val}.csv
rec=$1; out=$2; shift 2; mkdir -p $out
for n in "$@"; do
  s=$(date +%s.%N); u0=$(cut -d' ' -f1 /proc/loadavg)
  PYTHONPATH=. timeout 1200 python runs/s11_speed/stages.py $rec/${n}_cal.csv $rec/${n}_val.csv > $out/$n.txt 2> $out/$n.err
  echo "rc $?" >> $out/$n.txt
  e=$(date +%s.%N); echo "$n wall $(python -c "print(round($e-$s,1))") s load $u0 -> $(cut -d' ' -f1 /proc/loadavg)" >> $out/times.txt
done
