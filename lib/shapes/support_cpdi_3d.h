/*
 * support_cpdi_3d.h - the CPDI1 support of a 3D point (Sadeghirad, Brannon
 * & Burghardt 2011): the parallelepiped spanned by r_k = D r_k0 about the
 * point, D the point's domain map (cpdi_reset.c), r_k0 = (l_k / 2) e_k the
 * initial half edges (GM_FIELD_DOMAIN_SIZE), and the weights and gradients
 * its eight corners give (support_cpdi_3d.c says how). The functions below
 * take D as `f` (row-major); the callers pass the map through
 * gm_support_slots_3d (points.h).
 *
 * CPDI is no tensor product, so the support is kept dense: the weight and
 * gradient of every node of the box of nodes the corners' cells cover,
 * node (lowest + (a, b, c)) at entry (c span_y + b) span_x + a. Nodes of
 * that box no corner's cell touches have weight and gradient 0. The 3D
 * blocks (4 x 4 x 4) reach a support up to GM_SUPPORT_3D_MAX_SPAN = 5
 * nodes per axis from the block of its lowest node (support_3d.h); a
 * parallelepiped whose corners spread over more fails the step, or the
 * call that adds it, as a GIMP box does.
 *
 * D takes F's increments (g2p_3d.c) and the granular family's density
 * control (000 eqs 14, 18, density_control.c), so D = F bitwise until the
 * domain is reset to cbrt(det D) I, once its singular values differ by
 * more than GM_CPDI_MAX_DISTORTION (cpdi_reset.c, since 2026-11-29; until
 * then the domain followed F itself and a long shear failed the step here,
 * past GM_SUPPORT_3D_MAX_SPAN).
 */
#ifndef GM_SUPPORT_CPDI_3D_H
#define GM_SUPPORT_CPDI_3D_H

#include "shapes/support_3d.h"

/* Entries of a dense 3D support: GM_SUPPORT_3D_MAX_SPAN nodes per axis. */
#define GM_CPDI_3D_ENTRIES                                                     \
  (GM_SUPPORT_3D_MAX_SPAN * GM_SUPPORT_3D_MAX_SPAN * GM_SUPPORT_3D_MAX_SPAN)

typedef struct gm_cpdi_support_3d {
  int64_t lowest[3]; /* node index of the support's lower corner */
  int span[3];       /* nodes per axis */
  double weight[GM_CPDI_3D_ENTRIES];      /* -, S_i */
  double gradient[3][GM_CPDI_3D_ENTRIES]; /* 1/m, grad S_i */
} gm_cpdi_support_3d;

/* The eight corners (m) of the parallelepiped of centre x (m), domain map
 * D (f, row-major D_ij) and initial half edges half (m): corner c has
 * signs s_k = +1 where bit k of c is set, -1 where not, x_c = x + sum_k
 * s_k r_k, r_k = half_k (column k of D). */
void gm_cpdi_corners_3d(const double x[3], const double f[9],
                        const double half[3], double corners[8][3]);
/* The lowest node per axis of the support; false if a corner is not
 * finite, the corners' cells reach past the grid's nodes (ghost layer
 * included), or they span more than GM_SUPPORT_3D_MAX_SPAN nodes along an
 * axis. */
bool gm_cpdi_support_lowest_3d(const gm_shape_grid *grid, const double x[3],
                               const double f[9], const double half[3],
                               int64_t lowest[3]);
/* The lowest and highest node per axis; false as above (the granular
 * family's node boxes, components.c). */
bool gm_cpdi_support_bounds_3d(const gm_shape_grid *grid, const double x[3],
                               const double f[9], const double half[3],
                               int64_t lowest[3], int64_t highest[3]);
/* The whole support; false as gm_cpdi_support_lowest_3d, or where the
 * parallelepiped's volume 8 det[r1 r2 r3] is not positive and finite (out
 * is then undefined). */
bool gm_cpdi_support_compute_3d(const gm_shape_grid *grid, const double x[3],
                                const double f[9], const double half[3],
                                gm_cpdi_support_3d *out);

/* F (or CPDI's D, stored in the same slots) of point p, row-major, from
 * the nine SoA slots of core.h (F_XX, F_XY, F_YX, F_YY, F_ZZ, F_XZ, F_YZ,
 * F_ZX, F_ZY = 0..8). */
static inline void gm_deformation_rows_3d(const double *const deformation[9],
                                          size_t p, double f[9]) {
  static const int slot[9] = {0, 1, 5, 2, 3, 6, 7, 8, 4};
  for (int k = 0; k < 9; k++)
    f[k] = deformation[slot[k]][p];
}

/* The lowest node of point p's 3D support for every wide shape (CPDI's
 * parallelepiped, or the box of support_3d.h) from SoA arrays
 * (deformation: the slots gm_support_slots_3d gives, D for CPDI, F
 * otherwise); false as the support functions. */
static inline bool gm_wide_lowest_3d(const gm_shape_grid *grid,
                                     const double *const position[3],
                                     const double *const domain_size[3],
                                     const double *const deformation[9],
                                     size_t p, int64_t lowest[3]) {
  double x[3] = {position[0][p], position[1][p], position[2][p]}; /* m */
  double half[3];                                                 /* m */
  gm_box_half_edges_3d(grid->shape, domain_size, deformation, p, half);
  if (grid->shape != GM_SHAPE_CPDI)
    return gm_box_support_lowest_3d(grid, x, half, lowest);
  double f[9];
  gm_deformation_rows_3d(deformation, p, f);
  return gm_cpdi_support_lowest_3d(grid, x, f, half, lowest);
}

#endif
