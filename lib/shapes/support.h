/*
 * support.h - the grid nodes a material point reaches, with their weights
 * and weight gradients, for every shape-function variant (000 sec 2.1):
 * linear MPM, uGIMP, cpGIMP, CPDI1 and the quadratic and cubic B-splines.
 * The specialised linear kernels of
 * p2g.c and g2p.c do not go through here; everything else does (the GIMP
 * and CPDI transfers, block keys, domain corners, bounds checks).
 *
 * Node indices count from the grid's node 0, which lies one ghost layer
 * (GM_GHOST_LAYERS cells) below the box's lower corner on every axis: a
 * GIMP or CPDI domain may stick out of the box by up to one cell, and the
 * ghost nodes it then reaches take the boundary condition of the box face
 * they lie beyond (grid_update.c), so the support of a point against a
 * wall is complete. One layer is enough for the B-splines too: a point
 * lies inside the box, the quadratic reaches 1.5 cells out and the cubic
 * 2 cells, where its weight is 0 (shape_bspline.h).
 */
#ifndef GM_SUPPORT_H
#define GM_SUPPORT_H

#include "granmpm.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GM_GHOST_LAYERS 1
/* Nodes per axis a point may reach: its domain may span 8 cells, so that
 * the nodes of a point binned by its lowest node always lie in that block
 * and the next one along each axis (the grid's neighbour links). */
#define GM_SUPPORT_MAX_SPAN    9
#define GM_SUPPORT_MAX_ENTRIES (GM_SUPPORT_MAX_SPAN * GM_SUPPORT_MAX_SPAN)

/* What the support of a point depends on in a domain. */
typedef struct gm_shape_grid {
  gm_shape shape;
  int dim;              /* 1 or 2 */
  double origin[2];     /* m, position of node 0 (ghost layer included) */
  double inv_cell;      /* 1/m */
  int64_t last_node[2]; /* highest node index per axis */
} gm_shape_grid;

/* One point's domain: centre, deformation and initial half edges. */
typedef struct gm_point_domain {
  double position[2];    /* m */
  double deformation[4]; /* F_xx, F_xy, F_yx, F_yy */
  double half_size[2];   /* m, half the initial domain edges */
} gm_point_domain;

/* Weights of the nodes a point reaches. Entries may repeat a node (CPDI
 * adds one entry per corner and node); sums over entries are what count. */
typedef struct gm_support {
  int count;
  int64_t lowest[2]; /* node index of the support's lower corner */
  uint8_t offset[2][GM_SUPPORT_MAX_ENTRIES]; /* node - lowest, per axis */
  double weight[GM_SUPPORT_MAX_ENTRIES];
  double gradient[2][GM_SUPPORT_MAX_ENTRIES]; /* 1/m */
} gm_support;

/* The domain of point p from SoA arrays (deformation: F_xx, F_xy, F_yx,
 * F_yy; the y entries are ignored in 1D). */
static inline void gm_load_point_domain(int dim,
                                        const double *const position[2],
                                        const double *const deformation[4],
                                        const double *const domain_size[2],
                                        size_t p, gm_point_domain *out) {
  for (int k = 0; k < 2; k++) {
    out->position[k] = k < dim ? position[k][p] : 0.0;
    out->half_size[k] = k < dim ? 0.5 * domain_size[k][p] : 0.0;
  }
  for (int k = 0; k < 4; k++)
    out->deformation[k] = deformation[k][p];
}

/* Is the variant a B-spline (support from the position alone)? */
static inline bool gm_shape_is_bspline(gm_shape shape) {
  return shape == GM_SHAPE_BSPLINE2 || shape == GM_SHAPE_BSPLINE3;
}

/* Lowest and highest node per axis; false if the support leaves the nodes
 * of the grid or spans more than GM_SUPPORT_MAX_SPAN nodes. */
bool gm_support_bounds(const gm_shape_grid *grid, const gm_point_domain *point,
                       int64_t lowest[2], int64_t highest[2]);
/* The support; false as for gm_support_bounds (out is then undefined). */
bool gm_support_compute(const gm_shape_grid *grid, const gm_point_domain *point,
                        gm_support *out);
/* The support of a rectangle variant (linear MPM, uGIMP, cpGIMP) from its
 * centre x, y and current half edges (m; y and half_y unused in 1D), all
 * by value: the wide transfers call this once per point and pass, and a
 * gm_point_domain written just before the call and read back as a vector
 * stalled on store forwarding. False as gm_support_compute. */
bool gm_support_rectangle(const gm_shape_grid *grid, double x, double y,
                          double half_x, double half_y, gm_support *out);
/* Its bounds only, as gm_support_bounds. */
bool gm_support_rectangle_bounds(const gm_shape_grid *grid, double x, double y,
                                 double half_x, double half_y,
                                 int64_t lowest[2], int64_t highest[2]);
/* The support of a B-spline variant of a point at x, y (m; y unused in
 * 1D), by value as gm_support_rectangle. False as gm_support_compute. */
bool gm_support_bspline(const gm_shape_grid *grid, double x, double y,
                        gm_support *out);
/* Its bounds only, as gm_support_bounds. */
bool gm_support_bspline_bounds(const gm_shape_grid *grid, double x, double y,
                               int64_t lowest[2], int64_t highest[2]);
/* Current half edges (m) of point p of a rectangle variant: the initial
 * ones, stretched by |F_xx|, |F_yy| for cpGIMP, 0 for linear MPM. */
static inline void gm_rectangle_half_edges(gm_shape shape, int dim,
                                           const double *const domain_size[2],
                                           const double *const deformation[4],
                                           size_t p, double half[2]) {
  for (int k = 0; k < 2; k++) {
    half[k] =
        shape != GM_SHAPE_LINEAR && k < dim ? 0.5 * domain_size[k][p] : 0.0;
    if (shape == GM_SHAPE_CPGIMP && k < dim)
      half[k] *= fabs(deformation[3 * k][p]);
  }
}
/* Corners (m) of the point's current domain, counter-clockwise from the
 * lower left: a rectangle for linear MPM, uGIMP and the B-splines (the
 * initial domain, moved), a rectangle with edges stretched by |F_xx|, |F_yy|
 * for cpGIMP, the parallelogram spanned by F r1, F r2 for CPDI. In 1D, the two
 * ends (corners[0][0], corners[1][0]). */
void gm_point_domain_corners(gm_shape shape, int dim,
                             const gm_point_domain *point,
                             double corners[4][2]);

/* The support of point p from SoA arrays, any variant: B-splines from
 * the position, rectangles by value through gm_support_rectangle, CPDI
 * through its domain. */
static inline bool gm_wide_support(const gm_shape_grid *grid, int dim,
                                   const double *const position[2],
                                   const double *const deformation[4],
                                   const double *const domain_size[2], size_t p,
                                   gm_support *out) {
  if (gm_shape_is_bspline(grid->shape))
    return gm_support_bspline(grid, position[0][p],
                              dim > 1 ? position[1][p] : 0.0, out);
  if (grid->shape == GM_SHAPE_CPDI) {
    gm_point_domain domain;
    gm_load_point_domain(dim, position, deformation, domain_size, p, &domain);
    return gm_support_compute(grid, &domain, out);
  }
  double half[2];
  gm_rectangle_half_edges(grid->shape, dim, domain_size, deformation, p, half);
  return gm_support_rectangle(grid, position[0][p],
                              dim > 1 ? position[1][p] : 0.0, half[0], half[1],
                              out);
}

/* Whether a support whose lowest node lies (x0, y0) nodes from a block's
 * base stays within `edge` nodes of it along each axis (two blocks: the
 * block and its +x/+y neighbours, which is all the scatter tile and the
 * gather's neighbour links reach). The binning keys every point by its
 * support, so this holds unless the keys and the supports disagree; the
 * transfers check it anyway rather than write or read outside the tile. */
static inline bool gm_support_within(const gm_support *support, int dim,
                                     int64_t x0, int64_t y0, int64_t edge) {
  if (x0 < 0 || y0 < 0)
    return false;
  int64_t reach[2] = {0, 0};
  for (int e = 0; e < support->count; e++)
    for (int k = 0; k < dim; k++)
      reach[k] =
          support->offset[k][e] > reach[k] ? support->offset[k][e] : reach[k];
  return x0 + reach[0] < edge && (dim < 2 || y0 + reach[1] < edge);
}

/* Bounds of point p's support from SoA arrays, as gm_wide_support. */
static inline bool gm_wide_support_bounds(const gm_shape_grid *grid, int dim,
                                          const double *const position[2],
                                          const double *const deformation[4],
                                          const double *const domain_size[2],
                                          size_t p, int64_t lowest[2],
                                          int64_t highest[2]) {
  if (gm_shape_is_bspline(grid->shape))
    return gm_support_bspline_bounds(
        grid, position[0][p], dim > 1 ? position[1][p] : 0.0, lowest, highest);
  if (grid->shape == GM_SHAPE_CPDI) {
    gm_point_domain domain;
    gm_load_point_domain(dim, position, deformation, domain_size, p, &domain);
    return gm_support_bounds(grid, &domain, lowest, highest);
  }
  double half[2];
  gm_rectangle_half_edges(grid->shape, dim, domain_size, deformation, p, half);
  return gm_support_rectangle_bounds(grid, position[0][p],
                                     dim > 1 ? position[1][p] : 0.0, half[0],
                                     half[1], lowest, highest);
}

#endif
