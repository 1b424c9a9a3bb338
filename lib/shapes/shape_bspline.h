/*
 * shape_bspline.h - uniform B-spline shape functions along one axis.
 * Steffen, Kirby & Berzins (2008, IJNME 76:922) propose quadratic
 * B-splines on the grid nodes: the grid functions become C1, so the
 * internal-force quadrature no longer jumps when a point crosses a cell
 * edge (the "grid crossing error"). Only the paper's abstract could be
 * read here, not its equations; the functions below are the standard
 * cardinal B-splines (de Boor, A Practical Guide to Splines),
 * checked against the Cox-de Boor recursion in tests/unit/test_bspline.c.
 * Node i carries the B-spline centred on it; with u = x/h - i the
 * distance in cells,
 *   quadratic: N(u) = 3/4 - u^2              for |u| <= 1/2,
 *              N(u) = (3/2 - |u|)^2 / 2      for 1/2 <= |u| <= 3/2,
 *   cubic:     N(u) = 2/3 - u^2 + |u|^3 / 2  for |u| <= 1,
 *              N(u) = (2 - |u|)^3 / 6        for 1 <= |u| <= 2,
 * and 0 beyond. These are the cardinal B-splines (the tent convolved once,
 * resp. twice, with the unit box), so on a grid whose every node exists
 * they sum to 1 and reproduce linear fields exactly: sum_i N_i = 1,
 * sum_i N_i x_i = x_p. No node is ever missing here: a point lies inside
 * the box and the ghost layer (support.h) holds the node the quadratic
 * reaches 1.5 cells out and the cubic 2 cells out (where its weight is
 * already 0), so the box faces need no modified boundary splines.
 * Everything is in cell units here: s is the point's position in cells
 * from node 0, gradients are per cell.
 */
#ifndef GM_SHAPE_BSPLINE_H
#define GM_SHAPE_BSPLINE_H

#include "shapes/shape_gimp.h" /* gm_floor_index */

#include <stdint.h>

/* Lowest node the quadratic B-spline of a point at s reaches: the three
 * nodes lowest .. lowest + 2 are those within 1.5 cells (the farther one
 * of a pair exactly 1.5 cells away has weight 0). */
static inline int64_t gm_bspline2_lowest(double s) {
  return gm_floor_index(s - 0.5);
}

/* Weights and gradients (per cell) of the three nodes from
 * gm_bspline2_lowest(s). f = s - lowest lies in [0.5, 1.5): node 0 is f
 * cells below the point, node 1 f - 1, node 2 2 - f above. */
static inline void gm_bspline2_axis(double s, int64_t lowest, double weight[3],
                                    double gradient[3]) {
  double f = s - (double)lowest;
  double low = 1.5 - f;  /* 1.5 - |u| of node 0 */
  double mid = f - 1.0;  /* u of node 1, in [-0.5, 0.5) */
  double high = f - 0.5; /* 1.5 - |u| of node 2 */
  weight[0] = 0.5 * low * low;
  weight[1] = 0.75 - mid * mid;
  weight[2] = 0.5 * high * high;
  gradient[0] = -low;
  gradient[1] = -2.0 * mid;
  gradient[2] = high;
}

/* Lowest node the cubic B-spline of a point at s reaches: the four nodes
 * lowest .. lowest + 3 around the point's cell. */
static inline int64_t gm_bspline3_lowest(double s) {
  return gm_floor_index(s) - 1;
}

/* Weights and gradients (per cell) of the four nodes from
 * gm_bspline3_lowest(s); f = s - floor(s) in [0, 1). */
static inline void gm_bspline3_axis(double s, int64_t lowest, double weight[4],
                                    double gradient[4]) {
  double f = s - (double)(lowest + 1);
  double g = 1.0 - f;
  weight[0] = g * g * g / 6.0;                     /* |u| = 1 + f */
  weight[1] = 2.0 / 3.0 - f * f + 0.5 * f * f * f; /* |u| = f */
  weight[2] = 2.0 / 3.0 - g * g + 0.5 * g * g * g; /* |u| = 1 - f */
  weight[3] = f * f * f / 6.0;                     /* |u| = 2 - f */
  gradient[0] = -0.5 * g * g;
  gradient[1] = f * (1.5 * f - 2.0);
  gradient[2] = -g * (1.5 * g - 2.0);
  gradient[3] = 0.5 * f * f;
}

#endif
