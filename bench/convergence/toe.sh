#!/bin/sh
# bench/convergence/toe.sh - the collapse's front during the fall per cell,
# for docs/convergence.md section 18. One run at a time (shared machine).
#
# usage: toe.sh LABEL "CELLS" [toe_probe options...]
# e.g.   toe.sh slip_bs2_plain "0.015 0.0075 0.00375" --method bspline2 \
#          --family plain --friction 37 --floor slip
# Prints CSV: label,cell_m,ppc, then toe_probe's columns (lengths in L0,
# velocities in sqrt(g H)). PROBE is the toe_probe binary (build line at
# the top of toe_probe.c); --ppc is taken from the options (default 2).
PROBE=${PROBE:-./toe_probe}
label=$1 cells=$2
shift 2
ppc=2
prev=
for arg in "$@"; do
  [ "$prev" = "--ppc" ] && ppc=$arg
  prev=$arg
done
for cell in $cells; do
  "$PROBE" --cell "$cell" "$@" | grep -v '^[#t]' |
    sed "s/^/$label,$cell,$ppc,/"
done
