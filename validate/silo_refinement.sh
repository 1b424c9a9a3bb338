#!/bin/sh
# validate/silo_refinement.sh - the silo's discharge rate under refinement
# (issue 13 item 4; docs/convergence.md section 31):
# examples/papers/wieckowski1999_silo_discharge with quadratic B-splines
# (2 x 2 points per cell; a rigid floor holds its cells' nodes), the flat
# slot silo (D = 0.3 m) on D/6 to D/48 and 1 x 1 to 4 x 4 points on D/24,
# and the axisymmetric silo (circular orifice, D = 0.3 m) on D/6 to D/24;
# then Beverloo's exponents with k fitted (validate/silo_beverloo.sh,
# METHOD=bspline2). Writes validate/results/silo_refinement.csv and prints
# each rate's change per halving. Environment: BUILD (default build), PLAN
# (geometry:cell_m:ppc runs, default below), SWEEP=0 skips the Beverloo
# sweep. Cost (2026-11-29, one core at load 2-3): the planar D/48 run about
# 15 min, D/24 with 4 x 4 8 min, the axisymmetric D/24 7 min, the rest and
# the sweep about 5 min.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$top/build}
results=$top/validate/results
mkdir -p "$results"
PLAN=${PLAN-"plane:0.05:2 plane:0.025:2 plane:0.0125:2 plane:0.00625:2 \
plane:0.0125:1 plane:0.0125:3 plane:0.0125:4 \
axisym:0.05:2 axisym:0.025:2 axisym:0.0125:2"}
csv=$results/silo_refinement.csv
echo "geometry,cell_m,ppc,rate,rate_10_25,rate_25_40,unit,cpu_s" >"$csv"
example=$build/examples/papers/wieckowski1999_silo_discharge
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for run in $PLAN; do
  geometry=${run%%:*} rest=${run#*:}
  cell=${rest%%:*} ppc=${rest#*:}
  /usr/bin/time -f "%U" -o "$scratch/time" "$example" --geometry "$geometry" \
    --method bspline2 --cell "$cell" --ppc "$ppc" --out '' --quiet \
    >"$scratch/out" 2>&1
  awk -v g="$geometry" -v h="$cell" -v n="$ppc" \
    -v s="$(tail -n 1 "$scratch/time")" '
    /^rate by window:/ { a = $6; b = $9; sub(",", "", a); sub(",", "", b) }
    /^RESULT flow_rate_kg_m_s=/ { split($2, v, "="); w = v[2]; u = "kg/(m s)" }
    /^RESULT flow_rate_kg_s=/ { split($2, v, "="); w = v[2]; u = "kg/s" }
    END { printf "%s,%s,%s,%s,%s,%s,%s,%s\n", g, h, n, w, a, b, u, s }
  ' "$scratch/out" | tee -a "$csv"
done
# The change per halving of the cell (2 x 2) and per added point per axis
# (D/24 = 0.0125 m), in the order of the rows.
awk -F, 'NR > 1 && $3 == 2 {
    if ($1 in last) printf "%s, cell %s m: %+.1f %% over %s m\n", $1, $2,
      100 * ($4 / last[$1] - 1), cell[$1]
    last[$1] = $4; cell[$1] = $2 }
  NR > 1 && $1 == "plane" && $2 == 0.0125 { ppc[$3] = $4 }
  END { for (n = 2; n <= 4; n++) if ((n in ppc) && ((n - 1) in ppc))
      printf "plane, D/24, %d x %d points: %+.1f %% over %d x %d\n", n, n,
        100 * (ppc[n] / ppc[n - 1] - 1), n - 1, n - 1 }' "$csv" |
  tee "$results/silo_refinement.txt"
[ "${SWEEP:-1}" = 0 ] || METHOD=bspline2 CELL=0.05 \
  PLAN="plane:6 plane:8 plane:12 plane:16 plane:24 axisym:6 axisym:8 axisym:12 axisym:16 axisym:24" \
  BUILD="$build" sh "$top/validate/silo_beverloo.sh"
