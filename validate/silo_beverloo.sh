#!/bin/sh
# validate/silo_beverloo.sh - Beverloo's exponent for the circular orifice
# (issue 16 item 3): examples/papers/wieckowski1999_silo_discharge with
# --geometry 3d (a quarter square silo; the example then runs the
# axisymmetric silo of the same D, B, H and cell in the same process) or
# --geometry axisym, at a fixed cell for several orifice diameters D (even
# numbers of cells: the example rounds D to them). The silo is sized by D
# (B = 1.5 D, fill H = 2 B with --fill 1), so the scenes are geometrically
# similar and only D / h changes. The rate is the least-squares slope of the
# discharged mass over 10 % to WINDOW_END of the fill (default 0.25: the run
# stops at 30 % and costs about 0.6 of the full 10-40 % window).
# Writes validate/results/silo_beverloo.csv (one row per geometry and D;
# the 3D runs give a row for each of their two silos) and the fits of
# validate/silo_beverloo_fit.awk to validate/results/silo_beverloo_fit.txt.
# Environment: PLAN, a list of geometry:cells_across_D (geometry plane,
# axisym or 3d; default: the committed runs), CELL (m, default 0.05),
# WINDOW_END, BUILD (default build), APPEND=1 (keep the CSV's rows),
# METHOD (the example's --method, default linear; another method writes
# silo_beverloo_METHOD.csv and silo_beverloo_METHOD_fit.txt). A planar
# row is a slot's rate in kg/(m s) with an open area fraction of 1.
# Cost (2026-11-28, one core): the 3D run at D/6 about 1.2 min of CPU, at
# D/8 about 4, at D/10 about 9; the axisymmetric runs seconds.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$top/build}
results=$top/validate/results
mkdir -p "$results"
CELL=${CELL:-0.05}
WINDOW_END=${WINDOW_END:-0.25}
# The committed CSV: this plan on 0.05 m cells, and the axisymmetric D/h
# 6-16 on 0.1 and 0.025 m cells (CELL=... APPEND=1), and 3d:10 and 3d:12
# (APPEND=1 PLAN="3d:10 3d:12": 4 and 7 min of CPU, ninth session).
PLAN=${PLAN-"3d:6 3d:8 axisym:4 axisym:6 axisym:8 axisym:10 axisym:12 axisym:16 axisym:24"}
METHOD=${METHOD:-linear}
name=silo_beverloo
[ "$METHOD" = linear ] || name=silo_beverloo_$METHOD
csv=$results/$name.csv
[ "${APPEND:-0}" = 1 ] && [ -f "$csv" ] ||
  echo "geometry,cell_m,cells_across,orifice_m,window_end,rate_kg_s,open_area_fraction,window_reached,cpu_s" >"$csv"
example=$build/examples/papers/wieckowski1999_silo_discharge
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for run in $PLAN; do
  geometry=${run%%:*} n=${run#*:}
  orifice=$(awk -v n="$n" -v h="$CELL" 'BEGIN { printf "%.6g", n * h }')
  /usr/bin/time -f "%U" -o "$scratch/time" "$example" --geometry "$geometry" \
    --method "$METHOD" --cell "$CELL" --orifice "$orifice" --fill 1 \
    --window-end "$WINDOW_END" \
    --t-end 0.01 --out '' --quiet >"$scratch/out" 2>&1 || true
  seconds=$(tail -n 1 "$scratch/time")
  # The 10 %-to-end rate of each silo in the order printed (3D first), and
  # each silo's open area as a fraction of pi D^2 / 4.
  awk -v g="$geometry" -v h="$CELL" -v n="$n" -v d="$orifice" \
    -v w="$WINDOW_END" -v s="$seconds" '
    /^orifice:/ { area[++a] = $(NF - 3) }
    /^rate by window:/ { full[++r] = 1 }
    /^warning: less than/ { full[r] = 0 }
    /^RESULT flow_rate_kg(_m)?_s=/ { split($2, v, "="); first = v[2] }
    /^RESULT flow_rate_3d_vs_axisym_kg_s=/ { split($3, v, "="); second = v[2] }
    END {
      if (first == "") { print "no rate: " g " " n > "/dev/stderr"; exit 1 }
      if (g == "3d") {
        printf "3d,%s,%s,%s,%s,%s,%s,%s,%s\n", h, n, d, w, first, area[1], full[1], s
        printf "axisym,%s,%s,%s,%s,%s,%s,%s,%s\n", h, n, d, w, second, area[2], full[2], s
      } else
        printf "%s,%s,%s,%s,%s,%s,%s,%s,%s\n", g, h, n, d, w, first,
          g == "plane" ? 1 : area[1], full[1], s
    }' "$scratch/out" >>"$csv" || cat "$scratch/out"
  tail -n 2 "$csv"
done
{
  head -n 1 "$csv"
  tail -n +2 "$csv" | sort -t, -k1,1 -k2,2g -k3,3n
} | awk -f "$top/validate/silo_beverloo_fit.awk" | tee "$results/${name}_fit.txt"
