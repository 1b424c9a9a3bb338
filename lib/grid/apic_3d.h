/*
 * apic_3d.h - APIC's affine part in 3D (Jiang et al. 2015, the APIC
 * transfers; see transfer.h for the 2D form): the offsets x_i - x_p of a
 * point's support along each axis, and C_p = B_p D_p^-1 with the
 * inertia-like tensor D_p = sum_i N_ip (x_i - x_p)(x_i - x_p)^T. Shared by
 * p2g_3d.c (the scatter of m_p N_ip (v_p + C_p (x_i - x_p))) and g2p_3d.c
 * (the gather of B_p = sum_i N_ip v_i (x_i - x_p)^T). Matrices are 3 x 3
 * row-major, the slots of GM_FIELD_AFFINE (core.h). Private.
 */
#ifndef GM_APIC_3D_H
#define GM_APIC_3D_H

#include "grid/grid.h"

/* Offsets x_i - x_p (m) of the nodes lowest .. lowest + span - 1 of one
 * axis from a point at coordinate x (m): node n lies at origin + n h, as
 * in the 2D wide kernels (p2g_wide.c), so both transfers of a step use
 * the same numbers. */
static inline void gm_apic_axis_offsets_3d(double origin, double cell,
                                           int64_t lowest, int span, double x,
                                           double out[GM_SUPPORT_3D_MAX_SPAN]) {
  double node = origin + (double)lowest * cell - x; /* m */
  for (int a = 0; a < span; a++)
    out[a] = node + (double)a * cell;
}

/* C = B D^-1 (1/s) for a symmetric D (m^2, row-major); C = 0 when D's
 * determinant is not positive (a degenerate domain), as in 2D
 * (p2g_wide.c), rather than a division by zero. */
static inline void gm_apic_solve_3d(const double d[9], const double b[9],
                                    double c[9]) {
  /* The inverse by cofactors (symmetric, so the adjugate's rows are its
   * columns). */
  double co[9] = {d[4] * d[8] - d[5] * d[7], d[5] * d[6] - d[3] * d[8],
                  d[3] * d[7] - d[4] * d[6], d[2] * d[7] - d[1] * d[8],
                  d[0] * d[8] - d[2] * d[6], d[1] * d[6] - d[0] * d[7],
                  d[1] * d[5] - d[2] * d[4], d[2] * d[3] - d[0] * d[5],
                  d[0] * d[4] - d[1] * d[3]};
  double det = d[0] * co[0] + d[1] * co[1] + d[2] * co[2]; /* m^6 */
  for (int k = 0; k < 9; k++)
    c[k] = 0.0;
  if (!(det > 0.0 && det < INFINITY))
    return;
  double inverse[9]; /* 1/m^2: D^-1_jk = co_kj / det */
  for (int j = 0; j < 3; j++)
    for (int k = 0; k < 3; k++)
      inverse[3 * j + k] = co[3 * k + j] / det;
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++)
      c[3 * r + k] = b[3 * r] * inverse[k] + b[3 * r + 1] * inverse[3 + k] +
                     b[3 * r + 2] * inverse[6 + k];
}

/* C = B D^-1 (1/s) for a box support (uGIMP, cpGIMP) from its axis
 * factors: the weight of node (a, b, c) is w_x[a] w_y[b] w_z[c], so the
 * entries of D_p = sum_i N_ip o_i o_i^T factor into per-axis sums,
 *   D_xx = S2_x S0_y S0_z,   D_xy = S1_x S1_y S0_z,   ...
 * with S0 = sum w, S1 = sum w o, S2 = sum w o^2 (S0 = 1 and S1 = 0 up to
 * round-off, the partition of unity and the reproduction of x: the same
 * tensor as the node-by-node sum of the 2D code, to round-off, in 15
 * products instead of 6 per node). D_p is positive definite for a box of
 * non-zero size (each S2 > 0); should its determinant not be positive
 * (a degenerate box), the affine part is dropped, C = 0, as in 2D
 * (p2g_wide.c), rather than divided by zero. */
static inline void
gm_apic_box_velocity_3d(const gm_box_support_3d *support,
                        const double offset[3][GM_SUPPORT_3D_MAX_SPAN],
                        const double b[9], double c[9]) {
  double s0[3], s1[3], s2[3];
  for (int axis = 0; axis < 3; axis++) {
    s0[axis] = s1[axis] = s2[axis] = 0.0;
    for (int a = 0; a < support->span[axis]; a++) {
      double w = support->weight[axis][a], o = offset[axis][a]; /* -, m */
      s0[axis] += w;
      s1[axis] += w * o;
      s2[axis] += w * o * o;
    }
  }
  double d[9]; /* m^2, symmetric */
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++) {
      int other = 3 - r - k; /* the third axis when r != k */
      d[3 * r + k] = r == k ? s2[r] * s0[(r + 1) % 3] * s0[(r + 2) % 3]
                            : s1[r] * s1[k] * s0[other];
    }
  gm_apic_solve_3d(d, b, c);
}

/* C = B D^-1 (1/s) for CPDI's dense support (support_cpdi_3d.h): its
 * weights are no product of axis factors, so D_p = sum_i N_ip o_i o_i^T
 * is summed node by node over the span (entry (c span_y + b) span_x + a,
 * offsets o_i per axis as gm_apic_axis_offsets_3d gives them), the 2D
 * code's rule for CPDI (p2g_wide.c) in 3D. The corner-based weights are a
 * partition of unity that reproduces x, so sum_i N_ip o_i = 0 and the
 * affine momentum adds exactly the point's affine angular momentum, as
 * with the boxes. */
static inline void
gm_apic_dense_velocity_3d(const double *weight, const int span[3],
                          const double offset[3][GM_SUPPORT_3D_MAX_SPAN],
                          const double b[9], double c[9]) {
  double d[9] = {0}; /* m^2, symmetric */
  int entry = 0;
  for (int z = 0; z < span[2]; z++)
    for (int y = 0; y < span[1]; y++)
      for (int x = 0; x < span[0]; x++, entry++) {
        double w = weight[entry];
        if (w == 0.0)
          continue;
        double o[3] = {offset[0][x], offset[1][y], offset[2][z]}; /* m */
        for (int r = 0; r < 3; r++)
          for (int k = r; k < 3; k++)
            d[3 * r + k] += w * o[r] * o[k];
      }
  d[3] = d[1];
  d[6] = d[2];
  d[7] = d[5];
  gm_apic_solve_3d(d, b, c);
}

/* C = B D^-1 (1/s) for the B-splines, whose D_p is a constant: Jiang et
 * al. 2015 give D_p = h^2/4 I for quadratic and h^2/3 I for cubic
 * B-splines, the variance (n + 1) h^2 / 12 of the cardinal B-spline of
 * degree n: sum_i N_i(x) (x_i - x)^2 is that constant wherever the point
 * is, and the products of the axis sums off the diagonal vanish
 * (sum_i N_i (x_i - x) = 0). The node-by-node sum agrees to round-off
 * (tests/unit/test_support_3d.c); the constant skips it. */
static inline void gm_apic_bspline_velocity_3d(gm_shape shape, double cell,
                                               const double b[9], double c[9]) {
  double variance = shape == GM_SHAPE_BSPLINE2 ? 0.25 : 1.0 / 3.0; /* cells^2 */
  double inverse = 1.0 / (variance * cell * cell);                 /* 1/m^2 */
  for (int k = 0; k < 9; k++)
    c[k] = b[k] * inverse;
}

#endif
