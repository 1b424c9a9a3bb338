/*
 * test_axisymmetric.c - fundamental radial vibration of a free solid elastic
 * cylinder in plane strain along its axis, in axisymmetric geometry.
 *
 * Closed form (linear elasticity, u_z = 0): the radial displacement
 * u_r = A J1(k r) sin(omega t) satisfies the radial wave equation
 *   (lambda + 2 mu) d/dr( (1/r) d(r u_r)/dr ) = rho d2u_r/dt2
 * with omega = k sqrt((lambda + 2 mu)/rho). The stress
 *   sigma_rr = (lambda + 2 mu) du_r/dr + lambda u_r/r
 * must vanish at the free surface r = R; with J1'(x) = J0(x) - J1(x)/x this
 * is, for x = k R,
 *   (lambda + 2 mu) x J0(x) - 2 mu J1(x) = 0,
 * whose first positive root (below the first zero of J0) we find by
 * bisection. The initial velocity v_r(r) = v0 J1(k r) excites this mode
 * alone, so sum_p m_p v_r,p oscillates as cos(omega t).
 *
 * Set-up: x = r in [0, R] with origin[0] = 0 (the library holds v_r = 0 on
 * the axis; the XMIN face is left OPEN so that is what we test), y = z in
 * [0, H] between SLIP walls on the YMIN/YMAX faces, which keep u_z = 0 (plane
 * strain along z), and an OPEN XMAX face far beyond R.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

static const double PI = 3.14159265358979323846;

static const double CYLINDER_RADIUS = 1.25; /* m, R: 20 cells */
static const double CELL_SIZE = 0.0625;     /* m, h = 1/16, exact */
static const double SLAB_HEIGHT = 0.125;    /* m, H: 2 cells along z */
static const double YOUNGS = 100.0;         /* Pa */
static const double POISSON = 0.3;          /* - */
static const double DENSITY = 1.0;          /* kg/m^3 */
static const double VELOCITY_SCALE = 0.01;  /* m/s, v0; strain ~ 1e-3 */
static const double COURANT_NUMBER = 0.2;   /* dt = 0.2 h / c */
static const double PERIODS_SIMULATED = 2.3;

/* Bessel function of the first kind J_n(x), n = 0 or 1, by its power series
 * sum_m (-1)^m (x/2)^(2m+n) / (m! (m+n)!). For |x| < 5 the largest term is
 * ~10, so the alternating sum keeps ~15 significant digits; 40 terms reach
 * the double round-off. */
static double bessel_j(int n, double x) {
  double half = 0.5 * x;
  double term = n == 0 ? 1.0 : half; /* m = 0 term */
  double sum = term;
  for (int m = 1; m < 40; ++m) {
    term *= -half * half / ((double)m * (double)(m + n));
    sum += term;
  }
  return sum;
}

typedef double scalar_function(double x, const void *parameters);

/* Root of f in [low, high] by bisection; f(low) and f(high) differ in sign. */
static double bisect(scalar_function *f, const void *parameters, double low,
                     double high) {
  double f_low = f(low, parameters);
  ck_assert_msg(f_low * f(high, parameters) < 0, "root not bracketed");
  for (int iteration = 0; iteration < 200 && high - low > 1e-15; ++iteration) {
    double middle = 0.5 * (low + high);
    double f_middle = f(middle, parameters);
    if ((f_middle < 0) == (f_low < 0)) {
      low = middle;
      f_low = f_middle;
    } else {
      high = middle;
    }
  }
  return 0.5 * (low + high);
}

static double bessel_j0_at(double x, const void *unused) {
  (void)unused;
  return bessel_j(0, x);
}

static double bessel_j1_at(double x, const void *unused) {
  (void)unused;
  return bessel_j(1, x);
}

/* Lame constants, Pa. */
typedef struct lame_constants {
  double lambda;
  double mu;
} lame_constants;

/* sigma_rr(R) (up to the factor k A) as a function of x = k R; Pa. */
static double free_surface_residual(double x, const void *parameters) {
  const lame_constants *lame = parameters;
  return (lame->lambda + 2 * lame->mu) * x * bessel_j(0, x) -
         2 * lame->mu * bessel_j(1, x);
}

/* The helpers reproduce the tabulated first zeros of J0 and J1
 * (Abramowitz & Stegun table 9.5: 2.404825557695773, 3.831705970207512). */
START_TEST(test_bessel_helpers) {
  ck_assert_double_eq_tol(bisect(bessel_j0_at, NULL, 2.0, 3.0),
                          2.404825557695773, 1e-12);
  ck_assert_double_eq_tol(bisect(bessel_j1_at, NULL, 3.0, 4.5),
                          3.831705970207512, 1e-12);
}
END_TEST

static gm_domain *cylinder_domain(gm_update_scheme scheme, gm_shape shape) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_AXISYMMETRIC;
  def.scheme = scheme;
  def.shape = shape;
  def.cell_size = CELL_SIZE;
  def.origin[0] = 0.0; /* the axis */
  def.origin[1] = 0.0;
  def.extent[0] = 2.0; /* m: the surface moves < 1 mm */
  def.extent[1] = SLAB_HEIGHT;
  def.walls[GM_FACE_YMIN] = GM_WALL_SLIP;
  def.walls[GM_FACE_YMAX] = GM_WALL_SLIP;
  return test_create_domain(&def);
}

/* Sets v_r = v0 J1(k r) on every point, v_z = 0. */
static void set_mode_velocity(gm_domain *domain, double wave_number) {
  size_t count = gm_domain_point_count(domain);
  const double *radius = NULL;
  double *radial_velocity = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &radius));
  TEST_ASSERT_OK(domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0,
                                              &radial_velocity));
  for (size_t i = 0; i < count; ++i)
    radial_velocity[i] = VELOCITY_SCALE * bessel_j(1, wave_number * radius[i]);
}

/* sum_p m_p v_r,p (kg m/s): the mode's amplitude up to a constant. */
static double radial_momentum(const gm_domain *domain) {
  size_t count = gm_domain_point_count(domain);
  const double *mass = NULL, *radial_velocity = NULL;
  TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass));
  TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_VELOCITY, 0,
                                              &radial_velocity));
  double total = 0.0;
  for (size_t i = 0; i < count; ++i)
    total += mass[i] * radial_velocity[i];
  return total;
}

static double total_mass(const gm_domain *domain) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  return summary.mass; /* kg, full rings */
}

/* Loop index: shape-function variant (i / 3) and update scheme (i % 3). */
START_TEST(test_radial_mode) {
  gm_update_scheme scheme = (gm_update_scheme)(_i % 3);
  gm_shape shape = (gm_shape)(_i / 3);
  lame_constants lame;
  lame.lambda = YOUNGS * POISSON / ((1 + POISSON) * (1 - 2 * POISSON));
  lame.mu = YOUNGS / (2 * (1 + POISSON));
  double modulus = lame.lambda + 2 * lame.mu;  /* Pa */
  double wave_speed = sqrt(modulus / DENSITY); /* m/s */
  /* The residual is (lambda + mu) x > 0 near 0 and -2 mu J1 < 0 at the first
   * zero of J0, so the root is bracketed there. */
  double j0_zero = bisect(bessel_j0_at, NULL, 2.0, 3.0);
  double root = bisect(free_surface_residual, &lame, 0.1, j0_zero);
  double wave_number = root / CYLINDER_RADIUS;         /* 1/m */
  double omega = wave_number * wave_speed;             /* rad/s */
  double period = 2 * PI / omega;                      /* s */
  double dt = COURANT_NUMBER * CELL_SIZE / wave_speed; /* s */
  int steps = (int)ceil(PERIODS_SIMULATED * period / dt);

  gm_domain *domain = cylinder_domain(scheme, shape);
  int material = test_add_elastic(domain, YOUNGS, POISSON, DENSITY);
  const double lower[3] = {0.0, 0.0, 0.0};
  const double upper[3] = {CYLINDER_RADIUS, SLAB_HEIGHT, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  set_mode_velocity(domain, wave_number);

  /* Full-ring masses: sum over points of rho 2 pi r_p A_p is the midpoint
   * rule for rho int 2 pi r dr dz, exact for the linear integrand, so the
   * total is rho pi R^2 H to round-off (~count * eps; 1e-12 relative). */
  double mass0 = total_mass(domain);
  double exact_mass =
      DENSITY * PI * CYLINDER_RADIUS * CYLINDER_RADIUS * SLAB_HEIGHT;
  ck_assert_double_eq_tol(mass0, exact_mass, 1e-12 * exact_mass);

  double *momentum = malloc((size_t)(steps + 1) * sizeof *momentum);
  ck_assert_ptr_nonnull(momentum);
  momentum[0] = radial_momentum(domain);
  ck_assert_double_gt(momentum[0], 0.0);
  for (int k = 1; k <= steps; ++k) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    momentum[k] = radial_momentum(domain);
    /* Point masses never change: the total is bit-for-bit constant. */
    ck_assert_msg(total_mass(domain) == mass0,
                  "%s %s step %d: mass %.17g != %.17g", test_shape_name(shape),
                  test_scheme_name(scheme), k, total_mass(domain), mass0);
  }

  /* Zero crossings of sum m v_r at T/4, 3T/4, ..., 9T/4, by linear
   * interpolation; the first and fifth are two periods apart. */
  double crossing[5];
  int found = 0;
  for (int k = 0; k < steps && found < 5; ++k) {
    double a = momentum[k], b = momentum[k + 1];
    if ((a > 0 && b <= 0) || (a < 0 && b >= 0))
      crossing[found++] = dt * (k + a / (a - b));
  }
  ck_assert_int_eq(found, 5);
  double measured_period = (crossing[4] - crossing[0]) / 2.0;
  /* Error budget: interpolation of the crossings O((omega dt)^2) ~ 1e-4,
   * linear elements with lumped mass O((k h)^2 / 24) ~ 1e-3 (k h ~ 0.1), the
   * 1/r hoop terms of the points nearest the axis O(h/R) in a region that
   * carries little of the mode's energy (J1 ~ k r there). 2% bounds these;
   * a wrong sign or a missing hoop term moves the period by ~20% or more. */
  ck_assert_msg(fabs(measured_period - period) <= 0.02 * period,
                "%s %s: period %.6g s, expected %.6g s (k R = %.6f)",
                test_shape_name(shape), test_scheme_name(scheme),
                measured_period, period, root);

  /* First peak: near T/2 the radial momentum reaches -(its initial value).
   * Losses are the energy the sampled J1 puts into higher discrete modes,
   * O((k h)^2) ~ 1% of the energy at most (0.5% of the amplitude), and the
   * small dissipation of the grid transfers over half a period; 2% bounds
   * them, while a damped or mis-scaled hoop response fails. */
  double trough = 0.0;
  for (int k = 0; k <= steps && k * dt <= period; ++k)
    trough = fmin(trough, momentum[k]);
  ck_assert_msg(fabs(-trough - momentum[0]) <= 0.02 * momentum[0],
                "%s %s: first peak of sum m v_r %.6g, expected -%.6g",
                test_shape_name(shape), test_scheme_name(scheme), trough,
                momentum[0]);

  free(momentum);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *axisymmetric_suite(void) {
  Suite *suite = suite_create("axisymmetric");
  TCase *helpers = tcase_create("bessel");
  tcase_add_test(helpers, test_bessel_helpers);
  suite_add_tcase(suite, helpers);
  TCase *cylinder = tcase_create("free_cylinder_radial_mode");
  tcase_set_timeout(cylinder, 120);
  /* USL, MUSL, USF for each of linear MPM, uGIMP, cpGIMP, CPDI and the
   * quadratic and cubic B-splines. */
  tcase_add_loop_test(cylinder, test_radial_mode, 0, 18);
  suite_add_tcase(suite, cylinder);
  return suite;
}

int main(void) {
  return test_run_suite(axisymmetric_suite()) ? EXIT_FAILURE : 0;
}
