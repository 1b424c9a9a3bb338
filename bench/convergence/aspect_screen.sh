#!/bin/sh
# bench/convergence/aspect_screen.sh - one material at several aspect ratios,
# run-out and final height against Lube et al. (2005) (docs/convergence.md
# section 23: the screen for one material over a = 0.5-8).
#
# usage: aspect_screen.sh LABEL CELL PPC "ASPECTS" [column_collapse options...]
# e.g.   aspect_screen.sh p33 0.015 2 "0.5 1 3 8" --friction 33 --floor-mu 0.65
# The shape, family and material default to the README's setting
# (bspline2, plain, perzyna, floor wall); later options override them.
# Prints CSV: label,aspect,cell_m,ppc,runout,runout_err_pct,final_height,
# height_err_pct,seconds. The law is examples/collapse_laws.h's planar
# one outside Lube's transition (1.2 a for a <= 1.8, 1.9 a^(2/3) for
# a >= 2.8; the header interpolates between, this script does not, so
# keep ASPECTS outside 1.8-2.8); H_inf / L0 = a up to 1.15, a^0.4 above.
# COLLAPSE is the example binary.
COLLAPSE=${COLLAPSE:-./build/examples/column_collapse}
label=$1 cell=$2 ppc=$3 aspects=$4
shift 4
for a in $aspects; do
  t0=$(date +%s)
  out=$("$COLLAPSE" --aspect "$a" --cell "$cell" --ppc "$ppc" --out '' \
    --quiet --method bspline2 --family plain --floor-mu 0.45 \
    --material perzyna "$@" 2>&1)
  t1=$(date +%s)
  r=$(echo "$out" | sed -n 's/^RESULT runout=\([^ ]*\).*/\1/p')
  h=$(echo "$out" | sed -n 's/^RESULT final_height_over_L0=\([^ ]*\).*/\1/p')
  echo "$label,$a,$cell,$ppc,$r,$h,$((t1 - t0))" | awk -F, '{
    a = $2; law = (a < 2.3) ? 1.2 * a : 1.9 * a ^ (2 / 3);
    hl = (a < 1.15) ? a : a ^ 0.4;
    printf "%s,%s,%s,%s,%s,%+.1f,%s,%+.1f,%s\n", $1, a, $3, $4, $5,
      100 * ($5 / law - 1), $6, 100 * ($6 / hl - 1), $7 }'
done
