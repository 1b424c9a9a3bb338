#!/bin/sh
# bench/convergence/energy.sh - the energy budget of the planar column
# collapse per (cell, points per cell), for docs/convergence.md section 15.
# One run at a time (the machine is shared).
#
# usage: energy.sh LABEL "CELLS" "PPCS" [energy_budget collapse options...]
# e.g.   energy.sh bs2_plain "0.015 0.0075" "1 2 3 4" --aspect 1.3 \
#          --method bspline2 --friction 37 --floor face --family plain
# Prints CSV: label,cell_m,ppc,runout,released_J,kinetic_J,elastic_J,
# plastic_J,numerical_J, then the kinetic, plastic and numerical shares of
# the released energy at the end, the numerical share of the energy
# released at the end reached by 1, 2 and 3 tau_c, seconds, and with a
# Coulomb floor wall (--floor wall, --floor-mu MU) the share of the floor's
# slip work (an estimate, see energy_budget.c) at the end and by 2 tau_c (0
# on other floors; the numerical share less it is the discretisation's loss),
# and last the final height H_inf / L0 (the deposit's highest top; rows
# written before docs/convergence.md section 20 lack it). BUDGET is the
# energy_budget binary (build line at the top of energy_budget.c).
BUDGET=${BUDGET:-./energy_budget}
label=$1 cells=$2 ppcs=$3
shift 3
tmp=$(mktemp)
for cell in $cells; do
  for ppc in $ppcs; do
    start=$(date +%s.%N)
    "$BUDGET" collapse --cell "$cell" --ppc "$ppc" "$@" > "$tmp" 2>&1
    end=$(date +%s.%N)
    r=$(sed -n 's/^RESULT runout=\([^ ]*\).*/\1/p' "$tmp")
    h=$(sed -n 's/^RESULT .*height=\([^ ]*\).*/\1/p' "$tmp")
    if [ -z "$r" ]; then
      echo "$label,$cell,$ppc,failed:$(tail -1 "$tmp" | tr ',' ' ')"
      continue
    fi
    awk -v label="$label" -v cell="$cell" -v ppc="$ppc" -v r="$r" -v h="$h" \
      -v secs="$(echo "$end - $start" | bc)" '
      function field(line, name,   a) {
        if (match(line, name "=[^ ]*")) {
          a = substr(line, RSTART + length(name) + 1, RLENGTH - length(name) - 1)
          return a + 0
        }
        return 0
      }
      /^BUDGET/ {
        dpe = field($0, "released_J"); ke = field($0, "kinetic_J")
        el = field($0, "elastic_J"); wp = field($0, "plastic_J")
        num = field($0, "numerical_J"); fr = field($0, "floor_friction_J")
      }
      /^PHASES/ {
        split($0, head, ":"); n = split(head[2], rows, " ")
        for (k = 1; k <= 3 && k <= n; k++) {
          split(rows[k], v, ","); phase[k] = v[5]; friction[k] = v[7] + 0
        }
      }
      END {
        printf "%s,%s,%s,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.1f,%.4f,%.4f,%s\n",
          label, cell, ppc, r, dpe, ke, el, wp, num, ke / dpe, wp / dpe,
          num / dpe, phase[1] / dpe, phase[2] / dpe, phase[3] / dpe, secs,
          fr / dpe, friction[2] / dpe, h
      }' "$tmp"
  done
done
rm -f "$tmp"
