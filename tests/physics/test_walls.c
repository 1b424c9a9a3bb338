/*
 * test_walls.c - box walls act on the particles, not only on the grid.
 *
 * A small stress-free-enough block (soft, low speed) moves into a wall at
 * 1 m/s. Wall nodes get the boundary condition and the nodal acceleration
 * is recomputed as (v_constrained - v)/dt, so the FLIP particle velocity
 * loses its wall-normal component in the same step. Expected, for every
 * update scheme:
 *  - FIXED wall (no-slip), moving straight at it: the block stops at the
 *    wall instead of creeping into it, and its momentum toward the wall
 *    is gone (the elastic block may rebound, as material may leave a box
 *    face it no longer touches: grid_update.c);
 *  - SLIP wall, moving at it obliquely: the normal momentum vanishes, the
 *    tangential momentum is kept (frictionless wall, no gravity).
 * Regression: USF used to take the wall correction from already
 * constrained velocities, so particle velocities never felt the wall and
 * the points crept into it (0.05 m -> 0.0067 m in 0.2 s).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

static const gm_update_scheme schemes[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                            GM_SCHEME_USF};
static const double CELL = 0.1;  /* m */
static const double SPEED = 1.0; /* m/s, toward the wall */
static const double DT = 1e-3;   /* s, far below the stable dt (~0.03 s) */
enum { STEPS = 200 };

/* A 0.2 m x 0.2 m block touching the XMIN wall region at x = 0.05 m. */
static gm_domain *block_at_wall(gm_update_scheme scheme, gm_wall_type wall,
                                double tangential_speed) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = def.extent[1] = 1.0;
  def.walls[GM_FACE_XMIN] = wall;
  gm_domain *domain = test_create_domain(&def);
  /* Soft: c = sqrt(M/rho) ~ 3 m/s, so the contact does not ring for long. */
  int material = test_add_elastic(domain, 1e4, 0.3, 1000.0);
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.lower[0] = 0.0;
  fill.upper[0] = 0.2;
  fill.lower[1] = 0.4;
  fill.upper[1] = 0.6;
  fill.velocity[0] = -SPEED;
  fill.velocity[1] = tangential_speed;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  return domain;
}

static double smallest_x(const gm_domain *domain) {
  size_t count = gm_domain_point_count(domain);
  const double *x = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  double lowest = INFINITY;
  for (size_t i = 0; i < count; i++)
    lowest = fmin(lowest, x[i]);
  return lowest;
}

START_TEST(test_fixed_wall_stops_points) {
  gm_update_scheme scheme = schemes[_i];
  gm_domain *domain = block_at_wall(scheme, GM_WALL_FIXED, 0.0);
  double start = smallest_x(domain); /* 0.025 m: 2x2 points per cell */
  for (int step = 0; step < STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, DT));
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  /* Free motion would carry the block 0.2 m into the wall. Stopped, the
   * points nearest the wall move at most while the first wall layer
   * decelerates: allow one cell width of compression of a soft block. */
  double moved = start - smallest_x(domain);
  ck_assert_msg(moved < CELL && smallest_x(domain) > 0.0,
                "%s: the block moved %g m into a fixed wall",
                test_scheme_name(scheme), moved);
  /* The initial momentum is -SPEED * mass; after 0.2 s the wall must have
   * removed all of it that pointed into the wall (at most half may be
   * left, from the last compression of the soft block) and given back at
   * most as much: the elastic block rebounds (measured +0.51 to +0.53 of
   * the impact momentum by scheme; a perfectly elastic bar would leave at
   * the full impact speed). Until the box faces measured the gap to their
   * material, a fixed face held the block glued to it (|p| < 0.04 of it). */
  double initial = SPEED * summary.mass;
  ck_assert_msg(summary.momentum[0] > -0.5 * initial &&
                    summary.momentum[0] <= initial,
                "%s: x momentum %g kg m/s, impact momentum %g",
                test_scheme_name(scheme), summary.momentum[0], -initial);
  gm_domain_destroy(domain);
}
END_TEST

START_TEST(test_slip_wall_keeps_tangential_momentum) {
  gm_update_scheme scheme = schemes[_i];
  const double tangential = 0.5; /* m/s along the wall */
  gm_domain *domain = block_at_wall(scheme, GM_WALL_SLIP, tangential);
  for (int step = 0; step < STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, DT));
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  /* No force acts along a frictionless wall and there is no gravity: the
   * y momentum is conserved to round-off (sums of ~1e3 terms per step). */
  double expected = tangential * summary.mass;
  ck_assert_msg(fabs(summary.momentum[1] - expected) < 1e-9 * expected,
                "%s: y momentum %.17g, expected %.17g",
                test_scheme_name(scheme), summary.momentum[1], expected);
  ck_assert_msg(smallest_x(domain) > 0.0, "%s: a point crossed the wall",
                test_scheme_name(scheme));
  gm_domain_destroy(domain);
}
END_TEST

/* The sharpest case: one point, halfway between the wall node and the next
 * node, flying at the wall, its domain's edge a quarter cell from it. It
 * must fly that quarter cell and stop where its domain reaches the wall
 * (x = 0.025 m), within one step of free flight (1 mm) plus the 0.01
 * cells short of a face that material may stop (1 mm, grid_update.c,
 * GM_FACE_RELEASE; measured 0.75-1.0 mm short): free flight would take it
 * 0.2 m, through the wall. Until the box faces measured the gap to
 * their material, the held wall node stopped it where it started. */
START_TEST(test_single_point_stops_at_fixed_wall) {
  gm_update_scheme scheme = schemes[_i];
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = def.extent[1] = 1.0;
  def.walls[GM_FACE_XMIN] = GM_WALL_FIXED;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e4, 0.3, 1000.0);
  const double position[2] = {0.5 * CELL, 0.55}, velocity[2] = {-SPEED, 0.0};
  const double volume = 0.25 * CELL * CELL; /* m^2 per m */
  test_add_points(domain, material, 1, position, velocity, &volume);
  for (int step = 0; step < STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, DT));
  double x = smallest_x(domain), v[2];
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_VELOCITY, v, 2));
  double edge_on_wall = 0.5 * sqrt(volume); /* m, its half size */
  ck_assert_msg(x > edge_on_wall - SPEED * DT &&
                    x < edge_on_wall + SPEED * DT + 0.01 * CELL,
                "%s: the point stopped at x = %g m (from %g m); its domain "
                "reaches the wall at x = %g m",
                test_scheme_name(scheme), x, position[0], edge_on_wall);
  /* Its momentum went into the wall. What is left is the small elastic
   * ringing of the compressed point (measured 0.2-0.3 % of the impact
   * speed); a point still flying at the wall would keep v_x = -1 m/s. */
  ck_assert_msg(fabs(v[0]) < 0.01 * SPEED, "%s: v_x = %g m/s after the wall",
                test_scheme_name(scheme), v[0]);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("walls");
  TCase *tcase = tcase_create("box_walls");
  tcase_add_loop_test(tcase, test_fixed_wall_stops_points, 0, 3);
  tcase_add_loop_test(tcase, test_slip_wall_keeps_tangential_momentum, 0, 3);
  tcase_add_loop_test(tcase, test_single_point_stops_at_fixed_wall, 0, 3);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
