#!/bin/bash
# usage: run.sh OUTDIR TAG [TAG ...] ; default diagnose then calibrate on /tmp/s12_outside/TAG_{cal,val}.csv
out=$1; shift; mkdir -p $out; D=${S12_DATA:-/tmp/s12_outside}
for tag in "$@"; do
  for cmd in diagnose calibrate; do
    s=$(date +%s.%N); l0=$(cut -d' ' -f1 /proc/loadavg)
    timeout 600 python -m liquidamp $cmd $D/${tag}_cal.csv --validate $D/${tag}_val.csv \
      --json $out/$tag.$cmd.json > $out/$tag.$cmd.out 2> $out/$tag.$cmd.err
    echo $? > $out/$tag.$cmd.rc
    e=$(date +%s.%N); l1=$(cut -d' ' -f1 /proc/loadavg)
    python -c "print(round($e-$s,1), '$l0', '$l1')" > $out/$tag.$cmd.time
    echo "$tag $cmd rc=$(cat $out/$tag.$cmd.rc) $(cat $out/$tag.$cmd.time)"
  done
done
