/*
 * support.c - supports of the shape-function variants (see support.h).
 *
 * uGIMP and cpGIMP weights are tensor products of the axis functions of
 * shape_gimp.h (004 eq 3.27). CPDI1 (Sadeghirad, Brannon & Burghardt 2011)
 * approximates each tent N_i over the parallelogram domain by its bilinear
 * interpolation between the four corners x_c. The weight is then the
 * average of the corner values, w_i = 1/4 sum_c N_i(x_c), and the gradient
 * average (1/V) integral of grad N_i over the domain becomes, by the
 * divergence theorem on the four straight edges (the interpolant is linear
 * along each edge),
 *   grad w_i = sum_c N_i(x_c) g_c,  g_c = rot(x_{c+1} - x_{c-1}) / (2 V),
 * with rot(e) = (e_y, -e_x), corners counter-clockwise and V the domain
 * area. sum_c g_c = 0 and sum_c x_c (x) g_c = I hold exactly, so the
 * gradients sum to zero and reproduce linear fields.
 *
 * The B-splines are tensor products of the axis functions of
 * shape_bspline.h, evaluated at the point's position.
 */
#include "shapes/shapes.h"

#include <math.h>

/* Half edges (m) of the current rectangle of the GIMP-like variants. */
static void rectangle_half_size(gm_shape shape, const gm_point_domain *point,
                                double half[2]) {
  for (int k = 0; k < 2; k++) {
    half[k] = point->half_size[k];
    if (shape == GM_SHAPE_CPGIMP) /* F_xx, F_yy: stretch along the axes */
      half[k] *= fabs(point->deformation[3 * k]);
  }
}

void gm_point_domain_corners(gm_shape shape, int dim,
                             const gm_point_domain *point,
                             double corners[4][2]) {
  double r1[2], r2[2];          /* m, half edge vectors */
  if (shape == GM_SHAPE_CPDI) { /* r_i = F r_i0 */
    const double *f = point->deformation;
    r1[0] = f[0] * point->half_size[0];
    r1[1] = dim > 1 ? f[2] * point->half_size[0] : 0.0;
    r2[0] = dim > 1 ? f[1] * point->half_size[1] : 0.0;
    r2[1] = dim > 1 ? f[3] * point->half_size[1] : 0.0;
  } else {
    double half[2];
    rectangle_half_size(shape, point, half);
    r1[0] = half[0];
    r1[1] = 0.0;
    r2[0] = 0.0;
    r2[1] = dim > 1 ? half[1] : 0.0;
  }
  static const double sign1[4] = {-1.0, 1.0, 1.0, -1.0};
  static const double sign2[4] = {-1.0, -1.0, 1.0, 1.0};
  for (int c = 0; c < 4; c++)
    for (int k = 0; k < 2; k++)
      corners[c][k] = point->position[k] + sign1[c] * r1[k] + sign2[c] * r2[k];
}

/* Position (cells from node 0) of a coordinate (m) along an axis. */
static double in_cells(const gm_shape_grid *grid, int axis, double x) {
  return (x - grid->origin[axis]) * grid->inv_cell;
}

static bool bounds_valid(const gm_shape_grid *grid, const int64_t lowest[2],
                         const int64_t highest[2]) {
  for (int k = 0; k < grid->dim; k++)
    if (lowest[k] < 0 || highest[k] > grid->last_node[k] ||
        highest[k] - lowest[k] + 1 > GM_SUPPORT_MAX_SPAN)
      return false;
  return true;
}

/* Corner positions (m) and in cells from node 0; returns the corner
 * count (in 1D the two ends, corners 0 and 1). */
static int corners_in_cells(const gm_shape_grid *grid,
                            const gm_point_domain *point, double corners[4][2],
                            double cells[4][2]) {
  gm_point_domain_corners(grid->shape, grid->dim, point, corners);
  int count = grid->dim == 1 ? 2 : 4;
  for (int c = 0; c < count; c++)
    for (int k = 0; k < 2; k++)
      cells[c][k] = k < grid->dim ? in_cells(grid, k, corners[c][k]) : 0.0;
  return count;
}

bool gm_support_rectangle_bounds(const gm_shape_grid *grid, double x, double y,
                                 double half_x, double half_y,
                                 int64_t lowest[2], int64_t highest[2]) {
  lowest[1] = highest[1] = 0;
  for (int k = 0; k < grid->dim; k++) {
    double s = in_cells(grid, k, k == 0 ? x : y);
    double l = (k == 0 ? half_x : half_y) * grid->inv_cell;
    if (!(s - l >= -1.0 && s + l < (double)grid->last_node[k] + 1.0))
      return false;
    int span;
    lowest[k] = gm_gimp_axis_bounds(s, l, &span);
    highest[k] = lowest[k] + span - 1;
  }
  return bounds_valid(grid, lowest, highest);
}

bool gm_support_bspline_bounds(const gm_shape_grid *grid, double x, double y,
                               int64_t lowest[2], int64_t highest[2]) {
  lowest[1] = highest[1] = 0;
  bool quadratic = grid->shape == GM_SHAPE_BSPLINE2;
  for (int k = 0; k < grid->dim; k++) {
    double s = in_cells(grid, k, k == 0 ? x : y);
    if (!(s >= 0.0 && s < (double)grid->last_node[k]))
      return false; /* also catches NaN; keeps the casts in range */
    lowest[k] = quadratic ? gm_bspline2_lowest(s) : gm_bspline3_lowest(s);
    highest[k] = lowest[k] + (quadratic ? 2 : 3);
  }
  return bounds_valid(grid, lowest, highest);
}

bool gm_support_bspline(const gm_shape_grid *grid, double x, double y,
                        gm_support *out) {
  int64_t highest[2];
  if (!gm_support_bspline_bounds(grid, x, y, out->lowest, highest))
    return false;
  bool quadratic = grid->shape == GM_SHAPE_BSPLINE2;
  double weight[2][4] = {{1.0}, {1.0}}, gradient[2][4] = {{0.0}, {0.0}};
  int span[2] = {1, 1};
  for (int k = 0; k < grid->dim; k++) {
    double s = in_cells(grid, k, k == 0 ? x : y);
    span[k] = quadratic ? 3 : 4;
    if (quadratic)
      gm_bspline2_axis(s, out->lowest[k], weight[k], gradient[k]);
    else
      gm_bspline3_axis(s, out->lowest[k], weight[k], gradient[k]);
  }
  double inv_cell = grid->inv_cell; /* 1/m: gradients per cell -> per m */
  int entry = 0;
  for (int b = 0; b < span[1]; b++) {
    for (int a = 0; a < span[0]; a++, entry++) {
      out->offset[0][entry] = (uint8_t)a;
      out->offset[1][entry] = (uint8_t)b;
      out->weight[entry] = weight[0][a] * weight[1][b];
      out->gradient[0][entry] = inv_cell * gradient[0][a] * weight[1][b];
      out->gradient[1][entry] = inv_cell * weight[0][a] * gradient[1][b];
    }
  }
  out->count = entry;
  return true;
}

bool gm_support_bounds(const gm_shape_grid *grid, const gm_point_domain *point,
                       int64_t lowest[2], int64_t highest[2]) {
  lowest[1] = highest[1] = 0;
  if (gm_shape_is_bspline(grid->shape))
    return gm_support_bspline_bounds(grid, point->position[0],
                                     point->position[1], lowest, highest);
  if (grid->shape == GM_SHAPE_CPDI) {
    double corners[4][2], cells[4][2];
    int count = corners_in_cells(grid, point, corners, cells);
    for (int k = 0; k < grid->dim; k++) {
      double low = cells[0][k], high = cells[0][k];
      for (int c = 1; c < count; c++) {
        low = fmin(low, cells[c][k]);
        high = fmax(high, cells[c][k]);
      }
      if (!(low >= -1.0 && high < (double)grid->last_node[k] + 1.0))
        return false; /* also catches NaN; keeps the casts in range */
      lowest[k] = gm_floor_index(low);
      highest[k] = gm_floor_index(high) + 1;
    }
    return bounds_valid(grid, lowest, highest);
  }
  double half[2] = {0.0, 0.0};
  if (grid->shape != GM_SHAPE_LINEAR)
    rectangle_half_size(grid->shape, point, half);
  return gm_support_rectangle_bounds(grid, point->position[0],
                                     point->position[1], half[0], half[1],
                                     lowest, highest);
}

/* Tensor-product support of linear MPM, uGIMP and cpGIMP, for a rectangle
 * of centre x, y and half edges (m) whose bounds are lowest..highest. */
static void compute_rectangle(const gm_shape_grid *grid, double x, double y,
                              double half_x, double half_y,
                              const int64_t lowest[2], const int64_t highest[2],
                              gm_support *out) {
  double weight[2][GM_SUPPORT_MAX_SPAN], gradient[2][GM_SUPPORT_MAX_SPAN];
  int span[2] = {1, 1};
  weight[1][0] = 1.0;
  gradient[1][0] = 0.0;
  for (int k = 0; k < grid->dim; k++) {
    span[k] = (int)(highest[k] - lowest[k] + 1);
    gm_gimp_axis(in_cells(grid, k, k == 0 ? x : y),
                 (k == 0 ? half_x : half_y) * grid->inv_cell, lowest[k],
                 span[k], weight[k], gradient[k]);
  }
  /* Gradients per cell -> per metre here, not in a pass over gradient[]
   * right after gm_gimp_axis wrote it: reading back just-stored scalars as
   * a vector stalls on store forwarding. */
  double inv_cell = grid->inv_cell; /* 1/m */
  int entry = 0;
  for (int b = 0; b < span[1]; b++) {
    for (int a = 0; a < span[0]; a++, entry++) {
      out->offset[0][entry] = (uint8_t)a;
      out->offset[1][entry] = (uint8_t)b;
      out->weight[entry] = weight[0][a] * weight[1][b];
      out->gradient[0][entry] = inv_cell * gradient[0][a] * weight[1][b];
      out->gradient[1][entry] = inv_cell * weight[0][a] * gradient[1][b];
    }
  }
  out->count = entry;
}

bool gm_support_rectangle(const gm_shape_grid *grid, double x, double y,
                          double half_x, double half_y, gm_support *out) {
  int64_t highest[2];
  if (!gm_support_rectangle_bounds(grid, x, y, half_x, half_y, out->lowest,
                                   highest))
    return false;
  compute_rectangle(grid, x, y, half_x, half_y, out->lowest, highest, out);
  return true;
}

/* CPDI1: four linear corner supports (see the top of this file). */
static bool compute_cpdi(const gm_shape_grid *grid,
                         const gm_point_domain *point, gm_support *out) {
  double corners[4][2], cells[4][2];
  int count = corners_in_cells(grid, point, corners, cells);
  double corner_gradient[4][2]; /* g_c, 1/m */
  if (grid->dim == 1) {
    double length = corners[1][0] - corners[0][0]; /* m */
    if (!(length > 0.0))
      return false;
    corner_gradient[0][0] = -1.0 / length;
    corner_gradient[1][0] = 1.0 / length;
    corner_gradient[0][1] = corner_gradient[1][1] = 0.0;
  } else {
    double e1[2] = {corners[1][0] - corners[0][0],
                    corners[1][1] - corners[0][1]};
    double e2[2] = {corners[3][0] - corners[0][0],
                    corners[3][1] - corners[0][1]};
    double area = e1[0] * e2[1] - e1[1] * e2[0]; /* m^2 */
    if (!(area > 0.0))
      return false;
    for (int c = 0; c < 4; c++) {
      const double *next = corners[(c + 1) % 4], *prev = corners[(c + 3) % 4];
      corner_gradient[c][0] = (next[1] - prev[1]) / (2.0 * area);
      corner_gradient[c][1] = -(next[0] - prev[0]) / (2.0 * area);
    }
  }
  double share = 1.0 / count; /* each corner's part of the weight */
  int entry = 0;
  for (int c = 0; c < count; c++) {
    int64_t cell[2] = {0, 0};
    double fraction[2] = {0.0, 0.0};
    for (int k = 0; k < grid->dim; k++) {
      cell[k] = gm_floor_index(cells[c][k]);
      fraction[k] = cells[c][k] - (double)cell[k];
    }
    for (int b = 0; b < (grid->dim > 1 ? 2 : 1); b++) {
      for (int a = 0; a < 2; a++, entry++) {
        double wy = grid->dim > 1 ? (b ? fraction[1] : 1.0 - fraction[1]) : 1.0;
        double value = (a ? fraction[0] : 1.0 - fraction[0]) * wy; /* N_i */
        out->offset[0][entry] = (uint8_t)(cell[0] + a - out->lowest[0]);
        out->offset[1][entry] = (uint8_t)(cell[1] + b - out->lowest[1]);
        out->weight[entry] = share * value;
        out->gradient[0][entry] = value * corner_gradient[c][0];
        out->gradient[1][entry] = value * corner_gradient[c][1];
      }
    }
  }
  out->count = entry;
  return true;
}

bool gm_support_compute(const gm_shape_grid *grid, const gm_point_domain *point,
                        gm_support *out) {
  if (gm_shape_is_bspline(grid->shape))
    return gm_support_bspline(grid, point->position[0], point->position[1],
                              out);
  int64_t highest[2];
  if (!gm_support_bounds(grid, point, out->lowest, highest))
    return false;
  if (grid->shape == GM_SHAPE_CPDI)
    return compute_cpdi(grid, point, out);
  double half[2] = {0.0, 0.0};
  if (grid->shape != GM_SHAPE_LINEAR)
    rectangle_half_size(grid->shape, point, half);
  compute_rectangle(grid, point->position[0], point->position[1], half[0],
                    half[1], out->lowest, highest, out);
  return true;
}
