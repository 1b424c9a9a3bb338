# validate/collapse.gp - run-out error against Lube et al. (2005) over the
# cell size, one panel per aspect ratio, one line per points per cell (run
# in validate/results by validate/collapse.sh).
set terminal pngcairo size 1200,420 font ",10"
set output "convergence_runout.png"
set datafile separator ","
set multiplot layout 1,3 title "Planar column collapse: run-out (L - L0)/L0 against Lube et al. 2005, the recommended setting (docs/convergence.md sec. 20; make validate)"
set logscale x 2
set xlabel "cells per column width L0/h"
set ylabel "run-out error against the law (%)"
set xrange [8:50]
set xtics (10, 20, 40)
set yrange [-40:60]
set grid
set key top right
law(a) = a <= 1.8 ? 1.2 * a : 1.9 * a ** (2.0 / 3.0)
do for [a in "0.5 1.3 3"] {
  file = sprintf("collapse_a%s.csv", a)
  set title sprintf("a = %s", a)
  plot for [p = 2:4] file using (0.15 / $2):(($3 == p) ? 100 * ($4 - law(a + 0)) / law(a + 0) : 1/0) \
         with linespoints pointsize 1.2 title sprintf("%dx%d points per cell", p, p), \
       10 with lines dashtype 2 lc rgb "gray" notitle, \
       -10 with lines dashtype 2 lc rgb "gray" title "+-10 %"
}
unset multiplot
