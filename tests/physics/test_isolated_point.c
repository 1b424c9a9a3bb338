/*
 * test_isolated_point.c - what plain MPM does with a point that shares no
 * node with another point (gm_domain_step(3), "Stretched and isolated
 * points"): its internal forces sum to zero on its own nodes, so it flies
 * as a free body (gravity only), its velocity gradient is zero, and its F,
 * volume and stress stay as they were, while its volume still sets the
 * stable time step. Checked in USL, MUSL and USF with linear shapes.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

static const double GRAVITY = 9.81; /* m/s^2 */

START_TEST(test_isolated_point_flies_freely) {
  gm_update_scheme scheme = (gm_update_scheme)_i;
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.cell_size = 0.01;
  def.extent[0] = def.extent[1] = 1.0;
  def.gravity[1] = -GRAVITY;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1800.0);
  /* Off the node rows, with a volume 10 times a quarter cell (a point
   * stretched by a flow) and a stress it carried when it lost contact. */
  const double start[2] = {0.3137, 0.7021}, velocity[2] = {1.0, 2.0};
  const double volume = 10.0 * 2.5e-5;                      /* m^3 per m */
  const double stress[6] = {-5e4, 2e4, 6e3, 3e4, 0.0, 0.0}; /* Pa */
  gm_points_def points = gm_points_def_default();
  points.count = 1;
  points.material = material;
  points.position = start;
  points.velocity = velocity;
  points.volume = &volume;
  points.stress = stress;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  const double dt = 1e-4; /* s */
  const int steps = 200;
  for (int step = 0; step < steps; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
  double x[2], v[2], s[6], f[9], current = 0.0;
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION, x, 2));
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_VELOCITY, v, 2));
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_STRESS, s, 6));
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_DEFORMATION_GRADIENT, f, 9));
  TEST_ASSERT_OK(domain,
                 gm_domain_get_field(domain, GM_FIELD_VOLUME, &current, 1));
  /* The discrete free flight of the time integrator (the position takes
   * the updated velocity): v_n = v0 - g n dt, x_n = x0 + n dt v0 -
   * g dt^2 n (n + 1) / 2. Measured to 1e-15 m: asserted to 1e-12 m,
   * round-off over 200 steps. */
  double t = steps * dt;
  double expected_y = start[1] + velocity[1] * t -
                      GRAVITY * dt * dt * steps * (steps + 1) / 2.0;
  ck_assert_msg(fabs(x[0] - (start[0] + velocity[0] * t)) < 1e-12 &&
                    fabs(x[1] - expected_y) < 1e-12,
                "%s: isolated point at (%.17g, %.17g), free flight (%.17g, "
                "%.17g)",
                test_scheme_name(scheme), x[0], x[1],
                start[0] + velocity[0] * t, expected_y);
  ck_assert_msg(fabs(v[0] - velocity[0]) < 1e-12 &&
                    fabs(v[1] - (velocity[1] - GRAVITY * t)) < 1e-12,
                "%s: velocity (%g, %g) m/s", test_scheme_name(scheme), v[0],
                v[1]);
  /* Zero velocity gradient: F = I, the volume and the stress unchanged
   * (measured: F off the identity by < 1e-16, from the round-off of the
   * gradients of a uniform nodal velocity). */
  ck_assert_msg(fabs(f[0] - 1.0) < 1e-12 && fabs(f[1]) < 1e-12 &&
                    fabs(f[3]) < 1e-12 && fabs(f[4] - 1.0) < 1e-12,
                "%s: F = [%g %g; %g %g]", test_scheme_name(scheme), f[0], f[1],
                f[3], f[4]);
  ck_assert_msg(fabs(current / volume - 1.0) < 1e-12,
                "%s: volume %g, started %g", test_scheme_name(scheme), current,
                volume);
  for (int c = 0; c < 4; c++)
    ck_assert_msg(fabs(s[c] - stress[c]) < 1e-9 * 5e4,
                  "%s: stress component %d is %g Pa, started %g Pa",
                  test_scheme_name(scheme), c, s[c], stress[c]);
  /* Its frozen state still sets the stable dt: c = sqrt(M V / m), with
   * V / m = 1 / rho unchanged. */
  double youngs = 1e6, nu = 0.3, rho = 1800.0; /* Pa, -, kg/m^3 */
  double modulus = youngs * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
  double wave = sqrt(modulus / rho); /* m/s */
  double stable = 0.0;
  TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &stable));
  double speed = hypot(v[0], v[1]);
  ck_assert_msg(fabs(stable - def.cfl * def.cell_size / (wave + speed)) <
                    1e-12 * stable,
                "%s: stable dt %g s, expected cfl h / (c + |v|) = %g s",
                test_scheme_name(scheme), stable,
                def.cfl * def.cell_size / (wave + speed));
  gm_domain_destroy(domain);
}
END_TEST

static Suite *isolated_point_suite(void) {
  Suite *suite = suite_create("isolated_point");
  TCase *tcase = tcase_create("flight");
  tcase_add_loop_test(tcase, test_isolated_point_flies_freely, GM_SCHEME_USL,
                      GM_SCHEME_USF + 1);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(isolated_point_suite()) ? EXIT_FAILURE : 0;
}
