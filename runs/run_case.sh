#!/bin/bash
# usage: run_case.sh TAG OUTDIR ; runs default diagnose for a case
tag=$1; out=$2; mkdir -p $out
S=${LIQUIDAMP_SHARED:-$(cd "$(dirname "$0")/../.." && pwd)/shared}/data  # ../shared beside the repo
I=$S/independent-records; D=$S/friction-damper-backlash
case $tag in
  fd_steady) args="$D/brfd30_0.5Hz_0.5in_steady.csv --validate $D/brfd30_1Hz_0.5in_steady.csv --validate $D/brfd30_0.25Hz_0.5in_steady.csv";;
  fd_full) args="$D/brfd30_0.5Hz_0.5in_full.csv --validate $D/brfd30_1Hz_0.5in_full.csv --validate $D/brfd30_0.25Hz_0.5in_full.csv";;
  *) c=$(ls $I/${tag}_*cal.csv); v=${c%_cal.csv}_val.csv; args="$c --validate $v";;
esac
s=$(date +%s.%N)
python -m liquidamp diagnose $args --json $out/$tag.json > $out/$tag.out 2> $out/$tag.err
echo $? > $out/$tag.rc
e=$(date +%s.%N); python -c "print($e-$s)" > $out/$tag.time
