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

/* Weights and gradients (per cell) of nodes lowest .. lowest + span - 1. */
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
  double inverse_length = 0.5 / l;
  for (int n = 0; n < span; n++) {
    double upper = s + l - (double)(lowest + n);
    double lower = s - l - (double)(lowest + n);
    weight[n] =
        (gm_tent_integral(upper) - gm_tent_integral(lower)) * inverse_length;
    gradient[n] = (gm_tent(upper) - gm_tent(lower)) * inverse_length;
  }
}

#endif
