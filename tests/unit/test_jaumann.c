/*
 * test_jaumann.c - the objective stress update around the material call.
 *
 * A pre-stressed block starts spinning, v = omega (-y, x) about its
 * centre, with a material that leaves the (already rotated) stress
 * unchanged: every change of stress is the library's Jaumann rotation
 * sigma + (W sigma - sigma W) dt (002 sec 4.1, 004 eqs 3.20-3.21). Then:
 *  - the trace is unchanged to round-off: tr(W sigma - sigma W) = 0 for any
 *    W, so this holds at every point, edges included;
 *  - the norm sigma:sigma changes only at second order, by a factor
 *    (1 + O((w dt)^2)) per step;
 *  - the principal axes turn with the material's spin. Nothing supplies a
 *    centripetal force (the stress is a tiny 1 Pa on 1000 kg/m^3), so each
 *    point keeps its initial velocity: x = (I + omega J t) x0 with J the
 *    90-degree rotation, v = omega J x0, hence the velocity gradient
 *    L = omega J (I + omega J t)^-1 = (omega J + omega^2 t I)/(1 + (omega t)^2)
 *    whose spin is omega / (1 + (omega t)^2). The stress axes therefore
 *    turn by atan(omega t) (not omega t): sigma = R sigma_0 R^T with that
 *    angle, to first order in dt, at interior points (where the grid
 *    reproduces the linear velocity field exactly).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

static const double OMEGA = 2.0;  /* rad/s */
static const double STRESS = 1.0; /* Pa, sigma_xx of the initial state */
static const double DT = 1e-4;    /* s */
enum { STEPS = 2000 };            /* 0.2 s: the body turns 0.4 rad */

/* A material that keeps the stress it is given (the rotated one). */
static int keep_stress(const gm_material_batch *batch, void *user,
                       char *message, size_t message_size) {
  (void)batch;
  (void)user;
  (void)message;
  (void)message_size;
  return 0;
}

START_TEST(test_rigid_rotation_keeps_invariants) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = 0.1;
  def.origin[0] = def.origin[1] = -1.0;
  def.extent[0] = def.extent[1] = 2.0;
  gm_domain *domain = test_create_domain(&def);
  gm_material_def material = gm_material_def_default();
  material.update = keep_stress;
  material.p_wave_modulus = 1e4; /* Pa: only sets the stable dt */
  material.density = 1000.0;
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_material(domain, &material, &id));
  /* A 0.8 m square block centred on the origin, 2 x 2 points per cell,
   * uniaxial stress along x, spinning rigidly. */
  enum { SIDE = 16 };
  double position[2 * SIDE * SIDE], velocity[2 * SIDE * SIDE];
  double volume[SIDE * SIDE], stress[6 * SIDE * SIDE] = {0};
  for (int j = 0; j < SIDE; j++) {
    for (int i = 0; i < SIDE; i++) {
      int p = j * SIDE + i;
      double x = -0.4 + (i + 0.5) * 0.05, y = -0.4 + (j + 0.5) * 0.05;
      position[2 * p] = x;
      position[2 * p + 1] = y;
      velocity[2 * p] = -OMEGA * y;
      velocity[2 * p + 1] = OMEGA * x;
      volume[p] = 0.05 * 0.05;
      stress[6 * p + GM_XX] = STRESS;
    }
  }
  gm_points_def points = gm_points_def_default();
  points.count = SIDE * SIDE;
  points.material = id;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  points.stress = stress;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  for (int step = 0; step < STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, DT));

  double angle = atan(OMEGA * DT * STEPS); /* 0.3805 rad, see above */
  double c = cos(angle), s = sin(angle);
  /* R diag(S, 0) R^T */
  double expected_xx = STRESS * c * c, expected_yy = STRESS * s * s;
  double expected_xy = STRESS * c * s;
  double *now = malloc(6 * SIDE * SIDE * sizeof(double));
  double *where = malloc(2 * SIDE * SIDE * sizeof(double));
  ck_assert(now && where);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_STRESS, now,
                                             6 * SIDE * SIDE));
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION, where,
                                             2 * SIDE * SIDE));
  int interior = 0;
  for (int p = 0; p < SIDE * SIDE; p++) {
    const double *sigma = now + 6 * p;
    double trace = sigma[GM_XX] + sigma[GM_YY] + sigma[GM_ZZ];
    /* tr is exactly invariant; 2000 steps of round-off on 1 Pa. */
    ck_assert_msg(fabs(trace - STRESS) < 1e-12, "point %d: trace %.17g", p,
                  trace);
    double norm = sigma[GM_XX] * sigma[GM_XX] + sigma[GM_YY] * sigma[GM_YY] +
                  2.0 * sigma[GM_XY] * sigma[GM_XY];
    /* Forward Euler grows sigma:sigma by (1 + 4 (w dt)^2) per step at most
     * (w = omega for interior points, within a few % at the edges):
     * 2000 * 4 * (2e-4)^2 = 3.2e-4; allow 1e-3. */
    ck_assert_msg(fabs(norm - STRESS * STRESS) < 1e-3 * STRESS * STRESS,
                  "point %d: sigma:sigma %.17g", p, norm);
    /* Interior points: compare with R sigma_0 R^T. Forward Euler in time
     * and the time discretisation of the spin differ by O(omega dt) = 2e-4
     * relative per unit angle: 1e-3 of STRESS. */
    double radius = hypot(where[2 * p], where[2 * p + 1]);
    if (radius > 0.25)
      continue;
    interior++;
    ck_assert_msg(fabs(sigma[GM_XX] - expected_xx) < 1e-3 * STRESS &&
                      fabs(sigma[GM_YY] - expected_yy) < 1e-3 * STRESS &&
                      fabs(sigma[GM_XY] - expected_xy) < 1e-3 * STRESS,
                  "point %d: sigma (%g, %g, %g), expected (%g, %g, %g)", p,
                  sigma[GM_XX], sigma[GM_YY], sigma[GM_XY], expected_xx,
                  expected_yy, expected_xy);
  }
  ck_assert_int_gt(interior, 50);
  free(now);
  free(where);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("jaumann");
  TCase *tcase = tcase_create("objective_stress");
  tcase_set_timeout(tcase, 60);
  tcase_add_test(tcase, test_rigid_rotation_keeps_invariants);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
