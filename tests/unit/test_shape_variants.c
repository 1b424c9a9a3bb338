/*
 * test_shape_variants.c - white-box test of the supports of every shape
 * variant (lib/shapes/support.c, lib/shapes/shape_gimp.h): linear MPM, uGIMP,
 * cpGIMP and CPDI1, in 1D and 2D, at thousands of random points with random
 * domains and deformation gradients.
 *
 * Checked against the variants' defining properties (000 sec 2.1):
 * partition of unity, zero-sum gradients, exact reproduction of linear
 * fields, weights in [0, 1]; and node by node against references computed
 * here independently, in metres, from the tent functions:
 *  - GIMP weight: the average of the tent over the domain, by piecewise
 *    2-point Gauss-Legendre quadrature split at the tent's kinks and the
 *    domain ends (exact: the tent is linear on each piece); GIMP gradient:
 *    (N_i(x + l) - N_i(x - l)) / (2 l), and a central finite difference of
 *    the library's own weights;
 *  - uGIMP in 1D also against the closed form 004 eq 3.27;
 *  - CPDI: the average over the parallelogram of the bilinear interpolant
 *    of the corner values N_i(x_c) and of its gradient, by 2 x 2 Gauss
 *    points in the parallelogram's parametric coordinates (the interpolant
 *    is bilinear there and its gradient linear: exact).
 * Also the support bounds at the ghost layer and at the span limit, and the
 * uGIMP limit l -> 0 (the tent); and the inline 2D CPDI support the
 * kernels take (support_cpdi.h) against the general one, bit for bit,
 * refusals included.
 *
 * The grid has a non-zero origin and a cell size that is not a power of two
 * (0.37 m) so that the rounding in (x - origin) / h is exercised.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "shapes/shape_gimp.h"
#include "shapes/support.h"
#include "shapes/support_cpdi.h"

#include "test_random.h"
#include "test_util.h"

#include <check.h>
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The box: lower corner (m), cell edge (m), cells per axis. */
static const double box_origin[2] = {-1.3, 2.1};
static const double cell_size = 0.37;
static const int64_t cell_count[2] = {27, 19};
enum {
  SAMPLE_COUNT = 4000, /* random points per variant and dimension */
  WINDOW = 14          /* nodes per axis compared around a point */
};

static const gm_shape all_shapes[4] = {GM_SHAPE_LINEAR, GM_SHAPE_UGIMP,
                                       GM_SHAPE_CPGIMP, GM_SHAPE_CPDI};

static bool is_gimp(gm_shape shape) {
  return shape == GM_SHAPE_UGIMP || shape == GM_SHAPE_CPGIMP;
}

/* The grid as the library builds it (domain.c): node 0 one ghost layer
 * below the box, last node one ghost layer above it. */
static gm_shape_grid make_grid(gm_shape shape, int dim) {
  gm_shape_grid grid;
  memset(&grid, 0, sizeof grid);
  grid.shape = shape;
  grid.dim = dim;
  grid.inv_cell = 1.0 / cell_size;
  for (int k = 0; k < dim; k++) {
    grid.origin[k] = box_origin[k] - GM_GHOST_LAYERS * cell_size;
    grid.last_node[k] = cell_count[k] + 2 * GM_GHOST_LAYERS;
  }
  return grid;
}

/* Coordinate (m) of node `node` (counted from the ghost node 0), computed
 * from the box corner rather than from grid.origin. */
static double node_coordinate(int axis, int64_t node) {
  return box_origin[axis] + (double)(node - GM_GHOST_LAYERS) * cell_size;
}

/* Largest grid extent (m): the scale for position errors. */
static double grid_extent(void) {
  return (double)(cell_count[0] + 2 * GM_GHOST_LAYERS) * cell_size;
}

/* ------------------------------------------------------ the domain shape */

/* Half edge vectors r1, r2 (m) of the current domain, written here from
 * the definitions of gm_shape (not from support.c). Linear MPM has no
 * domain as far as its support is concerned: r1 = r2 = 0. */
static void half_edges(gm_shape shape, int dim, const gm_point_domain *point,
                       double r1[2], double r2[2]) {
  const double *f = point->deformation; /* F_xx, F_xy, F_yx, F_yy */
  double lx = point->half_size[0], ly = dim > 1 ? point->half_size[1] : 0.0;
  r1[0] = r1[1] = r2[0] = r2[1] = 0.0;
  if (shape == GM_SHAPE_UGIMP) {
    r1[0] = lx;
    r2[1] = ly;
  } else if (shape == GM_SHAPE_CPGIMP) {
    r1[0] = fabs(f[0]) * lx;
    r2[1] = fabs(f[3]) * ly;
  } else if (shape == GM_SHAPE_CPDI) {
    r1[0] = f[0] * lx;
    r1[1] = dim > 1 ? f[2] * lx : 0.0;
    r2[0] = dim > 1 ? f[1] * ly : 0.0;
    r2[1] = f[3] * ly;
  }
}

/* How far (m) the domain reaches from its centre along each axis. */
static void domain_reach(gm_shape shape, int dim, const gm_point_domain *point,
                         double reach[2]) {
  double r1[2], r2[2];
  half_edges(shape, dim, point, r1, r2);
  for (int k = 0; k < 2; k++)
    reach[k] = fabs(r1[k]) + fabs(r2[k]);
}

/* F = R(theta) [[a, g], [0, b]]: stretches a, b in [0.5, 2], shear g in
 * [-0.5, 0.5], rotation up to 60 degrees, so det F = a b > 0. F_xx and F_yy
 * are kept >= 0.25 in magnitude: cpGIMP's half-lengths are |F_kk| l0, and
 * the limit of a vanishing half-length is tested on its own below. In 1D
 * only F_xx = a counts; the other entries get values the 1D code must
 * ignore. */
static void random_deformation(int dim, double f[4]) {
  do {
    double a = lcg_between(0.5, 2.0), b = lcg_between(0.5, 2.0);
    double g = lcg_between(-0.5, 0.5);
    const double sixty_degrees = 1.0471975511965976; /* rad, pi / 3 */
    double theta = lcg_between(-sixty_degrees, sixty_degrees);
    double c = cos(theta), s = sin(theta);
    f[0] = c * a;
    f[1] = c * g - s * b;
    f[2] = s * a;
    f[3] = s * g + c * b;
    if (dim == 1) {
      f[0] = a;
      f[1] = f[2] = 7.0;
      f[3] = -3.0;
      return;
    }
  } while (fabs(f[0]) < 0.25 || fabs(f[3]) < 0.25);
}

/* A random point whose domain lies within the nodes of the grid (ghost
 * layer included), so the support must exist. */
static void random_point(gm_shape shape, int dim, gm_point_domain *point) {
  memset(point, 0, sizeof *point);
  random_deformation(dim, point->deformation);
  for (int k = 0; k < dim; k++) /* initial half edges 0.05 h .. 0.5 h */
    point->half_size[k] = lcg_between(0.05, 0.5) * cell_size;
  double reach[2];
  domain_reach(shape, dim, point, reach);
  gm_shape_grid grid = make_grid(shape, dim);
  for (int k = 0; k < dim; k++) {
    double low = grid.origin[k] + reach[k] + 1e-9 * cell_size; /* m */
    double high = grid.origin[k] + (double)grid.last_node[k] * cell_size -
                  reach[k] - 1e-9 * cell_size;
    REQUIRE(low < high, "domain reach %g m leaves no room", reach[k]);
    point->position[k] = lcg_between(low, high);
  }
}

/* --------------------------------------------------- node-value windows */

/* Weights and gradients of the nodes base .. base + WINDOW - 1 per axis
 * (only row y = 0 in 1D). */
typedef struct node_values {
  int64_t base[2];
  double weight[WINDOW][WINDOW];      /* [x][y] */
  double gradient[2][WINDOW][WINDOW]; /* 1/m */
} node_values;

/* A window that holds every node the point can reach, with two spare
 * nodes on each side so that stray weights outside the support show. */
static void window_around(gm_shape shape, int dim, const gm_point_domain *point,
                          node_values *values) {
  memset(values, 0, sizeof *values);
  double reach[2];
  domain_reach(shape, dim, point, reach);
  for (int k = 0; k < dim; k++) {
    double low = point->position[k] - reach[k] - node_coordinate(k, 0);
    values->base[k] = (int64_t)floor(low / cell_size) - 2;
    REQUIRE(2.0 * reach[k] / cell_size < WINDOW - 6, "window too small");
  }
}

/* The library's support, summed per node into the window (CPDI repeats
 * nodes across corners). */
static void library_values(const gm_shape_grid *grid,
                           const gm_point_domain *point, gm_support *support,
                           node_values *values) {
  REQUIRE(gm_support_compute(grid, point, support),
          "support refused for a domain inside the grid at (%g, %g)",
          point->position[0], point->position[1]);
  for (int e = 0; e < support->count; e++) {
    int64_t at[2];
    for (int k = 0; k < 2; k++)
      at[k] = support->lowest[k] + support->offset[k][e] - values->base[k];
    REQUIRE(at[0] >= 0 && at[0] < WINDOW && at[1] >= 0 && at[1] < WINDOW,
            "support node outside the window");
    values->weight[at[0]][at[1]] += support->weight[e];
    for (int k = 0; k < 2; k++)
      values->gradient[k][at[0]][at[1]] += support->gradient[k][e];
  }
}

/* ------------------------------------------------------------ references */

/* Tent N_i(x) of node `node` along `axis` (x in m). */
static double tent(int axis, int64_t node, double x) {
  return fmax(0.0, 1.0 - fabs(x - node_coordinate(axis, node)) / cell_size);
}

/* Its slope (1/m) at x, away from the kinks. */
static double tent_slope(int axis, int64_t node, double x) {
  double offset = x - node_coordinate(axis, node); /* m */
  if (fabs(offset) >= cell_size)
    return 0.0;
  return offset < 0.0 ? 1.0 / cell_size : -1.0 / cell_size;
}

/* (1 / (upper - lower)) * integral of N_i over [lower, upper] (m): 2-point
 * Gauss-Legendre on each piece between the domain ends and the tent's
 * kinks, exact because the tent is linear on each piece. */
static double tent_average(int axis, int64_t node, double lower, double upper) {
  double centre = node_coordinate(axis, node);
  double cuts[5] = {lower}; /* m */
  int cut_count = 1;
  const double kinks[3] = {centre - cell_size, centre, centre + cell_size};
  for (int j = 0; j < 3; j++)
    if (kinks[j] > lower && kinks[j] < upper)
      cuts[cut_count++] = kinks[j];
  cuts[cut_count++] = upper;
  const double gauss = 1.0 / sqrt(3.0); /* abscissa on [-1, 1], weight 1 */
  double integral = 0.0;                /* m */
  for (int j = 0; j + 1 < cut_count; j++) {
    double middle = 0.5 * (cuts[j] + cuts[j + 1]);
    double half = 0.5 * (cuts[j + 1] - cuts[j]);
    integral += half * (tent(axis, node, middle - gauss * half) +
                        tent(axis, node, middle + gauss * half));
  }
  return integral / (upper - lower);
}

/* Weight and gradient (1/m) of node `node` along one axis for the tensor
 * product variants; half_length in m (0 for linear MPM). */
static void axis_reference(gm_shape shape, int axis, int64_t node, double x,
                           double half_length, double *weight,
                           double *gradient) {
  if (shape == GM_SHAPE_LINEAR) {
    *weight = tent(axis, node, x);
    *gradient = tent_slope(axis, node, x);
    return;
  }
  *weight = tent_average(axis, node, x - half_length, x + half_length);
  *gradient =
      (tent(axis, node, x + half_length) - tent(axis, node, x - half_length)) /
      (2.0 * half_length);
}

static void tensor_reference(gm_shape shape, int dim,
                             const gm_point_domain *point,
                             node_values *values) {
  double r1[2], r2[2];
  half_edges(shape, dim, point, r1, r2);
  double half[2] = {r1[0], r2[1]}; /* m */
  double weight[2][WINDOW] = {{0.0}}, gradient[2][WINDOW] = {{0.0}};
  weight[1][0] = 1.0; /* 1D: the single row y = 0 */
  for (int k = 0; k < dim; k++)
    for (int n = 0; n < WINDOW; n++)
      axis_reference(shape, k, values->base[k] + n, point->position[k], half[k],
                     &weight[k][n], &gradient[k][n]);
  for (int a = 0; a < WINDOW; a++) {
    for (int b = 0; b < WINDOW; b++) {
      values->weight[a][b] = weight[0][a] * weight[1][b];
      values->gradient[0][a][b] = gradient[0][a] * weight[1][b];
      values->gradient[1][a][b] = weight[0][a] * gradient[1][b];
    }
  }
}

/* CPDI in 2D: the parallelogram x(xi, eta) = x_p + xi r1 + eta r2 with
 * xi, eta in [-1, 1]; the interpolant f = sum_c N_i(x_c) phi_c with the
 * bilinear phi_c = (1 + xi_c xi)(1 + eta_c eta) / 4. Its average is
 * (1/4) integral f dxi deta, and the average of its gradient is
 * (1/4) integral J^-T grad_(xi, eta) f dxi deta with J = [r1 r2]. */
static void cpdi_reference_2d(const gm_point_domain *point, const double r1[2],
                              const double r2[2], int64_t node_x,
                              int64_t node_y, double *weight,
                              double gradient[2]) {
  static const double xi_c[4] = {-1.0, 1.0, 1.0, -1.0};
  static const double eta_c[4] = {-1.0, -1.0, 1.0, 1.0};
  double corner_value[4];
  for (int c = 0; c < 4; c++) {
    double x = point->position[0] + xi_c[c] * r1[0] + eta_c[c] * r2[0];
    double y = point->position[1] + xi_c[c] * r1[1] + eta_c[c] * r2[1];
    corner_value[c] = tent(0, node_x, x) * tent(1, node_y, y);
  }
  double jacobian = r1[0] * r2[1] - r2[0] * r1[1]; /* m^2 */
  const double gauss = 1.0 / sqrt(3.0);
  *weight = gradient[0] = gradient[1] = 0.0;
  for (int q = 0; q < 4; q++) { /* 2 x 2 Gauss points, weights 1 */
    double xi = xi_c[q] * gauss, eta = eta_c[q] * gauss;
    double value = 0.0, d_xi = 0.0, d_eta = 0.0;
    for (int c = 0; c < 4; c++) {
      value += corner_value[c] * (1 + xi_c[c] * xi) * (1 + eta_c[c] * eta);
      d_xi += corner_value[c] * xi_c[c] * (1 + eta_c[c] * eta);
      d_eta += corner_value[c] * (1 + xi_c[c] * xi) * eta_c[c];
    }
    *weight += 0.25 * 0.25 * value; /* 1/4 of the area, 1/4 of phi */
    gradient[0] += 0.25 * 0.25 * (r2[1] * d_xi - r1[1] * d_eta) / jacobian;
    gradient[1] += 0.25 * 0.25 * (-r2[0] * d_xi + r1[0] * d_eta) / jacobian;
  }
}

static void cpdi_reference(int dim, const gm_point_domain *point,
                           node_values *values) {
  double r1[2], r2[2];
  half_edges(GM_SHAPE_CPDI, dim, point, r1, r2);
  for (int a = 0; a < WINDOW; a++) {
    int64_t node_x = values->base[0] + a;
    if (dim == 1) { /* the segment [x - r, x + r]: linear interpolant */
      double low = tent(0, node_x, point->position[0] - r1[0]);
      double high = tent(0, node_x, point->position[0] + r1[0]);
      values->weight[a][0] = 0.5 * (low + high);
      values->gradient[0][a][0] = (high - low) / (2.0 * r1[0]);
      continue;
    }
    for (int b = 0; b < WINDOW; b++) {
      double gradient[2];
      cpdi_reference_2d(point, r1, r2, node_x, values->base[1] + b,
                        &values->weight[a][b], gradient);
      values->gradient[0][a][b] = gradient[0];
      values->gradient[1][a][b] = gradient[1];
    }
  }
}

static void reference_values(gm_shape shape, int dim,
                             const gm_point_domain *point,
                             node_values *values) {
  if (shape == GM_SHAPE_CPDI)
    cpdi_reference(dim, point, values);
  else
    tensor_reference(shape, dim, point, values);
}

/* ----------------------------------------------------------- tolerances */

/* Rounding bounds of one sample, dimensionless: `weight` for weights and
 * their sums, `gradient` for gradients times h. */
typedef struct tolerances {
  double weight;
  double gradient;
} tolerances;

/* Largest |g_c| (1/m) of the CPDI corner gradients, 000 sec 2.1: the
 * diagonal across a corner over twice the area (2D), 1 / (2 r) in 1D. */
static double cpdi_corner_gradient(int dim, const gm_point_domain *point) {
  double r1[2], r2[2];
  half_edges(GM_SHAPE_CPDI, dim, point, r1, r2);
  if (dim == 1)
    return 1.0 / (2.0 * r1[0]);
  double area = 4.0 * fabs(r1[0] * r2[1] - r2[0] * r1[1]); /* m^2 */
  double diagonal = 2.0 * fmax(hypot(r1[0] + r2[0], r1[1] + r2[1]),
                               hypot(r1[0] - r2[0], r1[1] - r2[1])); /* m */
  return diagonal / (2.0 * area);
}

/* Where the rounding comes from. Positions enter as s = (x - origin) / h,
 * cells from node 0, rounded to eps * s_max / 2 with s_max ~ 30 here.
 *  - GIMP weights are differences of the tent's antiderivative at s + l
 *    and s - l: the rounding of s +- l and of the antiderivative values
 *    (a few eps each, two per node, up to ~10 nodes) is divided by 2 l
 *    (cells). About 35 eps / l per axis; 64 eps / l is the bound. The
 *    gradients, tent differences over 2 l, share it.
 *  - Linear MPM and CPDI weights are products of fractions in [0, 1]: a
 *    few eps, under the 1e-14 floor. CPDI gradients sum corner values
 *    N_i(x_c), each off by ~2 eps * s_max, times |g_c|: with four corners
 *    and both sides (library and reference) that is 16 eps s_max h |g_c|.
 *  - The floors, 1e-14 and 1e-12, are many ulps above what remains, and
 *    far below a real error, which would be of order 1 (a wrong node, a
 *    wrong formula) or at least of order l / h (a wrong domain edge). */
static tolerances sample_tolerances(gm_shape shape, int dim,
                                    const gm_point_domain *point) {
  tolerances tolerance = {1e-14, 0.0};
  double s_max = (double)(cell_count[0] + 2 * GM_GHOST_LAYERS); /* cells */
  if (is_gimp(shape)) {
    double r1[2], r2[2];
    half_edges(shape, dim, point, r1, r2);
    double half[2] = {r1[0], r2[1]}; /* m */
    for (int k = 0; k < dim; k++)
      tolerance.weight += 64.0 * DBL_EPSILON * cell_size / half[k];
  }
  tolerance.gradient = 1e-12 + 10.0 * tolerance.weight;
  if (shape == GM_SHAPE_CPDI)
    tolerance.gradient += 16.0 * DBL_EPSILON * s_max * cell_size *
                          cpdi_corner_gradient(dim, point);
  return tolerance;
}

/* ------------------------------------------------------ the checks proper */

/* Partition of unity, zero-sum gradients, weights in [0, 1]. */
static void check_sums(const gm_support *support, tolerances tolerance,
                       const char *label) {
  double sum = 0.0, gradient_sum[2] = {0.0, 0.0};
  for (int e = 0; e < support->count; e++) {
    /* Every computed weight is a difference of a monotone function or a
     * product of fractions in [0, 1]: no tolerance is needed. */
    REQUIRE(support->weight[e] >= 0.0 && support->weight[e] <= 1.0,
            "%s: weight %d is %.17g", label, e, support->weight[e]);
    sum += support->weight[e];
    gradient_sum[0] += support->gradient[0][e];
    gradient_sum[1] += support->gradient[1][e];
  }
  REQUIRE(fabs(sum - 1.0) <= tolerance.weight, "%s: sum of weights - 1 = %.3g",
          label, sum - 1.0);
  /* The terms are up to ~20 / h; they cancel to their rounding. */
  for (int k = 0; k < 2; k++)
    REQUIRE(fabs(gradient_sum[k]) * cell_size <= tolerance.gradient,
            "%s: sum of gradients %d * h = %.3g", label, k,
            gradient_sum[k] * cell_size);
}

/* Linear completeness: sum w_i x_i = x_p and sum x_i (x) grad w_i = I. */
static void check_linear_fields(const gm_support *support, int dim,
                                const gm_point_domain *point,
                                tolerances tolerance, const char *label) {
  double moment[2] = {0.0, 0.0};                    /* m */
  double identity[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; /* [coordinate][d/dk] */
  for (int e = 0; e < support->count; e++) {
    for (int j = 0; j < dim; j++) {
      double x = node_coordinate(j, support->lowest[j] + support->offset[j][e]);
      moment[j] += support->weight[e] * x;
      for (int k = 0; k < 2; k++)
        identity[j][k] += x * support->gradient[k][e];
    }
  }
  for (int j = 0; j < dim; j++) {
    /* Coordinates up to ~11 m, weights off by tolerance.weight in all. */
    REQUIRE(fabs(moment[j] - point->position[j]) <=
                grid_extent() * tolerance.weight,
            "%s: sum w x - x_p = %.3g m on axis %d", label,
            moment[j] - point->position[j], j);
    /* Terms x_i grad w_i reach 11 m * 20 / h ~ 600 and cancel to 1; the
     * errors are those of the gradients (GIMP: of s +- l; CPDI: of the
     * interpolated corners) times about one. */
    for (int k = 0; k < dim; k++)
      REQUIRE(fabs(identity[j][k] - (j == k ? 1.0 : 0.0)) <=
                  2.0 * tolerance.gradient,
              "%s: sum x_%d d w/d x_%d = %.17g", label, j, k, identity[j][k]);
  }
}

/* Node by node against the reference, over the whole window: a node the
 * library leaves out but the reference weights shows up too. The
 * quadratures are exact, so both sides carry only rounding. */
static void check_against_reference(const node_values *library,
                                    const node_values *reference, int dim,
                                    tolerances tolerance, const char *label) {
  int rows = dim > 1 ? WINDOW : 1;
  for (int a = 0; a < WINDOW; a++) {
    for (int b = 0; b < rows; b++) {
      long long node_x = (long long)(library->base[0] + a);
      long long node_y = (long long)(library->base[1] + b);
      /* The weight floor is 1e-12, not 1e-14: the reference adds a few
       * quadrature pieces of up to ~1 each. */
      REQUIRE(fabs(library->weight[a][b] - reference->weight[a][b]) <=
                  1e-12 + 10.0 * tolerance.weight,
              "%s: node (%lld, %lld) weight %.17g, reference %.17g", label,
              node_x, node_y, library->weight[a][b], reference->weight[a][b]);
      for (int k = 0; k < dim; k++) {
        double difference =
            library->gradient[k][a][b] - reference->gradient[k][a][b]; /* 1/m */
        REQUIRE(fabs(difference) * cell_size <= tolerance.gradient,
                "%s: node (%lld, %lld) gradient %d %.17g, reference %.17g",
                label, node_x, node_y, k, library->gradient[k][a][b],
                reference->gradient[k][a][b]);
      }
    }
  }
}

/* gm_support_bounds agrees with the computed support, and every node with
 * a reference weight or gradient lies within the bounds. */
static void check_bounds(const gm_shape_grid *grid,
                         const gm_point_domain *point,
                         const gm_support *support,
                         const node_values *reference, const char *label) {
  int64_t lowest[2], highest[2];
  REQUIRE(gm_support_bounds(grid, point, lowest, highest), "%s: bounds refused",
          label);
  int rows = grid->dim > 1 ? WINDOW : 1;
  for (int k = 0; k < 2; k++)
    REQUIRE(lowest[k] == support->lowest[k], "%s: lowest differs", label);
  for (int e = 0; e < support->count; e++)
    for (int k = 0; k < 2; k++)
      REQUIRE(support->lowest[k] + support->offset[k][e] <= highest[k],
              "%s: entry %d above the highest node", label, e);
  for (int a = 0; a < WINDOW; a++) {
    for (int b = 0; b < rows; b++) {
      double magnitude = fabs(reference->weight[a][b]) +
                         fabs(reference->gradient[0][a][b]) * cell_size +
                         fabs(reference->gradient[1][a][b]) * cell_size;
      if (magnitude <= 1e-12) /* zero up to the reference's rounding */
        continue;
      int64_t node[2] = {reference->base[0] + a, reference->base[1] + b};
      for (int k = 0; k < grid->dim; k++)
        REQUIRE(node[k] >= lowest[k] && node[k] <= highest[k],
                "%s: node %lld on axis %d carries %.3g outside the "
                "bounds %lld .. %lld",
                label, (long long)node[k], k, magnitude, (long long)lowest[k],
                (long long)highest[k]);
    }
  }
}

/* The domain's area from gm_point_domain_corners (shoelace) against
 * 4 l_x l_y times det F (CPDI), |F_xx F_yy| (cpGIMP) or 1. */
static void check_corner_area(gm_shape shape, const gm_point_domain *point,
                              const char *label) {
  double corners[4][2];
  gm_point_domain_corners(shape, 2, point, corners);
  double area = 0.0; /* m^2, triangles fanned from corner 0 */
  for (int c = 1; c + 1 < 4; c++) {
    double a[2] = {corners[c][0] - corners[0][0],
                   corners[c][1] - corners[0][1]};
    double b[2] = {corners[c + 1][0] - corners[0][0],
                   corners[c + 1][1] - corners[0][1]};
    area += 0.5 * (a[0] * b[1] - a[1] * b[0]);
  }
  const double *f = point->deformation;
  double factor = 1.0;
  if (shape == GM_SHAPE_CPDI)
    factor = f[0] * f[3] - f[1] * f[2];
  else if (shape == GM_SHAPE_CPGIMP)
    factor = fabs(f[0] * f[3]);
  double expected = 4.0 * point->half_size[0] * point->half_size[1] * factor;
  /* The corners are positions of up to ~11 m, rounded to ~1e-15 m, against
   * edges of 0.005 m and more: edge vectors, and so the area, are good to
   * ~1e-12 relative at worst. A positive area also means the corners run
   * counter-clockwise. */
  REQUIRE(fabs(area - expected) <= 1e-11 * expected,
          "%s: corner area %.17g m^2, expected %.17g", label, area, expected);
}

static void check_variant(gm_shape shape, int dim, uint64_t seed) {
  char label[64];
  lcg_state = seed;
  gm_shape_grid grid = make_grid(shape, dim);
  for (int s = 0; s < SAMPLE_COUNT; s++) {
    snprintf(label, sizeof label, "shape %d, %dD, sample %d", (int)shape, dim,
             s);
    gm_point_domain point;
    random_point(shape, dim, &point);
    node_values library, reference;
    window_around(shape, dim, &point, &library);
    window_around(shape, dim, &point, &reference);
    gm_support support;
    library_values(&grid, &point, &support, &library);
    reference_values(shape, dim, &point, &reference);
    tolerances tolerance = sample_tolerances(shape, dim, &point);
    check_sums(&support, tolerance, label);
    check_linear_fields(&support, dim, &point, tolerance, label);
    check_against_reference(&library, &reference, dim, tolerance, label);
    check_bounds(&grid, &point, &support, &reference, label);
    if (dim == 2)
      check_corner_area(shape, &point, label);
    if (dim == 1)
      for (int e = 0; e < support.count; e++)
        REQUIRE(support.gradient[1][e] == 0.0, "%s: 1D y gradient", label);
  }
}

START_TEST(test_random_points) {
  gm_shape shape = all_shapes[_i / 2];
  int dim = 1 + _i % 2;
  check_variant(shape, dim, 1000u + (uint64_t)_i);
}
END_TEST

/* GIMP: the gradient is the derivative of the weight with respect to the
 * point's position (Bardenhagen & Kober 2004), checked by central
 * differences of the library's own weights. */
static void check_gimp_derivative(gm_shape shape, int dim,
                                  const gm_point_domain *point,
                                  const char *label) {
  gm_shape_grid grid = make_grid(shape, dim);
  const double step = 1e-6 * cell_size; /* m */
  node_values centre;
  window_around(shape, dim, point, &centre);
  gm_support support;
  library_values(&grid, point, &support, &centre);
  double r1[2], r2[2];
  half_edges(shape, dim, point, r1, r2);
  double shortest = dim > 1 ? fmin(r1[0], r2[1]) : r1[0]; /* m */
  /* The weight is piecewise quadratic in x_p with |w''| <= 1 / (l h): the
   * central difference is exact on a quadratic and off by at most
   * step / (l h) where a kink falls within the step; the rounding of the
   * weights (sample_tolerances) is divided by the step. */
  double tolerance =
      step / shortest +
      2.0 * sample_tolerances(shape, dim, point).weight * cell_size / step;
  for (int k = 0; k < dim; k++) {
    node_values plus = centre, minus = centre;
    memset(plus.weight, 0, sizeof plus.weight);
    memset(minus.weight, 0, sizeof minus.weight);
    gm_point_domain moved = *point;
    moved.position[k] = point->position[k] + step;
    library_values(&grid, &moved, &support, &plus);
    moved.position[k] = point->position[k] - step;
    library_values(&grid, &moved, &support, &minus);
    for (int a = 0; a < WINDOW; a++) {
      for (int b = 0; b < (dim > 1 ? WINDOW : 1); b++) {
        double slope = (plus.weight[a][b] - minus.weight[a][b]) / (2 * step);
        REQUIRE(fabs(slope - centre.gradient[k][a][b]) * cell_size <= tolerance,
                "%s: d w / d x_%d by differences %.17g, gradient %.17g", label,
                k, slope, centre.gradient[k][a][b]);
      }
    }
  }
}

START_TEST(test_gimp_gradient_is_weight_derivative) {
  gm_shape shape = _i / 2 ? GM_SHAPE_CPGIMP : GM_SHAPE_UGIMP;
  int dim = 1 + _i % 2;
  lcg_state = 31u + (uint64_t)_i;
  char label[64];
  for (int s = 0; s < SAMPLE_COUNT / 4; s++) {
    snprintf(label, sizeof label, "shape %d, %dD, sample %d", (int)shape, dim,
             s);
    gm_point_domain point;
    random_point(shape, dim, &point);
    point.position[0] = fmin(point.position[0], 5.0); /* room for +-step */
    check_gimp_derivative(shape, dim, &point, label);
  }
}
END_TEST

/* 004 eq 3.27: the uGIMP weight of a node at distance x from the point,
 * with particle length lp = 2 l <= h. */
static double closed_form_gimp(double x, double lp) {
  double h = cell_size, distance = fabs(x);
  if (distance < 0.5 * lp)
    return 1.0 - (4.0 * x * x + lp * lp) / (4.0 * h * lp);
  if (distance < h - 0.5 * lp)
    return 1.0 - distance / h;
  if (distance < h + 0.5 * lp)
    return (h + 0.5 * lp - distance) * (h + 0.5 * lp - distance) /
           (2.0 * h * lp);
  return 0.0;
}

START_TEST(test_ugimp_closed_form) {
  lcg_state = 8080;
  gm_shape_grid grid = make_grid(GM_SHAPE_UGIMP, 1);
  for (int s = 0; s < SAMPLE_COUNT; s++) {
    gm_point_domain point;
    random_point(GM_SHAPE_UGIMP, 1, &point);
    node_values library;
    window_around(GM_SHAPE_UGIMP, 1, &point, &library);
    gm_support support;
    library_values(&grid, &point, &support, &library);
    double lp = 2.0 * point.half_size[0]; /* m, <= h */
    /* As against the quadrature reference: the library's rounding plus a
     * few eps for the closed form. */
    double tolerance =
        1e-12 + 10.0 * sample_tolerances(GM_SHAPE_UGIMP, 1, &point).weight;
    for (int a = 0; a < WINDOW; a++) {
      double x = point.position[0] - node_coordinate(0, library.base[0] + a);
      double expected = closed_form_gimp(x, lp);
      REQUIRE(fabs(library.weight[a][0] - expected) <= tolerance,
              "sample %d node %d: weight %.17g, eq 3.27 gives %.17g", s, a,
              library.weight[a][0], expected);
    }
  }
}
END_TEST

/* The closed form of a domain no longer than a cell (gm_gimp_axis for
 * l <= 1/2, shape_gimp.h) against the average written with the
 * antiderivative of the tent, (Phi(u + l) - Phi(u - l)) / (2 l), and its
 * derivative (N(u + l) - N(u - l)) / (2 l), node by node, in cells. Both
 * start from s +- l - node, which carries the rounding of s (an ulp of s,
 * s up to 300 cells here), and the antiderivative form divides that
 * rounding by 2 l (measured: at most 6e-14 apart for l = 1/8, 1/4, 1/2;
 * 4.8e-12 in a gradient at l = 1e-3, s = 139). The tolerance,
 * eps s (16 + 4 / l), fails any wrong term (each is O(e^2 / l) or
 * O(e / l), e up to 2 l: 1e-3 at the smallest l). */
START_TEST(test_gimp_short_domain_form) {
  lcg_state = 4242;
  static const double halves[] = {0.5, 0.25, 0.125, 0.3, 0.49, 1e-3};
  for (size_t h = 0; h < sizeof halves / sizeof halves[0]; h++) {
    double l = halves[h]; /* cells */
    for (int sample = 0; sample < SAMPLE_COUNT; sample++) {
      double s = 1.0 + 299.0 * lcg_uniform(); /* cells from node 0 */
      int span;
      int64_t lowest = gm_gimp_axis_bounds(s, l, &span);
      ck_assert(span == 2 || span == 3);
      double weight[3], gradient[3];
      gm_gimp_axis(s, l, lowest, span, weight, gradient);
      double tolerance = DBL_EPSILON * s * (16.0 + 4.0 / l);
      for (int n = 0; n < span; n++) {
        double upper = s + l - (double)(lowest + n);
        double lower = s - l - (double)(lowest + n);
        double average =
            (gm_tent_integral(upper) - gm_tent_integral(lower)) / (2.0 * l);
        double slope = (gm_tent(upper) - gm_tent(lower)) / (2.0 * l);
        REQUIRE(fabs(weight[n] - average) <= tolerance &&
                    fabs(gradient[n] - slope) <= tolerance,
                "l %g, s %.17g, node %d: weight %.17g against %.17g, "
                "gradient %.17g against %.17g",
                l, s, n, weight[n], average, gradient[n], slope);
      }
    }
  }
}
END_TEST

/* uGIMP with a vanishing domain tends to the tent of linear MPM: the
 * average of the tent over [x - l, x + l] differs from its value at x only
 * where a kink lies inside, by at most l / (2 h) (at the peak: 004 eq 3.27
 * gives 1 - l / (2 h) for a point on its node). Below the library's switch
 * GM_GIMP_MIN_HALF_LENGTH the weights are those of linear MPM, bitwise. */
START_TEST(test_ugimp_small_domain_limit) {
  gm_shape_grid grid = make_grid(GM_SHAPE_UGIMP, 1);
  gm_shape_grid linear_grid = make_grid(GM_SHAPE_LINEAR, 1);
  for (int power = 1; power <= 9; power++) {
    double half = pow(10.0, -power) * cell_size; /* m */
    lcg_state = 600u + (uint64_t)power;
    for (int s = 0; s < SAMPLE_COUNT / 4; s++) {
      gm_point_domain point;
      random_point(GM_SHAPE_UGIMP, 1, &point);
      point.half_size[0] = half;
      if (s % 4 == 0) /* on a node, where the peak's kink is inside */
        point.position[0] = node_coordinate(0, 1 + s % 25);
      node_values library;
      window_around(GM_SHAPE_UGIMP, 1, &point, &library);
      gm_support support, linear;
      library_values(&grid, &point, &support, &library);
      double bound = half / (2.0 * cell_size) +
                     10.0 * sample_tolerances(GM_SHAPE_UGIMP, 1, &point).weight;
      for (int a = 0; a < WINDOW; a++) {
        double expected = tent(0, library.base[0] + a, point.position[0]);
        REQUIRE(fabs(library.weight[a][0] - expected) <= bound,
                "l = 1e-%d h: node weight %.17g, tent %.17g", power,
                library.weight[a][0], expected);
      }
      if (half * grid.inv_cell >= GM_GIMP_MIN_HALF_LENGTH)
        continue;
      REQUIRE(gm_support_compute(&linear_grid, &point, &linear) &&
                  linear.count == support.count &&
                  linear.lowest[0] == support.lowest[0],
              "l = 1e-%d h: support differs from linear MPM's", power);
      for (int e = 0; e < support.count; e++)
        REQUIRE(linear.weight[e] == support.weight[e],
                "l = 1e-%d h: weight %.17g, linear MPM %.17g", power,
                support.weight[e], linear.weight[e]);
    }
  }
}
END_TEST

/* ------------------------------------------------------- support bounds */

/* A fixed deformation per variant (sheared and stretched; ignored by
 * linear MPM and uGIMP). */
static void fixed_point(gm_shape shape, gm_point_domain *point) {
  memset(point, 0, sizeof *point);
  static const double sheared[4] = {1.0, 0.5, 0.2, 0.8};
  static const double stretched[4] = {1.4, 0.3, -0.2, 0.7};
  memcpy(point->deformation, shape == GM_SHAPE_CPDI ? sheared : stretched,
         sizeof point->deformation);
  point->half_size[0] = 0.3 * cell_size;
  point->half_size[1] = 0.2 * cell_size;
  gm_shape_grid grid = make_grid(shape, 2);
  for (int k = 0; k < 2; k++) /* mid-grid */
    point->position[k] = node_coordinate(k, grid.last_node[k] / 2) + 0.1;
}

/* Does the support exist with the domain's end on `side` (0 low, 1 high)
 * of `axis` at `gap` cells inside the outermost node (negative: outside)?
 * Checks that compute agrees and, inside, that the end node is reached. */
static bool bounds_at_edge(gm_shape shape, int dim, int axis, int side,
                           double gap) {
  gm_shape_grid grid = make_grid(shape, dim);
  gm_point_domain point;
  fixed_point(shape, &point);
  double reach[2];
  domain_reach(shape, dim, &point, reach);
  double edge = side ? node_coordinate(axis, grid.last_node[axis]) - reach[axis]
                     : node_coordinate(axis, 0) + reach[axis]; /* m */
  point.position[axis] = edge + (side ? -gap : gap) * cell_size;
  int64_t lowest[2], highest[2];
  bool inside = gm_support_bounds(&grid, &point, lowest, highest);
  gm_support support;
  ck_assert(gm_support_compute(&grid, &point, &support) == inside);
  if (inside)
    ck_assert_int_eq(side ? highest[axis] : lowest[axis],
                     side ? grid.last_node[axis] : 0);
  return inside;
}

START_TEST(test_bounds_at_ghost_layer) {
  gm_shape shape = all_shapes[_i / 2];
  int dim = 1 + _i % 2;
  for (int axis = 0; axis < dim; axis++) {
    for (int side = 0; side < 2; side++) {
      /* 1e-6 cells is far above the rounding of positions (~1e-14 cells)
       * and far below any domain size. */
      REQUIRE(bounds_at_edge(shape, dim, axis, side, 1e-6),
              "shape %d %dD axis %d side %d: domain just inside the "
              "ghost layer refused",
              (int)shape, dim, axis, side);
      REQUIRE(!bounds_at_edge(shape, dim, axis, side, -1e-6),
              "shape %d %dD axis %d side %d: domain past the ghost "
              "layer accepted",
              (int)shape, dim, axis, side);
    }
  }
}
END_TEST

/* A point whose domain covers [low, high] cells from node 0 along `axis`
 * (the other axis kept short and centred); returns whether it has a
 * support and its node count along the axis. */
static bool bounds_for_extent(gm_shape shape, int dim, int axis, double low,
                              double high, int *nodes) {
  gm_shape_grid grid = make_grid(shape, dim);
  gm_point_domain point;
  fixed_point(shape, &point);
  int other = 1 - axis;
  point.half_size[other] = 0.05 * cell_size;
  /* The reach is linear in half_size[axis]: solve for the wanted one. */
  double reach_zero[2], reach_unit[2];
  point.half_size[axis] = 0.0;
  domain_reach(shape, dim, &point, reach_zero);
  point.half_size[axis] = 1.0;
  domain_reach(shape, dim, &point, reach_unit);
  double wanted = 0.5 * (high - low) * cell_size; /* m */
  point.half_size[axis] =
      (wanted - reach_zero[axis]) / (reach_unit[axis] - reach_zero[axis]);
  point.position[axis] =
      node_coordinate(axis, 0) + 0.5 * (low + high) * cell_size;
  int64_t lowest[2], highest[2];
  bool valid = gm_support_bounds(&grid, &point, lowest, highest);
  *nodes = valid ? (int)(highest[axis] - lowest[axis] + 1) : 0;
  return valid;
}

/* A domain over [11.9, 18.95] cells touches nodes 11 .. 19, nine, the
 * most allowed; over [11.9, 19.05] it touches ten and is refused. */
START_TEST(test_bounds_at_span_limit) {
  static const gm_shape shapes[3] = {GM_SHAPE_UGIMP, GM_SHAPE_CPGIMP,
                                     GM_SHAPE_CPDI};
  gm_shape shape = shapes[_i / 2];
  int dim = 1 + _i % 2;
  for (int axis = 0; axis < dim; axis++) {
    int nodes = 0;
    REQUIRE(bounds_for_extent(shape, dim, axis, 11.9, 18.95, &nodes),
            "shape %d %dD axis %d: a 9-node support refused", (int)shape, dim,
            axis);
    ck_assert_int_eq(nodes, GM_SUPPORT_MAX_SPAN);
    REQUIRE(!bounds_for_extent(shape, dim, axis, 11.9, 19.05, &nodes),
            "shape %d %dD axis %d: a 10-node support accepted", (int)shape, dim,
            axis);
  }
}
END_TEST

/* Domains of 2 to 6 cells whose ends or corners fall exactly on nodes, on
 * a grid where that is exact (dyadic origin and cell size): every entry of
 * the support lies within its bounds, the nodes just beyond an end get no
 * weight, and a domain whose lower end is exactly on the ghost node 0 is
 * accepted. */
START_TEST(test_domain_ends_on_nodes) {
  const gm_shape shapes[3] = {GM_SHAPE_UGIMP, GM_SHAPE_CPGIMP, GM_SHAPE_CPDI};
  gm_shape_grid grid;
  memset(&grid, 0, sizeof grid);
  grid.shape = shapes[_i];
  grid.dim = 2;
  grid.inv_cell = 4.0; /* h = 0.25 m */
  grid.origin[0] = -2.5;
  grid.origin[1] = 1.25;
  grid.last_node[0] = grid.last_node[1] = 12;
  for (int64_t centre = 1; centre <= 3; centre++) {
    gm_point_domain point = {{0.0, 0.0}, {1.0, 0.0, 0.0, 1.0}, {0.0, 0.0}};
    for (int k = 0; k < 2; k++) { /* a square from node 0 to 2 centre */
      point.position[k] = grid.origin[k] + 0.25 * (double)centre;
      point.half_size[k] = 0.25 * (double)centre;
    }
    gm_support support;
    REQUIRE(gm_support_compute(&grid, &point, &support),
            "shape %d: domain on nodes 0 .. %lld refused", (int)grid.shape,
            (long long)(2 * centre));
    int64_t lowest[2], highest[2];
    REQUIRE(gm_support_bounds(&grid, &point, lowest, highest),
            "bounds refused");
    double sum = 0.0;
    for (int e = 0; e < support.count; e++) {
      for (int k = 0; k < 2; k++) {
        int64_t node = support.lowest[k] + support.offset[k][e];
        REQUIRE(node >= 0 && node <= highest[k],
                "shape %d, half %lld cells: entry %d on node %lld beyond "
                "the bounds 0 .. %lld",
                (int)grid.shape, (long long)centre, e, (long long)node,
                (long long)highest[k]);
        if (node > 2 * centre) /* beyond the domain's upper end */
          REQUIRE(support.weight[e] == 0.0, "weight beyond the domain");
      }
      sum += support.weight[e];
    }
    /* Exact grid and ends: only the rounding of a few sums remains. */
    REQUIRE(fabs(sum - 1.0) <= 1e-14, "sum of weights - 1 = %.3g", sum - 1);
    ck_assert_int_eq(lowest[0], 0);
    ck_assert_int_eq(lowest[1], 0);
  }
}
END_TEST

/* ---------------------------------------------- the inline CPDI support */

/* Does the inline 2D CPDI support (support_cpdi.h) give every bit of the
 * general one (gm_cpdi_support_map, gm_support_bounds) and refuse the same
 * domains? The kernels take the inline one and fall back to the general
 * one only where it refuses, and the step's results are promised
 * bitwise (the scratch driver of bench/results/2026-11-28-cpdi.md checks
 * whole runs; this checks each support). Domains: the random ones above,
 * inverted and degenerate maps (area <= 0), domains stretched past the
 * span limit, centres up to two cells past the ghost layer and NaN. */
static void compare_cpdi_support(const gm_shape_grid *grid,
                                 const gm_point_domain *point,
                                 const char *label) {
  const double *d = point->deformation;
  double half_x = point->half_size[0], half_y = point->half_size[1];
  gm_cpdi_support general, inline_support;
  memset(&general, 0, sizeof general);
  memset(&inline_support, 0, sizeof inline_support);
  bool found = gm_cpdi_support_map(grid, point->position[0], point->position[1],
                                   d, half_x, half_y, &general);
  int64_t reach[2] = {-1, -1};
  bool inline_found = gm_cpdi_support_2d(
      grid, point->position[0], point->position[1], d[0], d[1], d[2], d[3],
      half_x, half_y, &inline_support, reach);
  REQUIRE(found == inline_found, "%s: general %d, inline %d", label, (int)found,
          (int)inline_found);
  int64_t lowest[2], highest[2], inline_lowest[2], inline_highest[2];
  double corners[4][2], cells[4][2];
  bool bounded = gm_support_bounds(grid, point, lowest, highest);
  bool inline_bounded = gm_cpdi_corners_2d(
      grid, point->position[0], point->position[1], d[0], d[1], d[2], d[3],
      half_x, half_y, corners, cells, inline_lowest, inline_highest);
  REQUIRE(bounded == inline_bounded, "%s: bounds general %d, inline %d", label,
          (int)bounded, (int)inline_bounded);
  for (int k = 0; bounded && k < 2; k++)
    REQUIRE(lowest[k] == inline_lowest[k] && highest[k] == inline_highest[k],
            "%s: axis %d bounds %lld..%lld, inline %lld..%lld", label, k,
            (long long)lowest[k], (long long)highest[k],
            (long long)inline_lowest[k], (long long)inline_highest[k]);
  /* The block keys' variant: the same answer and lowest node without the
   * highest node's floor. */
  int64_t key_lowest[2];
  bool keyed =
      gm_cpdi_lowest_2d(grid, point->position[0], point->position[1], d[0],
                        d[1], d[2], d[3], half_x, half_y, key_lowest);
  REQUIRE(keyed == bounded, "%s: bounds general %d, lowest only %d", label,
          (int)bounded, (int)keyed);
  for (int k = 0; bounded && k < 2; k++)
    REQUIRE(key_lowest[k] == lowest[k], "%s: axis %d lowest %lld, keys' %lld",
            label, k, (long long)lowest[k], (long long)key_lowest[k]);
  if (!found)
    return;
  REQUIRE(inline_support.corner_count == 4 && general.corner_count == 4 &&
              inline_support.share == general.share,
          "%s: corner count or share", label);
  for (int k = 0; k < 2; k++) {
    REQUIRE(inline_support.lowest[k] == general.lowest[k],
            "%s: lowest node of axis %d", label, k);
    int64_t far = 0; /* gm_wide_point_support's reach */
    for (int c = 0; c < 4; c++) {
      int64_t node = general.cell[c][k] + 1 - general.lowest[k];
      far = node > far ? node : far;
    }
    REQUIRE(reach[k] == far, "%s: reach %lld, expected %lld", label,
            (long long)reach[k], (long long)far);
  }
  for (int c = 0; c < 4; c++)
    for (int k = 0; k < 2; k++) {
      REQUIRE(inline_support.cell[c][k] == general.cell[c][k],
              "%s: corner %d cell", label, c);
      /* memcmp: every bit, the signs of zeros included */
      REQUIRE(memcmp(inline_support.axis[c][k], general.axis[c][k],
                     sizeof general.axis[c][k]) == 0 &&
                  memcmp(&inline_support.corner_gradient[c][k],
                         &general.corner_gradient[c][k], sizeof(double)) == 0,
              "%s: corner %d axis %d: fractions %.17g, %.17g against "
              "%.17g, %.17g; gradient %.17g against %.17g",
              label, c, k, inline_support.axis[c][k][0],
              inline_support.axis[c][k][1], general.axis[c][k][0],
              general.axis[c][k][1], inline_support.corner_gradient[c][k],
              general.corner_gradient[c][k]);
    }
}

START_TEST(test_cpdi_inline_support) {
  lcg_state = 9157;
  gm_shape_grid grid = make_grid(GM_SHAPE_CPDI, 2);
  char label[64];
  int accepted = 0, refused = 0;
  for (int s = 0; s < 4 * SAMPLE_COUNT; s++) {
    snprintf(label, sizeof label, "sample %d", s);
    gm_point_domain point;
    random_point(GM_SHAPE_CPDI, 2, &point);
    double *d = point.deformation;
    switch (s % 8) {
    case 1: /* inverted: det D < 0 */
      d[0] = -d[0];
      d[2] = -d[2];
      break;
    case 2: /* degenerate: r1 parallel to r2, area 0 */
      d[1] = d[0];
      d[3] = d[2];
      point.half_size[1] = point.half_size[0];
      break;
    case 3: /* stretched past the span limit along x, or nearly */
      d[0] *= lcg_between(5.0, 40.0);
      break;
    case 4: /* centre anywhere up to two cells past the ghost layer */
      for (int k = 0; k < 2; k++)
        point.position[k] =
            grid.origin[k] +
            lcg_between(-2.0, (double)grid.last_node[k] + 2.0) * cell_size;
      break;
    case 5: /* a NaN entry */
      d[s / 8 % 4] = NAN;
      break;
    default:
      break;
    }
    compare_cpdi_support(&grid, &point, label);
    gm_cpdi_support probe;
    if (gm_cpdi_support_map(&grid, point.position[0], point.position[1], d,
                            point.half_size[0], point.half_size[1], &probe))
      accepted++;
    else
      refused++;
  }
  /* Both outcomes must have been exercised. */
  REQUIRE(accepted > SAMPLE_COUNT && refused > SAMPLE_COUNT / 4,
          "accepted %d, refused %d", accepted, refused);
}
END_TEST

/* The block keys' test of the highest node (gm_cpdi_lowest_2d) at its
 * edges, where random domains never land: a domain whose upper corner
 * lies exactly on the last node, or exactly on the span limit past its
 * lowest node, is refused, and one a quarter cell short of either is
 * taken, as gm_support_bounds does (compare_cpdi_support checks every
 * answer). An exact grid (origin 0, half-metre cells) and dyadic
 * positions, so each corner's cell is the number written here. _i: the
 * axis stretched. */
START_TEST(test_cpdi_keys_at_edges) {
  int axis = _i;
  gm_shape_grid grid;
  memset(&grid, 0, sizeof grid);
  grid.shape = GM_SHAPE_CPDI;
  grid.dim = 2;
  grid.inv_cell = 2.0; /* 1/m: h = 0.5 m */
  grid.last_node[0] = grid.last_node[1] = 40;
  const double span = GM_SUPPORT_MAX_SPAN; /* nodes */
  /* cells of the lower and upper corner along the axis; expected answer */
  const struct {
    double low, high;
    bool taken;
  } edges[] = {
      {33.0, 40.0, false},              /* upper corner on the last node */
      {33.0, 39.75, true},              /* a quarter cell short of it */
      {2.0, 2.0 + span - 1.0, false},   /* on the span limit */
      {2.0, 2.0 + span - 1.25, true},   /* short of it */
      {2.5, 2.0 + span - 1.0, false},   /* lowest node 2 all the same */
      {2.5, 2.0 + span - 1.25, true},   /* short of it */
      {-0.5, -0.5 + span - 1.5, false}, /* below node 0 */
  };
  for (size_t e = 0; e < sizeof edges / sizeof edges[0]; e++) {
    char label[64];
    snprintf(label, sizeof label, "axis %d, edge %zu", axis, e);
    gm_point_domain point;
    memset(&point, 0, sizeof point);
    point.deformation[0] = point.deformation[3] = 1.0; /* D = 1 */
    for (int k = 0; k < 2; k++) {
      double low = k == axis ? edges[e].low : 10.0; /* cells */
      double high = k == axis ? edges[e].high : 11.0;
      point.position[k] = 0.25 * (low + high);  /* m: (cells / 2) */
      point.half_size[k] = 0.25 * (high - low); /* m */
    }
    compare_cpdi_support(&grid, &point, label);
    int64_t lowest[2];
    const double *d = point.deformation;
    bool taken = gm_cpdi_lowest_2d(&grid, point.position[0], point.position[1],
                                   d[0], d[1], d[2], d[3], point.half_size[0],
                                   point.half_size[1], lowest);
    REQUIRE(taken == edges[e].taken, "%s: taken %d, expected %d", label,
            (int)taken, (int)edges[e].taken);
  }
}
END_TEST

static Suite *shape_variants_suite(void) {
  Suite *suite = suite_create("shape_variants");
  TCase *random = tcase_create("random_points");
  tcase_set_timeout(random, 120);
  /* _i: variant all_shapes[_i / 2] in (_i % 2 + 1) dimensions. */
  tcase_add_loop_test(random, test_random_points, 0, 8);
  tcase_add_loop_test(random, test_gimp_gradient_is_weight_derivative, 0, 4);
  tcase_add_test(random, test_ugimp_closed_form);
  tcase_add_test(random, test_gimp_short_domain_form);
  tcase_add_test(random, test_ugimp_small_domain_limit);
  tcase_add_test(random, test_cpdi_inline_support);
  suite_add_tcase(suite, random);
  TCase *bounds = tcase_create("bounds");
  tcase_add_loop_test(bounds, test_bounds_at_ghost_layer, 0, 8);
  tcase_add_loop_test(bounds, test_bounds_at_span_limit, 0, 6);
  tcase_add_loop_test(bounds, test_domain_ends_on_nodes, 0, 3);
  tcase_add_loop_test(bounds, test_cpdi_keys_at_edges, 0, 2);
  suite_add_tcase(suite, bounds);
  return suite;
}

int main(void) {
  SRunner *runner = srunner_create(shape_variants_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
