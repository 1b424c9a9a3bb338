/*
 * test_bar.c - fixed-free elastic bar vibrating in its first mode
 * (docs/references.md, "Fixed-free elastic bar"; Sulsky/Bardenhagen benchmark).
 *
 * Bar of length L = 25 m, fixed at x = 0 (GM_WALL_FIXED on the XMIN face),
 * free at x = L, density rho = 1 kg/m^3, initial velocity
 * v(x) = v0 sin(beta_1 x) with beta_1 = pi/(2L), v0 = 0.1 m/s. In uniaxial
 * strain with wave modulus M the solution is v = v0 cos(omega_1 t)
 * sin(beta_1 x), omega_1 = beta_1 sqrt(M/rho), and the centre-of-mass
 * velocity is
 *   v_cm(t) = (1/L) int_0^L v dx = (2 v0/pi) cos(omega_1 t).
 * Two settings, each with USL, MUSL and USF, every shape-function
 * variant (linear MPM, uGIMP, cpGIMP, CPDI, quadratic and cubic
 * B-splines) and both velocity transfers (FLIP and APIC):
 *  (a) 1D geometry, nu = 0: M = E;
 *  (b) plane strain, bar filling a 3-cell channel between SLIP walls on the
 *      YMIN/YMAX faces, so v_y = 0 everywhere and the strain is uniaxial:
 *      nu = 0.3, M = E(1-nu)/((1+nu)(1-2nu)).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_util.h"

static const double PI = 3.14159265358979323846;

static const double BAR_LENGTH = 25.0;    /* m */
static const double BAR_YOUNGS = 100.0;   /* Pa */
static const double BAR_DENSITY = 1.0;    /* kg/m^3 */
static const double BAR_V0 = 0.1;         /* m/s */
static const double BAR_CELL_SIZE = 1.0;  /* m, 25 cells along the bar */
static const double CHANNEL_HEIGHT = 3.0; /* m, plane strain case */
static const double COURANT_NUMBER = 0.2; /* dt = 0.2 h / c */
static const double PERIODS_SIMULATED = 2.3;

/* Constrained (P-wave) modulus M = E(1-nu)/((1+nu)(1-2nu)), Pa. */
static double constrained_modulus(double youngs, double poisson) {
  return youngs * (1 - poisson) / ((1 + poisson) * (1 - 2 * poisson));
}

/* Sets v_x = v0 sin(pi x / (2L)) on every point (v_y stays 0). */
static void set_mode_one_velocity(gm_domain *domain) {
  size_t count = gm_domain_point_count(domain);
  const double *x = NULL;
  double *velocity_x = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  TEST_ASSERT_OK(
      domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity_x));
  for (size_t i = 0; i < count; ++i)
    velocity_x[i] = BAR_V0 * sin(PI * x[i] / (2.0 * BAR_LENGTH));
}

/* Builds the bar; returns the domain. The grid reaches x = 30 m so the free
 * end (moving by at most v0/omega_1 ~ 0.16 m) stays well inside. */
static gm_domain *bar_domain(gm_geometry geometry, gm_update_scheme scheme,
                             gm_shape shape, gm_transfer transfer,
                             double poisson) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = geometry;
  def.transfer = transfer;
  def.scheme = scheme;
  def.shape = shape;
  def.cell_size = BAR_CELL_SIZE;
  def.extent[0] = 30.0;
  def.extent[1] = CHANNEL_HEIGHT;
  def.walls[GM_FACE_XMIN] = GM_WALL_FIXED;
  if (geometry == GM_GEOMETRY_PLANE_STRAIN) {
    def.walls[GM_FACE_YMIN] = GM_WALL_SLIP;
    def.walls[GM_FACE_YMAX] = GM_WALL_SLIP;
  }
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, BAR_YOUNGS, poisson, BAR_DENSITY);
  const double lower[3] = {0.0, 0.0, 0.0};
  const double upper[3] = {BAR_LENGTH, CHANNEL_HEIGHT, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  set_mode_one_velocity(domain);
  return domain;
}

static const char *transfer_name(gm_transfer transfer) {
  return transfer == GM_TRANSFER_APIC ? "APIC" : "FLIP";
}

static double centre_of_mass_velocity(const gm_domain *domain) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  return summary.momentum[0] / summary.mass; /* m/s */
}

/* Times of the sign changes of samples[k] (taken at k dt), by linear
 * interpolation between neighbouring steps. Returns how many were found. */
static int zero_crossings(const double *samples, int sample_count, double dt,
                          double *times, int max_times) {
  int found = 0;
  for (int k = 0; k + 1 < sample_count && found < max_times; ++k) {
    double a = samples[k], b = samples[k + 1];
    if ((a > 0 && b <= 0) || (a < 0 && b >= 0))
      times[found++] = dt * (k + a / (a - b));
  }
  return found;
}

/* Loop index i: transfer (i / 24: FLIP, APIC), shape (i / 6 % 4),
 * geometry (0: 1D, 1: plane strain) and scheme. */
START_TEST(test_bar_vibration) {
  gm_transfer transfer = (gm_transfer)(_i / 36);
  gm_shape shape = (gm_shape)(_i / 6 % 6);
  gm_geometry geometry =
      _i % 6 / 3 == 0 ? GM_GEOMETRY_1D : GM_GEOMETRY_PLANE_STRAIN;
  gm_update_scheme scheme = (gm_update_scheme)(_i % 3);
  double poisson = geometry == GM_GEOMETRY_1D ? 0.0 : 0.3;
  double modulus = constrained_modulus(BAR_YOUNGS, poisson); /* Pa */
  double wave_speed = sqrt(modulus / BAR_DENSITY);           /* m/s */
  double omega = PI / (2.0 * BAR_LENGTH) * wave_speed;       /* rad/s */
  double period = 2.0 * PI / omega;                          /* s */
  double amplitude = 2.0 * BAR_V0 / PI;                      /* m/s */
  double dt = COURANT_NUMBER * BAR_CELL_SIZE / wave_speed;   /* s */
  int steps = (int)ceil(PERIODS_SIMULATED * period / dt);

  gm_domain *domain = bar_domain(geometry, scheme, shape, transfer, poisson);
  double *v_cm = malloc((size_t)(steps + 1) * sizeof *v_cm);
  ck_assert_ptr_nonnull(v_cm);
  v_cm[0] = centre_of_mass_velocity(domain);
  for (int k = 1; k <= steps; ++k) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    v_cm[k] = centre_of_mass_velocity(domain);
  }

  /* Initial v_cm: the points sample sin() at sub-cell centres (midpoint
   * rule, relative error (beta_1 h/2)^2 / 24 ~ 4e-5), so 1e-3 is ample. */
  ck_assert_msg(fabs(v_cm[0] - amplitude) <= 1e-3 * amplitude,
                "%s %s %s dim %d: v_cm(0) = %.6g, expected 2 v0/pi = %.6g",
                transfer_name(transfer), test_shape_name(shape),
                test_scheme_name(scheme), gm_geometry_dimension(geometry),
                v_cm[0], amplitude);

  /* Period from the zero crossings at T/4, 3T/4, ..., 9T/4: the first and
   * fifth are two periods apart. Expected errors: linear interpolation of
   * the crossings O((omega dt)^2) ~ 1e-4 of a period; lumped-mass linear
   * elements lengthen the period by (beta_1 h)^2 / 24 ~ 2e-4; the time
   * integrator shortens it by (omega dt)^2 / 24 ~ 1e-5; the geometric
   * nonlinearity at the 1% strain amplitude (v0 / c) adds O(1e-4). So 1%
   * (the target in design.md) is a real check: a wrong modulus (E for M in
   * 2D is 16%) or a free instead of a fixed end (period halved) fails it. */
  double crossing[5];
  int crossing_count = zero_crossings(v_cm, steps + 1, dt, crossing, 5);
  ck_assert_int_eq(crossing_count, 5);
  double measured_period = (crossing[4] - crossing[0]) / 2.0;
  double trough = 0.0;
  for (int k = 0; k <= steps && k * dt <= period; ++k)
    trough = fmin(trough, v_cm[k]);
  printf("bar %s %s %s dim %d: period error %+.3f %%, first peak %+.3f %%\n",
         transfer_name(transfer), test_shape_name(shape),
         test_scheme_name(scheme), gm_geometry_dimension(geometry),
         100.0 * (measured_period / period - 1.0),
         100.0 * (-trough / amplitude - 1.0));
  ck_assert_msg(
      fabs(measured_period - period) <= 0.01 * period,
      "%s %s %s dim %d: period %.6g s, expected 2 pi/omega_1 = %.6g s",
      transfer_name(transfer), test_shape_name(shape), test_scheme_name(scheme),
      gm_geometry_dimension(geometry), measured_period, period);

  /* First peak: the trough of v_cm near T/2 must reach -2 v0/pi. The
   * sampled sin() is not exactly the discrete mode, so O((beta_1 h)^2) ~ 0.4%
   * of the energy at most goes to higher modes (amplitude -0.2%), and the
   * grid transfers dissipate little of a mode resolved by 50 points over
   * half a period; elastic energy is bounded, so no overshoot beyond those
   * terms either. 2% bounds these with margin, while a scheme that damps
   * the mode (e.g. a PIC-like velocity update) or a slipping end fails. */
  ck_assert_msg(fabs(-trough - amplitude) <= 0.02 * amplitude,
                "%s %s %s dim %d: first peak of v_cm %.6g, expected -%.6g",
                transfer_name(transfer), test_shape_name(shape),
                test_scheme_name(scheme), gm_geometry_dimension(geometry),
                trough, amplitude);

  free(v_cm);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *bar_suite(void) {
  Suite *suite = suite_create("bar");
  TCase *tcase = tcase_create("fixed_free_mode_1");
  tcase_set_timeout(tcase, 120);
  /* Per transfer and shape: 0..2 1D with USL, MUSL, USF; 3..5 plane
   * strain, same. */
  tcase_add_loop_test(tcase, test_bar_vibration, 0, 72);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(bar_suite()) ? EXIT_FAILURE : 0;
}
