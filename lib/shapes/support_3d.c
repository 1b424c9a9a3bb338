/*
 * support_3d.c - the 3D tensor-product supports (support_3d.h): per axis,
 * for the GIMP boxes the lowest node and span of gm_gimp_axis_bounds and
 * the averages of gm_gimp_axis (004 eq 3.27, shape_gimp.h), for the
 * B-splines the three (quadratic) or four (cubic) nodes and weights of
 * shape_bspline.h at the point's position; the same axis functions the 2D
 * supports use (support.c), with the gradients turned from per cell into
 * per metre.
 */
#include "shapes/shapes.h"

/* B-splines: axis k's lowest node and span of a point at s cells from
 * node 0, as gm_support_bspline_bounds in 2D (support.c): the point lies
 * within the nodes, its support too (the ghost layer holds the node the
 * quadratic reaches 1.5 cells out, support.h). */
static bool bspline_axis_bounds(const gm_shape_grid *grid, int k, double s,
                                int64_t *lowest, int *span) {
  if (!(s >= 0.0 && s < (double)grid->last_node[k]))
    return false; /* also catches NaN; keeps the casts in range */
  bool quadratic = grid->shape == GM_SHAPE_BSPLINE2;
  *lowest = quadratic ? gm_bspline2_lowest(s) : gm_bspline3_lowest(s);
  *span = quadratic ? 3 : 4;
  return *lowest >= 0 && *lowest + *span - 1 <= grid->last_node[k];
}

/* Axis k's position s and half length l in cells from node 0, and its
 * lowest node and span; false as gm_box_support_3d. */
static bool axis_bounds(const gm_shape_grid *grid, int k, double x, double half,
                        double *s, double *l, int64_t *lowest, int *span) {
  *s = (x - grid->origin[k]) * grid->inv_cell;
  *l = half * grid->inv_cell;
  if (gm_shape_is_bspline(grid->shape)) /* no box: half is not used */
    return bspline_axis_bounds(grid, k, *s, lowest, span);
  /* Also catches NaN, and keeps the casts in range. */
  if (!(*s - *l >= -1.0 && *s + *l < (double)grid->last_node[k] + 1.0))
    return false;
  *lowest = gm_gimp_axis_bounds(*s, *l, span);
  return *lowest >= 0 && *lowest + *span - 1 <= grid->last_node[k] &&
         *span <= GM_SUPPORT_3D_MAX_SPAN;
}

bool gm_box_support_lowest_3d(const gm_shape_grid *grid, const double x[3],
                              const double half[3], int64_t lowest[3]) {
  for (int k = 0; k < 3; k++) {
    double s, l;
    int span;
    if (!axis_bounds(grid, k, x[k], half[k], &s, &l, &lowest[k], &span))
      return false;
  }
  return true;
}

bool gm_box_support_compute_3d(const gm_shape_grid *grid, const double x[3],
                               const double half[3], gm_box_support_3d *out) {
  double inv_cell = grid->inv_cell; /* 1/m: per cell -> per metre */
  for (int k = 0; k < 3; k++) {
    double s, l;
    if (!axis_bounds(grid, k, x[k], half[k], &s, &l, &out->lowest[k],
                     &out->span[k]))
      return false;
    double *gradient = out->gradient[k];
    if (grid->shape == GM_SHAPE_BSPLINE2)
      gm_bspline2_axis(s, out->lowest[k], out->weight[k], gradient);
    else if (grid->shape == GM_SHAPE_BSPLINE3)
      gm_bspline3_axis(s, out->lowest[k], out->weight[k], gradient);
    else
      gm_gimp_axis(s, l, out->lowest[k], out->span[k], out->weight[k],
                   gradient);
    for (int n = 0; n < out->span[k]; n++)
      gradient[n] *= inv_cell;
  }
  return true;
}
