#!/bin/sh
# tests/scripts/collapse_3d_axisym.sh - issue 16 item 3: the 3D cylindrical
# column collapse (examples/column_collapse_3d, a quarter cylinder between
# slip symmetry faces) against the library's own axisymmetric run of the
# same column (examples/column_collapse --geometry axisym): same shape
# functions (linear; 3D planar walls take no other), same Coulomb floor
# (mu 0.45), material (docs/convergence.md sec. 20's Perzyna), cell and
# points per cell; a = 1, R0 = 0.1 m, cells R0/6 and R0/8, 2 points per
# cell per axis. Asserts the run-outs (r_inf - R0)/R0 within 5 % of each
# other (the bound) and the final heights H_inf/R0 within 5 %.
# Measured (validate/collapse_3d.sh, validate/results/collapse_3d.md):
# run-out 3D against axisym -4.3 % (0.6626 / 0.6926) at R0/6, -2.1 %
# (0.7274 / 0.7430) at R0/8, -3.0 % at R0/12; heights -2.2 %, +1.0 %,
# +2.2 %. The 5 % therefore has a margin of 0.7 points at R0/6: a 3D
# change that moves the run-out by more than that shows here: with the
# symmetry faces x = 0, y = 0 made no-slip (a scratch copy of the driver)
# the run-out at R0/6 is 0.5932 (-14 %) and the height 0.9979 (+8 %), and
# this test fails. About 8 s on one core.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
SCENE="--family plain --method linear --floor wall --floor-mu 0.45 --material perzyna --friction 37 --fluidity 300 --reference-stress 1795 --aspect 1 --length 0.1 --ppc 2 --out '' --quiet"
value() { # value NAME FILE: the value of RESULT NAME=
  sed -n "s/^RESULT $1=\([^ ]*\) .*/\1/p" "$2"
}
failed=0
for cell in 0.0166666666667 0.0125; do
  # shellcheck disable=SC2086 # SCENE is a list of options
  eval "./examples/column_collapse --geometry axisym $SCENE --cell $cell" >"$scratch/axi" 2>&1 || true
  eval "./examples/column_collapse_3d $SCENE --cell $cell" >"$scratch/3d" 2>&1 || true
  ra=$(value runout "$scratch/axi")
  r3=$(value runout "$scratch/3d")
  ha=$(value final_height_over_L0 "$scratch/axi")
  h3=$(value final_height_over_R0 "$scratch/3d")
  if ! awk -v cell="$cell" -v ra="$ra" -v r3="$r3" -v ha="$ha" -v h3="$h3" 'BEGIN {
      if (ra == "" || r3 == "" || ha == "" || h3 == "") {
        printf "cell %s: a run gave no RESULT\n", cell; exit 1 }
      dr = (r3 - ra) / ra; dh = (h3 - ha) / ha
      printf "cell %s: run-out 3D %.4f axisym %.4f (%+.2f %%), height 3D %.4f axisym %.4f (%+.2f %%)\n",
        cell, r3, ra, 100 * dr, h3, ha, 100 * dh
      exit (dr < -0.05 || dr > 0.05 || dh < -0.05 || dh > 0.05) }'; then
    failed=1
    cat "$scratch/axi" "$scratch/3d"
  fi
done
exit $failed
