/*
 * test_cell_crossing.c - cell-crossing noise of linear MPM and its
 * reduction by uGIMP, cpGIMP and CPDI (000 sec 2.1; Bardenhagen & Kober
 * 2004 introduced GIMP for exactly this) and by the quadratic and cubic
 * B-splines (Steffen, Kirby & Berzins 2008 proposed them for the same).
 *
 * A 1D elastic column (uniaxial strain, nu = 0) of height H0 = 1 m stands
 * on a fixed base under gravity and is soft enough (rho g H0 / E = 0.2)
 * that its points move by up to two cells while it settles: every point
 * crosses cell edges. Local damping brings it to rest. At rest the stress
 * follows from equilibrium alone, whatever the constitutive law: in the
 * reference configuration d sigma / dX = rho0 g, so
 *   sigma(X) = -rho0 g (H0 - X)                                   (1)
 * at the point that started at height X. With the hypoelastic update in
 * 1D (sigma = E ln lambda, lambda = dx/dX) the settled height of a point is
 *   x(X) = (exp(-a (H0 - X)) - exp(-a H0)) / a,  a = rho0 g / E.  (2)
 * Linear MPM's gradients jump as points cross cells; the nodal forces then
 * jump too, and the column never settles: its point stresses scatter
 * around (1). The smooth GIMP/CPDI/B-spline weights remove the jumps.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

static const double COLUMN_HEIGHT = 1.0; /* m, H0 */
static const double CELL_SIZE = 0.05;    /* m: 20 cells, 40 points */
static const double DENSITY = 1000.0;    /* kg/m^3, rho0 */
static const double GRAVITY = 9.81;      /* m/s^2 */
static const double YOUNGS = 5e4;        /* Pa: rho0 g H0 / E = 0.196 */
static const double DAMPING = 0.3;       /* Cundall's local damping */
static const double SETTLE_TIME = 3.0;   /* s, ~30 periods of the column */

typedef struct column_result {
  double stress_error; /* RMS of sigma_p - (1), over rho0 g H0 */
  double top_error;    /* |x_top - (2)| / H0 of the highest point */
} column_result;

static column_result settle_column(gm_shape shape) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_1D;
  def.shape = shape;
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = CELL_SIZE;
  def.extent[0] = 1.2 * COLUMN_HEIGHT;
  def.gravity[0] = -GRAVITY;
  def.walls[GM_FACE_XMIN] = GM_WALL_FIXED;
  def.damping = DAMPING;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, YOUNGS, 0.0, DENSITY);
  const double lower[3] = {0.0, 0.0, 0.0};
  const double upper[3] = {COLUMN_HEIGHT, 0.0, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);

  size_t count = gm_domain_point_count(domain);
  double *start = malloc(count * sizeof *start); /* X by id, m */
  double *position = malloc(count * sizeof *position);
  double *stress = malloc(6 * count * sizeof *stress);
  int64_t *ids = malloc(count * sizeof *ids);
  ck_assert(start && position && stress && ids);
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_POSITION, position, count));
  TEST_ASSERT_OK(domain, gm_domain_get_ids(domain, ids, count));
  for (size_t i = 0; i < count; i++)
    start[ids[i]] = position[i]; /* fill_box ids are 0..count-1 */

  double wave_speed = sqrt(YOUNGS / DENSITY); /* m/s */
  double dt = 0.2 * CELL_SIZE / wave_speed;   /* s */
  for (double time = 0.0; time < SETTLE_TIME; time += dt)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));

  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_POSITION, position, count));
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_STRESS, stress, 6 * count));
  TEST_ASSERT_OK(domain, gm_domain_get_ids(domain, ids, count));
  double scale = DENSITY * GRAVITY * COLUMN_HEIGHT; /* Pa */
  double a = DENSITY * GRAVITY / YOUNGS;            /* 1/m */
  double squares = 0.0, top = -INFINITY, top_start = 0.0;
  for (size_t i = 0; i < count; i++) {
    double reference = start[ids[i]]; /* X, m */
    double exact = -DENSITY * GRAVITY * (COLUMN_HEIGHT - reference);
    squares += pow((stress[6 * i + GM_XX] - exact) / scale, 2);
    if (position[i] > top) {
      top = position[i];
      top_start = reference;
    }
  }
  double exact_top =
      (exp(-a * (COLUMN_HEIGHT - top_start)) - exp(-a * COLUMN_HEIGHT)) / a;
  column_result result = {sqrt(squares / (double)count),
                          fabs(top - exact_top) / COLUMN_HEIGHT};
  free(start);
  free(position);
  free(stress);
  free(ids);
  gm_domain_destroy(domain);
  return result;
}

START_TEST(test_wide_supports_remove_cell_crossing_noise) {
  column_result linear = settle_column(GM_SHAPE_LINEAR);
  /* Measured 0.22 (and the column keeps ~1.5 J of kinetic energy): the
   * noise is a fifth of the largest stress, far above the ~1% that the
   * discretisation of the free end alone gives (see below). */
  ck_assert_msg(linear.stress_error > 0.1,
                "linear MPM stress error %.4f: the case no longer shows "
                "cell-crossing noise",
                linear.stress_error);
  const gm_shape wide[5] = {GM_SHAPE_UGIMP, GM_SHAPE_CPGIMP, GM_SHAPE_CPDI,
                            GM_SHAPE_BSPLINE2, GM_SHAPE_BSPLINE3};
  /* Required reduction of the RMS stress error against linear MPM.
   * Measured: uGIMP 8.6x (0.026), cpGIMP 22x (0.010), CPDI 21x (0.011);
   * the domains of cpGIMP and CPDI follow the compression, so their
   * supports stay contiguous and they do better than uGIMP, whose fixed
   * domains overlap in the compressed base. The B-splines' gradients are
   * continuous (quadratic) or C1 (cubic) across cell edges whatever the
   * point spacing (Steffen, Kirby & Berzins 2008): measured 10x (0.022)
   * and 31x (0.0072). With the fixed base held by zeroing the ghost node
   * instead of by images (bspline_faces.c) the quadratic gave 0.048 (4.6x),
   * its error concentrated on the two lowest points (-0.20, -0.17). */
  const double reduction[5] = {5.0, 10.0, 10.0, 7.0, 15.0};
  for (int v = 0; v < 5; v++) {
    column_result result = settle_column(wide[v]);
    ck_assert_msg(result.stress_error * reduction[v] < linear.stress_error,
                  "%s: stress error %.4f, linear MPM %.4f: reduced by "
                  "%.1fx, expected at least %.0fx",
                  test_shape_name(wide[v]), result.stress_error,
                  linear.stress_error,
                  linear.stress_error / result.stress_error, reduction[v]);
    /* The settled top against (2): measured within 0.17% of H0 for all
     * five (uGIMP 0.17%, B-spline2 0.15%, the others <= 0.035%); 0.5% is the
     * scale of one point spacing's worth of strain error (0.025 m x 0.2) and
     * fails if the column settles wrongly. */
    ck_assert_msg(result.top_error < 0.005,
                  "%s: top of the column off by %.4f H0 from (2)",
                  test_shape_name(wide[v]), result.top_error);
  }
}
END_TEST

static Suite *cell_crossing_suite(void) {
  Suite *suite = suite_create("cell_crossing");
  TCase *tcase = tcase_create("settling_column");
  tcase_set_timeout(tcase, 120);
  tcase_add_test(tcase, test_wide_supports_remove_cell_crossing_noise);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(cell_crossing_suite()) ? EXIT_FAILURE : 0;
}
