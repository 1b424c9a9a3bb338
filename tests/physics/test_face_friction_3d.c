/*
 * test_face_friction_3d.c - a frictional box face in 3D (issue 16 item 1,
 * "planar walls of any normal with Coulomb friction"): the floor y = 0 is
 * the grid box's ymin face made frictional as in 2D, by a planar wall on
 * its plane (gm_wall_def, normal (0, 1, 0), the face left open), with the
 * linear and the uGIMP shapes.
 *
 * Slide: an elastic block (0.2 x 0.1 x 0.2 m, 2 x 2 x 2 points per cell
 * of 0.05 m, placed with the uniaxial stress of its weight) starts on the
 * floor with the tangential velocity v0 = (0.6, 0, 0.4) m/s, along no grid
 * axis. Coulomb's law with the normal force m g decelerates it at mu g
 * against its velocity, so the direction is kept and
 *   |v(t)| = |v0| - mu g t  until t_s = |v0| / (mu g),
 *   s_stop = |v0|^2 / (2 mu g)
 * (references.md "Block sliding on an incline" at zero slope). mu = 0.2:
 * t_s = 0.368 s, s_stop = 0.1325 m (2.65 cells). Asserted: the centre of
 * mass velocity along v0 within 2 % of |v0| at t = 0.1, 0.2, 0.3 s, the
 * stopping distance within 2 % (the 2 % of issue 16 item 3 for the
 * sliding block), the block at rest after t_s (below 2 % of |v0|), and
 * the direction kept: the velocity across v0 below 0.5 % of |v0| and the
 * final displacement across v0 below 0.5 % of that along it. A friction
 * that lost the direction, Coulomb's law on each component separately
 * (the z component, 0.4 m/s, stopping at 0.20 s, x at 0.31 s), gives
 * 0.055 m/s = 7.6 % of |v0| across at 0.1 s; the across velocity
 * measured is the elastic block's vibration, up to 0.07 % of |v0| at the
 * test's setting and 0.14 % on the refinements of docs/3d.md.
 *
 * Stick: the same block at rest under gravity with a tangential component
 * 0.6 mu g along (0.6, 0, 0.4)/|.|: Coulomb's static friction holds it.
 * Asserted: its displacement after 0.3 s below 2 % of the frictionless
 * 1/2 a t^2 (as test_walls_3d.c's stuck block).
 *
 * On main before this change a 3D domain with uGIMP refused the wall
 * (gm_domain_add_wall: "planar walls in 3D are supported with
 * GM_SHAPE_LINEAR only"), so the uGIMP cases fail there.
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
static const double CELL = 0.05;      /* m */
static const double BLOCK_W = 0.2;    /* m, along x and z */
static const double BLOCK_H = 0.1;    /* m, along y */
static const double DENSITY = 2000.0; /* kg/m^3 */
static const double POISSON = 0.3;
static const double YOUNGS = 2e7;          /* Pa: wave speed 100 m/s */
static const double FRICTION = 0.2;        /* mu_s = mu_k */
static const double SPEED[2] = {0.6, 0.4}; /* m/s, v0 along x and z */
static const gm_shape SHAPES[2] = {GM_SHAPE_LINEAR, GM_SHAPE_UGIMP};
static const gm_update_scheme SCHEMES[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                            GM_SCHEME_USF};

/* The box (0.8 x 0.4 x 0.8 m), the floor wall at y = 0 on the open ymin
 * face, and the block with its corner at (0.1, 0, 0.1) m moving at
 * `speed` (m/s, x and z; 0 = at rest); gravity `tangential` (m/s^2) along
 * SPEED's direction besides -g along y. */
static gm_domain *scene(gm_shape shape, gm_update_scheme scheme,
                        const double speed[2], double tangential, int workers,
                        int *wall_id) {
  double direction[2] = {SPEED[0] / hypot(SPEED[0], SPEED[1]),
                         SPEED[1] / hypot(SPEED[0], SPEED[1])};
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = shape;
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = CELL;
  def.extent[0] = def.extent[2] = 0.8;
  def.extent[1] = 0.4;
  def.gravity[0] = tangential * direction[0];
  def.gravity[1] = -GRAVITY;
  def.gravity[2] = tangential * direction[1];
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default(); /* y = 0, normal (0, 1, 0) */
  wall.friction_static = wall.friction_kinetic = FRICTION;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, wall_id));
  int material = test_add_elastic(domain, YOUNGS, POISSON, DENSITY);
  enum { PER_AXIS = 2 };
  int across = (int)lround(BLOCK_W / CELL) * PER_AXIS;
  int up = (int)lround(BLOCK_H / CELL) * PER_AXIS;
  size_t count = (size_t)(across * across * up);
  double spacing = CELL / PER_AXIS; /* m */
  double *position = malloc(count * 3 * sizeof(double));
  double *velocity = malloc(count * 3 * sizeof(double));
  double *volume = malloc(count * sizeof(double));
  double *stress = calloc(count * 6, sizeof(double));
  ck_assert(position && velocity && volume && stress);
  size_t p = 0;
  for (int k = 0; k < across; k++)
    for (int j = 0; j < up; j++)
      for (int i = 0; i < across; i++, p++) {
        double height = (j + 0.5) * spacing; /* m */
        position[3 * p + 0] = 0.1 + (i + 0.5) * spacing;
        position[3 * p + 1] = height;
        position[3 * p + 2] = 0.1 + (k + 0.5) * spacing;
        velocity[3 * p + 0] = speed[0];
        velocity[3 * p + 1] = 0.0;
        velocity[3 * p + 2] = speed[1];
        volume[p] = spacing * spacing * spacing;
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

/* Centre of mass (m) and its velocity (m/s). */
static void centre(const gm_domain *domain, double x[3], double v[3]) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  for (int k = 0; k < 3; k++) {
    x[k] = summary.centre_of_mass[k];
    v[k] = summary.momentum[k] / summary.mass;
  }
}

/* Steps to `until` (s) from `*time`. */
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

/* Components of (x, z) along and across SPEED's direction. */
static void split(const double v[3], double *along, double *across) {
  double norm = hypot(SPEED[0], SPEED[1]);
  *along = (v[0] * SPEED[0] + v[2] * SPEED[1]) / norm;
  *across = (v[2] * SPEED[0] - v[0] * SPEED[1]) / norm;
}

/* 2 %: the tolerance for the sliding block (item 3), which the 3D
 * oblique walls meet at this cell (test_walls_3d.c, +0.45 %). The
 * velocity is compared with 2 % of |v0| (an absolute error; near the
 * stop the relative one is meaningless). */
static const double TOLERANCE = 0.02;
/* Direction: 0.5 % of |v0| (velocity) or of the slide (displacement),
 * about 0.3 deg; see the top of the file. */
static const double ACROSS_TOLERANCE = 0.005;

/* _i: shape (2) x scheme (3). */
START_TEST(test_slide_to_rest) {
  gm_shape shape = SHAPES[_i % 2];
  gm_update_scheme scheme = SCHEMES[_i / 2];
  const char *name = shape == GM_SHAPE_LINEAR ? "linear" : "uGIMP";
  int wall_id = -1;
  gm_domain *domain = scene(shape, scheme, SPEED, 0.0, 1, &wall_id);
  double speed = hypot(SPEED[0], SPEED[1]);           /* m/s */
  double deceleration = FRICTION * GRAVITY;           /* m/s^2 */
  double stop_time = speed / deceleration;            /* s */
  double stop = speed * speed / (2.0 * deceleration); /* m */
  double x0[3], v[3], x[3], time = 0.0;
  centre(domain, x0, v);
  static const double SAMPLES[3] = {0.1, 0.2, 0.3}; /* s */
  for (int s = 0; s < 3; s++) {
    advance(domain, &time, SAMPLES[s]);
    centre(domain, x, v);
    double along, across;
    split(v, &along, &across);
    double expected = speed - deceleration * time; /* m/s */
    printf("%s %s t %.2f s: v along %.5f m/s (closed form %.5f, %+.2f %% "
           "of v0), across %.2e m/s\n",
           name, test_scheme_name(scheme), time, along, expected,
           100.0 * (along - expected) / speed, across);
    ck_assert_msg(fabs(along - expected) < TOLERANCE * speed,
                  "%s %s, t = %.2f s: velocity along v0 %.5f m/s, closed "
                  "form %.5f m/s (%+.2f %% of |v0|)",
                  name, test_scheme_name(scheme), time, along, expected,
                  100.0 * (along - expected) / speed);
    ck_assert_msg(fabs(across) < ACROSS_TOLERANCE * speed,
                  "%s %s, t = %.2f s: velocity across v0 %.3e m/s, |v0| = "
                  "%.4f m/s (direction lost)",
                  name, test_scheme_name(scheme), time, across, speed);
  }
  advance(domain, &time, stop_time + 0.1);
  centre(domain, x, v);
  double displacement[3] = {x[0] - x0[0], 0.0, x[2] - x0[2]};
  double along, across, v_along, v_across;
  split(displacement, &along, &across);
  split(v, &v_along, &v_across);
  printf("%s %s: stopped after %.5f m (closed form %.5f m, %+.2f %%), "
         "across %.2e m, final speed %.2e m/s, drop %.2e m\n",
         name, test_scheme_name(scheme), along, stop,
         100.0 * (along - stop) / stop, across, hypot(v_along, v_across),
         x[1] - x0[1]);
  ck_assert_msg(fabs(along - stop) < TOLERANCE * stop,
                "%s %s: stopping distance %.5f m, closed form %.5f m "
                "(%+.2f %%)",
                name, test_scheme_name(scheme), along, stop,
                100.0 * (along - stop) / stop);
  ck_assert_msg(fabs(across) < ACROSS_TOLERANCE * along,
                "%s %s: displacement across v0 %.3e m of %.5f m along", name,
                test_scheme_name(scheme), across, along);
  ck_assert_msg(hypot(v_along, v_across) < TOLERANCE * speed,
                "%s %s: still moving at %.4f m/s after the stop", name,
                test_scheme_name(scheme), hypot(v_along, v_across));
  gm_domain_destroy(domain);
}
END_TEST

/* _i: shape (2). */
START_TEST(test_stick) {
  gm_shape shape = SHAPES[_i];
  const char *name = shape == GM_SHAPE_LINEAR ? "linear" : "uGIMP";
  double tangential = 0.6 * FRICTION * GRAVITY; /* m/s^2, below mu g */
  static const double REST[2] = {0.0, 0.0};
  int wall_id = -1;
  gm_domain *domain =
      scene(shape, GM_SCHEME_USL, REST, tangential, 1, &wall_id);
  double x0[3], x[3], v[3], time = 0.0, duration = 0.3; /* m, m/s, s */
  centre(domain, x0, v);
  advance(domain, &time, duration);
  centre(domain, x, v);
  double frictionless = 0.5 * tangential * duration * duration; /* m */
  double moved = hypot(x[0] - x0[0], x[2] - x0[2]);             /* m */
  printf("%s stick: moved %.3e m = %.3f %% of the frictionless %.5f m\n", name,
         moved, 100.0 * moved / frictionless, frictionless);
  ck_assert_msg(moved < TOLERANCE * frictionless,
                "%s: the block at rest under 0.6 mu g moved %.3e m = %.2f %% "
                "of the frictionless %.5f m; should stick",
                name, moved, 100.0 * moved / frictionless, frictionless);
  gm_domain_destroy(domain);
}
END_TEST

/* The uGIMP slide bitwise the same with 1 and 2 workers (the gaps are
 * minima taken colour by colour, the patches pooled in block order). */
START_TEST(test_workers) {
  double state[2][7];
  for (int run = 0; run < 2; run++) {
    int wall_id = -1;
    gm_domain *domain =
        scene(GM_SHAPE_UGIMP, GM_SCHEME_USL, SPEED, 0.0, run + 1, &wall_id);
    double time = 0.0;
    advance(domain, &time, 0.1);
    centre(domain, state[run], state[run] + 3);
    gm_wall_force force = gm_wall_force_default();
    TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, wall_id, &force));
    state[run][6] = force.total_impulse[0];
    gm_domain_destroy(domain);
  }
  ck_assert_msg(memcmp(state[0], state[1], sizeof state[0]) == 0,
                "uGIMP slide: 1 and 2 workers differ (x %.17g / %.17g)",
                state[0][0], state[1][0]);
}
END_TEST

/* Which walls the wide shapes take in 3D (walls.c): any wall since
 * 2026-11-28, as linear MPM (a wall off the face, facing out of the box,
 * of an oblique normal, or over a slip face, which holds its nodes before
 * the walls act as it does with linear MPM). Until then uGIMP and cpGIMP
 * took the planes of open box faces only. The B-splines, refused until
 * 2026-11-29, take any wall but one parallel to a face they mirror and
 * less than a support radius from it (check_bspline_mirrors): that
 * refusal names the face. */
typedef struct wall_row {
  gm_shape shape;
  gm_wall_type ymin;         /* the ymin face's condition */
  double point_y, normal[3]; /* m, the wall */
  bool accepted;
} wall_row;

START_TEST(test_which_walls) {
  static const wall_row ROWS[] = {
      {GM_SHAPE_UGIMP, GM_WALL_OPEN, 0.0, {0, 1, 0}, true},
      {GM_SHAPE_CPGIMP, GM_WALL_OPEN, 0.0, {0, 2, 0}, true},
      {GM_SHAPE_UGIMP, GM_WALL_OPEN, 0.4, {0, -1, 0}, true}, /* ymax */
      {GM_SHAPE_UGIMP, GM_WALL_SLIP, 0.0, {0, 1, 0}, true},
      {GM_SHAPE_UGIMP, GM_WALL_OPEN, 0.01, {0, 1, 0}, true},
      {GM_SHAPE_CPGIMP, GM_WALL_OPEN, 0.0, {0, -1, 0}, true},
      {GM_SHAPE_CPDI, GM_WALL_OPEN, 0.01, {0.1, 1, 0}, true},
      {GM_SHAPE_BSPLINE3, GM_WALL_OPEN, 0.2, {0.1, 1, 0}, true},
      {GM_SHAPE_BSPLINE2, GM_WALL_OPEN, 0.0, {0, 1, 0}, true},
      /* B-splines over a slip face, which is their mirror (walls.c,
       * check_bspline_mirrors): refused parallel to it and less than a
       * support radius (1.5 cells quadratic, 2 cubic) from its plane,
       * facing in or out; accepted farther in or oblique. */
      {GM_SHAPE_BSPLINE2, GM_WALL_SLIP, 0.0, {0, 1, 0}, false},
      {GM_SHAPE_BSPLINE2, GM_WALL_SLIP, 1.4 * CELL, {0, -3, 0}, false},
      {GM_SHAPE_BSPLINE2, GM_WALL_SLIP, 1.6 * CELL, {0, 1, 0}, true},
      {GM_SHAPE_BSPLINE3, GM_WALL_SLIP, 1.9 * CELL, {0, 1, 0}, false},
      {GM_SHAPE_BSPLINE3, GM_WALL_SLIP, 2.1 * CELL, {0, 1, 0}, true},
      {GM_SHAPE_BSPLINE3, GM_WALL_SLIP, 0.0, {0.1, 1, 0}, true},
      {GM_SHAPE_LINEAR, GM_WALL_OPEN, 0.01, {0.1, 1, 0}, true},
  };
  for (size_t r = 0; r < sizeof ROWS / sizeof ROWS[0]; r++) {
    const wall_row *row = &ROWS[r];
    gm_domain_def def = gm_domain_def_default();
    def.geometry = GM_GEOMETRY_3D;
    def.shape = row->shape;
    def.cell_size = CELL;
    def.extent[0] = def.extent[2] = 0.8;
    def.extent[1] = 0.4;
    def.walls[GM_FACE_YMIN] = row->ymin;
    gm_domain *domain = test_create_domain(&def);
    gm_wall_def wall = gm_wall_def_default();
    wall.point[1] = row->point_y;
    for (int k = 0; k < 3; k++)
      wall.normal[k] = row->normal[k];
    int id = -1;
    gm_status status = gm_domain_add_wall(domain, &wall, &id);
    if (row->accepted)
      ck_assert_msg(status == GM_OK, "row %zu refused: %s", r,
                    gm_domain_last_error(domain));
    else
      ck_assert_msg(
          status == GM_ERR_UNSUPPORTED &&
              strstr(gm_domain_last_error(domain), "gm_domain_add_wall") !=
                  NULL &&
              strstr(gm_domain_last_error(domain), "ymin box face") != NULL &&
              id == -1,
          "row %zu: status %d (%s), expected a refusal", r, (int)status,
          gm_domain_last_error(domain));
    gm_domain_destroy(domain);
  }
}
END_TEST

int main(void) {
  Suite *suite = suite_create("face_friction_3d");
  TCase *tcase = tcase_create("frictional floor face");
  tcase_set_timeout(tcase, 600);
  tcase_add_loop_test(tcase, test_slide_to_rest, 0, 6);
  tcase_add_loop_test(tcase, test_stick, 0, 2);
  tcase_add_test(tcase, test_which_walls);
  tcase_add_test(tcase, test_workers);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) ? 1 : 0;
}
