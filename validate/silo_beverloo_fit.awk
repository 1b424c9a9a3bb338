# validate/silo_beverloo_fit.awk - Beverloo's exponent from
# validate/results/silo_beverloo.csv (written by validate/silo_beverloo.sh).
# Rows sorted by geometry, cell and D (validate/silo_beverloo.sh sorts
# them). For each geometry and cell (rows whose run reached the window's
# end; a geometry, cell and D measured twice counts once) it prints:
#   local: the exponent between successive D, ln(W2/W1) / ln(D2/D1);
#   plain: the least-squares slope of ln W against ln D (k d = 0);
#   open:  the same against the open orifice's diameter D sqrt(a), a the
#          open area's fraction of pi D^2 / 4 (the hole the grid cuts);
#   mesh:  against D - 2.7 h, the slot's mesh grain of
#          tests/physics/test_beverloo.c (k d = 2.7 h, fitted there on a
#          planar 0.025 m grid, not on these data);
#   beverloo: W = C (D - k h)^n (002 eq 20 with the cell h as the grain),
#          k from a scan in steps of 0.001 h (the least squares of ln W
#          for each k), then C and n by least squares; with three D the
#          fit is exact (no residual), the data set n and k;
# over all D and over each run of three successive D.
# SPDX-License-Identifier: BSD-2-Clause
BEGIN { FS = "," }
NR == 1 { next }
$8 == 1 && !(($1 SUBSEP $2 SUBSEP $3) in seen) {
  seen[$1, $2, $3] = 1
  g = $1 ", cell " $2 " m"
  if (!(g in count)) { order[++groups] = g; count[g] = 0 }
  i = ++count[g]
  cells[g, i] = $3 + 0; d[g, i] = $4 + 0; w[g, i] = $6 + 0
  area[g, i] = $7 + 0; h[g] = $2 + 0
}
# Least-squares slope of y on x over points a..b of geometry g; sets the
# global residual (the sum of squares) and intercept.
function slope(g, a, b, x, y,   i, n, sx, sy, sxx, sxy, m) {
  n = sx = sy = sxx = sxy = 0
  for (i = a; i <= b; i++) {
    n++; sx += x[i]; sy += y[i]; sxx += x[i] * x[i]; sxy += x[i] * y[i]
  }
  m = (n * sxy - sx * sy) / (n * sxx - sx * sx)
  intercept = (sy - m * sx) / n
  residual = 0
  for (i = a; i <= b; i++)
    residual += (y[i] - intercept - m * x[i]) ^ 2
  return m
}
function report(g, a, b,   i, x, y, n, k, best, bestk, bestn, kmax) {
  for (i = a; i <= b; i++) { x[i] = log(d[g, i]); y[i] = log(w[g, i]) }
  n = slope(g, a, b, x, y)
  printf "  D/h %d-%d: plain n = %.3f", cells[g, a], cells[g, b], n
  for (i = a; i <= b; i++) x[i] = log(d[g, i] * sqrt(area[g, i]))
  printf ", open n = %.3f", slope(g, a, b, x, y)
  for (i = a; i <= b; i++) x[i] = log(d[g, i] - 2.7 * h[g])
  printf ", mesh n = %.3f", slope(g, a, b, x, y)
  best = -1; kmax = cells[g, a] - 0.5
  for (k = -2; k <= kmax; k += 0.001) {
    for (i = a; i <= b; i++) x[i] = log(d[g, i] - k * h[g])
    n = slope(g, a, b, x, y)
    if (best < 0 || residual < best) { best = residual; bestk = k; bestn = n }
  }
  printf ", beverloo n = %.3f with k = %.3f", bestn, bestk
  if (bestk <= -2 + 0.0005 || bestk >= kmax - 0.0005)
    printf " (k at the scan's end)"
  printf " (rms %.2g in ln W)\n", sqrt(best / (b - a + 1))
}
END {
  for (o = 1; o <= groups; o++) {
    g = order[o]
    printf "%s (%d orifices):\n", g, count[g]
    for (i = 2; i <= count[g]; i++)
      printf "  local n, D/h %d to %d: %.3f\n", cells[g, i - 1], cells[g, i],
        log(w[g, i] / w[g, i - 1]) / log(d[g, i] / d[g, i - 1])
    if (count[g] >= 2) report(g, 1, count[g])
    for (i = 1; count[g] > 3 && i + 2 <= count[g]; i++) report(g, i, i + 2)
  }
}
