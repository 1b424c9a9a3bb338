/*
 * test_freefall.c - an elastic block falling freely under gravity (no wall
 * near it) moves as a rigid body, and every update scheme reproduces the
 * exact discrete solution of its time integrator to round-off.
 *
 * With a uniform velocity field every node gets v_I = v (mass-weighted mean
 * of equal velocities) and a_I = g (the internal forces of a zero stress
 * vanish, the external force is m_I g). Each scheme then advances a point by
 * the symplectic Euler rule
 *   v_{k+1} = v_k + g dt,   x_{k+1} = x_k + dt v_{k+1}
 * (USL: positions from sum N v_new; MUSL: from the re-mapped velocity, which
 * equals v_new for a uniform field; USF: same kinematics). Summing:
 *   v_n = v0 + g n dt,   x_n = x0 + v0 t + g dt^2 n(n+1)/2,   t = n dt,
 * which differs from the continuous x0 + v0 t + g t^2/2 by exactly
 * g dt^2 n/2 = g t dt/2: first order in dt, so it converges as dt -> 0.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

enum { FREEFALL_STEPS = 100 };

static const double FREEFALL_DT = 1e-3;         /* s */
static const double FREEFALL_CELL_SIZE = 0.125; /* m */
static const double FREEFALL_YOUNGS = 1e6;      /* Pa */
static const double FREEFALL_POISSON = 0.3;     /* - */
static const double FREEFALL_DENSITY = 1000.0;  /* kg/m^3 */

/* Initial velocity (m/s) and gravity (m/s^2): not aligned, and the vertical
 * velocity reverses sign during the fall. */
static const double FREEFALL_V0[2] = {1.0, 0.5};
static const double FREEFALL_GRAVITY[2] = {2.0, -9.81};

/* Loop index i: geometry (0: 1D, 1: plane strain) and scheme. */
static gm_geometry freefall_geometry(int i) {
  return i / 3 == 0 ? GM_GEOMETRY_1D : GM_GEOMETRY_PLANE_STRAIN;
}

static gm_update_scheme freefall_scheme(int i) {
  return (gm_update_scheme)(i % 3);
}

/* A 2 m grid box with no walls and the block in its middle: the block moves
 * by about 0.1 m, far from any edge. */
static gm_domain *freefall_domain(gm_geometry geometry,
                                  gm_update_scheme scheme) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = geometry;
  def.cell_size = FREEFALL_CELL_SIZE;
  def.scheme = scheme;
  for (int k = 0; k < 2; ++k) {
    def.origin[k] = 0.0;
    def.extent[k] = 2.0;
    def.gravity[k] = FREEFALL_GRAVITY[k];
  }
  return test_create_domain(&def);
}

/* Sets every point's velocity to FREEFALL_V0. */
static void set_uniform_velocity(gm_domain *domain, int dim) {
  size_t count = gm_domain_point_count(domain);
  for (int k = 0; k < dim; ++k) {
    double *velocity = NULL;
    TEST_ASSERT_OK(domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY,
                                                (size_t)k, &velocity));
    for (size_t i = 0; i < count; ++i)
      velocity[i] = FREEFALL_V0[k];
  }
}

START_TEST(test_free_fall) {
  gm_geometry geometry = freefall_geometry(_i);
  gm_update_scheme scheme = freefall_scheme(_i);
  int dim = gm_geometry_dimension(geometry);
  gm_domain *domain = freefall_domain(geometry, scheme);
  int material = test_add_elastic(domain, FREEFALL_YOUNGS, FREEFALL_POISSON,
                                  FREEFALL_DENSITY);
  const double lower[3] = {0.75, 0.75, 0.0}, upper[3] = {1.25, 1.25, 0.0};
  int64_t first_id = 0;
  size_t count = test_fill_box(domain, material, lower, upper, 2, &first_id);
  set_uniform_velocity(domain, dim);

  double *initial_position = malloc(count * (size_t)dim * sizeof(double));
  double *position = malloc(count * (size_t)dim * sizeof(double));
  double *velocity = malloc(count * (size_t)dim * sizeof(double));
  double *stress = malloc(count * 6 * sizeof(double));
  ck_assert(initial_position && position && velocity && stress);
  test_get_field_by_id(domain, GM_FIELD_POSITION, first_id, initial_position);

  /* Precondition: the fixed dt is below the stable bound, so no sub-step or
   * refusal can change the integrator. */
  double stable_dt = 0.0;
  TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &stable_dt));
  ck_assert_double_lt(FREEFALL_DT, stable_dt);

  for (int step = 0; step < FREEFALL_STEPS; ++step)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, FREEFALL_DT));

  const double n = FREEFALL_STEPS, dt = FREEFALL_DT, t = n * dt;
  double time = 0.0;
  uint64_t step_count = 0;
  TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &time, &step_count));
  ck_assert_uint_eq(step_count, FREEFALL_STEPS);
  ck_assert_double_eq_tol(time, t, 1e-12 * t);

  test_get_field_by_id(domain, GM_FIELD_POSITION, first_id, position);
  test_get_field_by_id(domain, GM_FIELD_VELOCITY, first_id, velocity);
  size_t stress_components =
      test_get_field_by_id(domain, GM_FIELD_STRESS, first_id, stress);

  double speed_scale = 0.0; /* m/s, largest |v| during the fall */
  for (int k = 0; k < dim; ++k) {
    double v0 = FREEFALL_V0[k], g = FREEFALL_GRAVITY[k];
    double scale = fabs(v0) + fabs(g) * t;
    speed_scale = fmax(speed_scale, scale);
    /* Velocity: n additions of g dt, each rounding at DBL_EPSILON relative,
     * plus the grid round trip (p_I / m_I, sum N_I a_I): about n * 10 eps
     * relative to |v0| + |g| t, i.e. ~2e-13 here; 1e-12 is the bound. */
    double expected_velocity = v0 + g * t;
    double velocity_tolerance = 1e-12 * scale;
    /* Position: the same count of roundings, relative to the largest
     * coordinate the block reaches (< 2 m). */
    double position_tolerance = 1e-12 * 2.0;
    double discrete_displacement = v0 * t + g * dt * dt * n * (n + 1.0) / 2.0;
    double continuous_displacement = v0 * t + 0.5 * g * t * t;
    for (size_t p = 0; p < count; ++p) {
      size_t slot = p * (size_t)dim + (size_t)k;
      ck_assert_msg(fabs(velocity[slot] - expected_velocity) <=
                        velocity_tolerance,
                    "%s dim %d: point %zu v[%d] = %.17g, expected %.17g",
                    test_scheme_name(scheme), dim, p, k, velocity[slot],
                    expected_velocity);
      double x0 = initial_position[slot];
      ck_assert_msg(fabs(position[slot] - (x0 + discrete_displacement)) <=
                        position_tolerance,
                    "%s dim %d: point %zu x[%d] = %.17g, expected %.17g",
                    test_scheme_name(scheme), dim, p, k, position[slot],
                    x0 + discrete_displacement);
      /* The first-order lag behind the continuous solution: g t dt / 2. */
      double lag = position[slot] - (x0 + continuous_displacement);
      ck_assert_msg(fabs(lag - 0.5 * g * t * dt) <= position_tolerance,
                    "%s dim %d: lag %.17g, expected g t dt/2 = %.17g",
                    test_scheme_name(scheme), dim, lag, 0.5 * g * t * dt);
    }
  }

  /* Stress: a rigid translation has zero strain rate. Round-off in
   * L = sum grad N_I v_I is at most ~ 8 eps |v| / h per step (4 nodes, two
   * terms each), so the strain after time t is <= 8 eps |v| t / h and the
   * stress <= M times that with M = E(1-nu)/((1+nu)(1-2nu)) ~ 1.35 E, about
   * 4e-9 Pa here. We allow 1000 eps M |v| t / h (~4e-7 Pa); a real error
   * (e.g. gravity loading the block) would be ~ rho g h ~ 1e3 Pa. */
  const double nu = FREEFALL_POISSON;
  const double p_wave_modulus =
      FREEFALL_YOUNGS * (1 - nu) / ((1 + nu) * (1 - 2 * nu)); /* Pa */
  double stress_tolerance = 1000.0 * DBL_EPSILON * p_wave_modulus *
                            speed_scale * t / FREEFALL_CELL_SIZE;
  for (size_t i = 0; i < count * stress_components; ++i)
    ck_assert_msg(fabs(stress[i]) <= stress_tolerance,
                  "%s dim %d: stress component %zu = %g Pa",
                  test_scheme_name(scheme), dim, i, stress[i]);

  free(initial_position);
  free(position);
  free(velocity);
  free(stress);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *freefall_suite(void) {
  Suite *suite = suite_create("freefall");
  TCase *tcase = tcase_create("rigid_translation");
  tcase_set_timeout(tcase, 60);
  /* 0..2: 1D with USL, MUSL, USF; 3..5: plane strain with the same. */
  tcase_add_loop_test(tcase, test_free_fall, 0, 6);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(freefall_suite()) ? EXIT_FAILURE : 0;
}
