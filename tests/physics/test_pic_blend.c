/*
 * test_pic_blend.c - gm_domain_def.pic_fraction, the FLIP-PIC blend of
 * the point velocity update,
 *   v_p <- (1 - a) (v_p + dt sum N_i a_i) + a sum N_i v_i,
 * against two closed forms:
 *
 *  1. A velocity pattern the grid cannot see. Three points of equal mass in
 *     one 1D cell at xi = 1/6, 1/2, 5/6 with velocities (u, -2u, u): the
 *     nodal momenta sum m N_i v_p vanish on both nodes (5/6 - 1 + 1/6 = 0
 *     and 1/6 - 1 + 5/6 = 0), so the nodal velocities, the velocity
 *     gradient, the stress and the motion all stay zero, and the update is
 *     v_p <- (1 - a) v_p: after n steps v = (1 - a)^n v0 exactly. Pure FLIP
 *     (a = 0, the default) keeps the pattern and its kinetic energy for
 *     ever: the ringing that stops a scene from coming to rest.
 *  2. A uniform velocity under gravity: every node gets v + g dt, which is
 *     also the FLIP update, so any blend advances v_n = v0 + g n dt
 *     (test_freefall.c for a = 0).
 * And values outside [0, 1] are refused, naming the field.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

enum { BLEND_STEPS = 20 };

static const double BLEND_DT = 1e-4;     /* s, far below the stable bound */
static const double BLEND_CELL = 0.1;    /* m */
static const double BLEND_SPEED = 0.01;  /* m/s, u of the hidden pattern */
static const double BLEND_DENSITY = 1e3; /* kg/m^3 */

static const double blend_fractions[] = {0.0, 0.05, 0.5, 1.0};

/* _i: scheme _i % 3, fraction blend_fractions[_i / 3]. */
static gm_domain *blend_domain(int i, gm_geometry geometry,
                               const double gravity[2]) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = geometry;
  def.scheme = (gm_update_scheme)(i % 3);
  def.pic_fraction = blend_fractions[i / 3];
  def.cell_size = BLEND_CELL;
  for (int k = 0; k < 2; k++) {
    def.extent[k] = 1.0; /* m */
    def.gravity[k] = gravity[k];
  }
  return test_create_domain(&def);
}

START_TEST(test_hidden_pattern_decays_geometrically) {
  const double no_gravity[2] = {0.0, 0.0};
  gm_domain *domain = blend_domain(_i, GM_GEOMETRY_1D, no_gravity);
  int material = test_add_elastic(domain, 1e6, 0.3, BLEND_DENSITY);
  /* The cell [0.4, 0.5] m, points at xi = 1/6, 1/2, 5/6. */
  double position[3],
      velocity[3] = {BLEND_SPEED, -2.0 * BLEND_SPEED, BLEND_SPEED};
  double volume[3];
  for (int p = 0; p < 3; p++) {
    position[p] = 0.4 + BLEND_CELL * (2 * p + 1) / 6.0;
    volume[p] = BLEND_CELL / 3.0;
  }
  gm_points_def points = gm_points_def_default();
  points.count = 3;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  int64_t first_id = 0;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, &first_id));
  for (int step = 0; step < BLEND_STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, BLEND_DT));

  double fraction = blend_fractions[_i / 3];
  double decay = pow(1.0 - fraction, BLEND_STEPS);
  double now_velocity[3], now_position[3];
  test_get_field_by_id(domain, GM_FIELD_VELOCITY, first_id, now_velocity);
  test_get_field_by_id(domain, GM_FIELD_POSITION, first_id, now_position);
  for (int p = 0; p < 3; p++) {
    /* The nodal momenta cancel to round-off, ~1e-16 of m u, so the
     * residual nodal velocity is ~1e-16 u per step; 1e-13 u over 20 steps
     * is the bound. The points do not move beyond that times dt. */
    double expected = decay * velocity[p];
    ck_assert_msg(fabs(now_velocity[p] - expected) <= 1e-13 * BLEND_SPEED,
                  "%s, pic_fraction %g: point %d v = %.17g, expected %.17g",
                  test_scheme_name((gm_update_scheme)(_i % 3)), fraction, p,
                  now_velocity[p], expected);
    ck_assert(fabs(now_position[p] - position[p]) <= 1e-15);
  }
  gm_domain_destroy(domain);
}
END_TEST

START_TEST(test_uniform_motion_unchanged_by_blend) {
  const double gravity[2] = {1.5, -9.81}, start[2] = {0.4, 0.3}; /* SI */
  gm_domain *domain = blend_domain(_i, GM_GEOMETRY_PLANE_STRAIN, gravity);
  int material = test_add_elastic(domain, 1e6, 0.3, BLEND_DENSITY);
  const double lower[3] = {0.35, 0.45, 0.0}, upper[3] = {0.65, 0.75, 0.0};
  int64_t first_id = 0;
  size_t count = test_fill_box(domain, material, lower, upper, 2, &first_id);
  for (int k = 0; k < 2; k++) {
    double *velocity = NULL;
    TEST_ASSERT_OK(domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY,
                                                (size_t)k, &velocity));
    for (size_t p = 0; p < count; p++)
      velocity[p] = start[k];
  }
  for (int step = 0; step < BLEND_STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, BLEND_DT));
  double *velocity = malloc(2 * count * sizeof *velocity);
  ck_assert_ptr_nonnull(velocity);
  test_get_field_by_id(domain, GM_FIELD_VELOCITY, first_id, velocity);
  for (size_t p = 0; p < count; p++)
    for (int k = 0; k < 2; k++) {
      /* n roundings of the sum and the grid round trip: ~1e-14 of the
       * largest speed (< 0.5 m/s); 1e-12 is the bound (test_freefall.c). */
      double expected = start[k] + gravity[k] * BLEND_STEPS * BLEND_DT;
      ck_assert_msg(fabs(velocity[2 * p + k] - expected) <= 1e-12,
                    "pic_fraction %g: point %zu v[%d] = %.17g, expected "
                    "%.17g",
                    blend_fractions[_i / 3], p, k, velocity[2 * p + k],
                    expected);
    }
  free(velocity);
  gm_domain_destroy(domain);
}
END_TEST

START_TEST(test_out_of_range_refused) {
  const double bad[] = {-0.01, 1.01, NAN, INFINITY};
  for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
    gm_domain_def def = gm_domain_def_default();
    def.pic_fraction = bad[b];
    gm_domain *domain = NULL;
    ck_assert_int_eq(gm_domain_create(&def, &domain), GM_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_null(domain);
    ck_assert_msg(strstr(gm_last_create_error(), "pic_fraction") != NULL,
                  "message: %s", gm_last_create_error());
  }
}
END_TEST

static Suite *pic_blend_suite(void) {
  Suite *suite = suite_create("pic_blend");
  TCase *tcase = tcase_create("blend");
  int variants = 3 * (int)(sizeof blend_fractions / sizeof blend_fractions[0]);
  tcase_add_loop_test(tcase, test_hidden_pattern_decays_geometrically, 0,
                      variants);
  tcase_add_loop_test(tcase, test_uniform_motion_unchanged_by_blend, 0,
                      variants);
  tcase_add_test(tcase, test_out_of_range_refused);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(pic_blend_suite()) ? 1 : 0;
}
