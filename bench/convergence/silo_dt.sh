#!/bin/sh
# bench/convergence/silo_dt.sh - the slot silo's discharge rate at fixed cell
# and varied Courant number, and the cross runs at a finer grid's time step
# (docs/convergence.md sec. 28, "Time step or cell?").
#
# usage: silo_dt.sh LABEL "CELL:CFL ..." [wieckowski1999_silo_discharge options]
# e.g.   silo_dt.sh plane "0.05:0.8 0.05:0.4 0.025:0.25"
#        silo_dt.sh axisym "0.05:0.5 0.05:0.9" --geometry axisym
# With no pairs (or "-") it runs the table of sec. 28: D/6, D/12 and D/24
# at cfl 1.0, 0.8, 0.5, 0.4, 0.2, 0.1 and D/12 at 0.25 (the D/24 step);
# the D/24 row at 0.1 takes about 4 min at load 1-2.
#
# Prints CSV: label,cell_m,cfl,dt_cp_s,flow_rate,rate_10_25,rate_25_40,
# seconds (rates in kg/(m s), or kg/s with --geometry axisym). dt_cp_s =
# cfl h / c_p with the fill's P-wave speed c_p =
# sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu) rho)) = 29.96 m/s (E = 1 MPa,
# nu = 0.3, rho = 1500 kg/m^3): the library's stable step is
# cfl h / (c_p + max |v_p|), so the real step is 5-10 % smaller while the
# points fall at 1.5-3 m/s; two runs with the same cfl h have the same step
# to within the difference of their largest point speeds. The options must
# not hold blanks. Runs JOBS (default 2) cases at a time; SILO is the
# example binary.
SILO=${SILO:-./build/examples/papers/wieckowski1999_silo_discharge}
JOBS=${JOBS:-2}
label=$1
pairs=$2
shift 2 2>/dev/null || shift $#
if [ -z "$pairs" ] || [ "$pairs" = "-" ]; then
  pairs="0.05:1.0 0.05:0.8 0.05:0.5 0.05:0.4 0.05:0.2 0.05:0.1
0.025:1.0 0.025:0.8 0.025:0.5 0.025:0.4 0.025:0.25 0.025:0.2 0.025:0.1
0.0125:1.0 0.0125:0.8 0.0125:0.5 0.0125:0.4 0.0125:0.2 0.0125:0.1"
fi
tmp=$(mktemp -d)
for p in $pairs; do
  echo "${p%%:*} ${p##*:}"
done | SILO=$SILO EXTRA="$*" TMP=$tmp xargs -P "$JOBS" -n 2 sh -c '
  # EXTRA: the options after the pairs, split on blanks (none hold a blank)
  start=$(date +%s.%N)
  "$SILO" --cell "$0" --cfl "$1" --out "" --quiet $EXTRA \
    > "$TMP/$0-$1.txt" 2>&1
  end=$(date +%s.%N)
  echo "$start $end" | awk "{printf \"%.1f\n\", \$2 - \$1}" > "$TMP/$0-$1.sec"'
for p in $pairs; do
  cell=${p%%:*} cfl=${p##*:}
  f=$tmp/$cell-$cfl.txt
  r=$(sed -n 's/^RESULT flow_rate_kg_\(m_\)\{0,1\}s=\([^ ]*\).*/\2/p' "$f")
  [ -n "$r" ] || r="failed:$(tail -1 "$f" | tr ',' ' ')"
  w=$(sed -n 's/^rate by window: 10-25 %: \([^,]*\), 25-40 %: \([^,]*\),.*/\1,\2/p' "$f")
  [ -n "$w" ] || w=","
  dt=$(awk -v c="$cfl" -v h="$cell" 'BEGIN { printf "%.4g", c * h / 29.96 }')
  echo "$label,$cell,$cfl,$dt,$r,$w,$(cat "$tmp/$cell-$cfl.sec")"
done
rm -rf "$tmp"
