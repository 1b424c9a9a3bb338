#!/bin/sh
# validate/silo_similar.sh - Beverloo's exponent on similar grids with the
# README's recommended silo setting (issue 13 item 4, issue 16 item 3;
# docs/convergence.md section 38 (d), (e), docs/3d.md):
# examples/papers/wieckowski1999_silo_discharge --method bspline2
# --fluidity 30 --reference-stress 1795 --edge-node open, FLIP, 2 points
# per cell axis, the rate over 10-25 % of the fill, at D = 0.15, 0.3, 0.6
# and 1.2 m with the silo sized by D (B = 1.5 D) and the cell D / n, so the
# grids are similar and the open nodes cut the same hole at every D: the
# exponent is the material's, not the staircase's. plane: the slot, fill
# two widths; axisym and 3d: the circular orifice, fill one width (3d: the
# quarter square silo; its RESULT against the axisymmetric silo of the same
# process is kept as a second rate). Writes validate/results/silo_similar.csv
# and fits W = C rho sqrt(g) (D - k d)^n per geometry and n with
# tests/scripts/beverloo_fit.awk (k d scanned over 0-0.12 m) into
# validate/results/silo_similar.txt.
# Environment: APPEND=1 adds the runs to the CSV (PLAN="" then only fits),
# BUILD (default build), PLAN (geometry:n runs, each over the four D;
# default "plane:12 axisym:12 plane:24 axisym:24"), DIAMETERS. Cost
# (2026-11-30, one core at load 2-4): plane D/12 1 min, axisym D/12 40 s,
# D/24 5-6 min each; 3d:6 about 4 min, 3d:8 about 10 min; the default
# plan about 13 min.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$top/build}
results=$top/validate/results
mkdir -p "$results"
PLAN=${PLAN-"plane:12 axisym:12 plane:24 axisym:24"}
DIAMETERS=${DIAMETERS:-"0.15 0.3 0.6 1.2"}
csv=$results/silo_similar.csv
[ "${APPEND:-0}" = 1 ] ||
  echo "geometry,cells_across,orifice_m,cell_m,rate,reference_d0,axisym_rate,unit,cpu_s" >"$csv"
example=$build/examples/papers/wieckowski1999_silo_discharge
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for run in $PLAN; do
  IFS=: read -r geometry n <<END
$run
END
  fill=1
  [ "$geometry" = plane ] && fill=2
  for d in $DIAMETERS; do
    cell=$(awk -v d="$d" -v n="$n" 'BEGIN { printf "%.6g", d / n }')
    /usr/bin/time -f "%U" -o "$scratch/time" "$example" --geometry "$geometry" \
      --method bspline2 --fluidity 30 --reference-stress 1795 --edge-node open \
      --orifice "$d" --cell "$cell" --fill "$fill" --window-end 0.25 \
      --out '' --quiet >"$scratch/out" 2>&1 || true
    awk -v g="$geometry" -v n="$n" -v d="$d" -v h="$cell" \
      -v s="$(tail -n 1 "$scratch/time")" '
      /^warning: less than/ { jammed = 1 }
      /^RESULT flow_rate_kg_m_s=/ { split($2, v, "="); w = v[2]; u = "kg/(m s)"
        split($3, r, "="); ref = r[2] }
      /^RESULT flow_rate_kg_s=/ { split($2, v, "="); w = v[2]; u = "kg/s"
        split($3, r, "="); ref = r[2] }
      /^RESULT flow_rate_3d_vs_axisym/ { split($3, r, "="); axi = r[2] }
      END { if (jammed || w == "") w = "nan"
        printf "%s,%s,%s,%s,%s,%s,%s,%s,%s\n", g, n, d, h, w, ref, axi, u, s }
    ' "$scratch/out" | tee -a "$csv"
  done
done
# One fit per geometry and n: n within 1.5 +- 0.1 (slot) or 2.5 +- 0.15.
: >"$results/silo_similar.txt"
for group in $(awk -F, 'NR > 1 { print $1 ":" $2 }' "$csv" | sort -u); do
  geometry=${group%:*} n=${group#*:}
  target=2.5 tolerance=0.15 law_c=0.59
  [ "$geometry" = plane ] && target=1.5 tolerance=0.1 law_c=1.06
  awk -F, -v g="$geometry" -v n="$n" \
    '$1 == g && $2 == n && $5 != "nan" { print $3, $5, $6 }' "$csv" \
    >"$scratch/rates"
  {
    echo "$geometry, D/$n: $(awk '{ printf "%s ", $2 }' "$scratch/rates")"
    awk -v kmax=0.12 -v kstep=0.0001 -v target="$target" \
      -v tolerance="$tolerance" -v law_c="$law_c" \
      -f "$top/tests/scripts/beverloo_fit.awk" "$scratch/rates" || true
  } | tee -a "$results/silo_similar.txt"
done
