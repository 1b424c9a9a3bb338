/*
 * support_3d.h - the support of a material point in 3D for the GIMP
 * variants (uGIMP, cpGIMP) and the B-splines: the nodes it reaches, with
 * the weight and gradient factors of each axis.
 *
 * GIMP's weight of node i is the tent N_i averaged over the point's domain
 * (004 eq 3.27 along one axis, shape_gimp.h). In 3D the grid basis is
 * separable, N_i(x) = N_i^x(x) N_i^y(y) N_i^z(z) (004 sec 3.3.6), and the
 * domain is a box with edges along the axes, so the average of the product
 * over the box is the product of the axis averages:
 *   S_i = S_a^x S_b^y S_c^z,
 *   grad S_i = (dS_a^x S_b^y S_c^z, S_a^x dS_b^y S_c^z, S_a^x S_b^y dS_c^z),
 * with i = (lowest + (a, b, c)). The kernels (p2g_3d.c, g2p_3d.c) form
 * these products node by node from the factors kept here, as the 2D wide
 * kernels do from gm_product_support.
 *
 * The box: uGIMP keeps the initial one (GM_FIELD_DOMAIN_SIZE), moved with
 * the point; cpGIMP stretches each edge by |F_kk| (the axis-aligned
 * approximation of the deformed domain used in 2D, support.h).
 *
 * The B-splines (GM_SHAPE_BSPLINE2, GM_SHAPE_BSPLINE3) are tensor products
 * of the axis functions of shape_bspline.h at the point's position, as in
 * 2D (support.c): N_i = N_a(s_x) N_b(s_y) N_c(s_z), 3 (quadratic) or 4
 * (cubic) nodes per axis, 27 or 64 in all; they have no box (the half
 * edges passed in are not used). The box faces mirror them
 * (bspline_faces.c).
 *
 * The 3D blocks are 4 x 4 x 4 nodes and a block reaches its seven upper
 * neighbours only (block_grid.h): a point binned by its support's lowest
 * node (local 0..3) may reach 5 nodes per axis. A box up to 3 cells long
 * always fits (uGIMP with one point per cell spans 3 nodes; cpGIMP with
 * 2 points per cell may stretch 6-fold); a longer one fits only where it
 * crosses at most 3 node planes, and otherwise fails the step or the call
 * that adds it.
 */
#ifndef GM_SUPPORT_3D_H
#define GM_SUPPORT_3D_H

#include "shapes/support.h"

/* Nodes per axis a 3D GIMP support may reach (see above). */
#define GM_SUPPORT_3D_MAX_SPAN 5

/* A 3D tensor-product support as its axis factors: node
 * (lowest[0] + a, lowest[1] + b, lowest[2] + c) has weight
 * weight[0][a] weight[1][b] weight[2][c] and gradient component k the same
 * product with gradient[k][.] in place of weight[k][.]. Entries past
 * span[k] are not part of the support. */
typedef struct gm_box_support_3d {
  int64_t lowest[3]; /* node index of the support's lower corner */
  int span[3];       /* nodes per axis */
  /* gm_gimp_axis writes three entries for a short domain even where its
   * span is 2, hence the margin. */
  double weight[3][GM_SUPPORT_3D_MAX_SPAN];   /* - */
  double gradient[3][GM_SUPPORT_3D_MAX_SPAN]; /* 1/m, dS/dx_p per axis */
} gm_box_support_3d;

/* The support of a box of centre x (m) and half edges half (m; 0 is the
 * tent of linear MPM) on a 3D grid (grid->dim == 3), or of the B-spline of
 * a point at x when grid->shape is one (half unused). False if the support
 * leaves the grid's nodes (ghost layer included) or spans more than
 * GM_SUPPORT_3D_MAX_SPAN nodes along an axis, or x is not finite (out is
 * then undefined). */
bool gm_box_support_compute_3d(const gm_shape_grid *grid, const double x[3],
                               const double half[3], gm_box_support_3d *out);
/* Its lowest node per axis only, under the same conditions. */
bool gm_box_support_lowest_3d(const gm_shape_grid *grid, const double x[3],
                              const double half[3], int64_t lowest[3]);

/* Half edges (m) of point p's current box from SoA arrays: the initial
 * half edges (domain_size / 2), times |F_xx|, |F_yy|, |F_zz| for cpGIMP
 * (deformation: the nine F slots of core.h, diagonal at F_XX, F_YY,
 * F_ZZ = 0, 3, 4). */
static inline void gm_box_half_edges_3d(gm_shape shape,
                                        const double *const domain_size[3],
                                        const double *const deformation[9],
                                        size_t p, double half[3]) {
  static const int diagonal[3] = {0, 3, 4}; /* F_XX, F_YY, F_ZZ */
  for (int k = 0; k < 3; k++) {
    half[k] = 0.5 * domain_size[k][p];
    if (shape == GM_SHAPE_CPGIMP)
      half[k] *= fabs(deformation[diagonal[k]][p]);
  }
}

#endif
