/*
 * shape_linear.h - linear (tent) shape functions of original MPM on a
 * Cartesian grid of square cells (004 eq 3.25): along each axis a point
 * at fraction f of its cell has weights (1 - f, f) on the cell's two nodes
 * and gradients (-1/h, 1/h). Tensor products give 2D.
 */
#ifndef GM_SHAPE_LINEAR_H
#define GM_SHAPE_LINEAR_H

#include <math.h>
#include <stdint.h>

/* The two tent weights and gradients (1/m) of a point `fraction` (in
 * [0, 1)) of the way across its cell, for both axis functions below. */
static inline void gm_shape_linear_tent(double fraction, double inv_h,
                                        double weight[2], double gradient[2]) {
  weight[0] = 1.0 - fraction;
  weight[1] = fraction;
  gradient[0] = -inv_h;
  gradient[1] = inv_h;
}

/* Cell index and the two node weights/gradients along one axis.
 * coordinate: m; origin: m, grid lower corner; inv_h: 1/m. */
static inline int64_t gm_shape_linear_axis(double coordinate, double origin,
                                           double inv_h, double weight[2],
                                           double gradient[2]) {
  double scaled = (coordinate - origin) * inv_h; /* position in cells */
  /* floor() without the libm call: truncate, then step down for negative
   * non-integers (points inside the grid have scaled >= 0 anyway). */
  int64_t cell = (int64_t)scaled;
  cell -= (double)cell > scaled;
  gm_shape_linear_tent(scaled - (double)cell, inv_h, weight, gradient);
  return cell;
}

/* gm_shape_linear_axis for a coordinate inside the grid, (coordinate -
 * origin) * inv_h >= 0 (every committed point: positions are validated
 * when added and when moved, block_grid.c gm_block_key_of): truncation is
 * then floor, and the step down for negative values is left out. The same
 * cell, weights and gradients, bit for bit, in 3 fewer instructions per
 * axis; the linear transfer kernels (p2g.c, g2p.c) call it 8 times per
 * point-step. */
static inline int64_t gm_shape_linear_axis_inside(double coordinate,
                                                  double origin, double inv_h,
                                                  double weight[2],
                                                  double gradient[2]) {
  double scaled = (coordinate - origin) * inv_h; /* position in cells, >= 0 */
  int64_t cell = (int64_t)scaled;
  gm_shape_linear_tent(scaled - (double)cell, inv_h, weight, gradient);
  return cell;
}

/* Offsets x_i - x_p (m) of the two nodes along one axis of a linear
 * cell, from the weights (1 - f, f) and the cell h (m): (-f h, (1 - f) h).
 * APIC's affine momentum (p2g.c). */
static inline void gm_linear_offsets(const double weight[2], double cell,
                                     double out[2]) {
  out[0] = -weight[1] * cell;
  out[1] = weight[0] * cell;
}

/* 2D weights and gradients of the 4 nodes (a, b) of the point's cell, node
 * k = a + 2 b at (cell_x + a, cell_y + b). */
static inline void gm_shape_linear_2d(const double position[2],
                                      const double origin[2], double inv_h,
                                      int64_t cell[2], double weight[4],
                                      double gradient_x[4],
                                      double gradient_y[4]) {
  double wx[2], gx[2], wy[2], gy[2];
  cell[0] = gm_shape_linear_axis(position[0], origin[0], inv_h, wx, gx);
  cell[1] = gm_shape_linear_axis(position[1], origin[1], inv_h, wy, gy);
  for (int b = 0; b < 2; b++) {
    for (int a = 0; a < 2; a++) {
      weight[a + 2 * b] = wx[a] * wy[b];
      gradient_x[a + 2 * b] = gx[a] * wy[b];
      gradient_y[a + 2 * b] = wx[a] * gy[b];
    }
  }
}

#endif
