/*
 * test_friction.c - a block on an incline with a Coulomb wall
 * (docs/references.md, "Block sliding on an incline"; design.md validation
 * table): at rest when tan(theta) < mu, otherwise its centre of mass
 * moves s = 1/2 g (sin(theta) - mu cos(theta)) t^2 down the slope.
 *
 * As in the papers, the slope is modelled as a horizontal floor with
 * gravity rotated by theta: g = g (sin(theta), -cos(theta)). The floor is a
 * planar wall (gm_domain_add_wall) on a grid line, normal +y, with
 * mu_s = mu_k = mu. Two angles each side of mu = 0.4 (21.8 degrees):
 * 10 and 15 degrees stick, 30 and 35 degrees slide, in USL, MUSL and
 * USF. (USL used to fail once a sliding block's front points entered
 * empty cells; since it takes its strain rate from the re-mapped
 * velocities (gm_domain_step(3)) it completes the slides.)
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "test_block.h"
#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81; /* m/s^2 */
static const double MU = 0.4;       /* wall friction coefficient */
static const double CELL = 0.025;   /* m */
static const double DURATION = 0.4; /* s simulated */
static const double FLOOR_Y = 0.1;  /* m, on a grid line (4 cells up) */
static const double BLOCK_W = 0.2;  /* m */
static const double BLOCK_H = 0.1;  /* m */

static const gm_update_scheme schemes[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                            GM_SCHEME_USF};
static const double angles_degrees[4] = {10.0, 15.0, 30.0, 35.0};

/* Stiff enough that the block is nearly rigid (wave speed ~ 100 m/s), so
 * its centre of mass follows the rigid-block law. */
static const double DENSITY = 2000.0; /* kg/m^3 */
static const double POISSON = 0.3;
/* The block on the floor, carrying the stress of its own weight (see
 * test_block.h). */
static void add_geostatic_block(gm_domain *domain, int material, double theta) {
  test_block block = test_block_on_floor(0.1, FLOOR_Y, BLOCK_W, BLOCK_H, CELL);
  block.weight_stress = DENSITY * GRAVITY * cos(theta); /* Pa/m */
  block.poisson = POISSON;
  test_add_block(domain, material, &block);
}

static int add_block_material(gm_domain *domain) {
  return test_add_elastic(domain, 2e7, POISSON, DENSITY);
}

static double centre_along(const gm_domain *domain, const double direction[2]) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  return summary.centre_of_mass[0] * direction[0] +
         summary.centre_of_mass[1] * direction[1];
}

/* Runs for `duration`; returns the time-averaged normal force of the wall
 * (N): the sum of the steps' normal impulses, divided by the duration. */
static double run(gm_domain *domain, int wall_id, double duration) {
  double time = 0.0, normal_impulse = 0.0;
  while (time < duration) {
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    if (time + dt > duration)
      dt = duration - time;
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    gm_wall_force force = gm_wall_force_default();
    TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, wall_id, &force));
    normal_impulse += force.normal_impulse;
    time += dt;
  }
  return normal_impulse / duration;
}

/* Expected slide (m) after t; 0 when friction holds the block. */
static double expected_slide(double theta, double t) {
  double acceleration = GRAVITY * (sin(theta) - MU * cos(theta));
  return acceleration > 0.0 ? 0.5 * acceleration * t * t : 0.0;
}

/* The slide the block would make without friction, for scale. */
static double frictionless_slide(double theta, double t) {
  return 0.5 * GRAVITY * sin(theta) * t * t;
}

START_TEST(test_rotated_gravity_incline) {
  gm_update_scheme scheme = schemes[_i % 3];
  double theta = angles_degrees[_i / 3] * PI / 180.0;
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = 1.0;
  def.extent[1] = 0.5;
  def.gravity[0] = GRAVITY * sin(theta);
  def.gravity[1] = -GRAVITY * cos(theta);
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default();
  wall.point[1] = FLOOR_Y;
  wall.normal[1] = 1.0;
  wall.friction_static = wall.friction_kinetic = MU;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  int material = add_block_material(domain);
  add_geostatic_block(domain, material, theta);
  const double downslope[2] = {1.0, 0.0};
  double start = centre_along(domain, downslope);
  double mean_normal = run(domain, wall_id, DURATION);
  double slide = centre_along(domain, downslope) - start;
  double expected = expected_slide(theta, DURATION);
  double scale = frictionless_slide(theta, DURATION); /* 0.19-0.42 m */
  if (expected > 0.0) {
    /* 2 % (design.md, issue 12 item 2). Measured at 30 degrees: USL
     * +0.30 % (0.1209 m for 0.1205 m), MUSL +0.39 %, USF +0.25 %; at 35
     * degrees +0.05 / +0.16 / +0.05 %. USL slid 2.4 % too far (MUSL 1.0 %,
     * USF 1.8 %) while the friction strips of this wall on a node row held
     * the row on the plane alone: it carries the column's normal load but a
     * tenth of its tangential momentum, and stuck in some steps (the wall's
     * friction 0.396 of its normal impulse instead of 0.4). The row a cell
     * in front now joins the strips (walls.c, gm_walls_share_friction):
     * friction 0.3995 of the normal impulse. This assert fails on the code
     * before that (USL, 30 degrees). */
    double tolerance = 0.02;
    ck_assert_msg(fabs(slide - expected) < tolerance * expected,
                  "%s, %.0f deg: slid %.6f m, expected %.6f m",
                  test_scheme_name(scheme), angles_degrees[_i / 3], slide,
                  expected);
  } else {
    /* At rest: the elastic settling and the contact of the block's edge
     * nodes, which carry little normal load and can slip in a step, let
     * the centre creep by < 1 % of the frictionless slide (measured
     * 0.3-0.8 % with MUSL and USF, 0 with USL). */
    ck_assert_msg(fabs(slide) < 0.01 * scale,
                  "%s, %.0f deg: slid %.6f m of a frictionless %.6f m, "
                  "should stay at rest",
                  test_scheme_name(scheme), angles_degrees[_i / 3], slide,
                  scale);
  }
  /* On average the wall carries the block's weight component normal to
   * it (the block neither leaves nor enters the wall): within 1 %
   * (measured < 0.7 %; the residual is the start-up transient). */
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  double weight_normal = summary.mass * GRAVITY * cos(theta);
  ck_assert_msg(fabs(mean_normal - weight_normal) < 0.01 * weight_normal,
                "%s: mean wall normal force %g N, weight component %g N",
                test_scheme_name(scheme), mean_normal, weight_normal);
  gm_domain_destroy(domain);
}
END_TEST

/* A wall not aligned with the grid: slope theta as a tilted plane under
 * vertical gravity. The nodes behind the plane form a staircase. A block
 * below the friction angle must stay at rest here too (< 1 % of the
 * frictionless slide). (Sliding along a tilted plane is not asserted: the
 * staircase lets the block ride off the plane and slide ~25 % too far at
 * 30 degrees; see the closing note of the walls work.) */
START_TEST(test_tilted_wall_holds_block) {
  double theta = angles_degrees[_i] * PI / 180.0; /* 10 and 15 degrees */
  gm_domain_def def = gm_domain_def_default();
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = CELL;
  def.extent[0] = 1.2;
  def.extent[1] = 1.0;
  def.gravity[1] = -GRAVITY;
  gm_domain *domain = test_create_domain(&def);
  const double normal[2] = {sin(theta), cos(theta)};   /* into the block */
  const double tangent[2] = {cos(theta), -sin(theta)}; /* downslope */
  const double origin[2] = {0.05, 0.85};               /* m, on the plane */
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = origin[0];
  wall.point[1] = origin[1];
  wall.normal[0] = normal[0];
  wall.normal[1] = normal[1];
  wall.friction_static = wall.friction_kinetic = MU;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  int material = add_block_material(domain);
  /* 16 x 8 points: 0.08 m x 0.04 m, 0.1 m down the plane from origin. */
  test_block block = {{origin[0], origin[1]},
                      {tangent[0], tangent[1]},
                      {normal[0], normal[1]},
                      0.1,
                      8 * CELL,
                      4 * CELL,
                      CELL,
                      DENSITY * GRAVITY * cos(theta),
                      POISSON};
  test_add_block(domain, material, &block);
  double start = centre_along(domain, tangent);
  run(domain, wall_id, DURATION);
  double slide = centre_along(domain, tangent) - start;
  double scale = frictionless_slide(theta, DURATION);
  ck_assert_msg(fabs(slide) < 0.01 * scale,
                "%.0f deg tilted wall: slid %.6f m of a frictionless %.6f m",
                angles_degrees[_i], slide, scale);
  gm_domain_destroy(domain);
}
END_TEST

/* The traction profile along the floor under a block at rest (theta = 0):
 * the nodes' forces add up to the wall's reported force, positions are
 * sorted, and under the middle of the block the normal traction is the
 * weight of the column above, rho g H (geostatic start, so no bounce). */
START_TEST(test_traction_profile) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = CELL;
  def.extent[0] = 1.0;
  def.extent[1] = 0.5;
  def.gravity[1] = -GRAVITY;
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default();
  wall.point[1] = FLOOR_Y;
  wall.friction_static = wall.friction_kinetic = MU;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  int material = add_block_material(domain);
  add_geostatic_block(domain, material, 0.0);
  run(domain, wall_id, 0.05);
  enum { CAPACITY = 64 };
  gm_wall_traction profile[CAPACITY];
  size_t count = 0;
  TEST_ASSERT_OK(domain, gm_domain_get_wall_tractions(domain, wall_id, profile,
                                                      CAPACITY, &count));
  ck_assert_uint_gt(count, 4);
  gm_wall_force force = gm_wall_force_default();
  TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, wall_id, &force));
  double total = 0.0;
  for (size_t i = 0; i < count; i++) {
    if (i > 0)
      ck_assert(profile[i].position > profile[i - 1].position);
    total += profile[i].normal * CELL;
  }
  /* Same nodal forces summed in another order: round-off. */
  ck_assert_msg(fabs(total - force.normal) < 1e-9 * force.normal,
                "profile sums to %.12g N, wall force %.12g N", total,
                force.normal);
  /* The block spans x = 0.1 .. 0.3 m; its middle node at x = 0.2 m. The
   * geostatic start is a discrete equilibrium (measured: 1962.0 Pa at every
   * interior node, half at the two edge nodes); 1 % allows ringing. */
  double column = DENSITY * GRAVITY * BLOCK_H; /* Pa */
  bool checked = false;
  for (size_t i = 0; i < count; i++) {
    if (fabs(profile[i].position - 0.2) > 0.5 * CELL)
      continue;
    ck_assert_msg(fabs(profile[i].normal - column) < 0.01 * column,
                  "traction %g Pa under the middle, rho g H = %g Pa",
                  profile[i].normal, column);
    checked = true;
  }
  ck_assert(checked);
  size_t small = 0;
  ck_assert_int_eq(
      gm_domain_get_wall_tractions(domain, wall_id, profile, 1, &small),
      GM_ERR_INVALID_ARGUMENT); /* too small: count returned */
  ck_assert_uint_eq(small, count);
  gm_domain_destroy(domain);
}
END_TEST

START_TEST(test_wall_arguments) {
  gm_domain_def def = gm_domain_def_default();
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default();
  int id = -1;
  wall.friction_static = 0.2;
  wall.friction_kinetic = 0.3; /* kinetic above static: refused */
  ck_assert_int_eq(gm_domain_add_wall(domain, &wall, &id),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_ptr_nonnull(strstr(gm_domain_last_error(domain), "friction"));
  wall = gm_wall_def_default();
  wall.normal[1] = 0.0; /* zero normal */
  ck_assert_int_eq(gm_domain_add_wall(domain, &wall, &id),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_ptr_nonnull(strstr(gm_domain_last_error(domain), "normal"));
  wall = gm_wall_def_default();
  wall.normal[2] = 1.0; /* out of plane in 2D */
  ck_assert_int_eq(gm_domain_add_wall(domain, &wall, &id),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_int_eq(gm_domain_add_wall(domain, NULL, &id), GM_ERR_NULL);
  gm_wall_force force = gm_wall_force_default();
  ck_assert_int_eq(gm_domain_get_wall_force(domain, 0, &force),
                   GM_ERR_INVALID_ARGUMENT); /* no wall yet */
  wall = gm_wall_def_default();
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &id));
  ck_assert_int_eq(id, 0);
  TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, 0, &force));
  ck_assert(force.normal == 0.0 && force.tangential == 0.0);
  gm_domain_destroy(domain);

  /* The report belongs to the last successful step: a failed one keeps
   * it (here a block resting on the default wall at y = 0 under gravity,
   * then a refused over-long step). */
  def.refuse_unstable_dt = 1;
  def.gravity[1] = -GRAVITY;
  domain = test_create_domain(&def);
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &id));
  int material = add_block_material(domain);
  const double lower[3] = {0.2, 0.0, 0.0}, upper[3] = {0.6, 0.2, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  for (int step = 0; step < 20; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
  gm_wall_force before = gm_wall_force_default();
  TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, id, &before));
  ck_assert(before.normal > 0.0);
  ck_assert_int_eq(gm_domain_step(domain, 1.0), GM_ERR_UNSTABLE_DT);
  gm_wall_force after = gm_wall_force_default();
  TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, id, &after));
  ck_assert(memcmp(&before, &after, sizeof before) == 0);
  gm_domain_destroy(domain);
}
END_TEST

/* A thin layer launched along the floor: the wall's friction must not
 * depend on how the layer sits in the grid. A layer half a cell thick (one
 * row of 2 x 2 points per cell) or two cells thick, 0.15 m long, sliding at
 * 1 m/s on mu = MU stops after v0^2 / (2 mu g), as a rigid slider.
 * docs/convergence.md section 17 leans on this: on a Coulomb floor below
 * the material's friction the base of the column collapse slides, and a
 * sheet thinner than a cell must feel mu g, not less (one feeling part of
 * its friction would run out further on finer grids). The wall is 4 cells
 * above the box face, so nodes behind the plane exist. Linear and
 * B-spline2 shapes; uGIMP is not asserted: its half-cell layer slides
 * 1.8-3.8 % too far (2 % with the wall on the box face), see section 17. */
START_TEST(test_thin_layer_stops) {
  static const gm_shape shapes[2] = {GM_SHAPE_LINEAR, GM_SHAPE_BSPLINE2};
  static const char *const names[2] = {"linear", "B-spline2"};
  const double cell = 0.015, floor_y = 4 * cell, speed = 1.0; /* m, m/s */
  double thickness = (_i / 2 == 0 ? 0.5 : 2.0) * cell;        /* m */
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = cell;
  def.shape = shapes[_i % 2];
  def.extent[0] = 0.6;
  def.extent[1] = floor_y + thickness + 4 * cell;
  def.gravity[1] = -GRAVITY;
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default();
  wall.point[1] = floor_y;
  wall.friction_static = wall.friction_kinetic = MU;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  int material = add_block_material(domain);
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.points_per_cell_axis = 2;
  fill.lower[0] = 0.06;
  fill.upper[0] = 0.21;
  fill.lower[1] = floor_y;
  fill.upper[1] = floor_y + thickness;
  fill.velocity[0] = speed;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  const double along[2] = {1.0, 0.0};
  double start = centre_along(domain, along);
  double stop_time = speed / (MU * GRAVITY); /* s */
  TEST_ASSERT_OK(domain,
                 gm_domain_advance(domain, 1.5 * stop_time, 0.0, NULL, NULL));
  double travel = centre_along(domain, along) - start;
  double expected = speed * speed / (2.0 * MU * GRAVITY); /* 0.127 m */
  /* 1 %: measured travel / expected 1.0002 (linear) and 0.9947
   * (B-spline2) for the half-cell layer, 1.0000 and 0.9999 for two cells;
   * the block slides above hold 2 % with +0.3 %. */
  ck_assert_msg(fabs(travel - expected) < 0.01 * expected,
                "%s, layer %.1f cells: travelled %.5f m, a rigid slider "
                "%.5f m",
                names[_i % 2], thickness / cell, travel, expected);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("friction");
  TCase *tcase = tcase_create("incline");
  tcase_set_timeout(tcase, 120);
  tcase_add_loop_test(tcase, test_rotated_gravity_incline, 0, 12);
  tcase_add_loop_test(tcase, test_tilted_wall_holds_block, 0, 2);
  tcase_add_test(tcase, test_traction_profile);
  tcase_add_test(tcase, test_wall_arguments);
  tcase_add_loop_test(tcase, test_thin_layer_stops, 0, 4);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
