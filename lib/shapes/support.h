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
  double origin[3];     /* m, position of node 0 (ghost layer included;
                           z: 3D only) */
  double inv_cell;      /* 1/m */
  int64_t last_node[3]; /* highest node index per axis */
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

/* A tensor-product support (linear MPM, uGIMP, cpGIMP, the B-splines),
 * kept as its axis factors: node (lowest[0] + a, lowest[1] + b) has
 *   weight      weight[0][a] * weight[1][b],
 *   gradient x  gradient_x[a] * weight[1][b],
 *   gradient y  weight_x_per_cell[a] * gradient_y[b],
 * the products gm_support_compute forms for each entry (the factors hold
 * inv_cell where it multiplied first, so the products are bitwise the
 * same). The wide transfers loop over a and b themselves: 2 x 3 axis
 * evaluations per point instead of a 9-entry table written and read back.
 * In 1D span[1] = 1, weight[1][0] = 1 and gradient_y[0] = 0. */
typedef struct gm_product_support {
  int64_t lowest[2]; /* node index of the support's lower corner */
  int span[2];       /* nodes per axis */
  double weight[2][GM_SUPPORT_MAX_SPAN];         /* - */
  double gradient_x[GM_SUPPORT_MAX_SPAN];        /* 1/m, inv_cell dS_a/ds */
  double weight_x_per_cell[GM_SUPPORT_MAX_SPAN]; /* 1/m, inv_cell S_a */
  double gradient_y[GM_SUPPORT_MAX_SPAN];        /* per cell, dS_b/ds */
} gm_product_support;

/* CPDI1 as its corners (see support.c): entry (c, a, b) is node
 * (cell[c][0] + a, cell[c][1] + b) with the bilinear value
 * N = axis[c][0][a] * axis[c][1][b] (the tent of that node at corner c),
 * weight share * N and gradient N * corner_gradient[c]. In 1D two corners
 * (the ends) and b = 0 only, axis[c][1][0] = 1. */
typedef struct gm_cpdi_support {
  int corner_count;             /* 4, or 2 in 1D */
  int64_t lowest[2];            /* node index of the support's lower corner */
  int64_t cell[4][2];           /* lower node of each corner's cell */
  double axis[4][2][2];         /* - , (1 - f, f) per corner and axis */
  double corner_gradient[4][2]; /* 1/m, g_c */
  double share;                 /* -, 1 / corner_count */
} gm_cpdi_support;

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
/* The same support as axis factors (gm_product_support). */
bool gm_product_support_rectangle(const gm_shape_grid *grid, double x, double y,
                                  double half_x, double half_y,
                                  gm_product_support *out);
/* Its bounds only, as gm_support_bounds. */
bool gm_support_rectangle_bounds(const gm_shape_grid *grid, double x, double y,
                                 double half_x, double half_y,
                                 int64_t lowest[2], int64_t highest[2]);
/* The support of a B-spline variant of a point at x, y (m; y unused in
 * 1D), by value as gm_support_rectangle. False as gm_support_compute. */
bool gm_support_bspline(const gm_shape_grid *grid, double x, double y,
                        gm_support *out);
/* The same support as axis factors (gm_product_support). */
bool gm_product_support_bspline(const gm_shape_grid *grid, double x, double y,
                                gm_product_support *out);
/* Its bounds only, as gm_support_bounds. */
bool gm_support_bspline_bounds(const gm_shape_grid *grid, double x, double y,
                               int64_t lowest[2], int64_t highest[2]);
/* The CPDI support of a point by its corners (gm_cpdi_support); false
 * as gm_support_compute. */
bool gm_cpdi_support_compute(const gm_shape_grid *grid,
                             const gm_point_domain *point,
                             gm_cpdi_support *out);
/* The same from the centre x, y (m; y unused in 1D), the domain map D
 * (D_xx, D_xy, D_yx, D_yy) and the initial half edges (m), by value (see
 * gm_support_rectangle). */
bool gm_cpdi_support_map(const gm_shape_grid *grid, double x, double y,
                         const double map[4], double half_x, double half_y,
                         gm_cpdi_support *out);
/* The entry table of a product or a CPDI support, as gm_support_compute
 * makes it (entries in the order b, a and c, b, a). */
void gm_product_support_expand(const gm_product_support *product,
                               gm_support *out);
void gm_cpdi_support_expand(const gm_cpdi_support *cpdi, int dim,
                            gm_support *out);
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

/* The support of point p of a tensor-product variant (every variant but
 * CPDI) from SoA arrays, as gm_wide_support. */
static inline bool gm_wide_product_support(const gm_shape_grid *grid, int dim,
                                           const double *const position[2],
                                           const double *const deformation[4],
                                           const double *const domain_size[2],
                                           size_t p, gm_product_support *out) {
  double y = dim > 1 ? position[1][p] : 0.0;
  if (gm_shape_is_bspline(grid->shape))
    return gm_product_support_bspline(grid, position[0][p], y, out);
  double half[2];
  gm_rectangle_half_edges(grid->shape, dim, domain_size, deformation, p, half);
  return gm_product_support_rectangle(grid, position[0][p], y, half[0], half[1],
                                      out);
}

/* The CPDI support of point p from SoA arrays (deformation: the domain
 * map D), as gm_wide_support. */
static inline bool gm_wide_cpdi_support(const gm_shape_grid *grid, int dim,
                                        const double *const position[2],
                                        const double *const deformation[4],
                                        const double *const domain_size[2],
                                        size_t p, gm_cpdi_support *out) {
  double map[4] = {deformation[0][p], deformation[1][p], deformation[2][p],
                   deformation[3][p]};
  bool planar = dim > 1;
  return gm_cpdi_support_map(
      grid, position[0][p], planar ? position[1][p] : 0.0, map,
      0.5 * domain_size[0][p], planar ? 0.5 * domain_size[1][p] : 0.0, out);
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
