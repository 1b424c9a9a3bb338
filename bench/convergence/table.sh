#!/bin/sh
# bench/convergence/table.sh - markdown table of one column of sweep.sh CSV
# rows: cell size as L0/n (L0 = 0.15 m) down, points per cell across.
# usage: table.sh FILE.csv [COLUMN]   COLUMN: 4 run-out (default),
#   5 farthest point, 6/7/8 thickness 1/2/5 % L0, 9 final height,
#   10 stop time / tau_c, 11 hidden kinetic energy share
col=${2:-4}
awk -F, -v col="$col" '
  { key = $2 SUBSEP $3; value[key] = $col; if (!($2 in seen)) { seen[$2] = 1; cells[++nc] = $2 }
    if (!($3 in pseen)) { pseen[$3] = 1; ppcs[++np] = $3 } }
  END {
    printf "| cell |"; for (j = 1; j <= np; j++) printf " %dx%d |", ppcs[j], ppcs[j]; printf "\n"
    printf "| --- |"; for (j = 1; j <= np; j++) printf " --- |"; printf "\n"
    for (i = 1; i <= nc; i++) {
      printf "| L0/%d |", 0.15 / cells[i] + 0.5
      for (j = 1; j <= np; j++) {
        v = value[cells[i], ppcs[j]]
        if (v ~ /^failed/) v = "failed"
        else if (v != "") v = sprintf("%.2f", v)
        printf " %s |", v
      }
      printf "\n"
    }
  }' "$1"
