#!/bin/sh
# bench/convergence/sweep.sh - one row per (cell, points per cell) of the
# planar column collapse (examples/column_collapse), for docs/convergence.md.
#
# usage: sweep.sh LABEL "CELLS" "PPCS" [column_collapse options...]
# e.g.   sweep.sh baseline "0.015 0.0075" "1 2 3" --aspect 1.3
# (--geometry axisym among the options runs the axisymmetric collapse; the
# run-out and height columns are then (r_inf - R0)/R0 and H_inf/R0)
# Prints CSV: label,cell_m,ppc,runout,farthest,thick_0.01,thick_0.02,
# thick_0.05,final_height,stop_tau,hidden_ke,seconds. Runs JOBS (default 2)
# cases at a time; COLLAPSE is the example binary. The options after PPCS
# must not hold blanks.
COLLAPSE=${COLLAPSE:-./build/examples/column_collapse}
JOBS=${JOBS:-2}
label=$1 cells=$2 ppcs=$3
shift 3
tmp=$(mktemp -d)
for cell in $cells; do
  for ppc in $ppcs; do
    echo "$cell $ppc"
  done
done | COLLAPSE=$COLLAPSE EXTRA="$*" TMP=$tmp xargs -P "$JOBS" -n 2 sh -c '
  # EXTRA: the options after PPCS, split on blanks (none hold a blank)
  "$COLLAPSE" --cell "$0" --ppc "$1" --out "" --quiet $EXTRA \
    > "$TMP/$0-$1.txt" 2>&1' 
for cell in $cells; do
  for ppc in $ppcs; do
    f=$tmp/$cell-$ppc.txt
    v() { sed -n "s/^RESULT $1=\([^ ]*\).*/\1/p" "$f"; }
    e=$(sed -n 's/^ENERGY hidden_over_kinetic_integral=\([^ ]*\).*/\1/p' "$f")
    s=$(sed -n 's/^STATS.* seconds=\([^ ]*\).*/\1/p' "$f")
    r=$(v runout)
    [ -n "$r" ] || r="failed:$(tail -1 "$f" | tr ',' ' ')"
    echo "$label,$cell,$ppc,$r,$(v runout_farthest_point),$(v runout_thickness_0.01_L0),$(v runout_thickness_0.02_L0),$(v runout_thickness_0.05_L0),$(v final_height_over_L0),$(v stop_time_over_tau_c),$e,$s"
  done
done
rm -rf "$tmp"
