#!/bin/bash
# s11 v3 measurements, one diagnosis at a time (stages.py; S11_NO_SCREEN=1 runs main's behaviour)
out=runs/s11_speed/v3; mkdir -p $out
one() {  # TAG ENV ARGS...
  tag=$1; env=$2; shift 2
  u=$(cut -d' ' -f1 /proc/loadavg); s=$(date +%s.%N)
  env $env PYTHONPATH=. timeout 1200 python runs/s11_speed/stages.py "$@" > $out/$tag.txt 2> $out/$tag.err
  e=$(date +%s.%N)
  echo "$tag rc $? wall $(python -c "print(round($e-$s,1))") s load $u -> $(cut -d' ' -f1 /proc/loadavg)" >> $out/times.txt
}
I=/work/shared/data/independent-records
one A_elastomer X=1 sweep A_elastomer
one d04 X=1 $I/d04_end_stops_2kHz_cal.csv $I/d04_end_stops_2kHz_val.csv
one bb2k X=1 /tmp/s11rec/bb2k_cal.csv /tmp/s11rec/bb2k_val.csv
one short100 X=1 /tmp/s11rec/short100_cal.csv /tmp/s11rec/short100_val.csv
one short100_main S11_NO_SCREEN=1 /tmp/s11rec/short100_cal.csv /tmp/s11rec/short100_val.csv
one B_coulomb_friction_main S11_NO_SCREEN=1 sweep B_coulomb_friction
one B_coulomb_friction X=1 sweep B_coulomb_friction
one long5k X=1 /tmp/s11rec/long5k_cal.csv /tmp/s11rec/long5k_val.csv
