/*
 * test_face_gaps.c - a block released a fraction of a cell above a box
 * face falls onto it (issue: with the floor a slip or fixed box face, a
 * block 0.3-0.7 cells above it hung there, held by the face nodes that
 * carry its bottom points, while the gm_wall planes already took the gap
 * to the material into account; grid_update.c, constrain_faces).
 *
 * An elastic block, 0.2 m x 0.1 m, 0.02 m cells, 2 x 2 points per cell,
 * its bottom at gap g above the floor (the y-min box face, slip or fixed;
 * the side faces slip, far from the block), released from rest under
 * gravity, in USL, MUSL and USF. Asserted:
 *  - the largest downward speed of its centre of mass is the free-fall
 *    impact speed sqrt(2 g g_0) within 2 % (measured 98.4-99.6 % for every
 *    case: the speed is sampled at the ends of steps of ~1e-4 s, up to g dt
 *    = 1e-3 m/s before the impact, and the face takes the material as
 *    touching from 0.01 cells on, grid_update.c: at 0.3 cells that is
 *    1.7 % of the fall height, 0.8 % of the speed);
 *  - it falls the whole gap and no further: the lowest its points come in
 *    0.25 s (impact and rebounds) is where a block standing on the floor
 *    has them, a quarter of a cell up (their domains' edges on the face),
 *    within 0.05 cells (measured 0.0053-0.0079 cells above it: the 0.01
 *    cells of the face's release gap);
 *  - it has not gained energy: kinetic energy after 0.25 s below the
 *    m g g_0 it fell by (measured 5-44 % of it; the elastic block
 *    rebounds, so it is not at rest).
 * Before the fix all 18 cases failed: the block at 0.3 and 0.7 cells hung
 * (largest speed 1.3-1.8 % of the impact speed), and the one at 1.5 cells
 * was held as its bottom points came within a cell of the face (71 %).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_block.h"
#include "test_util.h"

static const double GRAVITY = 9.81;   /* m/s^2 */
static const double CELL = 0.02;      /* m */
static const double BLOCK_W = 0.2;    /* m */
static const double BLOCK_H = 0.1;    /* m */
static const double DENSITY = 2000.0; /* kg/m^3 */
static const double SETTLED = 0.25;   /* s: impact and a few bounces */

static const gm_update_scheme SCHEMES[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                            GM_SCHEME_USF};
static const gm_wall_type FLOORS[2] = {GM_WALL_SLIP, GM_WALL_FIXED};
static const double GAPS[3] = {0.3, 0.7, 1.5}; /* cells */

/* _i: scheme (3) x floor (2) x gap (3). */
START_TEST(test_block_falls_onto_face) {
  gm_update_scheme scheme = SCHEMES[_i % 3];
  gm_wall_type floor = FLOORS[_i / 3 % 2];
  double gap_cells = GAPS[_i / 6];
  const char *name = floor == GM_WALL_SLIP ? "slip" : "fixed";
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = 0.4;
  def.extent[1] = 0.4;
  def.gravity[1] = -GRAVITY;
  def.walls[GM_FACE_YMIN] = floor;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  gm_domain *domain = test_create_domain(&def);
  /* Stiff enough to fall as a rigid block (wave speed ~100 m/s). */
  int material = test_add_elastic(domain, 2e7, 0.3, DENSITY);
  double gap = gap_cells * CELL; /* m */
  test_block block = test_block_on_floor(0.1, gap, BLOCK_W, BLOCK_H, CELL);
  test_add_block(domain, material, &block);
  double impact_speed = sqrt(2.0 * GRAVITY * gap);                 /* m/s */
  double fastest = 0.0, time = 0.0, mass = 0.0, lowest = INFINITY; /* m */
  while (time < SETTLED) {
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    time += dt;
    gm_summary summary = gm_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
    mass = summary.mass;
    fastest = fmax(fastest, -summary.momentum[1] / summary.mass);
    const double *y = NULL;
    TEST_ASSERT_OK(domain,
                   gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
    for (size_t p = 0; p < gm_domain_point_count(domain); p++)
      lowest = fmin(lowest, y[p]);
  }
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  printf("%-4s %-5s floor, %.1f cells: fastest fall %.1f %% of sqrt(2 g gap), "
         "lowest point %.4f cells, kinetic energy %.1f %% of m g gap\n",
         test_scheme_name(scheme), name, gap_cells,
         100.0 * fastest / impact_speed, lowest / CELL,
         100.0 * summary.kinetic_energy / (mass * GRAVITY * gap));
  ck_assert_msg(fabs(fastest - impact_speed) < 0.02 * impact_speed,
                "%s, %s floor, %.1f cells above it: fastest fall %.4f m/s, "
                "free-fall impact speed %.4f m/s (%.1f %%)",
                test_scheme_name(scheme), name, gap_cells, fastest,
                impact_speed, 100.0 * fastest / impact_speed);
  ck_assert_msg(fabs(lowest - 0.25 * CELL) < 0.05 * CELL,
                "%s, %s floor, %.1f cells above it: the points came down "
                "to %.4f cells in %.2f s; standing on the floor: 0.25",
                test_scheme_name(scheme), name, gap_cells, lowest / CELL,
                SETTLED);
  ck_assert_msg(summary.kinetic_energy < mass * GRAVITY * gap,
                "%s, %s floor, %.1f cells above it: kinetic energy %g J/m "
                "after the fall, more than the m g gap = %g J/m it fell by",
                test_scheme_name(scheme), name, gap_cells,
                summary.kinetic_energy, mass * GRAVITY * gap);
  gm_domain_destroy(domain);
}
END_TEST

/* A point centre at the slip face x = 0 must not pass it with the shapes
 * wider than a tent (issue: the uGIMP granular slot silo of
 * examples/papers/wieckowski1999_silo_discharge.c, cell 0.0125 m, lost
 * point 6578 through its symmetry face, x = -7.6e-7 m at t = 0.619 s, just
 * after the orifice opened). The face holds its face and ghost nodes while
 * the material touches it, but a point on the face gathers from the node
 * a cell in front too (uGIMP, 2 x 2 points per cell: 1/16 of its
 * velocity), which the face did not constrain.
 *
 * An elastic block, 5 x 5 cells of 2 x 2 points, its left column's centres
 * on the face (the state the silo's point had reached), moving toward it at
 * 1 m/s under gravity, on a slip floor. Asserted: every step is taken (a
 * centre past the face fails the step, "would leave the grid box") and
 * after every 2 ms of 20 ms no point centre lies left of the face,
 * tolerance 0 (the face is a geometric bound; a leak is the weight of the
 * free node times its velocity, ~1e-5 m per step, far above rounding). */
static const gm_shape CENTRE_SHAPES[3] = {GM_SHAPE_LINEAR, GM_SHAPE_UGIMP,
                                          GM_SHAPE_UGIMP};
static const gm_transfer CENTRE_TRANSFERS[3] = {
    GM_TRANSFER_FLIP, GM_TRANSFER_FLIP, GM_TRANSFER_APIC};

/* The smallest x of a point centre (m). */
static double leftmost_centre(const gm_domain *domain) {
  const double *x = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  double leftmost = INFINITY;
  for (size_t p = 0; p < gm_domain_point_count(domain); p++)
    leftmost = fmin(leftmost, x[p]);
  return leftmost;
}

/* _i: case (3). */
START_TEST(test_no_centre_through_face) {
  gm_domain_def def = gm_domain_def_default();
  def.shape = CENTRE_SHAPES[_i];
  def.transfer = CENTRE_TRANSFERS[_i];
  def.cell_size = CELL;
  def.extent[0] = 0.3;
  def.extent[1] = 0.3;
  def.gravity[1] = -GRAVITY;
  for (int face = 0; face < 4; face++)
    def.walls[face] = GM_WALL_SLIP;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, DENSITY);
  enum { COLUMNS = 10, ROWS = 10 };
  double spacing = CELL / 2.0; /* m */
  static double position[COLUMNS * ROWS * 2], volume[COLUMNS * ROWS],
      velocity[COLUMNS * ROWS * 2];
  for (int j = 0; j < ROWS; j++)
    for (int i = 0; i < COLUMNS; i++) {
      int p = j * COLUMNS + i;
      position[2 * p] = i * spacing;
      position[2 * p + 1] = (j + 0.5) * spacing;
      velocity[2 * p] = -1.0; /* m/s, toward the face */
      velocity[2 * p + 1] = 0.0;
      volume[p] = spacing * spacing;
    }
  test_add_points(domain, material, COLUMNS * ROWS, position, velocity, volume);
  const char *name = test_shape_name(def.shape);
  const char *transfer = def.transfer == GM_TRANSFER_APIC ? "APIC" : "FLIP";
  for (int k = 1; k <= 10; k++) {
    TEST_ASSERT_OK(domain,
                   gm_domain_advance(domain, 0.002 * k, 0.0, NULL, NULL));
    double leftmost = leftmost_centre(domain);
    ck_assert_msg(leftmost >= 0.0,
                  "%s, %s: a point centre at x = %g m, past the face, at "
                  "t = %g s",
                  name, transfer, leftmost, 0.002 * k);
  }
  printf("%s %s: leftmost centre %.3g cells from the face after 20 ms\n", name,
         transfer, leftmost_centre(domain) / CELL);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("face_gaps");
  TCase *tcase = tcase_create("block falling onto a box face");
  tcase_set_timeout(tcase, 120);
  tcase_add_loop_test(tcase, test_block_falls_onto_face, 0, 3 * 2 * 3);
  suite_add_tcase(suite, tcase);
  TCase *centres = tcase_create("point centre on a box face");
  tcase_add_loop_test(centres, test_no_centre_through_face, 0, 3);
  suite_add_tcase(suite, centres);
  return test_run_suite(suite) ? 1 : 0;
}
