#!/bin/bash
# usage: bash runs/s13_valved/queue.sh QUEUEFILE ; runs one job at a time, taking the first line of
# QUEUEFILE each time ("shared TAG" -> runs/run_case.sh into runs/s13_valved/shared;
# "outside TAG" -> runs/s12_outside/run.sh into runs/s13_valved/outside), so the order can change
q=$1
while [ -s "$q" ]; do
  line=$(head -1 "$q"); sed -i 1d "$q"; set -- $line
  case $1 in
    shared) out=runs/s13_valved/shared; mkdir -p $out
      echo "$2 start $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/load.txt
      LIQUIDAMP_SHARED=/work/shared timeout 900 bash runs/run_case.sh $2 $out
      echo "$2 end $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/load.txt;;
    outside) bash runs/s12_outside/run.sh runs/s13_valved/outside $2;;
  esac
done
