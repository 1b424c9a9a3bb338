/*
 * test_face_gaps_3d.c - a block released a fraction of a cell above a box
 * face falls onto it in 3D (issue 16 item 1: the box faces of 3D held
 * every face node their material reached, so a block 0.3-0.7 cells above
 * a slip or fixed floor hung there, as the 2D faces did before
 * tests/physics/test_face_gaps.c; grid_update_3d.c, wall_gaps_3d.c).
 *
 * An elastic cuboid, 0.1 x 0.1 x 0.06 m, 0.02 m cells, 2 x 2 x 2 points
 * per cell, its bottom at gap g above the floor (the z-min box face, slip
 * or fixed: the third axis, which the 2D test cannot reach; the side faces
 * slip, three cells from the block), released from rest under gravity
 * along -z. Linear shapes in USL, MUSL and USF, uGIMP and CPDI in USL.
 * Asserted as
 * in 2D:
 *  - the largest downward speed of its centre of mass is the free-fall
 *    impact speed sqrt(2 g g_0) within 2 % (the speed is sampled at the
 *    ends of steps of ~1e-4 s, up to g dt = 1e-3 m/s before the impact,
 *    and the face takes the material as touching from 0.01 cells on: at
 *    0.3 cells that is 1.7 % of the fall height, 0.8 % of the speed);
 *  - it falls the whole gap and no further: the lowest its points come in
 *    0.25 s is where a block standing on the floor has them, a quarter of
 *    a cell up (their domains' edges on the face), within 0.05 cells;
 *  - it has not gained energy: kinetic energy after 0.25 s below the
 *    m g g_0 it fell by.
 * Before this change (the 3D faces held their nodes regardless of the gap)
 * the blocks at 0.3 and 0.7 cells hung and the one at 1.5 cells was held
 * as its bottom points came within a cell of the face (the measured
 * fractions are in the commit message).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_util.h"

static const double GRAVITY = 9.81;   /* m/s^2 */
static const double CELL = 0.02;      /* m */
static const double BLOCK_W = 0.1;    /* m, along x and y */
static const double BLOCK_H = 0.06;   /* m, along z */
static const double DENSITY = 2000.0; /* kg/m^3 */
static const double SETTLED = 0.25;   /* s: impact and a few bounces */

static const gm_update_scheme SCHEMES[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                            GM_SCHEME_USF};
static const gm_wall_type FLOORS[2] = {GM_WALL_SLIP, GM_WALL_FIXED};
static const double GAPS[3] = {0.3, 0.7, 1.5}; /* cells */

/* The cuboid, its corner at (0.06, 0.06, gap) m, at rest. */
static void add_block(gm_domain *domain, int material, double gap) {
  enum { PER_AXIS = 2 };
  int across = (int)lround(BLOCK_W / CELL) * PER_AXIS;
  int up = (int)lround(BLOCK_H / CELL) * PER_AXIS;
  size_t count = (size_t)(across * across * up);
  double spacing = CELL / PER_AXIS; /* m */
  double *position = malloc(count * 3 * sizeof(double));
  double *volume = malloc(count * sizeof(double));
  ck_assert(position && volume);
  size_t p = 0;
  for (int k = 0; k < up; k++)
    for (int j = 0; j < across; j++)
      for (int i = 0; i < across; i++, p++) {
        position[3 * p + 0] = 0.06 + (i + 0.5) * spacing;
        position[3 * p + 1] = 0.06 + (j + 0.5) * spacing;
        position[3 * p + 2] = gap + (k + 0.5) * spacing;
        volume[p] = spacing * spacing * spacing;
      }
  test_add_points(domain, material, count, position, NULL, volume);
  free(position);
  free(volume);
}

/* _i: linear with scheme (3) x floor (2) x gap (3), then uGIMP and CPDI in
 * USL with floor (2) x gap (3). */
START_TEST(test_block_falls_onto_face_3d) {
  bool wide = _i >= 18;
  int k = wide ? (_i - 18) % 6 : _i;
  gm_update_scheme scheme = wide ? GM_SCHEME_USL : SCHEMES[k % 3];
  gm_wall_type floor = wide ? FLOORS[k % 2] : FLOORS[k / 3 % 2];
  double gap_cells = wide ? GAPS[k / 2] : GAPS[k / 6];
  gm_shape shape = !wide     ? GM_SHAPE_LINEAR
                   : _i < 24 ? GM_SHAPE_UGIMP
                             : GM_SHAPE_CPDI;
  const char *name = floor == GM_WALL_SLIP ? "slip" : "fixed";
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = shape;
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = def.extent[1] = 0.22;
  def.extent[2] = 0.16;
  def.gravity[2] = -GRAVITY;
  def.walls[GM_FACE_ZMIN] = floor;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  def.walls[GM_FACE_YMIN] = def.walls[GM_FACE_YMAX] = GM_WALL_SLIP;
  gm_domain *domain = test_create_domain(&def);
  /* Stiff enough to fall as a rigid block (wave speed ~100 m/s). */
  int material = test_add_elastic(domain, 2e7, 0.3, DENSITY);
  double gap = gap_cells * CELL; /* m */
  add_block(domain, material, gap);
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
    fastest = fmax(fastest, -summary.momentum[2] / summary.mass);
    const double *z = NULL;
    TEST_ASSERT_OK(domain,
                   gm_domain_view_field(domain, GM_FIELD_POSITION, 2, &z));
    for (size_t p = 0; p < gm_domain_point_count(domain); p++)
      lowest = fmin(lowest, z[p]);
  }
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  printf("%-6s %-4s %-5s floor, %.1f cells: fastest fall %.1f %% of "
         "sqrt(2 g gap), lowest point %.4f cells, kinetic energy %.1f %% of "
         "m g gap\n",
         test_shape_name(shape), test_scheme_name(scheme), name, gap_cells,
         100.0 * fastest / impact_speed, lowest / CELL,
         100.0 * summary.kinetic_energy / (mass * GRAVITY * gap));
  ck_assert_msg(fabs(fastest - impact_speed) < 0.02 * impact_speed,
                "%s %s, %s floor, %.1f cells above it: fastest fall %.4f "
                "m/s, free-fall impact speed %.4f m/s (%.1f %%)",
                test_shape_name(shape), test_scheme_name(scheme), name,
                gap_cells, fastest, impact_speed,
                100.0 * fastest / impact_speed);
  ck_assert_msg(fabs(lowest - 0.25 * CELL) < 0.05 * CELL,
                "%s %s, %s floor, %.1f cells above it: the points came down "
                "to %.4f cells in %.2f s; standing on the floor: 0.25",
                test_shape_name(shape), test_scheme_name(scheme), name,
                gap_cells, lowest / CELL, SETTLED);
  ck_assert_msg(summary.kinetic_energy < mass * GRAVITY * gap,
                "%s %s, %s floor, %.1f cells above it: kinetic energy %g J "
                "after the fall, more than the m g gap = %g J it fell by",
                test_shape_name(shape), test_scheme_name(scheme), name,
                gap_cells, summary.kinetic_energy, mass * GRAVITY * gap);
  gm_domain_destroy(domain);
}
END_TEST

/* A symmetry plane (GM_WALL_SYMMETRY) holds the normal velocity of its
 * face nodes whatever the gap, as v0.1 held every face: the quarter column
 * of examples/column_collapse_3d.c needs that on its planes x = 0 and
 * y = 0 (with them released as slip faces its run-out at R0/6 moved from
 * -4.3 % to -5.3 % against the axisymmetric run, outside the 5 % of
 * tests/scripts/collapse_3d_axisym.sh). Asserted: the block 0.3 cells above
 * a symmetry floor does not fall (its fastest fall below 2 % of the impact
 * speed; measured 1.2 %, the speed its points gain before the held nodes
 * stop them), where the same block on a slip floor reaches 98.4 %. */
START_TEST(test_symmetry_face_holds) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.cell_size = CELL;
  def.extent[0] = def.extent[1] = 0.22;
  def.extent[2] = 0.16;
  def.gravity[2] = -GRAVITY;
  def.walls[GM_FACE_ZMIN] = GM_WALL_SYMMETRY;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 2e7, 0.3, DENSITY);
  double gap = 0.3 * CELL; /* m */
  add_block(domain, material, gap);
  double fastest = 0.0, time = 0.0; /* m/s, s */
  while (time < 0.1) {
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    time += dt;
    gm_summary summary = gm_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
    fastest = fmax(fastest, -summary.momentum[2] / summary.mass);
  }
  double impact_speed = sqrt(2.0 * GRAVITY * gap); /* m/s */
  printf("symmetry floor, 0.3 cells: fastest fall %.1f %% of sqrt(2 g gap)\n",
         100.0 * fastest / impact_speed);
  ck_assert_msg(fastest < 0.02 * impact_speed,
                "symmetry floor: the block fell at up to %.4f m/s (%.1f %% "
                "of the impact speed); the plane should hold its nodes",
                fastest, 100.0 * fastest / impact_speed);
  gm_domain_destroy(domain);
}
END_TEST

/* A point centre on a 3D slip or fixed box face is not carried out of the
 * box (the 2D faces' rule, tests/physics/test_face_gaps.c: a uGIMP point
 * on the face gathers from the node a cell in front as well, which the
 * face does not hold; grid_update_3d.c, limit_face_centres_3d). An elastic
 * cube of 4 x 4 x 4 cells (2 x 2 x 2 points per cell, E = 1e6 Pa) whose
 * x-most layer of centres lies on the x = 0 face moves toward it at 1 m/s,
 * on a slip floor under gravity, with uGIMP (FLIP and APIC), cpGIMP and
 * CPDI; the face slip, or fixed for uGIMP, or (uGIMP and CPDI) open with
 * a Coulomb wall (mu 0.3) on its plane, whose wide-shape centre gaps are
 * the same rule (walls_3d.c). Asserted: every step is taken
 * (a centre past the face fails it, "would leave the grid box") and after
 * every 2 ms of 20 ms no point centre lies left of the face, tolerance 0
 * (a geometric bound; a leak is the free node's weight times its
 * velocity, ~1e-5 m per step). Before: every case failed its first step
 * (a centre at x = -2.3e-5 m with uGIMP and cpGIMP, -4.6e-5 m with CPDI,
 * t = 3.7e-4 s; through the wall -2.3e-5 m with uGIMP, -4.6e-5 m with
 * CPDI: that wall had no centre gaps while it lay on an open face). */
typedef struct face_centre_case {
  gm_shape shape;
  gm_transfer transfer;
  gm_wall_type face;
} face_centre_case;

static const face_centre_case FACE_CENTRE_CASES[] = {
    {GM_SHAPE_UGIMP, GM_TRANSFER_FLIP, GM_WALL_SLIP},
    {GM_SHAPE_UGIMP, GM_TRANSFER_APIC, GM_WALL_SLIP},
    {GM_SHAPE_UGIMP, GM_TRANSFER_FLIP, GM_WALL_FIXED},
    {GM_SHAPE_CPGIMP, GM_TRANSFER_FLIP, GM_WALL_SLIP},
    {GM_SHAPE_CPDI, GM_TRANSFER_FLIP, GM_WALL_SLIP},
    {GM_SHAPE_UGIMP, GM_TRANSFER_FLIP, GM_WALL_OPEN},
    {GM_SHAPE_CPDI, GM_TRANSFER_FLIP, GM_WALL_OPEN},
};
enum {
  FACE_CENTRE_COUNT = sizeof FACE_CENTRE_CASES / sizeof FACE_CENTRE_CASES[0]
};

START_TEST(test_no_centre_through_face_3d) {
  const face_centre_case *c = &FACE_CENTRE_CASES[_i];
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = c->shape;
  def.transfer = c->transfer;
  def.cell_size = CELL;
  for (int k = 0; k < 3; k++)
    def.extent[k] = 0.16;
  def.gravity[2] = -GRAVITY;
  for (int face = 0; face < 6; face++)
    def.walls[face] = GM_WALL_SLIP;
  def.walls[GM_FACE_XMIN] = c->face;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, DENSITY);
  if (c->face == GM_WALL_OPEN) { /* a frictional face: the plane x = 0 */
    gm_wall_def wall = gm_wall_def_default();
    wall.normal[0] = 1.0;
    wall.normal[1] = 0.0;
    wall.friction_static = wall.friction_kinetic = 0.3;
    int wall_id = -1;
    TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  }
  enum { SIDE = 8, COUNT = SIDE * SIDE * SIDE };
  double spacing = CELL / 2.0; /* m */
  static double position[COUNT * 3], volume[COUNT], velocity[COUNT * 3];
  int p = 0;
  for (int k = 0; k < SIDE; k++)
    for (int j = 0; j < SIDE; j++)
      for (int i = 0; i < SIDE; i++, p++) {
        position[3 * p] = i * spacing; /* the first layer on the face */
        position[3 * p + 1] = 0.04 + (j + 0.5) * spacing;
        position[3 * p + 2] = (k + 0.5) * spacing;
        velocity[3 * p] = -1.0; /* m/s, toward the face */
        velocity[3 * p + 1] = velocity[3 * p + 2] = 0.0;
        volume[p] = spacing * spacing * spacing;
      }
  test_add_points(domain, material, COUNT, position, velocity, volume);
  const char *name = test_shape_name(c->shape);
  const char *transfer = c->transfer == GM_TRANSFER_APIC ? "APIC" : "FLIP";
  const char *face = c->face == GM_WALL_FIXED  ? "fixed"
                     : c->face == GM_WALL_SLIP ? "slip"
                                               : "open with a wall";
  for (int check = 1; check <= 10; check++) {
    gm_status status =
        gm_domain_advance(domain, 0.002 * check, 0.0, NULL, NULL);
    ck_assert_msg(status == GM_OK, "3D %s, %s, %s face: %s", name, transfer,
                  face, gm_domain_last_error(domain));
    const double *x = NULL;
    TEST_ASSERT_OK(domain,
                   gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
    double leftmost = INFINITY; /* m */
    for (size_t q = 0; q < gm_domain_point_count(domain); q++)
      leftmost = fmin(leftmost, x[q]);
    ck_assert_msg(leftmost >= 0.0,
                  "3D %s, %s, %s face: a point centre at x = %g m, past the "
                  "face, at t = %g s",
                  name, transfer, face, leftmost, 0.002 * check);
  }
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("face_gaps_3d");
  /* The 0.3-cell gap (the one that hung before, in every scheme, floor and
   * shape) runs everywhere; the 0.7- and 1.5-cell gaps sweep the same code
   * with more steps of fall and are tagged slow (tests/README.md): 30 cases
   * took 340 s of CPU under AddressSanitizer. */
  TCase *tcase = tcase_create("block falling onto a 3D box face");
  tcase_set_timeout(tcase, 300);
  tcase_add_loop_test(tcase, test_block_falls_onto_face_3d, 0, 6);
  tcase_add_loop_test(tcase, test_block_falls_onto_face_3d, 18, 20);
  tcase_add_loop_test(tcase, test_block_falls_onto_face_3d, 24, 26);
  suite_add_tcase(suite, tcase);
  TCase *sweep = tcase_create("larger gaps");
  tcase_set_tags(sweep, "slow");
  tcase_set_timeout(sweep, 300);
  tcase_add_loop_test(sweep, test_block_falls_onto_face_3d, 6, 18);
  tcase_add_loop_test(sweep, test_block_falls_onto_face_3d, 20, 24);
  tcase_add_loop_test(sweep, test_block_falls_onto_face_3d, 26, 30);
  suite_add_tcase(suite, sweep);
  TCase *symmetry = tcase_create("symmetry plane");
  tcase_add_test(symmetry, test_symmetry_face_holds);
  suite_add_tcase(suite, symmetry);
  TCase *centres = tcase_create("point centre on a 3D box face");
  tcase_set_timeout(centres, 120);
  tcase_add_loop_test(centres, test_no_centre_through_face_3d, 0,
                      FACE_CENTRE_COUNT);
  suite_add_tcase(suite, centres);
  return test_run_suite(suite) ? 1 : 0;
}
