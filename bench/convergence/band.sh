#!/bin/sh
# bench/convergence/band.sh - the shear bands of the collapse's fall per
# cell, for docs/convergence.md section 19 (issue 13). One run at a time.
#
# usage: band.sh LABEL "CELLS" [toe_probe options...]
# e.g.   band.sh mohr_coulomb_psi0 "0.015 0.0075 0.00375 0.001875" \
#          --method bspline2 --family plain --friction 37 --floor slip
# Runs toe_probe --band (the plastic shear rate of every point, the mean
# over 0.02 tau_c before 0.25 and 0.5 tau_c) and prints CSV: label, cell_m,
# t_tau, then band_width.py's medians over the lines y = 0.2..0.5 H (bands
# found, horizontal width m, cells, normal width m, cells, peak rate 1/s)
# and band_share.py's (points in the window, share of the plastic rate in
# the most active 20 % of them). PROBE is the toe_probe binary (build line
# at the top of toe_probe.c); --ppc and --aspect are taken from the options
# (defaults 2 and 1.3; L0 = 0.15 m). KEEP=DIR keeps the point files there.
PROBE=${PROBE:-./toe_probe}
here=$(dirname "$0")
label=$1 cells=$2
shift 2
ppc=2 aspect=1.3 prev=
for arg in "$@"; do
  [ "$prev" = "--ppc" ] && ppc=$arg
  [ "$prev" = "--aspect" ] && aspect=$arg
  prev=$arg
done
height=$(echo "$aspect * 0.15" | bc -l)
dir=${KEEP:-$(mktemp -d)}
mkdir -p "$dir"
for cell in $cells; do
  prefix="$dir/${label}_$cell"
  "$PROBE" --cell "$cell" "$@" --band "$prefix" > "$prefix.txt" || {
    echo "$label,$cell,failed"
    continue
  }
  for t in 0.25 0.50; do
    w=$(python3 "$here/band_width.py" "${prefix}_$t.csv" "$cell" "$ppc" \
      "$height" | sed -n 's/^all,//p' | awk -F, '{print $1","$2","$3","$5","$6","$7}')
    [ -z "$w" ] && w="0,,,,,"
    s=$(python3 "$here/band_share.py" "${prefix}_$t.csv" "$height")
    echo "$label,$cell,$t,$w,$s"
  done
done
[ -z "$KEEP" ] && rm -r "$dir"
exit 0
