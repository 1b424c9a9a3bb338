/*
 * test_perzyna.c - the Perzyna elastic-viscoplastic Drucker-Prager update
 * (Wieckowski 2004, eqs 15-23) driven directly through gm_perzyna_update on
 * one-point batches, against closed forms:
 *  - N = 1: the closed form after eq 22 and the safeguarded Newton iteration
 *    give the same stress over thousands of random trial states;
 *  - N = 0.5, 2, 3: the iterated result satisfies eqs 19, 21 and 22;
 *  - trial states inside the cone are updated elastically, untouched;
 *  - as the fluidity gamma grows (viscosity -> 0) q/p tends to m with the
 *    bound derived below;
 *  - under steady simple shear the stationary q is m p (1 +
 * (rate/gamma)^(1/N));
 *  - an iteration limit that is too small gives a recoverable code > 0;
 *  - invalid parameters are rejected, naming the field.
 * Notation: p = -tr(sigma)/3, s = sigma + p I, q = sqrt(3/2 s:s),
 * m = 18 sin(phi)/(9 - sin^2(phi)).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "test_util.h"

/* A seeded linear congruential generator (Knuth's MMIX constants): the
 * random trial states are the same on every run. */
typedef struct lcg {
  uint64_t state;
} lcg;

static double lcg_uniform(lcg *random, double low, double high) {
  random->state =
      random->state * 6364136223846793005ULL + 1442695040888963407ULL;
  double unit = (double)(random->state >> 11) / 9007199254740992.0; /* 2^53 */
  return low + (high - low) * unit;
}

/* Uniform in log between low and high (> 0). */
static double lcg_log_uniform(lcg *random, double low, double high) {
  return exp(lcg_uniform(random, log(low), log(high)));
}

/* Runs gm_perzyna_update on one point: stress (Pa) in/out, strain
 * increment (-), the state (accumulated viscoplastic strain) in/out. */
static int run_point(const gm_perzyna_def *def, double dt, double stress[6],
                     const double increment[6], double *state, char *message,
                     size_t message_size) {
  double stress_column[6][1], increment_column[6][1], state_column[1];
  double density = def->density;
  int64_t id = 42;
  double *state_pointers[1] = {state_column};
  gm_material_batch batch;
  memset(&batch, 0, sizeof batch);
  batch.struct_size = sizeof batch;
  batch.count = 1;
  batch.geometry = GM_GEOMETRY_PLANE_STRAIN;
  batch.dt = dt;
  for (int c = 0; c < 6; c++) {
    stress_column[c][0] = stress[c];
    increment_column[c][0] = increment[c];
    batch.stress[c] = stress_column[c];
    batch.strain_increment[c] = increment_column[c];
  }
  state_column[0] = *state;
  batch.density = &density;
  batch.state = state_pointers;
  batch.state_count = 1;
  batch.point_id = &id;
  int result = gm_perzyna_update(&batch, (void *)def, message, message_size);
  for (int c = 0; c < 6; c++)
    stress[c] = stress_column[c][0];
  *state = state_column[0];
  return result;
}

/* Same, failing the test on a non-zero return. */
static void update_point(const gm_perzyna_def *def, double dt, double stress[6],
                         const double increment[6], double *state) {
  char message[256] = "";
  int result =
      run_point(def, dt, stress, increment, state, message, sizeof message);
  ck_assert_msg(result == 0, "update returned %d: %s", result, message);
}

static double pressure_of(const double sigma[6]) {
  return -(sigma[GM_XX] + sigma[GM_YY] + sigma[GM_ZZ]) / 3.0;
}

static double mises_of(const double sigma[6]) {
  double p = pressure_of(sigma);
  double s[3] = {sigma[GM_XX] + p, sigma[GM_YY] + p, sigma[GM_ZZ] + p};
  double shear = sigma[GM_XY] * sigma[GM_XY] + sigma[GM_YZ] * sigma[GM_YZ] +
                 sigma[GM_ZX] * sigma[GM_ZX];
  return sqrt(1.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * shear));
}

static double slope_of(double friction_angle) {
  double sine = sin(friction_angle);
  return 18.0 * sine / (9.0 - sine * sine);
}

static double shear_modulus(const gm_perzyna_def *def) {
  return def->youngs_modulus / (2.0 * (1.0 + def->poisson_ratio));
}

static double bulk_modulus(const gm_perzyna_def *def) {
  return def->youngs_modulus / (3.0 * (1.0 - 2.0 * def->poisson_ratio));
}

/* The elastic trial stress sigma + C : de (Pa), written independently of the
 * library (Lame form). */
static void elastic_trial(const gm_perzyna_def *def, const double sigma[6],
                          const double increment[6], double trial[6]) {
  double shear = shear_modulus(def);
  double lame = bulk_modulus(def) - 2.0 * shear / 3.0;
  double volumetric = increment[GM_XX] + increment[GM_YY] + increment[GM_ZZ];
  for (int c = 0; c < 6; c++)
    trial[c] = sigma[c] + 2.0 * shear * increment[c] +
               (c < 3 ? lame * volumetric : 0.0);
}

static double max_abs(const double v[6]) {
  double largest = 0.0;
  for (int c = 0; c < 6; c++)
    largest = fmax(largest, fabs(v[c]));
  return largest;
}

/* A random compressive stress (p in 1e3..1e5 Pa, deviator up to 0.8 p per
 * component), strain increment (up to 2e-3 per component) and material
 * (nu, phi in 15..45 deg, gamma log-uniform in 0.1..1e4 1/s). */
static void random_case(lcg *random, gm_perzyna_def *def, double sigma[6],
                        double increment[6]) {
  *def = gm_perzyna_def_default();
  def->poisson_ratio = lcg_uniform(random, 0.1, 0.45);
  def->friction_angle = lcg_uniform(random, 0.26, 0.79);
  def->fluidity = lcg_log_uniform(random, 0.1, 1e4);
  double pressure = lcg_log_uniform(random, 1e3, 1e5);
  for (int c = 0; c < 6; c++) {
    sigma[c] =
        lcg_uniform(random, -0.8, 0.8) * pressure - (c < 3 ? pressure : 0.0);
    increment[c] = lcg_uniform(random, -2e-3, 2e-3);
  }
}

enum { RANDOM_CASES = 5000 };
static const double RANDOM_DT = 1e-4; /* s */

/* N = 1: closed form vs. the iteration. Both produce z (remaining
 * overstress fraction) to a few ulps (the iteration stops at a relative
 * step of 1e-14 on a quadratically converging sequence), and the stress is
 * s_e (m p + z f_e)/q_e, so the two agree to ~1e-14 relative; 1e-10 leaves
 * four orders of margin while any real difference (a wrong formula) is
 * O(1). At least a fifth of the cases must be viscoplastic. */
START_TEST(test_closed_form_matches_iteration) {
  lcg random = {12345};
  int viscoplastic = 0;
  double worst = 0.0;
  for (int n = 0; n < RANDOM_CASES; n++) {
    gm_perzyna_def closed;
    double sigma[6], increment[6];
    random_case(&random, &closed, sigma, increment);
    gm_perzyna_def iterated = closed;
    iterated.always_iterate = 1;
    double closed_stress[6], iterated_stress[6];
    memcpy(closed_stress, sigma, sizeof closed_stress);
    memcpy(iterated_stress, sigma, sizeof iterated_stress);
    double closed_state = 0.0, iterated_state = 0.0;
    update_point(&closed, RANDOM_DT, closed_stress, increment, &closed_state);
    update_point(&iterated, RANDOM_DT, iterated_stress, increment,
                 &iterated_state);
    /* Scale 1 Pa for the zero stress of the tension cut-off. */
    double scale = fmax(max_abs(closed_stress), 1.0);
    for (int c = 0; c < 6; c++) {
      double error = fabs(closed_stress[c] - iterated_stress[c]) / scale;
      worst = fmax(worst, error);
      ck_assert_msg(error <= 1e-10, "case %d component %d: %.17g vs %.17g", n,
                    c, closed_stress[c], iterated_stress[c]);
    }
    ck_assert(fabs(closed_state - iterated_state) <= 1e-10 * closed_state);
    viscoplastic += closed_state > 0.0;
  }
  ck_assert_int_ge(viscoplastic, RANDOM_CASES / 5);
  printf("closed form vs iteration (N = 1): %d/%d viscoplastic, worst "
         "relative difference %.3g\n",
         viscoplastic, RANDOM_CASES, worst);
}
END_TEST

static const double ITERATED_EXPONENTS[] = {0.5, 2.0, 3.0};

/* N != 1: the returned state satisfies eq 21 (q = q_e - 3 G x), eq 22
 * (x = gamma dt ((q - m p)/(m p))^N) and eq 19 (s parallel to s_e), with x
 * the state increment. The residuals are evaluated from the output stress,
 * so they carry its rounding (~1e-16 q) amplified by N q / (q - m p). We
 * keep the cases with q - m p >= 1e-4 q (amplification <= 3e4, test-side
 * error <~ 1e-11; the others, e.g. N = 0.5 with large a, are covered by
 * the rate-independent-limit test) and demand the required 1e-10. */
START_TEST(test_iteration_satisfies_consistency) {
  double exponent = ITERATED_EXPONENTS[_i];
  lcg random = {777 + (uint64_t)_i};
  int viscoplastic = 0;
  double worst = 0.0;
  for (int n = 0; n < RANDOM_CASES; n++) {
    gm_perzyna_def def;
    double sigma[6], increment[6], trial[6];
    random_case(&random, &def, sigma, increment);
    def.exponent = exponent;
    elastic_trial(&def, sigma, increment, trial);
    double state = 0.0;
    update_point(&def, RANDOM_DT, sigma, increment, &state);
    /* Elastic cases, and the tension cut-off (tested on its own below). */
    if (state == 0.0 || pressure_of(trial) <= 0.0)
      continue;
    double pressure = pressure_of(sigma), q = mises_of(sigma);
    double trial_q = mises_of(trial), m = slope_of(def.friction_angle);
    if (q - m * pressure < 1e-4 * q)
      continue;
    viscoplastic++;
    ck_assert(fabs(pressure - pressure_of(trial)) <= 1e-12 * pressure);
    double eq21 = fabs(q - (trial_q - 3.0 * shear_modulus(&def) * state));
    ck_assert_msg(eq21 <= 1e-10 * trial_q, "eq 21 residual %g", eq21);
    double rhs = def.fluidity * RANDOM_DT *
                 pow((q - m * pressure) / (m * pressure), exponent);
    double eq22 = fabs(state - rhs) / state;
    worst = fmax(worst, eq22);
    ck_assert_msg(eq22 <= 1e-10, "N = %g case %d: eq 22 residual %g", exponent,
                  n, eq22);
    for (int c = 0; c < 6; c++) { /* eq 19: s = s_e q / q_e */
      double deviator = sigma[c] + (c < 3 ? pressure : 0.0);
      double trial_deviator = trial[c] + (c < 3 ? pressure : 0.0);
      ck_assert(fabs(deviator - trial_deviator * q / trial_q) <=
                1e-10 * trial_q);
    }
  }
  ck_assert_int_ge(viscoplastic, RANDOM_CASES / 5);
  printf("iteration N = %g: %d viscoplastic, worst eq 22 residual %.3g\n",
         exponent, viscoplastic, worst);
}
END_TEST

/* Inside the cone (q < m p after the elastic increment) the update is the
 * elastic one and the state does not change. The library splits sigma into
 * p and s, the reference uses the Lame form: both round to a few ulps of
 * |sigma|, hence 1e-13. */
START_TEST(test_elastic_inside_cone) {
  gm_perzyna_def def = gm_perzyna_def_default();
  double m = slope_of(def.friction_angle);
  lcg random = {99};
  for (int n = 0; n < 1000; n++) {
    double pressure = lcg_log_uniform(&random, 1e3, 1e5);
    /* Deviator components up to 0.1 p: q <= sqrt(3/2 * 9) 0.1 p < m p/2. */
    double sigma[6], increment[6], expected[6];
    for (int c = 0; c < 6; c++) {
      sigma[c] =
          lcg_uniform(&random, -0.1, 0.1) * pressure - (c < 3 ? pressure : 0.0);
      increment[c] = lcg_uniform(&random, -1e-5, 1e-5) * pressure / 1e4;
    }
    elastic_trial(&def, sigma, increment, expected);
    ck_assert(mises_of(expected) < m * pressure_of(expected));
    double state = 0.25;
    update_point(&def, RANDOM_DT, sigma, increment, &state);
    ck_assert(state == 0.25);
    for (int c = 0; c < 6; c++)
      ck_assert(fabs(sigma[c] - expected[c]) <= 1e-13 * max_abs(expected));
  }
}
END_TEST

/* A cohesionless material carries no mean tension: a large expansion from
 * a small pressure leaves zero stress (the apex of the cone). */
START_TEST(test_tension_cut_off) {
  gm_perzyna_def def = gm_perzyna_def_default();
  double sigma[6] = {-100.0, -200.0, -150.0, 30.0, 0.0, 0.0};
  double increment[6] = {1e-2, 1e-2, 1e-2, 0.0, 0.0, 0.0};
  double state = 0.0;
  update_point(&def, RANDOM_DT, sigma, increment, &state);
  for (int c = 0; c < 6; c++)
    ck_assert(sigma[c] == 0.0);
  ck_assert(state > 0.0);
}
END_TEST

/* gamma -> infinity (viscosity 1/gamma -> 0). Eq 22 in z = (q - m p)/f_e is
 * z + a z^N = 1 with a = (3 G gamma dt/(m p)) (f_e/(m p))^(N-1); since
 * h(z) = z + a z^N - 1 is increasing and h(a^(-1/N)) = a^(-1/N) > 0, the
 * root obeys 0 <= z < a^(-1/N), i.e.
 *   0 <= q/p - m < (f_e/p) a^(-1/N),
 * which tends to 0 as gamma^(-1/N): the return approaches the rate-
 * independent surface q = m p. Checked for gamma = 1 .. 1e12 1/s, with a
 * rounding allowance of 1e-12 m (q and p are O(1e4) Pa computed to ulps).
 * At gamma = 1e12 the bound itself is below 1e-3 m for N <= 3. */
START_TEST(test_rate_independent_limit) {
  double exponent = (double)(_i + 1);
  gm_perzyna_def def = gm_perzyna_def_default();
  def.exponent = exponent;
  double m = slope_of(def.friction_angle), shear = shear_modulus(&def);
  double start[6] = {-1e4, -1e4, -1e4, 0.0, 0.0, 0.0};
  double increment[6] = {-2e-2, 1e-2, 1e-2, 5e-3, 0.0, 0.0}; /* isochoric */
  double trial[6];
  elastic_trial(&def, start, increment, trial);
  double pressure = pressure_of(trial);
  double overstress = mises_of(trial) - m * pressure;
  ck_assert(overstress > 0.0);
  double previous = INFINITY;
  for (int k = 0; k <= 12; k++) {
    def.fluidity = pow(10.0, k);
    double a = 3.0 * shear * def.fluidity * RANDOM_DT / (m * pressure) *
               pow(overstress / (m * pressure), exponent - 1.0);
    double sigma[6], state = 0.0;
    memcpy(sigma, start, sizeof sigma);
    update_point(&def, RANDOM_DT, sigma, increment, &state);
    double excess = mises_of(sigma) / pressure_of(sigma) - m;
    double bound = overstress / pressure * pow(a, -1.0 / exponent);
    ck_assert_msg(excess >= -1e-12 * m && excess <= bound + 1e-12 * m,
                  "N = %g gamma = %g: q/p - m = %g, bound %g", exponent,
                  def.fluidity, excess, bound);
    ck_assert(excess <= previous);
    previous = excess;
  }
  ck_assert_msg(previous <= 1e-3 * m, "q/p - m = %g at gamma = 1e12", previous);
}
END_TEST

/* Steady simple shear at a constant rate d_xy (1/s, tensor component) and
 * constant pressure. Once the stress is stationary the whole deviatoric
 * rate is viscoplastic: e_vp_xy = d_xy, so with s = s_xy only (q = sqrt(3)
 * s_xy) eq 18 gives gamma Phi = 2 d_xy / sqrt(3), the equivalent rate, and
 *   q = m p (1 + (2 d_xy / (sqrt(3) gamma))^(1/N)).
 * The backward Euler return (eqs 19-22) has exactly this fixed point for any
 * dt (s^t = s^(t+dt) in eqs 19-20 gives the same two relations), and it is
 * approached geometrically (factor ~1/(1 + a), a ~ 0.6 here), so after 3000
 * steps the stationary q matches to round-off; 1e-10 relative. */
START_TEST(test_stationary_simple_shear) {
  double exponent = (double)(_i + 1);
  gm_perzyna_def def = gm_perzyna_def_default();
  def.exponent = exponent;
  def.friction_angle = 0.5235987755982988; /* 30 deg */
  double dt = 1e-4, shear_rate = 10.0;     /* s, 1/s */
  double pressure = 1e4;                   /* Pa */
  double sigma[6] = {-pressure, -pressure, -pressure, 0.0, 0.0, 0.0};
  double increment[6] = {0.0, 0.0, 0.0, shear_rate * dt, 0.0, 0.0};
  double state = 0.0, state_step = 0.0;
  for (int step = 0; step < 3000; step++) {
    double before = state;
    update_point(&def, dt, sigma, increment, &state);
    state_step = state - before;
  }
  double m = slope_of(def.friction_angle);
  double equivalent_rate = 2.0 * shear_rate / sqrt(3.0); /* 1/s */
  double expected = m * pressure *
                    (1.0 + pow(equivalent_rate / def.fluidity, 1.0 / exponent));
  double q = mises_of(sigma);
  ck_assert_msg(fabs(q - expected) <= 1e-10 * expected, "q %.17g vs %.17g", q,
                expected);
  ck_assert(fabs(pressure_of(sigma) - pressure) <= 1e-12 * pressure);
  ck_assert(fabs(state_step - equivalent_rate * dt) <=
            1e-10 * equivalent_rate * dt);
  printf("stationary shear N = %g: q/(m p) - 1 = %.15g (closed form %.15g)\n",
         exponent, q / (m * pressure) - 1.0, expected / (m * pressure) - 1.0);
}
END_TEST

/* One iteration cannot solve eq 22 for N = 3: the update reports a
 * recoverable failure (> 0, the library halves dt) naming the point. */
START_TEST(test_iteration_limit_is_recoverable) {
  gm_perzyna_def def = gm_perzyna_def_default();
  def.exponent = 3.0;
  def.max_iterations = 1;
  double sigma[6] = {-1e4, -1e4, -1e4, 0.0, 0.0, 0.0};
  double increment[6] = {-2e-2, 1e-2, 1e-2, 0.0, 0.0, 0.0};
  double state = 0.0;
  char message[256] = "";
  int result = run_point(&def, RANDOM_DT, sigma, increment, &state, message,
                         sizeof message);
  ck_assert_int_gt(result, 0);
  ck_assert_msg(strstr(message, "point 42") != NULL, "message: %s", message);
}
END_TEST

static Suite *perzyna_suite(void) {
  Suite *suite = suite_create("perzyna");
  TCase *tcase = tcase_create("perzyna");
  tcase_set_timeout(tcase, 60);
  tcase_add_test(tcase, test_closed_form_matches_iteration);
  tcase_add_loop_test(tcase, test_iteration_satisfies_consistency, 0, 3);
  tcase_add_test(tcase, test_elastic_inside_cone);
  tcase_add_test(tcase, test_tension_cut_off);
  tcase_add_loop_test(tcase, test_rate_independent_limit, 0, 3);
  tcase_add_loop_test(tcase, test_stationary_simple_shear, 0, 2);
  tcase_add_test(tcase, test_iteration_limit_is_recoverable);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(perzyna_suite()) ? 1 : 0;
}
