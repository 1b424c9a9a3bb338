/*
 * test_shape.c - white-box test of the linear (tent) shape functions in
 * lib/shapes/shape_linear.h (004 eq 3.25): partition of unity, zero-sum
 * gradients, exact reproduction of linear fields, bounds of the weights, the 1D
 * axis function, and weight 1 on a node a point sits on.
 *
 * The grid has a non-zero origin and a cell size that is not a power of two
 * (0.37 m) so that the rounding in (x - origin) / h is exercised.
 */
#include "shapes/shape_linear.h"

#include "test_random.h"

#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* Grid under test: origin (m), cell edge (m), cells per axis. */
static const double grid_origin[2] = {-1.3, 2.1};
static const double cell_size = 0.37;
static const int64_t cell_count[2] = {27, 19};
enum { SAMPLE_COUNT = 1000 };

/* Largest grid extent (m): the scale for position errors. */
static double grid_extent(void) {
  double ex = cell_count[0] * cell_size;
  double ey = cell_count[1] * cell_size;
  return ex > ey ? ex : ey;
}

/* A random position (m) strictly inside the grid box. */
static void random_position(double position[2]) {
  for (int axis = 0; axis < 2; axis++) {
    double extent = cell_count[axis] * cell_size;
    position[axis] = grid_origin[axis] + lcg_uniform() * extent;
  }
}

/* Coordinate (m) of node index `node` along `axis`. */
static double node_coordinate(int axis, int64_t node) {
  return grid_origin[axis] + (double)node * cell_size;
}

typedef struct shape_sample {
  double position[2]; /* m */
  int64_t cell[2];
  double weight[4];
  double gradient_x[4]; /* 1/m */
  double gradient_y[4]; /* 1/m */
} shape_sample;

static void evaluate(shape_sample *sample) {
  gm_shape_linear_2d(sample->position, grid_origin, 1.0 / cell_size,
                     sample->cell, sample->weight, sample->gradient_x,
                     sample->gradient_y);
}

/* Node k = a + 2 b of the sample's cell, as (x, y) coordinates in m. */
static void sample_node(const shape_sample *sample, int k, double node[2]) {
  node[0] = node_coordinate(0, sample->cell[0] + (k & 1));
  node[1] = node_coordinate(1, sample->cell[1] + (k >> 1));
}

START_TEST(test_partition_of_unity_and_bounds) {
  lcg_state = 12345;
  for (int s = 0; s < SAMPLE_COUNT; s++) {
    shape_sample sample;
    random_position(sample.position);
    evaluate(&sample);
    double sum = 0.0;
    for (int k = 0; k < 4; k++) {
      /* (1 - f) and f with f in [0, 1) are in [0, 1] exactly, and so are
       * their products: no tolerance is needed. */
      ck_assert_double_ge(sample.weight[k], 0.0);
      ck_assert_double_le(sample.weight[k], 1.0);
      sum += sample.weight[k];
    }
    /* Sum of four O(1) products: a few ulps of 1. */
    ck_assert_double_eq_tol(sum, 1.0, 1e-14);
  }
}
END_TEST

START_TEST(test_gradients_sum_to_zero) {
  lcg_state = 777;
  for (int s = 0; s < SAMPLE_COUNT; s++) {
    shape_sample sample;
    random_position(sample.position);
    evaluate(&sample);
    double sum_x = 0.0, sum_y = 0.0; /* 1/m */
    for (int k = 0; k < 4; k++) {
      sum_x += sample.gradient_x[k];
      sum_y += sample.gradient_y[k];
    }
    /* Terms are O(1/h); rounding leaves a few ulps of 1/h. */
    ck_assert_double_le(fabs(sum_x), 1e-12 / cell_size);
    ck_assert_double_le(fabs(sum_y), 1e-12 / cell_size);
  }
}
END_TEST

START_TEST(test_linear_fields_reproduced) {
  lcg_state = 2024;
  double scale = grid_extent(); /* m */
  for (int s = 0; s < SAMPLE_COUNT; s++) {
    shape_sample sample;
    random_position(sample.position);
    evaluate(&sample);
    double interpolated[2] = {0.0, 0.0}; /* m */
    double dx_dx = 0.0, dx_dy = 0.0, dy_dx = 0.0, dy_dy = 0.0;
    for (int k = 0; k < 4; k++) {
      double node[2];
      sample_node(&sample, k, node);
      interpolated[0] += sample.weight[k] * node[0];
      interpolated[1] += sample.weight[k] * node[1];
      dx_dx += sample.gradient_x[k] * node[0];
      dx_dy += sample.gradient_y[k] * node[0];
      dy_dx += sample.gradient_x[k] * node[1];
      dy_dy += sample.gradient_y[k] * node[1];
    }
    /* Linear completeness: sum N_i x_i = x. Errors are ulps of the
     * coordinates, i.e. ~1e-15 of the extent; 1e-12 leaves a wide margin
     * while still catching any wrong weight (an error of order h). */
    ck_assert_double_le(fabs(interpolated[0] - sample.position[0]),
                        1e-12 * scale);
    ck_assert_double_le(fabs(interpolated[1] - sample.position[1]),
                        1e-12 * scale);
    /* sum grad N_i x_i = grad x = identity. The sums are differences of
     * node coordinates (up to ~10 m) over h, so the rounding is about
     * |x| / h ulps = 1e-14; 1e-12 is still far below any real error. */
    ck_assert_double_eq_tol(dx_dx, 1.0, 1e-12);
    ck_assert_double_eq_tol(dy_dy, 1.0, 1e-12);
    ck_assert_double_le(fabs(dx_dy), 1e-12);
    ck_assert_double_le(fabs(dy_dx), 1e-12);
  }
}
END_TEST

START_TEST(test_axis_function) {
  lcg_state = 99;
  double inv_h = 1.0 / cell_size;
  double scale = grid_extent();
  for (int s = 0; s < SAMPLE_COUNT; s++) {
    double x = grid_origin[0] + lcg_uniform() * cell_count[0] * cell_size;
    double weight[2], gradient[2];
    int64_t cell =
        gm_shape_linear_axis(x, grid_origin[0], inv_h, weight, gradient);
    ck_assert_int_ge(cell, 0);
    ck_assert_int_lt(cell, cell_count[0]);
    /* The point lies in its cell, up to the rounding of (x - origin) / h. */
    ck_assert_double_ge(x, node_coordinate(0, cell) - 1e-12 * scale);
    ck_assert_double_le(x, node_coordinate(0, cell + 1) + 1e-12 * scale);
    ck_assert_double_ge(weight[0], 0.0);
    ck_assert_double_le(weight[0], 1.0);
    ck_assert_double_ge(weight[1], 0.0);
    ck_assert_double_le(weight[1], 1.0);
    ck_assert_double_eq_tol(weight[0] + weight[1], 1.0, 1e-15);
    /* The tent's slopes are exactly -1/h and +1/h. */
    ck_assert_double_eq(gradient[0], -inv_h);
    ck_assert_double_eq(gradient[1], inv_h);
    double interpolated = weight[0] * node_coordinate(0, cell) +
                          weight[1] * node_coordinate(0, cell + 1);
    ck_assert_double_le(fabs(interpolated - x), 1e-12 * scale);
  }
}
END_TEST

/* Weight of global node (node_x, node_y) in a sample; -1 if the node is not
 * one of the sample cell's four nodes. */
static double weight_of_node(const shape_sample *sample, int64_t node_x,
                             int64_t node_y) {
  int64_t a = node_x - sample->cell[0];
  int64_t b = node_y - sample->cell[1];
  if (a < 0 || a > 1 || b < 0 || b > 1) {
    return -1.0;
  }
  return sample->weight[a + 2 * b];
}

START_TEST(test_point_on_node_exact_grid) {
  /* With a dyadic origin and cell size every node coordinate and (x - o)/h
   * are exact, so a point on a node must get weight exactly 1 there and
   * exactly 0 on the other three nodes. */
  const double origin[2] = {-2.5, 1.25};
  const double h = 0.25; /* m */
  for (int64_t i = 0; i < 8; i++) {
    for (int64_t j = 0; j < 8; j++) {
      shape_sample sample;
      sample.position[0] = origin[0] + (double)i * h;
      sample.position[1] = origin[1] + (double)j * h;
      gm_shape_linear_2d(sample.position, origin, 1.0 / h, sample.cell,
                         sample.weight, sample.gradient_x, sample.gradient_y);
      ck_assert_int_eq(sample.cell[0], i);
      ck_assert_int_eq(sample.cell[1], j);
      ck_assert_double_eq(sample.weight[0], 1.0);
      ck_assert_double_eq(sample.weight[1], 0.0);
      ck_assert_double_eq(sample.weight[2], 0.0);
      ck_assert_double_eq(sample.weight[3], 0.0);
    }
  }
}
END_TEST

START_TEST(test_point_on_node_inexact_grid) {
  /* With h = 0.37 the node coordinate origin + i h is rounded, and the
   * point may land in either neighbouring cell; whichever cell it is, the
   * node it sits on must carry weight 1 to rounding (a few ulps of 1 times
   * |x| / h, below 1e-12). */
  for (int64_t i = 1; i < cell_count[0]; i++) {
    for (int64_t j = 1; j < cell_count[1]; j++) {
      shape_sample sample;
      sample.position[0] = node_coordinate(0, i);
      sample.position[1] = node_coordinate(1, j);
      evaluate(&sample);
      double on_node = weight_of_node(&sample, i, j);
      ck_assert_double_eq_tol(on_node, 1.0, 1e-12);
      double others = 0.0;
      for (int k = 0; k < 4; k++) {
        others += sample.weight[k];
      }
      ck_assert_double_le(fabs(others - on_node), 1e-12);
    }
  }
}
END_TEST

static Suite *shape_suite(void) {
  Suite *suite = suite_create("shape_linear");
  TCase *tcase = tcase_create("linear");
  tcase_add_test(tcase, test_partition_of_unity_and_bounds);
  tcase_add_test(tcase, test_gradients_sum_to_zero);
  tcase_add_test(tcase, test_linear_fields_reproduced);
  tcase_add_test(tcase, test_axis_function);
  tcase_add_test(tcase, test_point_on_node_exact_grid);
  tcase_add_test(tcase, test_point_on_node_inexact_grid);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  SRunner *runner = srunner_create(shape_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
