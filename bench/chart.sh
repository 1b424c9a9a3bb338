#!/bin/sh
# bench/chart.sh - the speed-vs-accuracy charts (make bench-chart).
#
# Each chart runs a scene over a list of settings (a setting: shape
# functions, family and the scene's other options; one colour each) times
# cell size times points per cell, and draws two panels against the run
# time of each run:
#   left:  the error against the experimental law (or the paper's value);
#   right: the difference from the numerical model's own converged answer
#          for that setting, so the chart shows the cost of reaching what
#          the model converges to, not crossings of the law.
# The converged answer of a setting is its run on the finest cell with the
# most points per cell (not a Richardson estimate: the run-out is not
# monotone in the cell for most settings, see docs/convergence.md, so an
# extrapolation from three cells would invent a number). It counts as
# converged only if that run's metric differs by at most 3 % from every
# run with the same points per cell on a cell up to twice as large (the
# last halving, the cells between included);
# otherwise the setting is drawn in the left panel only and the legend says
# "not converged" with the change in the last halving.
#
# SCENE=collapse (default): examples/column_collapse, a = 1, L0 = 0.15 m
# (the linear regime of Lube et al. 2005, run-out (L_inf - L0)/L0 = 1.2).
# SCENE=slope: examples/papers/seyedan2021_slope_density (000 sec 2.3,
# moderate flow down a 30 degree slope, 0.25 s): metric the final average
# density, reference rho_cr = 2235 kg/m^3.
#
# Writes RESULTS/NAME.csv, one row per run:
#   setting,cell,ppc,points,seconds,ns_per_point_step,metric,rel_error,
#   load1,reference,ref_change,ref_diff
# (rel_error: |metric - law| / law; load1: the machine's 1-minute load
# average when the run started, the times are only as good as it;
# reference: the setting's finest run's metric, ref_change: its change in
# the last halving, ref_diff: |metric - reference| / reference, nan where
# the setting did not converge; a failed run, e.g. a point leaving the grid,
# has metric nan and seconds up to the failure) and RESULTS/NAME.png.
#
# Usage: [SCENE=collapse|slope] chart.sh PROGRAM RESULTS_DIR [JOBS]
#   JOBS: runs at a time (default 2); 'plot' only redraws the PNG from the
#   existing CSV. Seconds are the wall-clock time of each run's time loop,
#   one worker per run.
# Cost on the 2-core development machine: see docs/performance.md.
set -eu

program=${1:?usage: [SCENE=collapse|slope] chart.sh PROGRAM RESULTS_DIR [JOBS]}
results=${2:?usage: [SCENE=collapse|slope] chart.sh PROGRAM RESULTS_DIR [JOBS]}
jobs=${3:-2}
scene=${SCENE:-collapse}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# settings: one line per setting, "key|legend text|options"; grid: one
# line per run, "key cell ppc".
case $scene in
collapse)
  reference=1.2 # Lube et al. 2005: 1.2 a at a = 1
  scene_args="--aspect 1 --length 0.15"
  width=0.15 # L0, m
  across="across L0"
  metric=runout
  name=accuracy_vs_cost
  title="Column collapse, a = 1, L0 = 0.15 m (examples/column_collapse, 6 tau_c)"
  law="run-out (L_inf - L0)/L0 against Lube et al. 2005 (1.2)"
  quantity="run-out"
  band=15 band_label="experimental scatter (15 %)"
  cat > "$work/settings" <<'EOF'
linear|linear MPM|--method linear --family granular
ugimp|uGIMP (the example's default)|--method ugimp --family granular
ugimp_plain|uGIMP, plain family|--method ugimp --family plain
cpgimp|cpGIMP|--method cpgimp --family granular
cpdi|CPDI|--method cpdi --family granular
bspline2|B-spline2|--method bspline2 --family granular
apic|uGIMP + APIC|--method ugimp --family granular --transfer apic
mu_i|uGIMP + mu(I)|--method ugimp --family granular --material mu_i
recommended|recommended (README): B-spline2, plain, Perzyna phi 37, floor mu 0.45|--method bspline2 --family plain --friction 37 --floor-mu 0.45 --material perzyna --fluidity 300 --reference-stress 1795
recommended_mu_i|the same with mu(I) (mu_s = sin 37)|--method bspline2 --family plain --friction 37 --floor-mu 0.45 --material mu_i
EOF
  # 10, 15 and 20 cells across the column, 1x1 to 3x3 points per cell;
  # the recommended setting (README, docs/convergence.md sec. 20) also on
  # 40 cells across (2x2 and 3x3), so its converged answer rests on a
  # halving from 20 to 40 cells.
  for key in $(cut -d'|' -f1 "$work/settings"); do
    for cell in 0.015 0.01 0.0075; do
      for ppc in 1 2 3; do echo "$key $cell $ppc"; done
    done
  done > "$work/grid"
  printf '%s\n' "recommended 0.00375 2" "recommended 0.00375 3" >> "$work/grid"
  ;;
slope)
  reference=2235 # rho_cr of 000 Table 1 (kg/m^3)
  scene_args=""
  width=0.1 # the layer's length, m
  across="along the layer"
  metric=average_density
  name=accuracy_vs_cost_slope
  title="Moderate flow down a 30 degree slope (Seyedan and Solowski 2021 [000] sec 2.3, Table 1, 0.25 s)"
  law="final average density against rho_cr = 2235 kg/m^3 (a moderate flow keeps it)"
  quantity="average density"
  band=0.5 band_label="granular target (0.5 %)"
  cat > "$work/settings" <<'EOF'
linear|linear MPM|--method linear --family granular
ugimp|uGIMP|--method ugimp --family granular
cpdi|CPDI|--method cpdi --family granular
bspline2|B-spline2|--method bspline2 --family granular
linear_plain|linear MPM, plain family|--method linear --family plain
linear_stress_free|linear MPM, stress_free family|--method linear --family stress_free
EOF
  for key in $(cut -d'|' -f1 "$work/settings"); do
    for cell in 0.01 0.005; do
      for ppc in 1 2; do echo "$key $cell $ppc"; done
    done
  done > "$work/grid"
  ;;
*)
  echo "chart.sh: SCENE must be collapse or slope" >&2
  exit 2
  ;;
esac
mkdir -p "$results"

# Runs one grid line and prints "key,cell,ppc,points,seconds,ns,metric,
# rel_error,load1" (the example prints STATS and RESULT lines; a failed run
# prints neither).
cat > "$work/one.sh" <<'ONE'
#!/bin/sh
program=$1 reference=$2 metric=$3 scene_args=$4 settings=$5
key=$6 cell=$7 ppc=$8
options=$(awk -F'|' -v k="$key" '$1 == k { print $3 }' "$settings")
load1=$(cut -d' ' -f1 /proc/loadavg 2> /dev/null || echo nan)
start=$(date +%s.%N)
# scene_args and options are split into words on purpose
# shellcheck disable=SC2086
output=$("$program" --quiet --out '' $scene_args $options \
  --cell "$cell" --ppc "$ppc" 2>&1) || true
end=$(date +%s.%N)
echo "$output" | awk -v k="$key" -v c="$cell" -v p="$ppc" -v load="$load1" \
  -v ref="$reference" -v start="$start" -v end="$end" -v metric="$metric" '
  /^STATS/ { for (i = 2; i <= NF; i++) { split($i, kv, "="); s[kv[1]] = kv[2] } }
  /^RESULT / && index($2, metric "=") == 1 { split($2, kv, "="); value = kv[2] }
  END {
    if (value == "") {
      printf "%s,%s,%s,nan,%.3f,nan,nan,nan,%s\n", k, c, p, end - start, load
    } else {
      err = (value - ref) / ref; if (err < 0) err = -err
      printf "%s,%s,%s,%s,%s,%s,%s,%.4g,%s\n", k, c, p, s["points"],
        s["seconds"], s["ns_per_point_step"], value, err, load
    }
  }'
ONE

csv="$results/$name.csv"
if [ "$jobs" != plot ]; then
  echo "bench-chart: $(wc -l < "$work/grid") runs, $jobs at a time" >&2
  xargs -P "$jobs" -L 1 sh "$work/one.sh" "$program" "$reference" \
    "$metric" "$scene_args" "$work/settings" < "$work/grid" > "$work/rows"
else
  # Redraw: the runs as recorded, the references recomputed below.
  awk -F, -v OFS=, 'NR > 1 { print $1, $2, $3, $4, $5, $6, $7, $8, $9 }' "$csv" > "$work/rows"
fi
# The converged answer of each setting (see the header) and every run's
# difference from it. The change in the last halving is the largest
# relative change between the reference and a run with the same points
# per cell on a cell up to twice as large (so a run-out that swings
# between 20 and 15 cells across is not taken for converged because its
# ends happen to agree); it needs the run on exactly twice the cell.
sort -t, -k1,1 -k2,2gr -k3,3n "$work/rows" | awk -F, -v OFS=, '
  { row[NR] = $0; key[NR] = $1; cell[NR] = $2; ppc[NR] = $3; m[NR] = $7 }
  $7 != "nan" && (!($1 in rc) || $2 + 0 < rc[$1] || ($2 + 0 == rc[$1] && $3 + 0 > rp[$1])) {
    rc[$1] = $2 + 0; rp[$1] = $3 + 0; rv[$1] = $7 }
  END {
    for (i = 1; i <= NR; i++) {
      k = key[i]
      if (!(k in rc) || ppc[i] + 0 != rp[k] || m[i] == "nan") continue
      if (cell[i] + 0 > 1.999 * rc[k] && cell[i] + 0 < 2.001 * rc[k]) half[k] = 1
      if (cell[i] + 0 > 1.001 * rc[k] && cell[i] + 0 < 2.001 * rc[k]) {
        c = (rv[k] - m[i]) / m[i]
        if (!(k in change) || (c < 0 ? -c : c) > (change[k] < 0 ? -change[k] : change[k])) change[k] = c
      }
    }
    print "setting,cell,ppc,points,seconds,ns_per_point_step,metric,rel_error,load1,reference,ref_change,ref_diff"
    for (i = 1; i <= NR; i++) {
      k = key[i]; ref = "nan"; ch = "nan"; diff = "nan"
      if (k in rc) {
        ref = rv[k]
        if (k in half) {
          ch = sprintf("%.4g", change[k])
          c = change[k] < 0 ? -change[k] : change[k]
          if (c <= 0.03 && m[i] != "nan") {
            d = (m[i] - rv[k]) / rv[k]; if (d < 0) d = -d
            diff = sprintf("%.4g", d)
          }
        }
      }
      print row[i], ref, ch, diff
    }
  }' > "$work/csv"
mv "$work/csv" "$csv"
echo "bench-chart: wrote $csv" >&2

# --- the chart --------------------------------------------------------
# Errors in percent (1 %, 0.1 %), time in seconds, both log. A setting is
# a colour (and a shape); the cell is the marker size (larger = finer); the
# points per cell are the fill: 1x1 open, 2x2 filled, 3x3 filled with a
# black rim. Numbers mark the Pareto fronts; the table under each panel
# says which run each number is, so no run label is printed on the chart.
awk -F'|' '{ print $1 }' "$work/settings" > "$work/keys"
nsettings=$(wc -l < "$work/keys")
colours="#1f77b4 #d62728 #8c564b #ff7f0e #9467bd #17becf #e377c2 #7f7f7f #2ca02c #bcbd22"
# open,filled point types: circle, square, triangle up/down, diamond, pentagon
shapes="6,7 4,5 8,9 10,11 12,13 14,15 4,5 8,9 6,7 10,11"
cells=$(awk -F, 'NR > 1 { print $2 + 0 }' "$csv" | sort -gr | uniq | tr '\n' ' ')
coarsest=$(echo "$cells" | cut -d' ' -f1)
for key in $(cat "$work/keys"); do
  # seconds, error vs law (%), difference from the converged answer (%,
  # NaN for the reference run itself and unconverged settings), marker
  # size, points per cell
  awk -F, -v k="$key" -v c0="$coarsest" 'NR > 1 && $1 == k && $7 != "nan" {
    size = 1.0 + 1.1 * log(c0 / $2) / log(2)
    print $5, 100 * $8, ($12 == "nan" || $12 == 0 ? "NaN" : 100 * $12), size, $3 }' "$csv" > "$work/$key.dat"
done

# Pareto fronts (by increasing time, the runs more accurate than every
# faster one), numbered; the tables under the panels say what each is.
# The reference runs themselves (difference 0) are not on the right one.
front() { # column of the error, output file, first number
  awk -F, -v col="$1" 'NR > 1 && $col != "nan"' "$csv" | sort -t, -k5,5g |
    awk -F, -v col="$1" -v n="$3" 'BEGIN { best = 1e300 }
      $col < best && $col > 0 { best = $col; print $5, 100 * $col, $1, $2, $3, n++ }' > "$2"
}
front 8 "$work/front_law" 1
next_n=$(($(wc -l < "$work/front_law") + 1))
front 12 "$work/front_ref" "$next_n"

# Legend text of a setting: its name, whether it converged, to what, on
# which run and by how much it moved in the last halving.
legend() { # key
  awk -F, -v k="$1" -v sf="$work/settings" 'BEGIN {
      while ((getline line < sf) > 0) { split(line, f, "|"); if (f[1] == k) text = f[2] } }
    NR > 1 && $1 == k && $10 != "nan" { ref = $10; ch = $11 }
    NR > 1 && $1 == k && $7 != "nan" && (fc == "" || $2 + 0 < fc || ($2 + 0 == fc && $3 + 0 > fp)) { fc = $2 + 0; fp = $3 }
    END {
      if (ref == "") { printf "%s: every run failed", text; exit }
      if (ch == "nan") { printf "%s: no halving to judge", text; exit }
      c = ch < 0 ? -ch : ch
      moved = sprintf(c < 0.01 ? "%+.2f" : "%+.1f", 100 * ch)
      if (c <= 0.03)
        printf "%s: converged to %.4g (%g m, %dx%d; moved %s %% in the last halving)", text, ref, fc, fp, fp, moved
      else
        printf "%s: NOT converged (%g m, %dx%d: %.4g, moved %s %% in the last halving)", text, fc, fp, fp, ref, moved
    }' "$csv"
}

table() { # front file, title
  awk -v title="$2" -v sf="$work/settings" 'BEGIN { printf "%s", title
      while ((getline line < sf) > 0) { split(line, f, "|"); name[f[1]] = f[2] } }
    { printf "\\n%2d  %s, %g m, %dx%d: %.2g %% in %.2g s", $6, name[$3], $4, $5, $5, $2, $1 }
    END { if (NR == 0) printf "\\n(none: no setting converged)" }' "$1"
}

if ! command -v gnuplot > /dev/null 2>&1; then
  echo "bench-chart: gnuplot not found (apt-get install gnuplot-nox): no PNG" >&2
  exit 0
fi
failed=$(awk -F, 'NR > 1 && $7 == "nan"' "$csv" | wc -l)
total=$(($(wc -l < "$csv") - 1))
loads=$(awk -F, 'NR > 1 && $9 != "nan" { if (lo == "" || $9 < lo) lo = $9; if ($9 > hi) hi = $9 }
  END { printf "%s-%s", lo, hi }' "$csv")
cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2> /dev/null || echo unknown)
cores=$(nproc 2> /dev/null || echo '?')
times="times: wall-clock seconds of each run's time loop, one worker, on a shared $cores-core $cpu, 1-minute load average $loads when the runs started (noisy)"

plotcmd() { # column (2: law, 3: converged), front file
  i=0
  for key in $(cat "$work/keys"); do
    i=$((i + 1))
    colour=$(echo "$colours" | cut -d' ' -f"$i")
    open=$(echo "$shapes" | cut -d' ' -f"$i" | cut -d, -f1)
    filled=$(echo "$shapes" | cut -d' ' -f"$i" | cut -d, -f2)
    d="'$work/$key.dat'"
    y="(\$$1 > 0.001 ? \$$1 : 0.001)"
    printf "%s using 1:(\$5 == 1 ? %s : NaN):4 with points pt %s ps variable lw 1.5 lc rgb '%s' notitle, \\\\\n" "$d" "$y" "$open" "$colour"
    printf "%s using 1:(\$5 > 1 ? %s : NaN):4 with points pt %s ps variable lc rgb '%s' notitle, \\\\\n" "$d" "$y" "$filled" "$colour"
    printf "%s using 1:(\$5 > 2 ? %s : NaN):4 with points pt %s ps variable lw 1 lc rgb 'black' notitle, \\\\\n" "$d" "$y" "$open"
    if [ "$1" = 2 ]; then
      printf "NaN with points pt %s ps 1.6 lc rgb '%s' title \"%s\", \\\\\n" "$filled" "$colour" "$(legend "$key")"
    fi
  done
  if [ "$1" = 2 ]; then
    printf "NaN with lines dt 2 lc rgb 'gray40' title '%s', \\\\\n" "$band_label"
  fi
  if [ "$1" = 3 ]; then
    printf "NaN with points pt 6 ps 1.6 lw 1.5 lc rgb 'gray30' title '1x1 points per cell: open marker', \\\\\n"
    printf "NaN with points pt 7 ps 1.6 lc rgb 'gray30' title '2x2: filled', \\\\\n"
    printf "NaN with points pt 7 ps 1.6 lc rgb 'black' title '3x3: filled, black rim', \\\\\n"
    for cell in $cells; do
      printf "NaN with points pt 7 ps %s lc rgb 'gray60' title 'cell %s m (%s cells %s)', \\\\\n" \
        "$(awk -v c="$cell" -v c0="$coarsest" 'BEGIN { print 1.0 + 1.1 * log(c0 / c) / log(2) }')" \
        "$cell" "$(awk -v c="$cell" -v l="$width" 'BEGIN { printf "%.0f", l / c }')" "$across"
    done
  fi
  title=$([ "$1" = 3 ] && echo "Pareto front (the numbers: tables below)" || echo '')
  printf "'%s' using 1:2 with steps lw 1.5 lc rgb 'black' title '%s', \\\\\n" "$2" "$title"
  # odd numbers above right, even below left: neighbours on the front do
  # not cover each other
  printf "'%s' using 1:2:(int(\$6) %% 2 ? sprintf('%%d', \$6) : '') with labels offset char 1.0,char 0.8 font 'sans,10' tc rgb 'black' notitle, \\\\\n" "$2"
  printf "'%s' using 1:2:(int(\$6) %% 2 ? '' : sprintf('%%d', \$6)) with labels offset char -1.0,char -0.8 font 'sans,10' tc rgb 'black' notitle\n" "$2"
}

none_converged=
if [ ! -s "$work/front_ref" ]; then
  none_converged='set label 8 "No setting converged (3 % in its last halving; legend on the left):\nthere is no converged answer to draw its runs against." at graph 0.5, graph 0.6 center font "sans,13" front'
fi

{
  cat <<PLOT
set terminal pngcairo size 1800,1250 font 'sans,11' noenhanced
set output '$results/$name.png'
set multiplot
set label 1 "$title: $total runs ($nsettings settings x cell x points per cell), $failed failed (not drawn)" at screen 0.5, screen 0.985 center font 'sans,13'
set label 2 "$times" at screen 0.5, screen 0.962 center font 'sans,10'
set label 3 "colour: setting; marker size: cell (larger = finer); fill: points per cell; errors below 0.001 % drawn at 0.001 %" at screen 0.5, screen 0.944 center font 'sans,10'
set logscale xy
set grid
set format x '%g'
set format y '%g %%'
set xlabel 'run time, s (log)'
set lmargin at screen 0.06
set rmargin at screen 0.48
set tmargin at screen 0.875
set bmargin at screen 0.43
set ylabel "|$quantity - law| / law (log)"
set title "Against the law: $law\n(where a setting has not converged, a small error is a crossing of the law, not accuracy)"
set key at screen 0.06, screen 0.365 left top Left reverse maxrows $((nsettings + 1)) spacing 1.15 font 'sans,10' samplen 1.5 width 2
set yrange [0.001:200]
set arrow 1 from graph 0, first $band to graph 1, first $band nohead dt 2 lc rgb 'gray40'
plot $(plotcmd 2 "$work/front_law")
unset arrow 1
set lmargin at screen 0.56
set rmargin at screen 0.98
set ylabel "|$quantity - converged| / converged (log)"
set title "Against the setting's own converged answer\n(its run on the finest cell with the most points per cell, where that has converged)"
set arrow 2 from graph 0, first 3 to graph 1, first 3 nohead dt 2 lc rgb 'gray40'
set label 7 'convergence criterion: 3 % in the last halving' at graph 0.02, first 3 * 1.25 tc rgb 'gray40' front
set key at screen 0.74, screen 0.365 left top Left reverse maxrows 9 spacing 1.15 font 'sans,10' samplen 1.5 width 2
$none_converged
plot $(plotcmd 3 "$work/front_ref")
unset label 8
unset title
unset key
unset label 1
unset label 2
unset label 3
set label 5 "$(table "$work/front_law" 'Pareto front against the law (left):')" at screen 0.06, screen 0.15 left font 'sans,10' front
set label 6 "$(table "$work/front_ref" 'Pareto front against the converged answer (right):')" at screen 0.56, screen 0.15 left font 'sans,10' front
unset border
unset tics
unset xlabel
unset ylabel
unset grid
unset logscale
set lmargin at screen 0
set rmargin at screen 1
set tmargin at screen 1
set bmargin at screen 0
plot [0:1][0:1] NaN notitle
unset multiplot
PLOT
} > "$work/plot.gp"
gnuplot "$work/plot.gp" 2>&1 | grep -v 'no valid points' >&2 || true
echo "bench-chart: wrote $results/$name.png" >&2
echo "Pareto front against the law (seconds error% setting cell ppc n):" >&2
cat "$work/front_law" >&2
echo "Pareto front against the converged answer:" >&2
cat "$work/front_ref" >&2
