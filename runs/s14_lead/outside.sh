#!/bin/bash
# default diagnose on the outside-family records (runs/s12_outside), one at a time
out=$1; shift; mkdir -p $out; D=/tmp/s12_outside
for tag in "$@"; do
  s=$(date +%s.%N); l0=$(cut -d' ' -f1 /proc/loadavg)
  timeout 600 python -m liquidamp diagnose $D/${tag}_cal.csv --validate $D/${tag}_val.csv \
    --json $out/$tag.diagnose.json > $out/$tag.diagnose.out 2> $out/$tag.diagnose.err
  echo $? > $out/$tag.diagnose.rc
  e=$(date +%s.%N); l1=$(cut -d' ' -f1 /proc/loadavg)
  python -c "print(round($e-$s,1), '$l0', '$l1')" > $out/$tag.diagnose.time
  echo "$tag rc=$(cat $out/$tag.diagnose.rc) $(cat $out/$tag.diagnose.time)"
done
