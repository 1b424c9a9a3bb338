/*
 * test_support_3d.c - white-box test of the 3D GIMP supports
 * (lib/shapes/support_3d.c): uGIMP and cpGIMP boxes at thousands of random
 * points with random half edges (up to 1.5 cells, the longest box that
 * always fits the 4 x 4 x 4 blocks), on a grid with a non-zero origin and
 * a cell size that is not a power of two.
 *
 * Checked against the defining properties of the weights (000 sec 2.1):
 * partition of unity, zero-sum gradients, exact reproduction of linear
 * fields (sum S_i x_i = x_p, sum x_i (x) grad S_i = I), weights in [0, 1];
 * and node by node against a reference computed here in metres from the
 * tent: per axis the tent's average over the box edge by 2-point
 * Gauss-Legendre quadrature split at the kinks (exact: the tent is linear
 * on each piece), its derivative (N(x + l) - N(x - l)) / (2 l), and the 3D
 * weight as the product of the axis averages (004 sec 3.3.6: the basis is
 * separable and the box axis-aligned). Also the bounds: a box past the
 * ghost layer, a box spanning 6 nodes, a NaN centre are refused.
 *
 * The quadratic and cubic B-splines through the same functions (27 and 64
 * nodes): the same properties at random points of the box, node by node
 * against the closed forms, and APIC's D_p = h^2/4 I, h^2/3 I.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "shapes/shapes.h"

#include "test_random.h"
#include "test_util.h"

#include <check.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double box_origin[3] = {-1.3, 2.1, 0.4}; /* m */
static const double cell_size = 0.37;                 /* m */
static const int64_t cell_count[3] = {13, 9, 11};
enum { SAMPLE_COUNT = 3000 };

/* The grid as domain.c builds it: node 0 one ghost layer below the box. */
static gm_shape_grid make_grid(gm_shape shape) {
  gm_shape_grid grid;
  memset(&grid, 0, sizeof grid);
  grid.shape = shape;
  grid.dim = 3;
  grid.inv_cell = 1.0 / cell_size;
  for (int k = 0; k < 3; k++) {
    grid.origin[k] = box_origin[k] - GM_GHOST_LAYERS * cell_size;
    grid.last_node[k] = cell_count[k] + 2 * GM_GHOST_LAYERS;
  }
  return grid;
}

/* Coordinate (m) of node `node` along axis, from the box corner. */
static double node_coordinate(int axis, int64_t node) {
  return box_origin[axis] + (double)(node - GM_GHOST_LAYERS) * cell_size;
}

/* The tent of a node at coordinate xi (m) evaluated at x. */
static double tent(double xi, double x) {
  double u = fabs(x - xi) / cell_size;
  return u < 1.0 ? 1.0 - u : 0.0;
}

/* The tent's average over [x - l, x + l] (l > 0), exact by 2-point Gauss
 * on each piece between the ends and the kinks xi - h, xi, xi + h. */
static double tent_average(double xi, double x, double l) {
  double cuts[5] = {x - l, xi - cell_size, xi, xi + cell_size, x + l};
  double sorted[5];
  int n = 0;
  sorted[n++] = cuts[0];
  for (int c = 1; c < 4; c++)
    if (cuts[c] > x - l && cuts[c] < x + l)
      sorted[n++] = cuts[c];
  sorted[n++] = cuts[4];
  const double gauss = 1.0 / sqrt(3.0);
  double integral = 0.0;
  for (int piece = 0; piece + 1 < n; piece++) {
    double middle = 0.5 * (sorted[piece] + sorted[piece + 1]);
    double half = 0.5 * (sorted[piece + 1] - sorted[piece]);
    integral += half * (tent(xi, middle - gauss * half) +
                        tent(xi, middle + gauss * half));
  }
  return integral / (2.0 * l);
}

/* A random box inside the nodes: half edges 0 (the tent), 1e-9 h, or
 * uniform up to 1.5 h, centre so that the box stays within the nodes. */
static void random_box(const gm_shape_grid *grid, double x[3], double half[3]) {
  for (int k = 0; k < 3; k++) {
    double pick = lcg_uniform();
    half[k] = pick < 0.05   ? 0.0
              : pick < 0.10 ? 1e-9 * cell_size
                            : lcg_between(0.01, 1.5) * cell_size;
    double low = grid->origin[k] + half[k] + 1e-9 * cell_size;
    double high = grid->origin[k] + (double)grid->last_node[k] * cell_size -
                  half[k] - 1e-9 * cell_size;
    x[k] = lcg_between(low, high);
  }
}

/* Per axis reference weight and gradient (1/m) of node `node`. */
static void axis_reference(int axis, int64_t node, double x, double l,
                           double *weight, double *gradient) {
  double xi = node_coordinate(axis, node);
  if (l < GM_GIMP_MIN_HALF_LENGTH * cell_size) { /* the tent's limit */
    *weight = tent(xi, x);
    double u = (x - xi) / cell_size;
    *gradient = fabs(u) < 1.0 ? (u < 0.0 ? 1.0 : -1.0) / cell_size : 0.0;
    return;
  }
  *weight = tent_average(xi, x, l);
  *gradient = (tent(xi, x + l) - tent(xi, x - l)) / (2.0 * l);
}

/* The support depends on the box alone: uGIMP and cpGIMP differ only in
 * the half edges they hand it (test_box_half_edges_3d). */
START_TEST(test_gimp_box_3d_properties) {
  gm_shape_grid grid = make_grid(GM_SHAPE_UGIMP);
  lcg_state = 20261127u;
  double worst_sum = 0.0, worst_linear = 0.0, worst_gradient = 0.0;
  double worst_reference = 0.0;
  for (int sample = 0; sample < SAMPLE_COUNT; sample++) {
    double x[3], half[3];
    random_box(&grid, x, half);
    gm_box_support_3d support;
    REQUIRE(gm_box_support_compute_3d(&grid, x, half, &support),
            "support refused for a box inside the nodes at (%g, %g, %g)", x[0],
            x[1], x[2]);
    int64_t lowest[3];
    REQUIRE(gm_box_support_lowest_3d(&grid, x, half, lowest) &&
                lowest[0] == support.lowest[0] &&
                lowest[1] == support.lowest[1] &&
                lowest[2] == support.lowest[2],
            "lowest node differs from the support's");
    double sum = 0.0, moment[3] = {0, 0, 0}; /* -, m */
    double gradient_sum[3] = {0, 0, 0};      /* 1/m */
    double identity[3][3] = {{0}};           /* sum x_i (x) grad S_i */
    for (int c = 0; c < support.span[2]; c++)
      for (int b = 0; b < support.span[1]; b++)
        for (int a = 0; a < support.span[0]; a++) {
          int offset[3] = {a, b, c};
          double weight = 1.0, gradient[3] = {1.0, 1.0, 1.0};
          double reference = 1.0, reference_gradient[3] = {1.0, 1.0, 1.0};
          double node[3]; /* m */
          for (int k = 0; k < 3; k++) {
            int64_t index = support.lowest[k] + offset[k];
            node[k] = node_coordinate(k, index);
            double w, g;
            axis_reference(k, index, x[k], half[k], &w, &g);
            weight *= support.weight[k][offset[k]];
            reference *= w;
            for (int j = 0; j < 3; j++) {
              gradient[j] *= j == k ? support.gradient[k][offset[k]]
                                    : support.weight[k][offset[k]];
              reference_gradient[j] *= j == k ? g : w;
            }
          }
          ck_assert_msg(weight >= -1e-15 && weight <= 1.0 + 1e-15,
                        "weight %g outside [0, 1]", weight);
          worst_reference = fmax(worst_reference, fabs(weight - reference));
          for (int j = 0; j < 3; j++)
            worst_reference =
                fmax(worst_reference,
                     fabs(gradient[j] - reference_gradient[j]) * cell_size);
          sum += weight;
          for (int k = 0; k < 3; k++) {
            moment[k] += weight * node[k];
            gradient_sum[k] += gradient[k];
            for (int j = 0; j < 3; j++)
              identity[k][j] += node[k] * gradient[j];
          }
        }
    worst_sum = fmax(worst_sum, fabs(sum - 1.0));
    for (int k = 0; k < 3; k++) {
      worst_linear = fmax(worst_linear, fabs(moment[k] - x[k]) / cell_size);
      worst_gradient = fmax(worst_gradient, fabs(gradient_sum[k]) * cell_size);
      for (int j = 0; j < 3; j++)
        worst_gradient =
            fmax(worst_gradient, fabs(identity[k][j] - (k == j ? 1.0 : 0.0)));
    }
  }
  printf("3D GIMP supports: |sum S - 1| %.2g, |sum S x - x_p| %.2g h, "
         "gradient sums %.2g, against the reference %.2g\n",
         worst_sum, worst_linear, worst_gradient, worst_reference);
  /* Round-off: sums of at most 125 products of three factors, each a few
   * ulps; positions up to ~16 cells from node 0, so x_p carries ~1e-15 h
   * of its own rounding; sum x_i grad S_i sums terms up to ~16 / (2 l)
   * for the shortest boxes (l = 0.01 h), ~1e-13. The reference's own
   * rounding is ~1e-15 h^-1 for l = 1e-9 h's limit. A wrong axis average
   * (the tent at the centre, say) is off by O(l^2/h^2) ~ 1e-2, a missing
   * node by O(1). */
  ck_assert_msg(worst_sum <= 1e-13, "partition of unity off by %g", worst_sum);
  ck_assert_msg(worst_linear <= 1e-12, "linear reproduction off by %g h",
                worst_linear);
  ck_assert_msg(worst_gradient <= 1e-11, "gradient sums off by %g",
                worst_gradient);
  ck_assert_msg(worst_reference <= 1e-11, "reference differs by %g",
                worst_reference);
}
END_TEST

START_TEST(test_gimp_box_3d_bounds) {
  gm_shape_grid grid = make_grid(GM_SHAPE_UGIMP);
  gm_box_support_3d support;
  int64_t lowest[3];
  /* A box centred on the lower z face reaching one cell below it: the
   * ghost node 0 along z is its lowest node, and it is accepted. */
  double x[3] = {box_origin[0] + 3.2 * cell_size,
                 box_origin[1] + 4.6 * cell_size, box_origin[2]};
  double half[3] = {0.25 * cell_size, 0.25 * cell_size, 0.999 * cell_size};
  ck_assert(gm_box_support_compute_3d(&grid, x, half, &support));
  ck_assert_int_eq((int)support.lowest[2], 0);
  /* Half a cell more and it reaches past the ghost layer. */
  half[2] = 1.5 * cell_size;
  ck_assert(!gm_box_support_compute_3d(&grid, x, half, &support));
  ck_assert(!gm_box_support_lowest_3d(&grid, x, half, lowest));
  /* A 3.2-cell box crossing 4 node planes spans 6 nodes: refused; at 3
   * cells it spans at most 5 and fits. */
  x[2] = box_origin[2] + 5.5 * cell_size;
  half[2] = 1.6 * cell_size;
  ck_assert(!gm_box_support_compute_3d(&grid, x, half, &support));
  half[2] = 1.5 * cell_size;
  ck_assert(gm_box_support_compute_3d(&grid, x, half, &support));
  ck_assert_int_eq(support.span[2], 5);
  x[1] = NAN;
  ck_assert(!gm_box_support_compute_3d(&grid, x, half, &support));
  ck_assert(!gm_box_support_lowest_3d(&grid, x, half, lowest));
}
END_TEST

/* uGIMP's box is the initial one whatever F; cpGIMP's edges are
 * stretched by |F_xx|, |F_yy|, |F_zz| (slots 0, 3, 4 of core.h's F
 * layout), the off-diagonal components ignored. */
START_TEST(test_box_half_edges_3d) {
  double size[3][2] = {{0.2, 0.3}, {0.4, 0.5}, {0.6, 0.7}}; /* m */
  double f[9][2];
  const double *domain_size[3] = {size[0], size[1], size[2]};
  const double *deformation[9];
  for (int c = 0; c < 9; c++) {
    f[c][0] = f[c][1] = 0.1 * (c + 1); /* off-diagonal: must not count */
    deformation[c] = f[c];
  }
  f[0][1] = -1.5; /* F_xx */
  f[3][1] = 0.8;  /* F_yy */
  f[4][1] = -2.0; /* F_zz */
  double half[3];
  gm_box_half_edges_3d(GM_SHAPE_UGIMP, domain_size, deformation, 1, half);
  for (int k = 0; k < 3; k++)
    ck_assert(half[k] == 0.5 * size[k][1]);
  gm_box_half_edges_3d(GM_SHAPE_CPGIMP, domain_size, deformation, 1, half);
  ck_assert(half[0] == 0.5 * 0.3 * 1.5);
  ck_assert(half[1] == 0.5 * 0.5 * 0.8);
  ck_assert(half[2] == 0.5 * 0.7 * 2.0);
}
END_TEST

/* The cardinal B-spline of a node at xi (m) evaluated at x, and its
 * derivative (1/m), from the closed forms in cells (shape_bspline.h's
 * header, de Boor), computed here in metres from u = (x - xi) / h. */
static void bspline_reference(gm_shape shape, double xi, double x, double *w,
                              double *g) {
  double u = (x - xi) / cell_size, a = fabs(u), sign = u < 0 ? -1.0 : 1.0;
  if (shape == GM_SHAPE_BSPLINE2) {
    *w = a <= 0.5 ? 0.75 - u * u : a <= 1.5 ? 0.5 * (1.5 - a) * (1.5 - a) : 0;
    *g = a <= 0.5 ? -2.0 * u : a <= 1.5 ? -sign * (1.5 - a) : 0;
  } else {
    *w = a <= 1.0   ? 2.0 / 3.0 - u * u + 0.5 * a * a * a
         : a <= 2.0 ? (2.0 - a) * (2.0 - a) * (2.0 - a) / 6.0
                    : 0.0;
    *g = a <= 1.0   ? -2.0 * u + 1.5 * sign * a * a
         : a <= 2.0 ? -0.5 * sign * (2.0 - a) * (2.0 - a)
                    : 0.0;
  }
  *g /= cell_size;
}

/* The 3D B-splines (GM_SHAPE_BSPLINE2, GM_SHAPE_BSPLINE3): 27 or 64 nodes
 * of weights N_a(x) N_b(y) N_c(z) at random points of the box, checked for
 * the partition of unity, the reproduction of linear fields, zero-sum
 * gradients and sum x_i (x) grad N_i = I, node by node against the closed
 * form, and APIC's D_p = sum_i N_i (x_i - x_p) (x) (x_i - x_p), which must
 * be the constant h^2/4 I (quadratic), h^2/3 I (cubic) that p2g_3d.c uses
 * (apic_3d.h). _i: 0 quadratic, 1 cubic. */
START_TEST(test_bspline_3d_properties) {
  gm_shape shape = _i ? GM_SHAPE_BSPLINE3 : GM_SHAPE_BSPLINE2;
  gm_shape_grid grid = make_grid(shape);
  int span = _i ? 4 : 3;
  double variance = (_i ? 1.0 / 3.0 : 0.25) * cell_size * cell_size; /* m^2 */
  lcg_state = 20261128u + (uint64_t)_i;
  double worst_sum = 0.0, worst_linear = 0.0, worst_gradient = 0.0;
  double worst_reference = 0.0, worst_inertia = 0.0, missed = 0.0;
  for (int sample = 0; sample < SAMPLE_COUNT; sample++) {
    double x[3], half[3] = {0.0, 0.0, 0.0}; /* m; half: not used */
    for (int k = 0; k < 3; k++) /* inside the box, as every point is */
      x[k] = lcg_between(box_origin[k],
                         box_origin[k] + (double)cell_count[k] * cell_size);
    if (sample % 7 == 0) /* on a node plane, or half way between */
      x[sample % 3] =
          node_coordinate(sample % 3, 3) + (sample % 2 ? 0.5 * cell_size : 0.0);
    gm_box_support_3d support;
    REQUIRE(gm_box_support_compute_3d(&grid, x, half, &support),
            "support refused at (%g, %g, %g)", x[0], x[1], x[2]);
    int64_t lowest[3];
    REQUIRE(gm_box_support_lowest_3d(&grid, x, half, lowest) &&
                lowest[0] == support.lowest[0] &&
                lowest[1] == support.lowest[1] &&
                lowest[2] == support.lowest[2],
            "lowest node differs from the support's");
    double sum = 0.0, moment[3] = {0, 0, 0}; /* -, m */
    double gradient_sum[3] = {0, 0, 0};      /* 1/m */
    double identity[3][3] = {{0}};           /* sum x_i (x) grad N_i */
    double inertia[3][3] = {{0}};            /* m^2, D_p */
    for (int k = 0; k < 3; k++) {
      ck_assert_int_eq(support.span[k], span);
      /* The nodes just outside the support weigh nothing there. */
      for (int n = -1; n <= span; n += span + 1) {
        double w, g;
        bspline_reference(shape, node_coordinate(k, support.lowest[k] + n),
                          x[k], &w, &g);
        missed = fmax(missed, w);
      }
    }
    for (int c = 0; c < span; c++)
      for (int b = 0; b < span; b++)
        for (int a = 0; a < span; a++) {
          int offset[3] = {a, b, c};
          double weight = 1.0, gradient[3] = {1.0, 1.0, 1.0};
          double reference = 1.0, reference_gradient[3] = {1.0, 1.0, 1.0};
          double node[3]; /* m */
          for (int k = 0; k < 3; k++) {
            int64_t index = support.lowest[k] + offset[k];
            node[k] = node_coordinate(k, index);
            double w, g;
            bspline_reference(shape, node[k], x[k], &w, &g);
            weight *= support.weight[k][offset[k]];
            reference *= w;
            for (int j = 0; j < 3; j++) {
              gradient[j] *= j == k ? support.gradient[k][offset[k]]
                                    : support.weight[k][offset[k]];
              reference_gradient[j] *= j == k ? g : w;
            }
          }
          ck_assert_msg(weight >= 0.0 && weight <= 1.0, "weight %g", weight);
          worst_reference = fmax(worst_reference, fabs(weight - reference));
          for (int j = 0; j < 3; j++)
            worst_reference =
                fmax(worst_reference,
                     fabs(gradient[j] - reference_gradient[j]) * cell_size);
          sum += weight;
          for (int k = 0; k < 3; k++) {
            moment[k] += weight * node[k];
            gradient_sum[k] += gradient[k];
            for (int j = 0; j < 3; j++) {
              identity[k][j] += node[k] * gradient[j];
              inertia[k][j] += weight * (node[k] - x[k]) * (node[j] - x[j]);
            }
          }
        }
    worst_sum = fmax(worst_sum, fabs(sum - 1.0));
    for (int k = 0; k < 3; k++) {
      worst_linear = fmax(worst_linear, fabs(moment[k] - x[k]) / cell_size);
      worst_gradient = fmax(worst_gradient, fabs(gradient_sum[k]) * cell_size);
      for (int j = 0; j < 3; j++) {
        worst_gradient =
            fmax(worst_gradient, fabs(identity[k][j] - (k == j ? 1.0 : 0.0)));
        worst_inertia =
            fmax(worst_inertia,
                 fabs(inertia[k][j] - (k == j ? variance : 0.0)) / variance);
      }
    }
  }
  printf("3D %s: |sum N - 1| %.2g, |sum N x - x_p| %.2g h, gradient sums "
         "%.2g, against the closed form %.2g, D_p off %.2g, outside %.2g\n",
         _i ? "cubic" : "quadratic", worst_sum, worst_linear, worst_gradient,
         worst_reference, worst_inertia, missed);
  /* Round-off: sums of 27 or 64 products of three factors of a few ulps;
   * positions up to ~15 cells from node 0 carry ~1e-15 h of their own
   * rounding, and sum x_i grad N_i sums terms up to ~15 / h * h. A missing
   * node, a wrong lowest node or a gradient sign is off by O(1e-2..1); D_p
   * taken as the other degree's constant by 1/3. */
  ck_assert_msg(worst_sum <= 1e-13, "partition of unity off by %g", worst_sum);
  ck_assert_msg(worst_linear <= 1e-12, "linear reproduction off by %g h",
                worst_linear);
  ck_assert_msg(worst_gradient <= 1e-12, "gradient sums off by %g",
                worst_gradient);
  ck_assert_msg(worst_reference <= 1e-12, "closed form differs by %g",
                worst_reference);
  ck_assert_msg(worst_inertia <= 1e-12, "D_p off by %g of h^2 / %g",
                worst_inertia, _i ? 3.0 : 4.0);
  /* Outside: 0, or the square of a rounding where a node is 1.5 cells off
   * (the quadratic's pair at the edge); a node left out would weigh up to
   * 1/8 (quadratic) or 1/6 (cubic). */
  ck_assert_msg(missed <= 1e-14, "a node outside the support weighs %g",
                missed);
  /* Bounds: a NaN, and a point past the ghost layer, are refused. */
  gm_box_support_3d support;
  double outside[3] = {box_origin[0] - 1.01 * cell_size, box_origin[1],
                       box_origin[2]};
  ck_assert(!gm_box_support_compute_3d(&grid, outside, outside, &support));
  outside[0] = NAN;
  ck_assert(!gm_box_support_compute_3d(&grid, outside, outside, &support));
}
END_TEST

static Suite *support_3d_suite(void) {
  Suite *suite = suite_create("support_3d");
  TCase *tc = tcase_create("gimp");
  tcase_add_test(tc, test_gimp_box_3d_properties);
  tcase_add_test(tc, test_box_half_edges_3d);
  tcase_add_test(tc, test_gimp_box_3d_bounds);
  tcase_add_loop_test(tc, test_bspline_3d_properties, 0, 2);
  suite_add_tcase(suite, tc);
  return suite;
}

int main(void) {
  return test_run_suite(support_3d_suite()) ? EXIT_FAILURE : 0;
}
