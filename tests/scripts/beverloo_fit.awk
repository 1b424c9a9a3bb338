# tests/scripts/beverloo_fit.awk - Beverloo's law W = C rho sqrt(g)
# (D - k d)^n fitted to a silo sweep, for the script tests that run one
# (awk -f, one line "D W" per orifice: D in m, W the rate).
# Variables (-v): kmax, the largest k d tried (m; scanned from 0 in steps
# of kstep m); target and tolerance, the exponent asserted (exit 1 when the
# fitted n lies outside target +- tolerance); cell (m, optional): k d is
# also printed in cells of that size; law_c (optional): Beverloo's C of the
# reference in a third column (the example's RESULT reference, the law
# with d = 0), and then C is also fitted with n held at target and
# printed against law_c.
# For each k d, n is the least-squares slope of ln W against ln(D - k d);
# the k d kept is the one of the smallest residual (Beverloo's k d is a
# length of the material, or of the grid standing for the grain, not a
# constant of the law). Prints n, k d, the rms residual in ln W, and n
# with k d = 0 for comparison.
# SPDX-License-Identifier: BSD-2-Clause
{ d[++m] = $1; w[m] = $2; reference[m] = $3 }
# Slope of ln W against ln(D - kd); sets residual (sum of squares).
function fit(kd,   i, x, y, sx, sy, sxx, sxy, slope, mean) {
  sx = sy = sxx = sxy = 0
  for (i = 1; i <= m; i++) {
    x = log(d[i] - kd); y = log(w[i])
    sx += x; sy += y; sxx += x * x; sxy += x * y
  }
  slope = (m * sxy - sx * sy) / (m * sxx - sx * sx)
  mean = (sy - slope * sx) / m
  residual = 0
  for (i = 1; i <= m; i++)
    residual += (log(w[i]) - mean - slope * log(d[i] - kd)) ^ 2
  return slope
}
# With n held at target: the k d of the smallest residual and the geometric
# mean over the orifices of C = law_c (W / reference) (D / (D - k d))^n.
function fit_c(   kd, i, sum, mean, r, best_r, c) {
  best_r = -1
  for (kd = 0; kd <= kmax && kd < smallest; kd += kstep) {
    sum = 0
    for (i = 1; i <= m; i++) sum += log(w[i]) - target * log(d[i] - kd)
    mean = sum / m
    r = 0
    for (i = 1; i <= m; i++)
      r += (log(w[i]) - target * log(d[i] - kd) - mean) ^ 2
    if (best_r < 0 || r < best_r) { best_r = r; c_kd = kd }
  }
  sum = 0
  for (i = 1; i <= m; i++)
    sum += log(law_c * w[i] / reference[i]) + target * log(d[i] / (d[i] - c_kd))
  return exp(sum / m)
}
END {
  if (m < 3) { print "FAIL: " m " rates, at least 3 needed"; exit 1 }
  smallest = d[1]
  for (i = 2; i <= m; i++) if (d[i] < smallest) smallest = d[i]
  plain = fit(0)
  best = -1
  for (kd = 0; kd <= kmax && kd < smallest; kd += kstep) {
    n = fit(kd)
    if (best < 0 || residual < best) { best = residual; bk = kd; bn = n }
  }
  printf "Beverloo fit: n = %.3f, k d = %.4f m", bn, bk
  if (cell > 0) printf " (%.3f cells)", bk / cell
  printf " (rms %.4f in ln W); with k d = 0 n = %.3f; asserted %s +- %s\n",
    sqrt(best / m), plain, target, tolerance
  if (law_c > 0) {
    c = fit_c()
    printf "with n = %s: k d = %.4f m, C = %.3f against %s (%+.1f %%)\n",
      target, c_kd, c, law_c, 100 * (c / law_c - 1)
  }
  exit (bn < target - tolerance || bn > target + tolerance)
}
