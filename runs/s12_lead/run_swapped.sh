#!/bin/bash
# usage: run_swapped.sh TAG OUTDIR: the default diagnose of a shared independent case with its
# records swapped (calibrated on *_val.csv, validated on *_cal.csv): another split of records
# made by the independent simulator, which the shared table never ran.
tag=$1; out=$2; mkdir -p "$out"
S=${LIQUIDAMP_SHARED:-$(cd "$(dirname "$0")/../.." && pwd)/shared}/data
I=$S/independent-records
c=$(ls "$I"/"${tag}"_*cal.csv); v=${c%_cal.csv}_val.csv
s=$(date +%s.%N)
python -m liquidamp diagnose "$v" --validate "$c" --json "$out/$tag.json" > "$out/$tag.out" 2> "$out/$tag.err"
echo $? > "$out/$tag.rc"
e=$(date +%s.%N); python -c "print($e-$s)" > "$out/$tag.time"
