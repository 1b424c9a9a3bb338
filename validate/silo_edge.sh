#!/bin/sh
# validate/silo_edge.sh - the silo's discharge rate under refinement with
# the orifice's two floor edges (issue 13 item 4; docs/convergence.md
# section 38): examples/papers/wieckowski1999_silo_discharge, quadratic
# B-splines, MUSL, FLIP, the rate over 10-25 % of the fill; the flat slot
# (fill two widths) and the axisymmetric silo (fill one width), D = 0.3 m,
# with the floor holding the node on the orifice's edge (--edge-node held)
# or starting a cell beyond it (open); the fill 002's rate-free
# Drucker-Prager (dp) or the Perzyna material of sections 36-37 (perzyna:
# --fluidity 30 --reference-stress 1795). Writes
# validate/results/silo_edge.csv and prints each rate's change per
# halving, per added point per axis, and the gap open - held on each cell.
# Environment: APPEND=1 adds the runs to the CSV instead of starting it
# afresh (PLAN="" then only prints the summary), BUILD (default build), PLAN
# (geometry:cell_m:ppc:edge:material runs, default below). Cost
# (2026-11-29, one core at load 2-3): the D/48 runs 8-10 min each, the
# rest about 8 min; the default plan about 45 min.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$top/build}
results=$top/validate/results
mkdir -p "$results"
PLAN=${PLAN-"axisym:0.025:2:held:dp axisym:0.0125:2:held:dp \
axisym:0.00625:2:held:dp axisym:0.025:2:open:dp axisym:0.0125:2:open:dp \
axisym:0.00625:2:open:dp axisym:0.025:3:open:dp axisym:0.0125:3:open:dp \
axisym:0.025:2:open:perzyna axisym:0.0125:2:open:perzyna \
axisym:0.00625:2:open:perzyna plane:0.025:2:open:dp plane:0.0125:2:open:dp \
plane:0.00625:2:open:dp"}
csv=$results/silo_edge.csv
[ "${APPEND:-0}" = 1 ] ||
  echo "geometry,cell_m,ppc,edge,material,rate,rate_10_25,rate_25_40,unit,cpu_s" >"$csv"
example=$build/examples/papers/wieckowski1999_silo_discharge
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for run in $PLAN; do
  IFS=: read -r geometry cell ppc edge material <<EOF
$run
EOF
  fill=2
  [ "$geometry" = axisym ] && fill=1
  rate_term=""
  [ "$material" = perzyna ] && rate_term="--fluidity 30 --reference-stress 1795"
  /usr/bin/time -f "%U" -o "$scratch/time" "$example" --geometry "$geometry" \
    --method bspline2 --cell "$cell" --ppc "$ppc" --fill "$fill" \
    --window-end 0.25 $rate_term --edge-node "$edge" --out '' --quiet >"$scratch/out" 2>&1
  awk -v g="$geometry" -v h="$cell" -v n="$ppc" -v e="$edge" -v m="$material" \
    -v s="$(tail -n 1 "$scratch/time")" '
    /^rate by window:/ { a = $6; b = $9; sub(",", "", a); sub(",", "", b) }
    /^RESULT flow_rate_kg_m_s=/ { split($2, v, "="); w = v[2]; u = "kg/(m s)" }
    /^RESULT flow_rate_kg_s=/ { split($2, v, "="); w = v[2]; u = "kg/s" }
    END { printf "%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n", g, h, n, e, m, w, a, b, u,
      s }
  ' "$scratch/out" | tee -a "$csv"
done
# Per geometry and edge: the change per halving (2 x 2) and from 2 x 2 to
# 3 x 3 on each cell; the gap open - held on each cell (2 x 2).
awk -F, 'NR == 1 { next }
  { g = $1 " " $5; all[NR] = $0 }
  $3 == 2 {
    key = g ", " $4 " edge"
    if (key in last) printf "%s, cell %s m: %+.1f %% over %s m\n", key, $2,
      100 * ($6 / last[key] - 1), cell[key]
    last[key] = $6; cell[key] = $2; two[g, $2, $4] = $6 }
  END {
    for (i = 2; i <= NR; i++) {
      split(all[i], f, ",")
      g = f[1] " " f[5]
      if (f[3] == 3 && ((g, f[2], f[4]) in two))
        printf "%s, %s edge, cell %s m: 3 x 3 %+.1f %% over 2 x 2\n", g, f[4],
          f[2], 100 * (f[6] / two[g, f[2], f[4]] - 1)
      if (f[3] == 2 && f[4] == "open" && ((g, f[2], "held") in two))
        printf "%s, cell %s m: gap open - held %.2f\n", g, f[2],
          f[6] - two[g, f[2], "held"]
    }
  }' "$csv" | tee "$results/silo_edge.txt"
