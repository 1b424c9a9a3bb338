/*
 * support_cpdi.h - the CPDI1 support of a 2D point (Sadeghirad, Brannon &
 * Burghardt 2011; support.c says how the corners give the weights and
 * gradients) inline and straight-line: the corners x_c = x -+ r1 -+ r2 of
 * the parallelogram r_i = D r_i0, each corner's cell and its bilinear
 * fractions, and the corner gradients g_c = rot(x_{c+1} - x_{c-1}) / (2 V).
 * The same expressions in the same order as gm_cpdi_support_map and
 * gm_support_bounds (support.c) in 2D, the same tests in the same order,
 * so every bit and every refusal is theirs.
 *
 * Why: the general support goes through an out-of-line call that loops
 * over the dimension and the corner count and writes a structure read back
 * by the kernels, about 420 instructions per support, four times per point
 * and USL step (bench/results/2026-11-28-cpdi.md); here the dimension and
 * the corner count are constants and the reach per axis comes with it.
 */
#ifndef GM_SUPPORT_CPDI_H
#define GM_SUPPORT_CPDI_H

#include "shapes/pair.h"
#include "shapes/shape_gimp.h"
#include "shapes/support.h"

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

/* The corners (m) of the parallelogram of centre x, y, domain map D
 * (D_xx, D_xy, D_yx, D_yy) and initial half edges half_x, half_y (m),
 * counter-clockwise from the lower left (gm_point_domain_corners). */
static inline void gm_cpdi_corner_positions_2d(double x, double y, double d_xx,
                                               double d_xy, double d_yx,
                                               double d_yy, double half_x,
                                               double half_y,
                                               double corners[4][2]) {
  double r1[2] = {d_xx * half_x, d_yx * half_x}; /* m, D r1_0 */
  double r2[2] = {d_xy * half_y, d_yy * half_y}; /* m, D r2_0 */
  double position[2] = {x, y};
  for (int k = 0; k < 2; k++) { /* signs (-,-), (+,-), (+,+), (-,+) */
    corners[0][k] = position[k] + -1.0 * r1[k] + -1.0 * r2[k];
    corners[1][k] = position[k] + 1.0 * r1[k] + -1.0 * r2[k];
    corners[2][k] = position[k] + 1.0 * r1[k] + 1.0 * r2[k];
    corners[3][k] = position[k] + -1.0 * r1[k] + 1.0 * r2[k];
  }
}

/* The corner gradients g_c = rot(x_{c+1} - x_{c-1}) / (2 V) (1/m) of the
 * parallelogram with these corners; false where its area is not
 * positive (gm_cpdi_support_map refuses it). */
static inline bool gm_cpdi_corner_gradients_2d(double corners[4][2],
                                               double gradient[4][2]) {
  double e1[2] = {corners[1][0] - corners[0][0], corners[1][1] - corners[0][1]};
  double e2[2] = {corners[3][0] - corners[0][0], corners[3][1] - corners[0][1]};
  double area = e1[0] * e2[1] - e1[1] * e2[0]; /* m^2 */
  if (!(area > 0.0))
    return false;
  double inverse = 0.5 / area; /* 1 / (2 V), 1/m^2 */
  for (int c = 0; c < 4; c++) {
    const double *next = corners[(c + 1) & 3], *prev = corners[(c + 3) & 3];
#if defined(__GNUC__) /* the x and y differences as one pair */
    gm_pair to, from;
    memcpy(&to, next, sizeof to);
    memcpy(&from, prev, sizeof from);
    gm_pair edge = to - from; /* m */
    gm_pair g = (gm_pair){edge[1], -edge[0]} * inverse;
    memcpy(gradient[c], &g, sizeof g);
#else
    gradient[c][0] = (next[1] - prev[1]) * inverse;
    gradient[c][1] = -(next[0] - prev[0]) * inverse;
#endif
  }
  return true;
}

#if defined(__GNUC__)
/* gm_cpdi_corner_positions_2d's corners with x and y as one pair (its
 * expressions per lane, so its bits), their positions in cells from node
 * 0 and the extreme cells per axis as gm_cpdi_corners_2d takes them
 * (gm_pair_min and gm_pair_max: its selects per lane): half the
 * arithmetic and no minimum per axis. */
static inline void gm_cpdi_cells_pair_2d(const gm_shape_grid *grid, double x,
                                         double y, double d_xx, double d_xy,
                                         double d_yx, double d_yy,
                                         double half_x, double half_y,
                                         gm_pair corner[4], gm_pair cell[4],
                                         gm_pair *low, gm_pair *high) {
  gm_pair centre = {x, y};                             /* m */
  gm_pair r1 = {d_xx * half_x, d_yx * half_x};         /* m, D r1_0 */
  gm_pair r2 = {d_xy * half_y, d_yy * half_y};         /* m, D r2_0 */
  corner[0] = centre + -1.0 * r1 + -1.0 * r2;          /* signs (-,-) */
  corner[1] = centre + 1.0 * r1 + -1.0 * r2;           /* (+,-) */
  corner[2] = centre + 1.0 * r1 + 1.0 * r2;            /* (+,+) */
  corner[3] = centre + -1.0 * r1 + 1.0 * r2;           /* (-,+) */
  gm_pair origin = {grid->origin[0], grid->origin[1]}; /* m */
  for (int c = 0; c < 4; c++)
    cell[c] = (corner[c] - origin) * grid->inv_cell;
  *low = cell[0];
  *high = cell[0];
  for (int c = 1; c < 4; c++) {
    *low = gm_pair_min(cell[c], *low);
    *high = gm_pair_max(cell[c], *high);
  }
}
#endif

/* The corners (m) of the parallelogram of centre x, y, domain map D
 * (D_xx, D_xy, D_yx, D_yy) and initial half edges half_x, half_y (m),
 * counter-clockwise from the lower left (gm_point_domain_corners), and
 * their positions in cells from node 0; the lowest and highest node per
 * axis. False where gm_support_bounds refuses (a corner below the ghost
 * layer or past the last node, NaN, a span over GM_SUPPORT_MAX_SPAN). */
static inline bool gm_cpdi_corners_2d(const gm_shape_grid *grid, double x,
                                      double y, double d_xx, double d_xy,
                                      double d_yx, double d_yy, double half_x,
                                      double half_y, double corners[4][2],
                                      double cells[4][2], int64_t lowest[2],
                                      int64_t highest[2]) {
#if defined(__GNUC__)
  gm_pair corner[4], cell[4], low, high; /* m, cells */
  gm_cpdi_cells_pair_2d(grid, x, y, d_xx, d_xy, d_yx, d_yy, half_x, half_y,
                        corner, cell, &low, &high);
  for (int c = 0; c < 4; c++) {
    memcpy(corners[c], &corner[c], sizeof corner[c]);
    memcpy(cells[c], &cell[c], sizeof cell[c]);
  }
  for (int k = 0; k < 2; k++) {
    if (!(low[k] >= -1.0 && high[k] < (double)grid->last_node[k] + 1.0))
      return false; /* also catches NaN; keeps the casts in range */
    lowest[k] = gm_floor_index(low[k]);
    highest[k] = gm_floor_index(high[k]) + 1;
    if (lowest[k] < 0 || highest[k] > grid->last_node[k] ||
        highest[k] - lowest[k] + 1 > GM_SUPPORT_MAX_SPAN)
      return false; /* as bounds_valid */
  }
#else
  gm_cpdi_corner_positions_2d(x, y, d_xx, d_xy, d_yx, d_yy, half_x, half_y,
                              corners);
  for (int k = 0; k < 2; k++) {
    double origin = grid->origin[k], inv_cell = grid->inv_cell;
    for (int c = 0; c < 4; c++)
      cells[c][k] = (corners[c][k] - origin) * inv_cell;
    /* Not fmin/fmax (see support.c); a NaN corner other than the first
     * is skipped here as there. */
    double low = cells[0][k], high = cells[0][k];
    for (int c = 1; c < 4; c++) {
      low = cells[c][k] < low ? cells[c][k] : low;
      high = cells[c][k] > high ? cells[c][k] : high;
    }
    if (!(low >= -1.0 && high < (double)grid->last_node[k] + 1.0))
      return false; /* also catches NaN; keeps the casts in range */
    lowest[k] = gm_floor_index(low);
    highest[k] = gm_floor_index(high) + 1;
    if (lowest[k] < 0 || highest[k] > grid->last_node[k] ||
        highest[k] - lowest[k] + 1 > GM_SUPPORT_MAX_SPAN)
      return false; /* as bounds_valid */
  }
#endif
  return true;
}

/* Only the lowest node per axis of such a point and gm_cpdi_corners_2d's
 * answer (the block keys need no more): its tests on the highest node
 * without the highest node's floor. The corners' extreme cell high is
 * finite and below last + 1 once the first test passes, so (floor
 * monotonic, last and lowest integers) floor(high) + 1 > last exactly
 * where high >= last, and floor(high) + 2 - lowest > GM_SUPPORT_MAX_SPAN
 * exactly where high >= lowest + GM_SUPPORT_MAX_SPAN - 1. */
static inline bool gm_cpdi_lowest_2d(const gm_shape_grid *grid, double x,
                                     double y, double d_xx, double d_xy,
                                     double d_yx, double d_yy, double half_x,
                                     double half_y, int64_t lowest[2]) {
#if defined(__GNUC__)
  gm_pair corner[4], cell[4], low, high; /* m, cells */
  gm_cpdi_cells_pair_2d(grid, x, y, d_xx, d_xy, d_yx, d_yy, half_x, half_y,
                        corner, cell, &low, &high);
  for (int k = 0; k < 2; k++) {
    double last = (double)grid->last_node[k];
    if (!(low[k] >= -1.0 && high[k] < last + 1.0))
      return false;
    lowest[k] = gm_floor_index(low[k]);
    if (lowest[k] < 0 || high[k] >= last ||
        high[k] >= (double)(lowest[k] + GM_SUPPORT_MAX_SPAN - 1))
      return false;
  }
#else
  double corners[4][2];
  gm_cpdi_corner_positions_2d(x, y, d_xx, d_xy, d_yx, d_yy, half_x, half_y,
                              corners);
  for (int k = 0; k < 2; k++) {
    double origin = grid->origin[k], inv_cell = grid->inv_cell;
    double cells[4]; /* cells from node 0 */
    for (int c = 0; c < 4; c++)
      cells[c] = (corners[c][k] - origin) * inv_cell;
    double low = cells[0], high = cells[0]; /* as gm_cpdi_corners_2d */
    for (int c = 1; c < 4; c++) {
      low = cells[c] < low ? cells[c] : low;
      high = cells[c] > high ? cells[c] : high;
    }
    double last = (double)grid->last_node[k];
    if (!(low >= -1.0 && high < last + 1.0))
      return false;
    lowest[k] = gm_floor_index(low);
    if (lowest[k] < 0 || high >= last ||
        high >= (double)(lowest[k] + GM_SUPPORT_MAX_SPAN - 1))
      return false;
  }
#endif
  return true;
}

/* The whole support of such a point (gm_cpdi_support, corner_count 4,
 * share 1/4), and the reach per axis (the farthest node past lowest that
 * a corner's cell touches, as gm_wide_point_support takes it). False
 * where gm_cpdi_support_map refuses (the bounds above, or an area that is
 * not positive). */
static inline bool gm_cpdi_support_2d(const gm_shape_grid *grid, double x,
                                      double y, double d_xx, double d_xy,
                                      double d_yx, double d_yy, double half_x,
                                      double half_y, gm_cpdi_support *out,
                                      int64_t reach[2]) {
  double corners[4][2], cells[4][2];
  int64_t highest[2];
  if (!gm_cpdi_corners_2d(grid, x, y, d_xx, d_xy, d_yx, d_yy, half_x, half_y,
                          corners, cells, out->lowest, highest))
    return false;
  if (!gm_cpdi_corner_gradients_2d(corners, out->corner_gradient))
    return false;
  out->corner_count = 4;
  out->share = 0.25;
  for (int c = 0; c < 4; c++) {
    for (int k = 0; k < 2; k++) {
      int64_t cell = gm_floor_index(cells[c][k]);
      double fraction = cells[c][k] - (double)cell;
      out->cell[c][k] = cell;
      out->axis[c][k][0] = 1.0 - fraction;
      out->axis[c][k][1] = fraction;
    }
  }
  /* The farthest corner cell's upper node: floor is monotonic, so the
   * largest floor of the corners is the floor of the largest, highest - 1. */
  reach[0] = highest[0] - out->lowest[0];
  reach[1] = highest[1] - out->lowest[1];
  return true;
}

/* The support of point p from SoA arrays (map: the domain map D), as
 * gm_wide_cpdi_support in 2D. */
static inline bool gm_cpdi_point_support_2d(const gm_shape_grid *grid,
                                            const double *const position[2],
                                            const double *const map[4],
                                            const double *const domain_size[2],
                                            size_t p, gm_cpdi_support *out,
                                            int64_t reach[2]) {
  return gm_cpdi_support_2d(
      grid, position[0][p], position[1][p], map[0][p], map[1][p], map[2][p],
      map[3][p], 0.5 * domain_size[0][p], 0.5 * domain_size[1][p], out, reach);
}

#endif
