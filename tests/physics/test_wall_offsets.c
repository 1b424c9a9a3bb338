/*
 * test_wall_offsets.c - Coulomb friction of a planar wall that does not lie
 * on a row of grid nodes (issue: a block at 12 deg on mu = 0.3 slid 3 %,
 * 16 % and 76 % of the frictionless distance with the plane 0.2, 0.5 and
 * 0.8 cells above a node row, because only the nodes behind the plane
 * acted; walls.c, gm_walls_contact).
 *
 * An elastic block on a frictional plane (gm_domain_add_wall), 0.02 m
 * cells, 2 x 2 points per cell, placed with the geostatic stress of its
 * weight. Two slopes (design.md, references.md "Block sliding on an
 * incline"): 12 deg on mu = 0.3 sticks (tan 12 deg = 0.21 < 0.3), 40 deg on
 * mu = 0.5 slides s = 1/2 g (sin th - mu cos th) t^2. Two ways to make the
 * slope:
 *  - a horizontal plane under gravity rotated by th, the plane at eight
 *    offsets across one cell above a node row (0, 1/8, ..., 7/8 cells)
 *    and at 0.7, 0.8 and 0.85 cells;
 *  - a tilted plane under vertical gravity (normal along no grid axis) at
 *    four offsets.
 * A third slope, 30 deg on mu = 0.4, is the most sensitive to lost
 * friction (a friction coefficient 1 % short makes it slide 2.3 % too
 * far), and a ninth offset, 0.7 cells, is not a multiple of 1/8: there
 * the block slid +119 % (MUSL, 30 deg) before the nodes in front of the
 * plane joined the friction strips (walls.c, gm_walls_share_friction).
 * Each in USL, MUSL and USF. Asserted: the slide within 2 % of the closed
 * form (slip), or below 2 % of the frictionless slide (stick); the mean
 * normal force of the wall over the second half of the run equal to
 * m g cos th within 1.5 %. Before the first fix (nodes in front of the
 * plane act) 37 of the 60 checks of 12 and 40 deg failed; before the
 * second (they join the friction strips) the slides at 0.625 and 0.7
 * cells and on the tilted plane failed (see check()).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "test_block.h"
#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;   /* m/s^2 */
static const double CELL = 0.02;      /* m */
static const double DURATION = 0.3;   /* s simulated */
static const double BLOCK_W = 0.2;    /* m, along the slope */
static const double BLOCK_H = 0.1;    /* m, normal to it */
static const double DENSITY = 2000.0; /* kg/m^3 */
static const double POISSON = 0.3;
/* Stiff enough to move as a rigid block (wave speed ~100 m/s). */
static const double YOUNGS = 2e7; /* Pa */

typedef struct slope_case {
  double degrees;  /* slope angle */
  double friction; /* mu_s = mu_k */
} slope_case;
enum { SLOPE_COUNT = 3 };
static const slope_case SLOPES[SLOPE_COUNT] = {
    {12.0, 0.3}, {30.0, 0.4}, {40.0, 0.5}};
static const gm_update_scheme SCHEMES[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                            GM_SCHEME_USF};
/* Floor offsets above a node row, cells: eight across the cell, 0.7, and
 * 0.8 and 0.85, where the bottom points lie just above the row in front of
 * the plane and the strips lost friction (see SLIDE_TOLERANCE). */
enum { OFFSET_COUNT = 11, TILTED_OFFSETS = 4 };
static const double OFFSETS[OFFSET_COUNT] = {
    0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 0.7, 0.8, 0.85};
/* Tilted plane offsets (cells, vertical, from a node row): 0.3 and 0.7, and
 * 0.2 and 0.9, where the plane's strips lost friction as the floor's did
 * at 0.8 cells (see SLIDE_TOLERANCE). */
static const double TILTED[TILTED_OFFSETS] = {0.3, 0.7, 0.2, 0.9};

static double centre_along(const gm_domain *domain, const double direction[2],
                           double *mass) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  if (mass)
    *mass = summary.mass;
  return summary.centre_of_mass[0] * direction[0] +
         summary.centre_of_mass[1] * direction[1];
}

/* One run: slide along the tangent (m) and the mean normal force (N). */
typedef struct run_result {
  double slide;
  double mean_normal;
  double mass; /* kg per m */
} run_result;

static run_result run(gm_update_scheme scheme, double theta, double mu,
                      bool tilted, double offset_cells) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = 1.2;
  def.extent[1] = tilted ? 1.0 : 0.4;
  double normal[2], tangent[2], origin[2];
  if (tilted) { /* plane falling to the right at theta, gravity down */
    def.gravity[1] = -GRAVITY;
    normal[0] = sin(theta);
    normal[1] = cos(theta);
    tangent[0] = cos(theta);
    tangent[1] = -sin(theta);
    /* Through (0.1, 0.8 + offset cells) m: off the node rows by offset. */
    origin[0] = 0.1;
    origin[1] = 0.8 + offset_cells * CELL;
  } else { /* floor 4 cells up plus the offset, gravity rotated */
    def.gravity[0] = GRAVITY * sin(theta);
    def.gravity[1] = -GRAVITY * cos(theta);
    normal[0] = 0.0;
    normal[1] = 1.0;
    tangent[0] = 1.0;
    tangent[1] = 0.0;
    origin[0] = 0.1;
    origin[1] = (4.0 + offset_cells) * CELL;
  }
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = origin[0];
  wall.point[1] = origin[1];
  wall.normal[0] = normal[0];
  wall.normal[1] = normal[1];
  wall.friction_static = wall.friction_kinetic = mu;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  int material = test_add_elastic(domain, YOUNGS, POISSON, DENSITY);
  test_block block = {{origin[0], origin[1]},
                      {tangent[0], tangent[1]},
                      {normal[0], normal[1]},
                      0.0,
                      BLOCK_W,
                      BLOCK_H,
                      CELL,
                      DENSITY * GRAVITY * cos(theta),
                      POISSON};
  test_add_block(domain, material, &block);
  run_result result;
  double start = centre_along(domain, tangent, &result.mass);
  double time = 0.0;
  double weighted = 0.0, weight = 0.0; /* N s, s */
  while (time < DURATION) {
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    if (time + dt > DURATION)
      dt = DURATION - time;
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    time += dt;
    if (time <= 0.5 * DURATION)
      continue;
    /* The mean normal force since the start, J_n(t) / t, averaged over the
     * second half: J_n(T) / T alone differs from m g cos th by the block's
     * normal momentum at T over m g cos th T, and the elastic vibration
     * (rms normal velocity of the centre of mass 0.02-0.06 m/s, 1-3 % of
     * g cos th T) put it off by up to 4 % at one end time while the
     * average stayed within 1 %. */
    gm_wall_force force = gm_wall_force_default();
    TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, wall_id, &force));
    double impulse = force.total_impulse[0] * normal[0] +
                     force.total_impulse[1] * normal[1]; /* N s */
    weighted += impulse / force.total_duration * dt;
    weight += dt;
  }
  result.mean_normal = weighted / weight;
  result.slide = centre_along(domain, tangent, NULL) - start;
  gm_domain_destroy(domain);
  return result;
}

/* 2 % (design.md, the issue). Measured here at most 1.61 % (MUSL, 30
 * deg, floor 0.875 cells above a row); at 25 and 50 deg, floor offsets 0.3,
 * 0.55, 0.65 and 0.94 cells and tilted planes 0.1, 0.5 and 0.85 cells off
 * a row, at most 1.73 % (before the change below). The floor on a node row
 * at 30 deg in USL slid 2.15 % too far (issue 12 item 2) until the row a
 * cell in front joined the friction strips (walls.c): the row on the plane
 * carried the block's normal load but a small part of its tangential
 * momentum and stuck in some steps (friction 0.396 of the normal impulse);
 * now +0.66 % (friction 0.3989), and this case fails on the code before.
 * The floor 0.7 cells above a row at 40 deg in MUSL slid 2.2 % short
 * (asserted at 3 % until then): the block hops on the wall as it slides
 * (its bottom points sit 0.05 cells below a node row and cross it; the
 * centre rises by up to 0.3 cells), and MUSL's re-map applied the wall's
 * friction again to the re-mapped velocities that move the points, so
 * every landing took friction from the displacement a second time. Without
 * friction in MUSL's re-map (grid_update.c, wall_friction) it slides
 * -0.13 %, and this case fails on the code before.
 * The floor 0.8 and 0.85 cells above a row at 30 deg in USL slid 2.12 %
 * and 2.26 % too far (MUSL 1.83 % at 0.8, USF 1.92 % at 0.85): the bottom
 * points then lie just above the row in front of the plane, that light row
 * alone made each strip, and it stuck while the contact chattered (the
 * wall's friction 0.396 of its normal impulse). With the second row of the
 * bottom points' cells in the strips (walls.c, GM_STRIP_REACH), and the
 * walls' friction in the full update only in every scheme (grid_update.c),
 * +0.61 % and +0.62 %; these two cases fail on the code before. The
 * tilted plane lost friction the same way: 0.2 and 0.9 cells off a row
 * at 30 deg it slid +2.0 / +3.9 % (USL), +2.2 / +5.0 % (MUSL) and +2.9 /
 * +3.2 % (USF) too far before, +0.3 to +0.6 % after; those cases fail on
 * the code before too. Now measured at most +1.38 % (MUSL, 30 deg, floor
 * 0.7 cells) over these offsets, a sweep of 20 floor offsets (0, 0.05,
 * ..., 0.95 cells) at 25, 30 and 40 deg and ten tilted offsets (0, 0.1,
 * ..., 0.9 cells) at 30 and 40 deg (tilted at most +0.86 %). */
static const double SLIDE_TOLERANCE = 0.02;

static void check(gm_update_scheme scheme, const slope_case *slope, bool tilted,
                  double offset_cells) {
  double theta = slope->degrees * PI / 180.0, mu = slope->friction;
  run_result r = run(scheme, theta, mu, tilted, offset_cells);
  double t = DURATION;
  double frictionless = 0.5 * GRAVITY * sin(theta) * t * t; /* m */
  double acceleration = GRAVITY * (sin(theta) - mu * cos(theta));
  double expected = acceleration > 0.0 ? 0.5 * acceleration * t * t : 0.0;
  const char *how = tilted ? "tilted plane" : "rotated gravity";
  if (expected > 0.0) {
    ck_assert_msg(fabs(r.slide - expected) < SLIDE_TOLERANCE * expected,
                  "%s, %s, %.0f deg mu %.1f, plane %.3f cells off a node row: "
                  "slid %.5f m, expected %.5f m (%+.1f %%)",
                  test_scheme_name(scheme), how, slope->degrees, mu,
                  offset_cells, r.slide, expected,
                  100.0 * (r.slide - expected) / expected);
  } else {
    /* At rest: below 2 % of the frictionless slide (the elastic settling
     * and the edge nodes, which carry little normal load, let the centre
     * creep a little; on a node row version 0.1 measured 0.15 %). */
    ck_assert_msg(fabs(r.slide) < 0.02 * frictionless,
                  "%s, %s, %.0f deg mu %.1f, plane %.3f cells off a node row: "
                  "slid %.5f m = %.1f %% of the frictionless %.5f m; should "
                  "stick",
                  test_scheme_name(scheme), how, slope->degrees, mu,
                  offset_cells, r.slide, 100.0 * r.slide / frictionless,
                  frictionless);
  }
  /* The wall carries the weight's normal component on average (the block
   * neither leaves nor enters it). Measured within 1.36 % (MUSL, 30 deg,
   * floor 0.7 cells above a row, where the block hops; 1.03 % before the
   * re-map change, also at 25 and 50 deg, offsets 0.3, 0.55, 0.94 and
   * tilted 0.1, 0.5, 0.85 cells); 1.5 %. */
  double weight_normal = r.mass * GRAVITY * cos(theta); /* N per m */
  double normal_tolerance = 0.015;
  ck_assert_msg(fabs(r.mean_normal - weight_normal) <
                    normal_tolerance * weight_normal,
                "%s, %s, %.0f deg, plane %.3f cells off a node row: mean "
                "normal force %g N, m g cos(theta) = %g N",
                test_scheme_name(scheme), how, slope->degrees, offset_cells,
                r.mean_normal, weight_normal);
}

/* _i: scheme (3) x slope (3) x offset (OFFSET_COUNT, 11). */
START_TEST(test_floor_offsets) {
  check(SCHEMES[_i % 3], &SLOPES[_i / 3 % SLOPE_COUNT], false,
        OFFSETS[_i / (3 * SLOPE_COUNT)]);
}
END_TEST

/* _i: scheme (3) x slope (3) x offset (TILTED). */
START_TEST(test_tilted_plane) {
  check(SCHEMES[_i % 3], &SLOPES[_i / 3 % SLOPE_COUNT], true,
        TILTED[_i / (3 * SLOPE_COUNT)]);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("wall_offsets");
  TCase *tcase = tcase_create("friction off the node rows");
  tcase_set_timeout(tcase, 600);
  /* Floor offsets 0, 0.5, 0.8 and 0.85 cells (the last two where the
   * strips lost friction) and every tilted offset run everywhere; the other
   * seven floor offsets sweep the same code and are tagged slow
   * (tests/README.md). */
  enum { PER_OFFSET = 3 * SLOPE_COUNT };
  tcase_add_loop_test(tcase, test_floor_offsets, 0, PER_OFFSET);
  tcase_add_loop_test(tcase, test_floor_offsets, 4 * PER_OFFSET,
                      5 * PER_OFFSET);
  tcase_add_loop_test(tcase, test_floor_offsets, 9 * PER_OFFSET,
                      OFFSET_COUNT * PER_OFFSET);
  tcase_add_loop_test(tcase, test_tilted_plane, 0, PER_OFFSET * TILTED_OFFSETS);
  suite_add_tcase(suite, tcase);
  TCase *sweep = tcase_create("other floor offsets");
  tcase_set_tags(sweep, "slow");
  tcase_set_timeout(sweep, 600);
  tcase_add_loop_test(sweep, test_floor_offsets, PER_OFFSET, 4 * PER_OFFSET);
  tcase_add_loop_test(sweep, test_floor_offsets, 5 * PER_OFFSET,
                      9 * PER_OFFSET);
  suite_add_tcase(suite, sweep);
  return test_run_suite(suite) ? 1 : 0;
}
