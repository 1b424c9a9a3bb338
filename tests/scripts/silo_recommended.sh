#!/bin/sh
# tests/scripts/silo_recommended.sh - silo discharge with the README's
# recommended setting converges in the cell and follows Beverloo's
# exponents (issue 13 item 4; docs/convergence.md section 38):
# examples/papers/wieckowski1999_silo_discharge --method bspline2
# --fluidity 30 --reference-stress 1795 --edge-node open (quadratic
# B-splines, the Perzyna fill of section 37, the orifice's edge node open),
# FLIP, 2 x 2 points per cell, the rate over 10-25 % of the fill; 1 and 2
# are the circular orifice (--geometry axisym --fill 1, one full width).
#
# 1. D = 0.3 m on D/6, D/12 and D/24: asserts that the rate moves at most
#    5 % (issue 13's bound for the two finest cells) from D/12 to D/24.
#    Measured 127.99, 134.31, 130.59 kg/s (+4.9 %, -2.8 %; then 127.31 on
#    D/48, -2.5 %, too long for make check: 8 min). With the held edge
#    node (the example's default) the same runs move +77 % and +28 %
#    (44.15, 78.28, 100.35 kg/s): it would fail.
# 2. Beverloo's exponent on similar grids: D = 0.15, 0.3, 0.6 and 1.2 m
#    with the silo sized by D and the cell D/12, W = C rho sqrt(g)
#    (D - k d)^n fitted with k d free (the Perzyna fill has lengths of its
#    own, g / gamma^2 and sigma_ref / (rho g), which Beverloo's k d takes;
#    docs/convergence.md section 38 (d)): asserts n within 2.5 +- 0.15.
#    Measured n = 2.43 (k d = 39 mm; 2.43 and 2.41 on D/24 and D/48); with
#    k d = 0 n = 2.74, which would fail. C with n = 2.5 is printed against
#    0.59 of 002 eq 20 (measured 0.747), not asserted: the continuum's C
#    is not the experiments' (docs/convergence.md section 38).
# 3. The flat slot (plane strain, the example's default fill of two widths)
#    on the same similar grids, D/12: W' = C rho sqrt(g) (D - k d)^n per
#    unit length with k d fitted, asserts n within issue 13's 1.5 +- 0.1.
#    Measured n = 1.439 (k d = 33 mm; 1.425 on D/24, where each D's rate
#    moves -2.0 to -4.2 %); with k d = 0 1.591. C with n = 1.5 printed
#    against 1.06 of 002 eq 19 (measured 1.189).
# About 2.5 min of one core.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
. "$(dirname "$0")/slow_case.sh" # skip if slow is excluded; $scratch
silo=./examples/papers/wieckowski1999_silo_discharge
setting="--method bspline2 --window-end 0.25 --fluidity 30
  --reference-stress 1795 --edge-node open"
circle="--geometry axisym --fill 1"
# run D CELL [OPTIONS]: appends "D W reference" to $scratch/rates
run() {
  # shellcheck disable=SC2086 # $setting and $3 are lists of options
  $silo $setting ${3:-$circle} --orifice "$1" --cell "$2" --out '' --quiet \
    >"$scratch/out" 2>&1 || true
  line=$(sed -n 's/^RESULT flow_rate[_a-z]*=\([^ ]*\) reference=\([^ ]*\) .*/\1 \2/p' \
    "$scratch/out")
  if [ -z "$line" ] || grep -q '^warning: less than' "$scratch/out"; then
    cat "$scratch/out"
    echo "FAIL: no steady rate for D = $1 m on $2 m cells"
    exit 1
  fi
  echo "$1 $line" >>"$scratch/rates"
  echo "D = $1 m, cell $2 m: $line (rate, Beverloo with d = 0)"
}
for cell in 0.05 0.025 0.0125; do run 0.3 "$cell"; done
awk '
  { w[NR] = $2 }
  END {
    first = w[2] / w[1] - 1; last = w[3] / w[2] - 1
    printf "D/6 -> D/12 %+.1f %%, D/12 -> D/24 %+.1f %% (at most 5 %%)\n",
      100 * first, 100 * last
    exit (last > 0.05 || last < -0.05)
  }' "$scratch/rates"
sed -n 2p "$scratch/rates" >"$scratch/similar" # D = 0.3 m on D/12, above
for d in 0.15 0.6 1.2; do
  : >"$scratch/rates"
  run "$d" "$(awk -v d="$d" 'BEGIN { printf "%.6g", d / 12 }')"
  cat "$scratch/rates" >>"$scratch/similar"
done
# k d scanned over 0-0.12 m (below the smallest D) in steps of 0.1 mm
awk -v kmax=0.12 -v kstep=0.0001 -v target=2.5 -v tolerance=0.15 \
  -v law_c=0.59 -f "$(dirname "$0")/beverloo_fit.awk" "$scratch/similar"
: >"$scratch/rates"
for d in 0.15 0.3 0.6 1.2; do
  run "$d" "$(awk -v d="$d" 'BEGIN { printf "%.6g", d / 12 }')" \
    "--geometry plane"
done
awk -v kmax=0.12 -v kstep=0.0001 -v target=1.5 -v tolerance=0.1 \
  -v law_c=1.06 -f "$(dirname "$0")/beverloo_fit.awk" "$scratch/rates"
