/*
 * test_wall_watertight.c - no point centre passes through a planar wall
 * with the shapes wider than a tent (issue: the column collapse of
 * docs/convergence.md lost points through its floor wall with APIC on
 * uGIMP, y = -1.2e-7 m at t = 0.37 s, and with the quadratic B-spline,
 * y = -1.0e-6 m at t = 0.33 s; walls.c, gm_walls_contact).
 *
 * A point on the plane gathers its velocity from nodes up to 1 + l_p/h
 * (uGIMP), 1.5 (quadratic B-spline) or 2 cells (cubic) in front of it, and
 * the wall's contact held only the nodes within a cell. Here an elastic
 * block whose bottom row of points has its centres on a Coulomb floor wall
 * (the state the collapse's leaking point had reached, y = 8e-8 m) falls
 * onto it at 1 m/s. The grid box extends two cells below the wall, so a
 * point through the wall stays in the grid and is seen rather than failing
 * the step. Asserted: after every 2 ms of 20 ms no point centre lies below
 * the plane, tolerance 0 (an impenetrable plane is a geometric bound, and
 * a point that leaked did so by the weight of the free node times its
 * velocity, ~1e-4 m per step here, far above rounding). Before the fix
 * every case but linear MPM failed at the first check.
 *
 * In 3D (test_no_centre_through_oblique_wall): the same fall onto a wall
 * inside the grid box whose normal lies along no grid axis, with uGIMP,
 * cpGIMP and CPDI (FLIP) and uGIMP with APIC, which take such walls
 * since 2026-11-28 with the centre-gap rule of 2D (walls_3d.c), and with
 * linear MPM: a node of a cell the oblique plane cuts may lie up to
 * |n_x| + |n_y| + |n_z| = 1.47 cells in front of it, beyond the nodes
 * within a cell that the contact held, and before it got the centre-gap
 * bound (gm_wall_tent_reach, walls.c) a centre was 3.3e-5 m behind the
 * plane at the first check (FLIP and APIC). In 2D
 * (test_no_centre_through_oblique_wall_2d) linear MPM on seven oblique
 * normals, falling and sliding, every update scheme and transfer.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "test_util.h"

static const double CELL = 0.02;      /* m */
static const double DENSITY = 2000.0; /* kg/m^3 */
static const double YOUNGS = 1e6;     /* Pa: wave speed ~24 m/s */
static const double SPEED = 1.0;      /* m/s, toward the wall */

typedef struct leak_case {
  gm_shape shape;
  gm_transfer transfer;
} leak_case;

static const leak_case CASES[] = {
    {GM_SHAPE_LINEAR, GM_TRANSFER_FLIP},
    {GM_SHAPE_UGIMP, GM_TRANSFER_FLIP},
    {GM_SHAPE_UGIMP, GM_TRANSFER_APIC},
    {GM_SHAPE_BSPLINE2, GM_TRANSFER_FLIP},
    {GM_SHAPE_BSPLINE2, GM_TRANSFER_APIC},
    {GM_SHAPE_BSPLINE3, GM_TRANSFER_FLIP},
};
enum { CASE_COUNT = sizeof CASES / sizeof CASES[0] };

/* The lowest point centre above the wall plane y = 0 (m). */
static double lowest_centre(const gm_domain *domain) {
  size_t count = gm_domain_point_count(domain);
  double *position = malloc(count * 2 * sizeof *position);
  ck_assert_ptr_nonnull(position);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             position, count * 2));
  double lowest = INFINITY;
  for (size_t p = 0; p < count; p++)
    lowest = position[2 * p + 1] < lowest ? position[2 * p + 1] : lowest;
  free(position);
  return lowest;
}

START_TEST(test_no_centre_through_floor) {
  const leak_case *c = &CASES[_i];
  gm_domain_def def = gm_domain_def_default();
  def.shape = c->shape;
  def.transfer = c->transfer;
  def.cell_size = CELL;
  def.origin[1] = -2.0 * CELL; /* room below the wall: a leak is visible */
  def.extent[0] = 0.4;
  def.extent[1] = 0.3;
  def.gravity[1] = -9.81;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, YOUNGS, 0.3, DENSITY);
  gm_wall_def wall = gm_wall_def_default();
  wall.normal[1] = 1.0; /* the floor y = 0, on a node row */
  wall.friction_static = wall.friction_kinetic = 0.5;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  /* 10 x 5 cells of 2 x 2 points, the bottom row's centres at y = 0. */
  enum { COLUMNS = 20, ROWS = 10 };
  double spacing = CELL / 2.0; /* m */
  static double position[COLUMNS * ROWS * 2], volume[COLUMNS * ROWS],
      velocity[COLUMNS * ROWS * 2];
  for (int j = 0; j < ROWS; j++)
    for (int i = 0; i < COLUMNS; i++) {
      int p = j * COLUMNS + i;
      position[2 * p] = 0.1 + (i + 0.5) * spacing;
      position[2 * p + 1] = j * spacing;
      velocity[2 * p] = 0.0;
      velocity[2 * p + 1] = -SPEED;
      volume[p] = spacing * spacing;
    }
  test_add_points(domain, material, COLUMNS * ROWS, position, velocity, volume);
  for (int k = 1; k <= 10; k++) {
    TEST_ASSERT_OK(domain,
                   gm_domain_advance(domain, 0.002 * k, 0.0, NULL, NULL));
    double lowest = lowest_centre(domain);
    ck_assert_msg(lowest >= 0.0,
                  "%s, %s: a point centre at y = %g m, behind the wall, at "
                  "t = %g s",
                  test_shape_name(c->shape),
                  c->transfer == GM_TRANSFER_APIC ? "APIC" : "FLIP", lowest,
                  0.002 * k);
  }
  gm_domain_destroy(domain);
}
END_TEST

static const leak_case CASES_3D[] = {
    {GM_SHAPE_LINEAR, GM_TRANSFER_FLIP}, {GM_SHAPE_LINEAR, GM_TRANSFER_APIC},
    {GM_SHAPE_UGIMP, GM_TRANSFER_FLIP},  {GM_SHAPE_UGIMP, GM_TRANSFER_APIC},
    {GM_SHAPE_CPGIMP, GM_TRANSFER_FLIP}, {GM_SHAPE_CPDI, GM_TRANSFER_FLIP},
};
enum { CASE_COUNT_3D = sizeof CASES_3D / sizeof CASES_3D[0] };

/* The lowest signed distance (m) of a point centre from the plane through
 * `point` with unit normal n. */
static double lowest_distance_3d(const gm_domain *domain, const double point[3],
                                 const double n[3]) {
  size_t count = gm_domain_point_count(domain);
  double *position = malloc(count * 3 * sizeof *position);
  ck_assert_ptr_nonnull(position);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             position, count * 3));
  double lowest = INFINITY;
  for (size_t p = 0; p < count; p++) {
    double distance = 0.0;
    for (int k = 0; k < 3; k++)
      distance += (position[3 * p + k] - point[k]) * n[k];
    lowest = distance < lowest ? distance : lowest;
  }
  free(position);
  return lowest;
}

/* A block of 4 x 4 x 2 cells (2 x 2 x 2 points per cell), its bottom
 * layer's centres on the plane through node (6, 6, 4) with normal
 * (0.25, 0.35, 1) / |.|, falling onto it at 1 m/s along -n under gravity
 * along -n. Asserted: no point centre behind the plane after every 2 ms
 * of 20 ms, to 1e-12 m (the rounding of the plane distance of centres
 * placed on it, ~1e-17 m; a leak moves a centre by ~1e-4 m per step). */
START_TEST(test_no_centre_through_oblique_wall) {
  const leak_case *c = &CASES_3D[_i];
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = c->shape;
  def.transfer = c->transfer;
  def.cell_size = CELL;
  double n[3] = {0.25, 0.35, 1.0}, length = sqrt(0.25 * 0.25 + 0.35 * 0.35 + 1);
  for (int k = 0; k < 3; k++) {
    n[k] /= length;
    def.extent[k] = 0.24;
    def.gravity[k] = -9.81 * n[k];
  }
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, YOUNGS, 0.3, DENSITY);
  double point[3] = {6 * CELL, 6 * CELL, 4 * CELL}; /* m */
  gm_wall_def wall = gm_wall_def_default();
  for (int k = 0; k < 3; k++) {
    wall.point[k] = point[k];
    wall.normal[k] = n[k];
  }
  wall.friction_static = wall.friction_kinetic = 0.5;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  /* the plane's axes: d = x projected onto it, e = n x d */
  double d[3] = {1.0 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]};
  double d_length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int k = 0; k < 3; k++)
    d[k] /= d_length;
  double e[3] = {n[1] * d[2] - n[2] * d[1], n[2] * d[0] - n[0] * d[2],
                 n[0] * d[1] - n[1] * d[0]};
  enum { ALONG = 8, UP = 4, COUNT = ALONG * ALONG * UP };
  double spacing = CELL / 2.0; /* m */
  static double position[COUNT * 3], volume[COUNT], velocity[COUNT * 3];
  int p = 0;
  for (int j = 0; j < UP; j++)
    for (int b = 0; b < ALONG; b++)
      for (int a = 0; a < ALONG; a++, p++) {
        double s = (a - 0.5 * (ALONG - 1)) * spacing; /* m, along d */
        double r = (b - 0.5 * (ALONG - 1)) * spacing; /* m, along e */
        for (int k = 0; k < 3; k++) {
          position[3 * p + k] =
              point[k] + s * d[k] + r * e[k] + j * spacing * n[k];
          velocity[3 * p + k] = -SPEED * n[k];
        }
        volume[p] = spacing * spacing * spacing;
      }
  test_add_points(domain, material, COUNT, position, velocity, volume);
  for (int k = 1; k <= 10; k++) {
    TEST_ASSERT_OK(domain,
                   gm_domain_advance(domain, 0.002 * k, 0.0, NULL, NULL));
    double lowest = lowest_distance_3d(domain, point, n);
    ck_assert_msg(lowest >= -1e-12,
                  "3D %s, %s: a point centre %g m behind the oblique wall "
                  "at t = %g s",
                  test_shape_name(c->shape),
                  c->transfer == GM_TRANSFER_APIC ? "APIC" : "FLIP", lowest,
                  0.002 * k);
  }
  gm_domain_destroy(domain);
}
END_TEST

/* 2D, linear MPM, a wall through the grid whose normal lies along no
 * axis: a node of a cell the plane cuts may lie up to |n_x| + |n_y|
 * (up to 1.41) cells in front of it, beyond the nodes within a cell that
 * the contact held, and before it got the centre-gap bound (walls.c,
 * gm_walls_contact, the band rule of 3D) centres went behind such planes.
 * A block of 8 x 4 cells (2 x 2 points per cell), its bottom row's
 * centres on the plane, either falls onto it at 1 m/s along -n under
 * gravity along -n ("fall"), or slides down it as on a 30 degree incline
 * (gravity 9.81 m/s^2 at 30 degrees from -n toward -t, friction
 * 0.4 < tan 30 deg) starting at 1 m/s along -t and 0.2 m/s along -n
 * ("slide"); seven normals, two places of the plane, FLIP and APIC, USL,
 * MUSL and USF: 168 cases (the loop index runs over scheme, transfer,
 * motion, place, normal). Asserted: no centre behind the plane after any
 * step of 20 ms, to 1e-12 m: the centres placed on the plane start at a
 * rounding of ~1e-17 m from it (with the fix the lowest seen is
 * -9.7e-17 m), while a leak moves a centre by ~1e-5 m a step. Before the
 * fix 120 of the 168 failed, every normal and scheme among them, the
 * deepest centres 8.4e-5 m (normal (1, 1)), 6.6e-5 m ((0.35, 1) and
 * (-1, -0.7)), 5.4e-5 m ((0.6, -1)), 3.1e-5 m ((-0.5, 1)), 1.4e-5 m
 * ((0.25, 1)) and 1.6e-7 m ((1, 0.2)) behind the plane. */
static const double OBLIQUE_NORMALS_2D[][2] = {
    {0.35, 1.0}, {1.0, 1.0},  {0.6, -1.0}, {0.25, 1.0},
    {1.0, 0.2},  {-0.5, 1.0}, {-1.0, -0.7}};
enum {
  NORMAL_COUNT_2D = sizeof OBLIQUE_NORMALS_2D / sizeof OBLIQUE_NORMALS_2D[0],
  SCHEME_COUNT_2D = 3,
  SHIFT_COUNT_2D = 2,
  OBLIQUE_COUNT_2D = NORMAL_COUNT_2D * SHIFT_COUNT_2D * 2 * 2 * SCHEME_COUNT_2D
};
/* Where the plane passes (cells from the node (0.2, 0.2) m): how far the
 * nodes lie in front of it, so which fall in the band, depends on it, and
 * every normal above leaked at one of these before the fix. */
static const double PLANE_SHIFTS_2D[SHIFT_COUNT_2D][2] = {{0.37, 0.21},
                                                          {0.5, 0.5}};
static const gm_update_scheme SCHEMES_2D[SCHEME_COUNT_2D] = {
    GM_SCHEME_USL, GM_SCHEME_MUSL, GM_SCHEME_USF};

/* The plane watched after every step: its point (m) and unit normal, the
 * lowest signed distance of a centre from it seen so far (m) and when
 * (s), and a buffer for the positions (m). */
typedef struct plane_watch {
  double point[2], normal[2];
  double lowest, when;
  double *position;
} plane_watch;

static int watch_plane(const gm_domain *domain, double time, double end_time,
                       void *user) {
  (void)end_time;
  plane_watch *watch = user;
  size_t count = gm_domain_point_count(domain);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             watch->position, count * 2));
  for (size_t p = 0; p < count; p++) {
    double distance = 0.0; /* m */
    for (int k = 0; k < 2; k++)
      distance +=
          (watch->position[2 * p + k] - watch->point[k]) * watch->normal[k];
    if (distance < watch->lowest) {
      watch->lowest = distance;
      watch->when = time;
    }
  }
  return 0;
}

START_TEST(test_no_centre_through_oblique_wall_2d) {
  int index = _i;
  gm_update_scheme scheme = SCHEMES_2D[index % SCHEME_COUNT_2D];
  index /= SCHEME_COUNT_2D;
  gm_transfer transfer = index % 2 ? GM_TRANSFER_APIC : GM_TRANSFER_FLIP;
  index /= 2;
  bool slide = index % 2;
  index /= 2;
  const double *shift = PLANE_SHIFTS_2D[index % SHIFT_COUNT_2D];
  const double *raw = OBLIQUE_NORMALS_2D[index / SHIFT_COUNT_2D];
  gm_domain_def def = gm_domain_def_default();
  def.transfer = transfer;
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = def.extent[1] = 0.4;
  double length = hypot(raw[0], raw[1]);
  plane_watch watch = {{0.2 + shift[0] * CELL, 0.2 + shift[1] * CELL},
                       {raw[0] / length, raw[1] / length},
                       INFINITY,
                       0.0,
                       NULL}; /* the plane through the middle */
  const double *n = watch.normal, *point = watch.point;
  double t[2] = {n[1], -n[0]};           /* along the plane */
  double g_n = slide ? sqrt(0.75) : 1.0; /* of g, toward the wall: cos 30 deg */
  double g_t = slide ? 0.5 : 0.0;        /* of g, along -t: sin 30 deg */
  double v_n = slide ? 0.2 : SPEED;      /* m/s, toward the wall */
  double v_t = slide ? 1.0 : 0.0;        /* m/s, along -t */
  for (int k = 0; k < 2; k++)
    def.gravity[k] = -9.81 * (g_n * n[k] + g_t * t[k]);
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, YOUNGS, 0.3, DENSITY);
  gm_wall_def wall = gm_wall_def_default();
  for (int k = 0; k < 2; k++) {
    wall.point[k] = point[k];
    wall.normal[k] = n[k];
  }
  wall.friction_static = wall.friction_kinetic = slide ? 0.4 : 0.5;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  enum { ALONG = 16, UP = 8, COUNT = ALONG * UP };
  double spacing = CELL / 2.0; /* m */
  static double position[COUNT * 2], volume[COUNT], velocity[COUNT * 2];
  for (int j = 0; j < UP; j++)
    for (int a = 0; a < ALONG; a++) {
      int p = j * ALONG + a;
      double s = (a - 0.5 * (ALONG - 1)) * spacing; /* m, along t */
      for (int k = 0; k < 2; k++) {
        position[2 * p + k] = point[k] + s * t[k] + j * spacing * n[k];
        velocity[2 * p + k] = -v_n * n[k] - v_t * t[k];
      }
      volume[p] = spacing * spacing;
    }
  test_add_points(domain, material, COUNT, position, velocity, volume);
  watch.position = malloc(gm_domain_point_count(domain) * 2 * sizeof(double));
  ck_assert_ptr_nonnull(watch.position);
  TEST_ASSERT_OK(domain,
                 gm_domain_advance(domain, 0.02, 0.0, watch_plane, &watch));
  ck_assert_msg(watch.lowest >= -1e-12,
                "2D linear, %s, %s, %s, normal (%g, %g): a point centre %g m "
                "behind the oblique wall at t = %g s",
                slide ? "slide" : "fall", test_scheme_name(scheme),
                transfer == GM_TRANSFER_APIC ? "APIC" : "FLIP", raw[0], raw[1],
                watch.lowest, watch.when);
  free(watch.position);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("wall_watertight");
  TCase *tc = tcase_create("floor");
  tcase_add_loop_test(tc, test_no_centre_through_floor, 0, CASE_COUNT);
  tcase_add_loop_test(tc, test_no_centre_through_oblique_wall, 0,
                      CASE_COUNT_3D);
  tcase_add_loop_test(tc, test_no_centre_through_oblique_wall_2d, 0,
                      OBLIQUE_COUNT_2D);
  suite_add_tcase(suite, tc);
  return test_run_suite(suite) ? 1 : 0;
}
