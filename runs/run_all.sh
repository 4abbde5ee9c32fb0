#!/bin/bash
# run all cases, two at a time: run_all.sh OUTDIR
out=$1
printf "%s\n" d01 d02 d03 d04 d05 d11 d12 d07 d08 fd_steady fd_full d06 d09 d10 | xargs -P 2 -I{} bash runs/run_case.sh {} $out
