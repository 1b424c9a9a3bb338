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

bool gm_product_support_bspline(const gm_shape_grid *grid, double x, double y,
                                gm_product_support *out) {
  int64_t highest[2];
  if (!gm_support_bspline_bounds(grid, x, y, out->lowest, highest))
    return false;
  bool quadratic = grid->shape == GM_SHAPE_BSPLINE2;
  double gradient[2][4] = {{0.0}, {0.0}}; /* per cell */
  out->span[0] = out->span[1] = 1;
  out->weight[1][0] = 1.0;
  for (int k = 0; k < grid->dim; k++) {
    double s = in_cells(grid, k, k == 0 ? x : y);
    out->span[k] = quadratic ? 3 : 4;
    if (quadratic)
      gm_bspline2_axis(s, out->lowest[k], out->weight[k], gradient[k]);
    else
      gm_bspline3_axis(s, out->lowest[k], out->weight[k], gradient[k]);
  }
  double inv_cell = grid->inv_cell; /* 1/m: gradients per cell -> per m */
  for (int a = 0; a < out->span[0]; a++) {
    out->gradient_x[a] = inv_cell * gradient[0][a];
    out->weight_x_per_cell[a] = inv_cell * out->weight[0][a];
  }
  for (int b = 0; b < out->span[1]; b++)
    out->gradient_y[b] = gradient[1][b];
  return true;
}

void gm_product_support_expand(const gm_product_support *product,
                               gm_support *out) {
  int entry = 0;
  for (int k = 0; k < 2; k++)
    out->lowest[k] = product->lowest[k];
  for (int b = 0; b < product->span[1]; b++) {
    for (int a = 0; a < product->span[0]; a++, entry++) {
      double weight_y = product->weight[1][b];
      out->offset[0][entry] = (uint8_t)a;
      out->offset[1][entry] = (uint8_t)b;
      out->weight[entry] = product->weight[0][a] * weight_y;
      out->gradient[0][entry] = product->gradient_x[a] * weight_y;
      out->gradient[1][entry] =
          product->weight_x_per_cell[a] * product->gradient_y[b];
    }
  }
  out->count = entry;
}

bool gm_support_bspline(const gm_shape_grid *grid, double x, double y,
                        gm_support *out) {
  gm_product_support product;
  if (!gm_product_support_bspline(grid, x, y, &product))
    return false;
  gm_product_support_expand(&product, out);
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
      for (int c = 1; c < count; c++) { /* as cpdi_from_corners */
        low = cells[c][k] < low ? cells[c][k] : low;
        high = cells[c][k] > high ? cells[c][k] : high;
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

bool gm_product_support_rectangle(const gm_shape_grid *grid, double x, double y,
                                  double half_x, double half_y,
                                  gm_product_support *out) {
  double inv_cell = grid->inv_cell; /* 1/m */
  out->lowest[1] = 0;
  out->span[1] = 1;
  out->weight[1][0] = 1.0;
  out->gradient_y[0] = 0.0;
  for (int k = 0; k < grid->dim; k++) {
    double s = in_cells(grid, k, k == 0 ? x : y);
    double l = (k == 0 ? half_x : half_y) * inv_cell;
    if (!(s - l >= -1.0 && s + l < (double)grid->last_node[k] + 1.0))
      return false; /* also catches NaN; keeps the casts in range */
    int span;
    int64_t lowest = gm_gimp_axis_bounds(s, l, &span);
    if (lowest < 0 || lowest + span - 1 > grid->last_node[k] ||
        span > GM_SUPPORT_MAX_SPAN)
      return false; /* as bounds_valid */
    out->lowest[k] = lowest;
    out->span[k] = span;
    if (k == 1) {
      gm_gimp_axis(s, l, lowest, span, out->weight[1], out->gradient_y);
      continue;
    }
    /* Per cell -> per metre as the axis is computed (gm_gimp_axis_scaled):
     * a pass over just-stored values stalls on store forwarding. */
    gm_gimp_axis_scaled(s, l, lowest, span, inv_cell, out->weight[0],
                        out->gradient_x, out->weight_x_per_cell);
  }
  return true;
}

bool gm_support_rectangle(const gm_shape_grid *grid, double x, double y,
                          double half_x, double half_y, gm_support *out) {
  gm_product_support product;
  if (!gm_product_support_rectangle(grid, x, y, half_x, half_y, &product))
    return false;
  gm_product_support_expand(&product, out);
  return true;
}

/* CPDI from the domain's corners (m; count 4, or 2 in 1D). */
static bool cpdi_from_corners(const gm_shape_grid *grid, double corners[4][2],
                              int count, gm_cpdi_support *out) {
  double cells[4][2]; /* as corners_in_cells */
  for (int c = 0; c < count; c++)
    for (int k = 0; k < 2; k++)
      cells[c][k] = k < grid->dim ? in_cells(grid, k, corners[c][k]) : 0.0;
  out->lowest[1] = 0;
  for (int k = 0; k < grid->dim; k++) { /* as gm_support_bounds */
    /* Not fmin/fmax, library calls here (no SSE4.1 by default); a NaN
     * corner fails the checks below or the area's. */
    double low = cells[0][k], high = cells[0][k];
    for (int c = 1; c < count; c++) {
      low = cells[c][k] < low ? cells[c][k] : low;
      high = cells[c][k] > high ? cells[c][k] : high;
    }
    if (!(low >= -1.0 && high < (double)grid->last_node[k] + 1.0))
      return false; /* also catches NaN; keeps the casts in range */
    int64_t lowest = gm_floor_index(low);
    int64_t highest = gm_floor_index(high) + 1;
    if (lowest < 0 || highest > grid->last_node[k] ||
        highest - lowest + 1 > GM_SUPPORT_MAX_SPAN)
      return false; /* as bounds_valid */
    out->lowest[k] = lowest;
  }
  /* g_c (1/m): see the top of this file. */
  if (grid->dim == 1) {
    double length = corners[1][0] - corners[0][0]; /* m */
    if (!(length > 0.0))
      return false;
    out->corner_gradient[0][0] = -1.0 / length;
    out->corner_gradient[1][0] = 1.0 / length;
    out->corner_gradient[0][1] = out->corner_gradient[1][1] = 0.0;
  } else {
    double e1[2] = {corners[1][0] - corners[0][0],
                    corners[1][1] - corners[0][1]};
    double e2[2] = {corners[3][0] - corners[0][0],
                    corners[3][1] - corners[0][1]};
    double area = e1[0] * e2[1] - e1[1] * e2[0]; /* m^2 */
    if (!(area > 0.0))
      return false;
    /* One division, not eight (a division costs a dozen multiplications;
     * the gradients move by an ulp at most). */
    double inverse = 0.5 / area; /* 1 / (2 V), 1/m^2 */
    for (int c = 0; c < 4; c++) {
      const double *next = corners[(c + 1) % 4], *prev = corners[(c + 3) % 4];
      out->corner_gradient[c][0] = (next[1] - prev[1]) * inverse;
      out->corner_gradient[c][1] = -(next[0] - prev[0]) * inverse;
    }
  }
  out->corner_count = count;
  out->share = count == 4 ? 0.25 : 0.5; /* each corner's part, 1 / count */
  for (int c = 0; c < count; c++) {
    for (int k = 0; k < 2; k++) {
      if (k >= grid->dim) { /* 1D: one row of unit weight */
        out->cell[c][k] = 0;
        out->axis[c][k][0] = out->axis[c][k][1] = 1.0;
        continue;
      }
      out->cell[c][k] = gm_floor_index(cells[c][k]);
      double fraction = cells[c][k] - (double)out->cell[c][k];
      out->axis[c][k][0] = 1.0 - fraction;
      out->axis[c][k][1] = fraction;
    }
  }
  return true;
}

bool gm_cpdi_support_compute(const gm_shape_grid *grid,
                             const gm_point_domain *point,
                             gm_cpdi_support *out) {
  double corners[4][2];
  gm_point_domain_corners(grid->shape, grid->dim, point, corners);
  return cpdi_from_corners(grid, corners, grid->dim == 1 ? 2 : 4, out);
}

bool gm_cpdi_support_map(const gm_shape_grid *grid, double x, double y,
                         const double map[4], double half_x, double half_y,
                         gm_cpdi_support *out) {
  /* The arithmetic of gm_point_domain_corners: r_i = D r_i0. */
  bool planar = grid->dim > 1;
  double r1[2] = {map[0] * half_x, planar ? map[2] * half_x : 0.0};
  double r2[2] = {planar ? map[1] * half_y : 0.0,
                  planar ? map[3] * half_y : 0.0};
  double position[2] = {x, y};
  static const double sign1[4] = {-1.0, 1.0, 1.0, -1.0};
  static const double sign2[4] = {-1.0, -1.0, 1.0, 1.0};
  double corners[4][2];
  for (int c = 0; c < 4; c++)
    for (int k = 0; k < 2; k++)
      corners[c][k] = position[k] + sign1[c] * r1[k] + sign2[c] * r2[k];
  return cpdi_from_corners(grid, corners, planar ? 4 : 2, out);
}

void gm_cpdi_support_expand(const gm_cpdi_support *cpdi, int dim,
                            gm_support *out) {
  int entry = 0;
  for (int k = 0; k < 2; k++)
    out->lowest[k] = cpdi->lowest[k];
  for (int c = 0; c < cpdi->corner_count; c++) {
    for (int b = 0; b < (dim > 1 ? 2 : 1); b++) {
      for (int a = 0; a < 2; a++, entry++) {
        double value = cpdi->axis[c][0][a] * cpdi->axis[c][1][b]; /* N_i */
        out->offset[0][entry] =
            (uint8_t)(cpdi->cell[c][0] + a - cpdi->lowest[0]);
        out->offset[1][entry] =
            (uint8_t)(cpdi->cell[c][1] + b - cpdi->lowest[1]);
        out->weight[entry] = cpdi->share * value;
        out->gradient[0][entry] = value * cpdi->corner_gradient[c][0];
        out->gradient[1][entry] = value * cpdi->corner_gradient[c][1];
      }
    }
  }
  out->count = entry;
}

bool gm_support_compute(const gm_shape_grid *grid, const gm_point_domain *point,
                        gm_support *out) {
  if (gm_shape_is_bspline(grid->shape))
    return gm_support_bspline(grid, point->position[0], point->position[1],
                              out);
  if (grid->shape == GM_SHAPE_CPDI) {
    gm_cpdi_support cpdi;
    if (!gm_cpdi_support_compute(grid, point, &cpdi))
      return false;
    gm_cpdi_support_expand(&cpdi, grid->dim, out);
    return true;
  }
  double half[2] = {0.0, 0.0};
  if (grid->shape != GM_SHAPE_LINEAR)
    rectangle_half_size(grid->shape, point, half);
  return gm_support_rectangle(grid, point->position[0], point->position[1],
                              half[0], half[1], out);
}
