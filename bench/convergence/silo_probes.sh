#!/bin/sh
# docs/convergence.md sec. 29: the planar silo's rate under refinement with
# one candidate changed at a time, in a mass-flow hopper (20 deg from the
# vertical, no stagnant zone) and on the flat floor. Prints CSV rows
#   probe,hopper_deg,cell_m,rate_kg_m_s,rate_10_25,rate_25_40,wall_s
# Usage: bench/convergence/silo_probes.sh [PROBES] [CELLS]
#   PROBES: space-separated tag:options pairs (default: the section's list)
#   CELLS:  default "0.05 0.025 0.0125" (D/6, D/12, D/24 for D = 0.3 m)
# A D/24 hopper run takes 30-60 s of CPU, D/48 about 4 min (Mohr-Coulomb
# with psi = phi and E = 100 MPa: 5-6 min at D/24).
set -eu
top=$(cd "$(dirname "$0")/../.." && pwd)
silo=$top/build/examples/papers/wieckowski1999_silo_discharge
probes=${1:-"dp:--hopper=20 cell_mean:--hopper=20,--volumetric=cell \
mu_i:--hopper=20,--grain=0.001 e100:--hopper=20,--youngs=1e8 \
ppc3:--hopper=20,--ppc=3 mc0:--hopper=20,--dilation=0 \
mc25:--hopper=20,--dilation=25 pic02:--hopper=20,--pic=0.02 \
pic10:--hopper=20,--pic=0.1 pic50:--hopper=20,--pic=0.5 \
usl:--hopper=20,--scheme=usl usf:--hopper=20,--scheme=usf \
wall0:--hopper=20,--wall-friction=0 h10:--hopper=10 h30:--hopper=30 \
flat_mc0:--dilation=0 flat_mc25:--dilation=25"}
cells=${2:-"0.05 0.025 0.0125"}
log=$(mktemp)
trap 'rm -f "$log"' EXIT
echo "probe,hopper_deg,cell_m,rate_kg_m_s,rate_10_25,rate_25_40,wall_s"
for probe in $probes; do
  tag=${probe%%:*}
  opts=$(echo "${probe#*:}" | tr ',=' '  ')
  hopper=$(echo "$opts" | sed -n 's/.*--hopper \([0-9.]*\).*/\1/p')
  for cell in $cells; do
    start=$(date +%s)
    # shellcheck disable=SC2086 # the options are words
    "$silo" --cell "$cell" $opts --out '' --quiet >"$log" 2>&1
    awk -v tag="$tag" -v hopper="${hopper:-flat}" -v cell="$cell" \
      -v wall=$(($(date +%s) - start)) '
      /^rate by window/ { gsub(/,/, ""); a = $6; b = $9 }
      /^RESULT flow_rate/ { split($2, r, "="); rate = r[2] }
      END { printf "%s,%s,%s,%s,%s,%s,%s\n", tag, hopper, cell, rate, a, b, wall }
    ' "$log"
  done
done
