#!/bin/sh
# bench/chart.sh - the speed-vs-accuracy charts (make bench-chart).
#
# SCENE=collapse (default): runs examples/column_collapse (a = 1,
# L0 = 0.15 m: the linear regime of Lube et al. 2005, reference run-out
# (L_inf - L0)/L0 = 1.2) over method x family x cell size x points per
# cell, records
#   RESULTS/accuracy_vs_cost.csv
#     method,family,cell,ppc,points,seconds,ns_per_point_step,metric,rel_error
# (metric: the simulated run-out; rel_error: |metric - 1.2| / 1.2; a run
# that failed, e.g. a point leaving the grid, has metric and rel_error nan
# and seconds up to the failure), and draws RESULTS/accuracy_vs_cost.png:
# relative error against wall-clock seconds, log axes, the Pareto front
# (no run both faster and more accurate) joined by a line.
# SCENE=slope: the same for examples/papers/seyedan2021_slope_density (000 sec 2.3, moderate
# flow down a 30 degree slope, 0.25 s): metric the final average density,
# reference rho_cr = 2235 kg/m^3 (a moderate flow keeps the critical
# density), to RESULTS/accuracy_vs_cost_slope.{csv,png}.
#
# Usage: [SCENE=collapse|slope] chart.sh PROGRAM RESULTS_DIR [JOBS]
#   JOBS: runs at a time (default 2); 'plot' only redraws the PNG from the
#   existing CSV. Seconds are wall-clock time of each
#   run's time loop, one worker per run, so run on an otherwise idle machine.
# The grid (96 runs) takes ~10 minutes on 2 cores.
set -eu

program=${1:?usage: [SCENE=collapse|slope] chart.sh PROGRAM RESULTS_DIR [JOBS]}
results=${2:?usage: [SCENE=collapse|slope] chart.sh PROGRAM RESULTS_DIR [JOBS]}
jobs=${3:-2}
scene=${SCENE:-collapse}
case $scene in
collapse)
  reference=1.2 # Lube et al. 2005: 1.2 a at a = 1
  scene_args="--aspect 1 --length 0.15"
  metric=runout
  cells="0.015 0.01 0.0075"
  ppcs="1 2 3"
  name=accuracy_vs_cost
  title="Column collapse a = 1: run-out error against Lube et al. 2005 vs run time"
  note="the run-out grows with refinement, so errors below about 5 % are crossings of the law"
  ylabel="|run-out - law| / law"
  band=0.15 band_label="experimental scatter (+-15 %)"
  floor=1e-3 # errors below this are drawn at it
  ;;
slope)
  reference=2235 # rho_cr of 000 Table 1 (kg/m^3)
  scene_args=""
  metric=average_density
  cells="0.01 0.0075"
  ppcs="1 2"
  name=accuracy_vs_cost_slope
  title="Moderate flow down a slope (000 sec 2.3): average density error vs run time"
  note="the reference is rho_cr: a moderate flow keeps the critical density"
  ylabel="|average density - rho_cr| / rho_cr"
  band=0.005 band_label="granular target (0.5 %)"
  floor=1e-5
  ;;
*)
  echo "chart.sh: SCENE must be collapse or slope" >&2
  exit 2
  ;;
esac
mkdir -p "$results"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One line per run: method family cell ppc (10, 15 and 20 cells across
# the column). The finest cell skips 3x3 points per cell (the most
# expensive corner).
for method in linear ugimp cpgimp cpdi; do
  for family in plain stress_free granular; do
    for cell in $cells; do
      for ppc in $ppcs; do
        [ "$cell" = 0.0075 ] && [ "$ppc" = 3 ] && continue
        echo "$method $family $cell $ppc"
      done
    done
  done
done > "$work/grid"

# Runs one grid line and prints its CSV row (the example prints STATS and
# RESULT lines; a failed run prints neither).
cat > "$work/one.sh" <<'ONE'
#!/bin/sh
program=$1 reference=$2 metric=$3 scene_args=$4
method=$5 family=$6 cell=$7 ppc=$8
start=$(date +%s.%N)
# scene_args is split into words on purpose
# shellcheck disable=SC2086
output=$("$program" --quiet --out '' $scene_args \
  --method "$method" --family "$family" --cell "$cell" --ppc "$ppc" 2>&1) || true
end=$(date +%s.%N)
echo "$output" | awk -v m="$method" -v f="$family" -v c="$cell" -v p="$ppc" \
  -v ref="$reference" -v start="$start" -v end="$end" -v metric="$metric" '
  /^column collapse:/ { for (i = 1; i <= NF; i++) if ($(i+1) ~ /^points/) n = $i }
  /^STATS/ { for (i = 2; i <= NF; i++) { split($i, kv, "="); s[kv[1]] = kv[2] } }
  /^RESULT / && index($2, metric "=") == 1 { split($2, kv, "="); runout = kv[2] }
  END {
    if (runout == "") {
      printf "%s,%s,%s,%s,%s,%.3f,nan,nan,nan\n", m, f, c, p, n, end - start
    } else {
      err = (runout - ref) / ref; if (err < 0) err = -err
      printf "%s,%s,%s,%s,%s,%s,%s,%s,%.4g\n", m, f, c, p, s["points"],
        s["seconds"], s["ns_per_point_step"], runout, err
    }
  }'
ONE

csv="$results/$name.csv"
if [ "$jobs" != plot ]; then
  echo "bench-chart: $(wc -l < "$work/grid") runs, $jobs at a time" >&2
  xargs -P "$jobs" -L 1 sh "$work/one.sh" "$program" "$reference" \
    "$metric" "$scene_args" < "$work/grid" > "$work/rows"
  {
    echo "method,family,cell,ppc,points,seconds,ns_per_point_step,metric,rel_error"
    sort -t, -k1,1 -k2,2 -k3,3gr -k4,4n "$work/rows"
  } > "$csv"
  echo "bench-chart: wrote $csv" >&2
fi

# Pareto front: by increasing time, the runs more accurate than every
# faster one.
awk -F, 'NR > 1 && $9 != "nan"' "$csv" | sort -t, -k6,6g |
  awk -F, 'BEGIN { best = 1e300 } $9 < best { best = $9; print $6, $9, $1 "/" $2 "/" $3 "/" $4, ++n }' \
  > "$work/front"
# The key to the numbered front points, drawn as a text block beside the
# chart: "n  method / family / cell (m) / points per cell axis". Numbers
# instead of the full labels keep the labels from covering each other.
key=$(awk '{ split($3, f, "/");
  printf "%s%2d  %s / %s / %s m / %dx%d", (NR > 1 ? "\\n" : ""), $4, f[1], f[2], f[3], f[4], f[4] }' \
  "$work/front")
for family in plain stress_free granular; do
  awk -F, -v f="$family" -v floor="$floor" 'NR > 1 && $2 == f && $9 != "nan" {
    e = $9 < floor ? floor : $9; print $6, e }' "$csv" > "$work/$family"
done

if ! command -v gnuplot > /dev/null 2>&1; then
  echo "bench-chart: gnuplot not found (apt-get install gnuplot-nox): no PNG" >&2
  exit 0
fi
failed=$(awk -F, 'NR > 1 && $9 == "nan"' "$csv" | wc -l)
gnuplot <<PLOT
set terminal pngcairo size 1100,750 font 'sans,11'
set output '$results/$name.png'
set title "$title\n(method x family x cell x points per cell; $failed failed runs not shown;\n$note)"
set logscale xy
set xlabel 'wall-clock seconds (one core)'
set ylabel '$ylabel'
set grid
set key outside right top
set rmargin 44
set yrange [$floor:1]
# Decimal tick labels (0.001, 0.01, ...), not 1.000000 ... 0.000010.
set format x '%g'
set format y '%g'
set arrow from graph 0, first $band to graph 1, first $band nohead dt 2 lc rgb 'gray40'
set label '$band_label' at graph 0.62, first $band * 1.13 tc rgb 'gray40'
set label "Pareto front, by run time:\\n$key" at screen 0.645, screen 0.62 left font 'sans,9' noenhanced
plot '$work/plain' using 1:2 with points pt 6 ps 1.3 lc rgb '#1f77b4' title 'plain', \
     '$work/stress_free' using 1:2 with points pt 8 ps 1.3 lc rgb '#ff7f0e' title 'stress\_free', \
     '$work/granular' using 1:2 with points pt 7 ps 1.3 lc rgb '#2ca02c' title 'granular', \
     '$work/front' using 1:(\$2 < $floor ? $floor : \$2) with steps lw 2 lc rgb 'black' title 'Pareto front', \
     '$work/front' using 1:(\$2 < $floor ? $floor : \$2):(int(\$4) % 2 ? sprintf('%d', \$4) : '') with labels offset -0.9,0.8 font 'sans,9' notitle, \\
     '$work/front' using 1:(\$2 < $floor ? $floor : \$2):(int(\$4) % 2 ? '' : sprintf('%d', \$4)) with labels offset 1.1,-0.6 font 'sans,9' notitle
PLOT
echo "bench-chart: wrote $results/$name.png" >&2
echo "Pareto front (seconds rel_error method/family/cell/ppc):" >&2
cat "$work/front" >&2
