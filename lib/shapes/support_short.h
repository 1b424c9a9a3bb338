/*
 * support_short.h - one axis of a GIMP support whose domain is no longer
 * than a cell (half edge in (GM_GIMP_MIN_HALF_LENGTH, 1/2] cells: uGIMP
 * with 2 or more points per cell, cpGIMP until its domain stretches past a
 * cell), as three fixed factors: the node lowest + n has weight weight[n]
 * and gradient gradient[n] (per cell), n = 0, 1, 2, the closed form of
 * gm_gimp_axis_short (004 eq 3.27), the same expressions in the same order,
 * so every bit is that of gm_product_support_rectangle.
 *
 * Why: the general support (support.c) goes through out-of-line calls
 * that write a 9-entry structure (gm_product_support) and loop over each
 * axis's span, four times per point and USL step; this one is inline
 * straight-line code with the arrays' length fixed at 3. The kernels
 * still loop over the nodes up to the reach (span 2 or 3 per axis, 6.25
 * nodes on average at 2 points per cell): visiting all 3 x 3 nodes, the
 * ones past the reach with zero factors (which would add exact zeros, so
 * the same bits), was measured slower, 3634 against 3210 instructions per
 * point-step (bench/results/2026-11-28-ugimp.md). The factors past the
 * reach are zeros all the same, so a 3D box (three such axes) or a
 * kernel that wants the fixed loop can read them. 2D takes two of these.
 */
#ifndef GM_SUPPORT_SHORT_H
#define GM_SUPPORT_SHORT_H

#include "shapes/shape_gimp.h"
#include "shapes/support.h"

#include <stdbool.h>
#include <stdint.h>

/* One axis of a short support. */
typedef struct gm_short_axis {
  int64_t lowest;     /* node index of the lowest node */
  int64_t reach;      /* 1 or 2: the highest node is lowest + reach */
  double weight[3];   /* -, 0 past the reach */
  double gradient[3]; /* per cell, dS/ds; 0 past the reach */
} gm_short_axis;

/* The lowest node and the reach of a domain of centre s and half edge l (cells
 * from node 0) on an axis whose highest node is last_node. False when the
 * domain is not short (l outside (GM_GIMP_MIN_HALF_LENGTH, 1/2], or NaN) or its
 * support leaves the grid's nodes: the caller then takes the general support
 * (gm_product_support_rectangle), which gives the same answer or the same
 * failure. The tests are gm_product_support_rectangle's. */
static inline bool gm_short_axis_bounds(double s, double l, int64_t last_node,
                                        int64_t *lowest, int64_t *reach) {
  if (!(l >= GM_GIMP_MIN_HALF_LENGTH && l <= 0.5))
    return false;
  /* gm_product_support_rectangle's tests (s - l >= -1, s + l < last + 1,
   * then floor(s - l) >= 0 and floor(s + l) + 1 <= last) in two
   * comparisons: with s - l >= 0 and s + l >= 0 the floors are the
   * truncations (no correction for negative non-integers, 28 fewer
   * instructions per point and support), and floor(s + l) <= last - 1 is
   * s + l < last. Also catches NaN and keeps the casts in range. */
  double low = s - l, high = s + l; /* cells */
  if (!(low >= 0.0 && high < (double)last_node))
    return false;
  *lowest = (int64_t)low;               /* = gm_floor_index(low) */
  *reach = (int64_t)high + 1 - *lowest; /* span - 1 */
  return *reach <= 2; /* 3: 2 l = 1 with s - l rounded down and s + l up */
}

/* The whole axis, under the same conditions. */
static inline bool gm_short_axis_compute(double s, double l, int64_t last_node,
                                         gm_short_axis *out) {
  int64_t lowest, reach;
  if (!gm_short_axis_bounds(s, l, last_node, &lowest, &reach))
    return false;
  /* gm_gimp_axis_short, term by term. */
  double inverse_length = 0.5 / l;    /* 1 / (2 l) */
  double centre = s - (double)lowest; /* cells, m of gm_gimp_axis_short */
  double past = centre + l - 1.0;     /* e */
  past = past > 0.0 ? past : 0.0;
  double far = 0.5 * inverse_length * past * past; /* S_2 */
  double slope = inverse_length * past;            /* e / (2 l) */
  out->lowest = lowest;
  out->reach = reach;
  out->weight[0] = 1.0 - centre + far;
  out->weight[1] = centre - 2.0 * far;
  out->gradient[0] = slope - 1.0;
  out->gradient[1] = 1.0 - 2.0 * slope;
  /* The third node's factors need no test of the reach: with reach 1,
   * s + l < lowest + 1 as computed, so exactly (lowest + 1 is a double);
   * centre = s - lowest is exact (Sterbenz: lowest <= s < lowest + 1
   * <= 2 lowest, or lowest = 0), so centre + l rounds to at most 1, past
   * clamps to +0 and far and slope are +0: the zeros of before, bit for
   * bit, without the two selects (six axes per point and step). */
  out->weight[2] = far;
  out->gradient[2] = slope;
  return true;
}

/* Both axes of a 2D rectangle of centre x, y and half edges half_x,
 * half_y (m), as gm_product_support_rectangle reads them (in_cells of
 * support.c); false if either axis is not short (see above). */
static inline bool gm_short_support_2d(const gm_shape_grid *grid, double x,
                                       double y, double half_x, double half_y,
                                       gm_short_axis axis[2]) {
  double inv_cell = grid->inv_cell; /* 1/m */
  double s_x = (x - grid->origin[0]) * inv_cell;
  double s_y = (y - grid->origin[1]) * inv_cell;
  return gm_short_axis_compute(s_x, half_x * inv_cell, grid->last_node[0],
                               &axis[0]) &&
         gm_short_axis_compute(s_y, half_y * inv_cell, grid->last_node[1],
                               &axis[1]);
}

/* The lowest node of a 2D rectangle's short support (the block key's
 * node), as gm_short_support_2d; false as there. */
static inline bool gm_short_lowest_2d(const gm_shape_grid *grid, double x,
                                      double y, double half_x, double half_y,
                                      int64_t lowest[2]) {
  double inv_cell = grid->inv_cell; /* 1/m */
  double s_x = (x - grid->origin[0]) * inv_cell;
  double s_y = (y - grid->origin[1]) * inv_cell;
  int64_t reach[2];
  return gm_short_axis_bounds(s_x, half_x * inv_cell, grid->last_node[0],
                              &lowest[0], &reach[0]) &&
         gm_short_axis_bounds(s_y, half_y * inv_cell, grid->last_node[1],
                              &lowest[1], &reach[1]);
}

#endif
