/*
 * test_face_mirror_walls.c - a planar wall near a box face that the
 * B-spline shapes mirror, in 1D, plane strain and axisymmetry (walls.c,
 * check_bspline_mirrors; the 3D rows are test_face_friction_3d.c's
 * test_which_walls).
 *
 * With the B-splines a slip, fixed or symmetry face (and the axis r = 0
 * in axisymmetry) acts by images (grid/bspline_faces.c): after the grid
 * update its ghost nodes take their mirror nodes' reflected velocities,
 * which overwrites what a wall on or near that plane did to them. Until
 * 2026-11-29 only 3D refused such a wall; in 1D and 2D it was accepted and
 * its friction lost. A block at 0.6 m/s on a floor wall of mu = 0.2 on the
 * plane of a slip ymin face (quadratic B-spline, USL) kept 0.600 m/s to
 * 0.3 s on 0.05, 0.025 and 0.0125 m cells, where Coulomb's law gives
 * 0.208 m/s at 0.2 s, and the wall reported no impulse at all (the face
 * holds its nodes first); on a fixed ymin face the block stuck (no slip)
 * instead of sliding 0.092 m; with the floor 0.5 and 1 cell above a slip
 * face it was +27 and +7 % of v0 fast at 0.2 s on 0.05 m cells.
 *
 * Refusal (test_refused): a wall parallel to such a face and less than a
 * support radius (1.5 cells quadratic, 2 cubic) from its plane, in front
 * of it or behind, is refused with GM_ERR_UNSUPPORTED, the message naming
 * the face and the distance in cells, and the domain keeps its walls (the
 * next valid wall gets the next id). A wall exactly a radius from the
 * plane, farther in, oblique, or on an open face's plane is accepted.
 *
 * The supported way (test_open_face_slide): the same block on a wall on
 * the plane of the ymin face left GM_WALL_OPEN decelerates at mu g,
 *   v(t) = v0 - mu g t  until t_s = v0 / (mu g),  s_stop = v0^2 / (2 mu g)
 * (references.md "Block sliding on an incline" at zero slope).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

static const double GRAVITY = 9.81;   /* m/s^2 */
static const double BLOCK_W = 0.2;    /* m, along x */
static const double BLOCK_H = 0.1;    /* m, along y */
static const double DENSITY = 2000.0; /* kg/m^3 */
static const double POISSON = 0.3;
static const double YOUNGS = 2e7;   /* Pa: wave speed 100 m/s */
static const double FRICTION = 0.2; /* mu_s = mu_k */
static const double SPEED = 0.6;    /* m/s, v0 along x */

/* The box (0.8 x 0.4 m, plane strain, quadratic B-spline, cells of
 * `cell` m) with its ymin face `ymin`, the floor wall y = 0 of friction
 * FRICTION, and the block (2 x 2 points per cell, its corner at (0.1, 0)
 * m, the uniaxial stress of its weight) moving at SPEED along x. */
static gm_domain *slide_scene(gm_wall_type ymin, double cell) {
  gm_domain_def def = gm_domain_def_default();
  def.shape = GM_SHAPE_BSPLINE2;
  def.cell_size = cell;
  def.extent[0] = 0.8;
  def.extent[1] = 0.4;
  def.gravity[1] = -GRAVITY;
  def.walls[GM_FACE_YMIN] = ymin;
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default(); /* y = 0, normal (0, 1, 0) */
  wall.friction_static = wall.friction_kinetic = FRICTION;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  int material = test_add_elastic(domain, YOUNGS, POISSON, DENSITY);
  enum { PER_AXIS = 2 };
  int across = (int)lround(BLOCK_W / cell) * PER_AXIS;
  int up = (int)lround(BLOCK_H / cell) * PER_AXIS;
  size_t count = (size_t)(across * up);
  double spacing = cell / PER_AXIS; /* m */
  double *position = malloc(count * 2 * sizeof(double));
  double *velocity = malloc(count * 2 * sizeof(double));
  double *volume = malloc(count * sizeof(double));
  double *stress = calloc(count * 6, sizeof(double));
  ck_assert(position && velocity && volume && stress);
  size_t p = 0;
  for (int j = 0; j < up; j++)
    for (int i = 0; i < across; i++, p++) {
      double height = (j + 0.5) * spacing; /* m */
      position[2 * p + 0] = 0.1 + (i + 0.5) * spacing;
      position[2 * p + 1] = height;
      velocity[2 * p + 0] = SPEED;
      velocity[2 * p + 1] = 0.0;
      volume[p] = spacing * spacing;
      stress[6 * p + GM_YY] = -DENSITY * GRAVITY * (BLOCK_H - height);
    }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  points.stress = stress;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  free(position);
  free(velocity);
  free(volume);
  free(stress);
  return domain;
}

/* Centre of mass x (m) and its velocity along x (m/s). */
static void centre_x(const gm_domain *domain, double *x, double *v) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  *x = summary.centre_of_mass[0];
  *v = summary.momentum[0] / summary.mass;
}

/* Steps to `until` (s) from `*time` with the stable dt. */
static void advance(gm_domain *domain, double *time, double until) {
  while (*time < until) {
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    if (*time + dt > until)
      dt = until - *time;
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    *time += dt;
  }
}

/* 2 %: the tolerance for the sliding block (issue 16 item 3), as
 * test_face_friction_3d.c. Measured on 0.05, 0.025 and 0.0125 m cells:
 * the velocity within +0.34 % of v0 at 0.1, 0.2 and 0.3 s, the stopping
 * distance -0.04, +0.11 and -0.04 % off; a lost friction (the wall on a
 * slip face's plane) is +65 % of v0 at 0.2 s. The velocity is compared
 * with 2 % of v0 (an absolute error; near the stop the relative one is
 * meaningless). */
static const double TOLERANCE = 0.02;

START_TEST(test_open_face_slide) {
  const double cell = 0.05; /* m */
  gm_domain *domain = slide_scene(GM_WALL_OPEN, cell);
  double deceleration = FRICTION * GRAVITY;           /* m/s^2 */
  double stop_time = SPEED / deceleration;            /* s */
  double stop = SPEED * SPEED / (2.0 * deceleration); /* m */
  double x0, x, v, time = 0.0;
  centre_x(domain, &x0, &v);
  static const double SAMPLES[3] = {0.1, 0.2, 0.3}; /* s */
  for (int s = 0; s < 3; s++) {
    advance(domain, &time, SAMPLES[s]);
    centre_x(domain, &x, &v);
    double expected = SPEED - deceleration * time; /* m/s */
    printf("open ymin face, t %.2f s: v %.5f m/s (closed form %.5f, %+.2f "
           "%% of v0)\n",
           time, v, expected, 100.0 * (v - expected) / SPEED);
    ck_assert_msg(fabs(v - expected) < TOLERANCE * SPEED,
                  "t = %.2f s: velocity %.5f m/s, closed form %.5f m/s "
                  "(%+.2f %% of v0)",
                  time, v, expected, 100.0 * (v - expected) / SPEED);
  }
  advance(domain, &time, stop_time + 0.1);
  centre_x(domain, &x, &v);
  /* The friction impulse is the momentum the block lost: m v0 (N s per
   * unit thickness). */
  double mass = DENSITY * BLOCK_W * BLOCK_H; /* kg/m */
  gm_wall_force force = gm_wall_force_default();
  TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, 0, &force));
  printf("open ymin face: stopped after %.5f m (closed form %.5f m, %+.2f "
         "%%), final speed %.2e m/s, friction impulse %.4f N s (m v0 = "
         "%.4f)\n",
         x - x0, stop, 100.0 * (x - x0 - stop) / stop, v,
         -force.total_impulse[0], mass * SPEED);
  ck_assert_msg(fabs(x - x0 - stop) < TOLERANCE * stop,
                "stopping distance %.5f m, closed form %.5f m (%+.2f %%)",
                x - x0, stop, 100.0 * (x - x0 - stop) / stop);
  ck_assert_msg(fabs(v) < TOLERANCE * SPEED,
                "still moving at %.4f m/s after the stop", v);
  ck_assert_msg(fabs(-force.total_impulse[0] - mass * SPEED) <
                    TOLERANCE * mass * SPEED,
                "friction impulse %.4f N s, momentum lost m v0 = %.4f N s",
                -force.total_impulse[0], mass * SPEED);
  gm_domain_destroy(domain);
}
END_TEST

/* Cells of 1/16 m, so that every distance below is exact in binary and a
 * wall exactly a radius from a plane is not a rounding off it. */
static const double REFUSAL_CELL = 0.0625; /* m */
static const double REFUSAL_BOX = 0.5;     /* m, 8 cells along each axis */

typedef struct mirror_row {
  gm_geometry geometry;
  gm_shape shape;
  int face;          /* GM_FACE_*, the one the wall is parallel to */
  gm_wall_type type; /* that face's condition */
  double inside;     /* cells from its plane into the box (< 0: behind) */
  bool facing_out;   /* the normal points out of the box */
  bool oblique;      /* the normal tilted off the face's axis */
  double origin_x;   /* m, the box's x origin */
  bool accepted;
} mirror_row;

static const mirror_row MIRROR_ROWS[] = {
    /* plane strain, quadratic (radius 1.5 cells) */
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_SLIP,
     0.0, false, false, 0.0, false},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_SLIP,
     1.0, false, false, 0.0, false},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_SLIP,
     -1.25, true, false, 0.0, false},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_SLIP,
     1.5, false, false, 0.0, true},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_SLIP,
     -1.5, false, false, 0.0, true},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_FIXED,
     1.25, false, false, 0.0, false},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMAX,
     GM_WALL_SYMMETRY, 0.5, false, false, 0.0, false},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_XMAX, GM_WALL_FIXED,
     1.0, true, false, 0.0, false},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_SLIP,
     1.5, false, false, 0.0, true},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_OPEN,
     0.0, false, false, 0.0, true},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_SLIP,
     0.0, false, true, 0.0, true},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_UGIMP, GM_FACE_YMIN, GM_WALL_SLIP, 0.0,
     false, false, 0.0, true},
    /* plane strain, cubic (radius 2 cells) */
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE3, GM_FACE_YMIN, GM_WALL_SLIP,
     1.75, false, false, 0.0, false},
    {GM_GEOMETRY_PLANE_STRAIN, GM_SHAPE_BSPLINE3, GM_FACE_YMIN, GM_WALL_SLIP,
     2.0, false, false, 0.0, true},
    /* axisymmetry: the axis r = 0 is a mirror whatever walls[xmin] says */
    {GM_GEOMETRY_AXISYMMETRIC, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_OPEN,
     1.0, false, false, 0.0, false},
    {GM_GEOMETRY_AXISYMMETRIC, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_SLIP,
     1.25, true, false, 0.0, false},
    {GM_GEOMETRY_AXISYMMETRIC, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_SLIP,
     1.5, false, false, 0.0, true},
    {GM_GEOMETRY_AXISYMMETRIC, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_OPEN,
     0.0, false, false, REFUSAL_BOX, true},
    {GM_GEOMETRY_AXISYMMETRIC, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_FIXED,
     0.0, false, false, 0.0, false},
    {GM_GEOMETRY_AXISYMMETRIC, GM_SHAPE_BSPLINE2, GM_FACE_YMIN, GM_WALL_OPEN,
     0.0, false, false, 0.0, true},
    /* 1D: the x faces */
    {GM_GEOMETRY_1D, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_FIXED, 0.0, false,
     false, 0.0, false},
    {GM_GEOMETRY_1D, GM_SHAPE_BSPLINE2, GM_FACE_XMAX, GM_WALL_SLIP, -1.0, true,
     false, 0.0, false},
    {GM_GEOMETRY_1D, GM_SHAPE_BSPLINE3, GM_FACE_XMAX, GM_WALL_SLIP, 1.75, false,
     false, 0.0, false},
    {GM_GEOMETRY_1D, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_FIXED, 1.5, false,
     false, 0.0, true},
    {GM_GEOMETRY_1D, GM_SHAPE_BSPLINE2, GM_FACE_XMIN, GM_WALL_OPEN, 0.0, false,
     false, 0.0, true},
};
enum { MIRROR_ROW_COUNT = sizeof MIRROR_ROWS / sizeof MIRROR_ROWS[0] };

static const char *const FACE_NAMES[4] = {"xmin", "xmax", "ymin", "ymax"};

/* The row's domain: a box of 8 cells along each axis. */
static gm_domain *mirror_domain(const mirror_row *row) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = row->geometry;
  def.shape = row->shape;
  def.cell_size = REFUSAL_CELL;
  def.origin[0] = row->origin_x;
  def.extent[0] = def.extent[1] = REFUSAL_BOX;
  def.walls[row->face] = row->type;
  return test_create_domain(&def);
}

/* A wall through the box's centre, normal x: 4 cells from every face, so
 * accepted in every row's domain. */
static gm_status add_centre_wall(gm_domain *domain, const mirror_row *row,
                                 int *id) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = row->origin_x + 0.5 * REFUSAL_BOX;
  wall.point[1] = row->geometry == GM_GEOMETRY_1D ? 0.0 : 0.5 * REFUSAL_BOX;
  wall.normal[0] = 1.0;
  wall.normal[1] = 0.0;
  return gm_domain_add_wall(domain, &wall, id);
}

START_TEST(test_refused) {
  const mirror_row *row = &MIRROR_ROWS[_i];
  gm_domain *domain = mirror_domain(row);
  int first = -1;
  TEST_ASSERT_OK(domain, add_centre_wall(domain, row, &first));
  ck_assert_int_eq(first, 0);
  int axis = row->face / 2, side = row->face % 2;
  double inward = side ? -1.0 : 1.0; /* the box's side of the face */
  double plane =
      (axis == 0 ? row->origin_x : 0.0) + (side ? REFUSAL_BOX : 0.0); /* m */
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = row->origin_x + 0.5 * REFUSAL_BOX;
  wall.point[1] = row->geometry == GM_GEOMETRY_1D ? 0.0 : 0.5 * REFUSAL_BOX;
  wall.point[axis] = plane + inward * row->inside * REFUSAL_CELL;
  wall.normal[0] = wall.normal[1] = 0.0;
  wall.normal[axis] = row->facing_out ? -inward : inward;
  if (row->oblique)
    wall.normal[1 - axis] = 0.1;
  int id = -1;
  gm_status status = gm_domain_add_wall(domain, &wall, &id);
  const char *message = gm_domain_last_error(domain);
  if (row->accepted) {
    ck_assert_msg(status == GM_OK && id == 1, "row %d refused: %s", _i,
                  message);
  } else {
    /* The face and the distance, as "lies 1.25 cells from the ymin box
     * face". */
    char expected[96];
    snprintf(expected, sizeof expected, "lies %.3g cells from the %s box face",
             fabs(row->inside), FACE_NAMES[row->face]);
    printf("row %d: %s\n", _i, message);
    ck_assert_msg(status == GM_ERR_UNSUPPORTED && id == -1,
                  "row %d: status %d, id %d (%s); expected a refusal", _i,
                  (int)status, id, message);
    ck_assert_msg(strstr(message, "gm_domain_add_wall") != NULL &&
                      strstr(message, expected) != NULL,
                  "row %d: the message does not say '%s': %s", _i, expected,
                  message);
    if (row->geometry == GM_GEOMETRY_AXISYMMETRIC &&
        row->face == GM_FACE_XMIN && row->origin_x == 0.0)
      ck_assert_msg(strstr(message, "symmetry axis") != NULL,
                    "row %d: the message does not name the axis: %s", _i,
                    message);
    /* The domain keeps its one wall: the next valid one is wall 1. */
    int next = -1;
    TEST_ASSERT_OK(domain, add_centre_wall(domain, row, &next));
    ck_assert_msg(next == 1,
                  "row %d: a valid wall after the refusal got id "
                  "%d, expected 1",
                  _i, next);
  }
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("face_mirror_walls");
  TCase *tcase = tcase_create("walls near B-spline mirror faces");
  tcase_set_timeout(tcase, 600);
  tcase_add_loop_test(tcase, test_refused, 0, MIRROR_ROW_COUNT);
  tcase_add_test(tcase, test_open_face_slide);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) ? 1 : 0;
}
