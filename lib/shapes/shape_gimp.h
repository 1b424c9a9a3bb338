/*
 * shape_gimp.h - GIMP weighting functions along one axis (004 eq 3.27;
 * Bardenhagen & Kober 2004): the weight of node i is the average of its
 * tent function N_i over the particle's domain,
 *   S_i = 1 / (2 l) * integral over [x_p - l, x_p + l] of N_i(x) dx,
 * and its gradient is d S_i / d x_p = (N_i(x_p + l) - N_i(x_p - l)) / (2 l).
 * The integral is written with the antiderivative of the tent, which holds
 * for any half-length l (uGIMP, and cpGIMP where l follows the
 * deformation and may exceed half a cell), instead of the usual piecewise
 * formula that assumes l <= h / 2. Everything is in cell units here.
 */
#ifndef GM_SHAPE_GIMP_H
#define GM_SHAPE_GIMP_H

#include <math.h>
#include <stdint.h>

/* Below this half-length (cells) the average is replaced by its limit, the
 * tent itself: (Phi(u + l) - Phi(u - l)) / (2 l) loses digits as l -> 0. */
#define GM_GIMP_MIN_HALF_LENGTH 1e-6
/* Most nodes an axis may reach (GM_SUPPORT_MAX_SPAN, support.h). */
#define GM_GIMP_AXIS_MAX_SPAN 9

/* The unit tent max(0, 1 - |u|) (u in cells). */
static inline double gm_tent(double u) {
  double value = 1.0 - fabs(u);
  return value > 0.0 ? value : 0.0;
}

/* Its antiderivative from -infinity: 0 below -1, 1 above 1. */
static inline double gm_tent_integral(double u) {
  if (u <= -1.0)
    return 0.0;
  if (u <= 0.0)
    return 0.5 * (1.0 + u) * (1.0 + u);
  if (u < 1.0)
    return 1.0 - 0.5 * (1.0 - u) * (1.0 - u);
  return 1.0;
}

/* floor(x) as an integer without the libm call (a function call in the
 * hot loops unless the target has SSE4.1): truncate, then step down for
 * negative non-integers. x must be finite and within int64 range; the
 * callers check the support lies inside the grid first. */
static inline int64_t gm_floor_index(double x) {
  int64_t truncated = (int64_t)x;
  return truncated - ((double)truncated > x);
}

/* Lowest node and node count a domain of centre s and half-length l (both
 * in cells, from node 0) reaches along one axis. */
static inline int64_t gm_gimp_axis_bounds(double s, double l, int *span) {
  if (l < GM_GIMP_MIN_HALF_LENGTH) {
    *span = 2;
    return gm_floor_index(s);
  }
  int64_t lowest = gm_floor_index(s - l);
  *span = (int)(gm_floor_index(s + l) + 1 - lowest + 1);
  return lowest;
}

/* The averages of a domain no longer than a cell (l <= 1/2, uGIMP with 2
 * or more points per cell: the range of 004 eq 3.27's piecewise form),
 * which crosses at most one node line, the one at lowest + 1. With
 * m = s - lowest (the centre, in cells past the lowest node) and
 * e = max(0, m + l - 1) the length past that line, each tent's average is
 * its value at the centre corrected by the kink the domain crosses:
 *   S_0 = 1 - m + e^2 / (4 l),  S_1 = m - e^2 / (2 l),  S_2 = e^2 / (4 l),
 * with the derivatives in s (de/ds = 1 where e > 0)
 *   -1 + e / (2 l),  1 - e / l,  e / (2 l).
 * Equal to the antiderivative form to round-off (measured: at most
 * 6e-14 apart for s up to 300 cells, l = 1/8, 1/4, 1/2: a few ulps of s,
 * which both forms start from; the antiderivative form also loses digits
 * as l shrinks, this one does not), without its branches per node, whose
 * outcome changes from point to point. Writes
 * three nodes; the third has S_2 = 0 when span is 2 (e = 0). */
static inline void gm_gimp_axis_short(double s, double l, int64_t lowest,
                                      double weight[3], double gradient[3]) {
  double inverse_length = 0.5 / l;    /* 1 / (2 l) */
  double centre = s - (double)lowest; /* m */
  double past = centre + l - 1.0;     /* e */
  past = past > 0.0 ? past : 0.0;
  double far = 0.5 * inverse_length * past * past; /* S_2 */
  double slope = inverse_length * past;            /* e / (2 l) */
  weight[0] = 1.0 - centre + far;
  weight[1] = centre - 2.0 * far;
  weight[2] = far;
  gradient[0] = slope - 1.0;
  gradient[1] = 1.0 - 2.0 * slope;
  gradient[2] = slope;
}

/* Weights and gradients (per cell) of nodes lowest .. lowest + span - 1
 * (arrays of at least 3 entries: a short domain writes three). */
static inline void gm_gimp_axis(double s, double l, int64_t lowest, int span,
                                double *weight, double *gradient) {
  if (l < GM_GIMP_MIN_HALF_LENGTH) { /* the tent: linear MPM */
    double fraction = s - (double)lowest;
    weight[0] = 1.0 - fraction;
    weight[1] = fraction;
    gradient[0] = -1.0;
    gradient[1] = 1.0;
    return;
  }
  if (l <= 0.5) {
    gm_gimp_axis_short(s, l, lowest, weight, gradient);
    return;
  }
  double inverse_length = 0.5 / l;
  for (int n = 0; n < span; n++) {
    double upper = s + l - (double)(lowest + n);
    double lower = s - l - (double)(lowest + n);
    weight[n] =
        (gm_tent_integral(upper) - gm_tent_integral(lower)) * inverse_length;
    gradient[n] = (gm_tent(upper) - gm_tent(lower)) * inverse_length;
  }
}

/* gm_gimp_axis with the gradients and weights also times scale (inv_cell,
 * 1/m): gradient_scaled = scale * gradient, weight_scaled = scale * weight
 * (the per-metre factors of gm_product_support). */
static inline void gm_gimp_axis_scaled(double s, double l, int64_t lowest,
                                       int span, double scale, double *weight,
                                       double *gradient_scaled,
                                       double *weight_scaled) {
  double gradient[GM_GIMP_AXIS_MAX_SPAN]; /* per cell */
  gm_gimp_axis(s, l, lowest, span, weight, gradient);
  for (int n = 0; n < span; n++) {
    gradient_scaled[n] = scale * gradient[n];
    weight_scaled[n] = scale * weight[n];
  }
}

#endif
