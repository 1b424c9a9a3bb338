#!/bin/sh
# bench/convergence/energy_validate.sh - the instrument of energy_budget.c on
# scenes with a known budget (docs/convergence.md section 15), one run at a
# time: an elastic bar (KE + E_el conserved, W_int = E_el change), an
# elastic block in free fall (dPE = KE) and landing on the no-slip floor, a
# Mohr-Coulomb block sliding to rest on it (KE(0) + dPE dissipated).
# Prints CSV: case,method,cell_m,ppc,option,input_J,kinetic,elastic_change,
# plastic,numerical (shares of dPE + KE(0) at the end).
BUDGET=${BUDGET:-./energy_budget}
row() {
  name=$1 method=$2 cell=$3 ppc=$4 option=$5
  shift 5
  "$BUDGET" "$@" --method "$method" --cell "$cell" --ppc "$ppc" \
    --family plain | sed -n "s/^SHARES of dPE + KE(0) = \([^ ]*\) J\/m: kinetic=\([^ ]*\) elastic_change=\([^ ]*\) plastic=\([^ ]*\) numerical=\([^ ]*\)/$name,$method,$cell,$ppc,$option,\1,\2,\3,\4,\5/p"
}
for cfl in 0.5 0.25 0.1; do
  row bar linear 0.05 2 "cfl $cfl" bar --youngs 1e6 --cfl "$cfl"
done
for method in ugimp bspline2; do
  row fall "$method" 0.015 2 "t 0.12 s" drop --gap 0.1 --t-end 0.12 --youngs 5e5
  for youngs in 5e5 5e6; do
    row drop "$method" 0.015 2 "E $youngs" drop --gap 0.1 --t-end 0.2 \
      --youngs "$youngs"
  done
  for cell in 0.015 0.0075; do
    for ppc in 2 4; do
      row slide "$method" "$cell" "$ppc" "1 m per s" slide --friction 37 --rows 50
    done
  done
done
