#!/bin/bash
# the s11 regression chain, one diagnosis at a time: shared cases, 200 Hz bench, sweep records
out=runs/s11_speed/after; mkdir -p $out/cases $out/sweep
for t in d01 d02 d05 d11 d12; do
  echo "$t start load $(cut -d' ' -f1 /proc/loadavg)" >> $out/cases/load.txt
  LIQUIDAMP_SHARED=/work/shared timeout 900 bash runs/run_case.sh $t $out/cases
  echo "$t end load $(cut -d' ' -f1 /proc/loadavg)" >> $out/cases/load.txt
done
python runs/tabulate.py $out/cases > $out/cases_table.md 2>&1
echo "bench start $(uptime)" >> $out/bench_load.txt
timeout 1200 python -m liquidamp bench --cases diagnosis_200hz_10_cycles --json $out/b_200.json > $out/b_200.out 2>&1
echo "bench end $(uptime)" >> $out/bench_load.txt
PYTHONPATH=. python runs/s10_unseen/sweep.py all $out/sweep B_coulomb_friction B_end_stops A_relief_valve A_digressive_valve A_series_compliance A_elastomer C_freeplay B_series_compliance > $out/sweep.out 2>&1
