/*
 * support_cpdi_3d.c - the CPDI1 support of a 3D point (support_cpdi_3d.h).
 *
 * CPDI1 (Sadeghirad, Brannon & Burghardt 2011) replaces each grid tent
 * N_i over the point's domain by its interpolation between the domain's
 * corners, as in 2D (support.c). The 3D domain is the parallelepiped
 * x = x_p + xi_1 r1 + xi_2 r2 + xi_3 r3, xi in [-1, 1]^3, and the
 * interpolant sum_c N_i(x_c) phi_c(xi) with the trilinear
 * phi_c = (1 + s1 xi_1)(1 + s2 xi_2)(1 + s3 xi_3) / 8 (corner signs s_k).
 * Averaged over the domain (its Jacobian J = [r1 r2 r3] is constant):
 *   S_i      = 1/8 sum_c N_i(x_c),
 *   grad S_i = J^-T <grad_xi> = sum_c N_i(x_c) g_c,
 *   g_c      = (s1 r2 x r3 + s2 r3 x r1 + s3 r1 x r2) / V,
 * since <d phi_c / d xi_k> = s_k / 8, J^-T has the columns
 * (r2 x r3, r3 x r1, r1 x r2) / det J and V = 8 det J. Opposite corners
 * have opposite g_c (the paired form of the paper). sum_c g_c = 0 and
 * sum_c x_c (x) g_c = 8 sum_k r_k (x) (row k of det J J^-1) / V = I hold
 * exactly, so the gradients sum to zero and reproduce linear fields, and
 * the weights are a partition of unity (each corner's tent weights are);
 * tests/unit/test_support_cpdi_3d.c measures these. The 2D form of
 * support.c is the same construction with the bilinear phi_c.
 */
#include "shapes/shapes.h"

#include <math.h>
#include <string.h>

void gm_cpdi_corners_3d(const double x[3], const double f[9],
                        const double half[3], double corners[8][3]) {
  double r[3][3]; /* m, r[k] = half_k (column k of F) */
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < 3; i++)
      r[k][i] = f[3 * i + k] * half[k];
  for (int c = 0; c < 8; c++)
    for (int i = 0; i < 3; i++) {
      double value = x[i];
      for (int k = 0; k < 3; k++)
        value += ((c >> k) & 1 ? 1.0 : -1.0) * r[k][i];
      corners[c][i] = value;
    }
}

/* The corners in cells from node 0 and the lowest node and span per
 * axis; false as gm_cpdi_support_lowest_3d. */
static bool corner_bounds(const gm_shape_grid *grid, double corners[8][3],
                          double cells[8][3], int64_t lowest[3], int span[3]) {
  for (int k = 0; k < 3; k++) {
    double low = 0.0, high = 0.0;
    for (int c = 0; c < 8; c++) {
      cells[c][k] = (corners[c][k] - grid->origin[k]) * grid->inv_cell;
      low = c == 0 || cells[c][k] < low ? cells[c][k] : low;
      high = c == 0 || cells[c][k] > high ? cells[c][k] : high;
    }
    /* A NaN corner: every comparison below it fails. */
    bool finite = true;
    for (int c = 0; c < 8; c++)
      finite = finite && cells[c][k] >= low && cells[c][k] <= high;
    /* Also keeps the casts in range. */
    if (!finite || !(low >= -1.0 && high < (double)grid->last_node[k] + 1.0))
      return false;
    lowest[k] = gm_floor_index(low);
    int64_t highest = gm_floor_index(high) + 1;
    if (lowest[k] < 0 || highest > grid->last_node[k] ||
        highest - lowest[k] + 1 > GM_SUPPORT_3D_MAX_SPAN)
      return false;
    span[k] = (int)(highest - lowest[k] + 1);
  }
  return true;
}

bool gm_cpdi_support_lowest_3d(const gm_shape_grid *grid, const double x[3],
                               const double f[9], const double half[3],
                               int64_t lowest[3]) {
  double corners[8][3], cells[8][3];
  int span[3];
  gm_cpdi_corners_3d(x, f, half, corners);
  return corner_bounds(grid, corners, cells, lowest, span);
}

bool gm_cpdi_support_bounds_3d(const gm_shape_grid *grid, const double x[3],
                               const double f[9], const double half[3],
                               int64_t lowest[3], int64_t highest[3]) {
  double corners[8][3], cells[8][3];
  int span[3];
  gm_cpdi_corners_3d(x, f, half, corners);
  if (!corner_bounds(grid, corners, cells, lowest, span))
    return false;
  for (int k = 0; k < 3; k++)
    highest[k] = lowest[k] + span[k] - 1;
  return true;
}

static void cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

bool gm_cpdi_support_compute_3d(const gm_shape_grid *grid, const double x[3],
                                const double f[9], const double half[3],
                                gm_cpdi_support_3d *out) {
  double corners[8][3], cells[8][3];
  gm_cpdi_corners_3d(x, f, half, corners);
  if (!corner_bounds(grid, corners, cells, out->lowest, out->span))
    return false;
  double r[3][3]; /* m, the half edge vectors */
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < 3; i++)
      r[k][i] = f[3 * i + k] * half[k];
  double area[3][3]; /* m^2: r2 x r3, r3 x r1, r1 x r2 */
  for (int k = 0; k < 3; k++)
    cross(r[(k + 1) % 3], r[(k + 2) % 3], area[k]);
  double volume = 8.0 * (r[0][0] * area[0][0] + r[0][1] * area[0][1] +
                         r[0][2] * area[0][2]); /* m^3 */
  if (!(volume > 0.0 && volume < INFINITY))
    return false;
  double inverse = 1.0 / volume; /* 1/m^3 */
  int sx = out->span[0], sy = out->span[1], sz = out->span[2];
  size_t used = (size_t)(sx * sy * sz);
  memset(out->weight, 0, used * sizeof(double));
  for (int k = 0; k < 3; k++)
    memset(out->gradient[k], 0, used * sizeof(double));
  for (int c = 0; c < 8; c++) {
    double g[3]; /* 1/m, g_c */
    for (int i = 0; i < 3; i++) {
      double value = 0.0;
      for (int k = 0; k < 3; k++)
        value += ((c >> k) & 1 ? 1.0 : -1.0) * area[k][i];
      g[i] = value * inverse;
    }
    int64_t local[3];  /* the corner's cell from lowest */
    double tent[3][2]; /* the cell's two tent values per axis */
    for (int k = 0; k < 3; k++) {
      int64_t cell = gm_floor_index(cells[c][k]);
      double fraction = cells[c][k] - (double)cell;
      local[k] = cell - out->lowest[k];
      tent[k][0] = 1.0 - fraction;
      tent[k][1] = fraction;
    }
    for (int dz = 0; dz < 2; dz++)
      for (int dy = 0; dy < 2; dy++)
        for (int dx = 0; dx < 2; dx++) {
          double value = tent[0][dx] * tent[1][dy] * tent[2][dz]; /* N_i */
          size_t entry = (size_t)(((local[2] + dz) * sy + local[1] + dy) * sx +
                                  local[0] + dx);
          out->weight[entry] += 0.125 * value;
          for (int i = 0; i < 3; i++)
            out->gradient[i][entry] += value * g[i];
        }
  }
  return true;
}
