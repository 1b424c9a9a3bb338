/*
 * test_von_mises.c - the built-in von Mises material against the closed
 * forms of its radial return, driven directly through gm_von_mises_update
 * with hand-built batches.
 *
 * Conventions: stress in Pa, tension positive; p = -tr(sigma)/3,
 * s = sigma + p I, q = sqrt(3/2 s:s) with shear terms counted twice. The
 * invariants are recomputed here independently of the library's helper.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granmpm/von_mises.h"
#include "test_batch.h"
#include "test_util.h"

enum { RANDOM_POINTS = MAX_POINTS };

/* The steel of 001 sec 5.3.1. */
static const double YOUNGS = 2e11;      /* Pa */
static const double POISSON = 0.3;      /* - */
static const double DENSITY = 7800;     /* kg/m^3 */
static const double YIELD_STRESS = 2e7; /* Pa */

/* ------------------------------------------------------------ batch setup */

static gm_von_mises_def vm_def(void) {
  gm_von_mises_def def = gm_von_mises_def_default();
  def.youngs_modulus = YOUNGS;
  def.poisson_ratio = POISSON;
  def.density = DENSITY;
  def.yield_stress = YIELD_STRESS;
  return def;
}

static void run_vm(test_points *points, gm_von_mises_def *def) {
  char message[128] = "";
  int result =
      gm_von_mises_update(&points->batch, def, message, sizeof message);
  ck_assert_msg(result == 0, "update returned %d: %s", result, message);
}

/* ------------------------------------------------------------- invariants */

/* Elastic strain of a stress change (isotropic compliance), tensor shear. */
static void elastic_strain(const double stress_change[6], double out[6]) {
  double trace = stress_change[0] + stress_change[1] + stress_change[2];
  double shear_modulus = YOUNGS / (2.0 * (1.0 + POISSON));
  for (int c = 0; c < 3; c++)
    out[c] = ((1.0 + POISSON) * stress_change[c] - POISSON * trace) / YOUNGS;
  for (int c = 3; c < 6; c++)
    out[c] = stress_change[c] / (2.0 * shear_modulus);
}

/* ---------------------------------------------------------- random states */

/* Knuth's MMIX LCG; uniform double in [lo, hi) from the top 53 bits. */
static double lcg_uniform(uint64_t *seed, double lo, double hi) {
  *seed = *seed * 6364136223846793005ULL + 1442695040888963407ULL;
  return lo + (hi - lo) * (double)(*seed >> 11) * 0x1.0p-53;
}

/* Random stress: pressure in [-1, 1] sigma_y (von Mises does not care about
 * its sign), deviator components up to a random size in [0, sigma_y], and
 * strain increments up to 1e-4 (up to ~1.5 sigma_y of stress). Every fourth
 * point is plane-strain-like (yz = zx = 0 in stress and strain). */
static void fill_random(test_points *points, size_t count, uint64_t seed) {
  for (size_t i = 0; i < count; i++) {
    double p = lcg_uniform(&seed, -1.0, 1.0) * YIELD_STRESS;
    double size = lcg_uniform(&seed, 0.0, 1.0) * YIELD_STRESS;
    for (int c = 0; c < 6; c++) {
      double normal = c < 3 ? -p : 0.0;
      points->stress[c][i] = normal + size * lcg_uniform(&seed, -1.0, 1.0);
      points->strain[c][i] = lcg_uniform(&seed, -1e-4, 1e-4);
    }
    if (i % 4 == 3)
      for (int c = GM_YZ; c <= GM_ZX; c++)
        points->stress[c][i] = points->strain[c][i] = 0.0;
    points->plastic[i] = lcg_uniform(&seed, 0.0, 0.1);
  }
}

/* Checks one plastic return of point i against the closed form
 * sigma = (sigma_y / q_e) s_e - p_e I. */
static void check_plastic_return(const test_points *before,
                                 const test_points *after, size_t i,
                                 const double trial[6]) {
  double sigma[6], old_sigma[6], change[6], elastic[6], plastic[6];
  point_stress(after, i, sigma);
  point_stress(before, i, old_sigma);
  double p_trial = pressure_of(trial), q_trial = equivalent_of(trial);
  double p = pressure_of(sigma), q = equivalent_of(sigma);
  /* On the surface: round-off of q is a few ulp, 1e-10 leaves 5 orders. */
  ck_assert_msg(fabs(q - YIELD_STRESS) / YIELD_STRESS < 1e-10,
                "point %zu off the surface: q %.17g", i, q);
  /* The return is deviatoric: p is the trial p up to a few ulp of the
   * stress components (|p| + q). */
  ck_assert_msg(fabs(p - p_trial) <= 1e-14 * (fabs(p_trial) + q_trial),
                "point %zu pressure moved: %.17g -> %.17g", i, p_trial, p);
  double scale = YIELD_STRESS / q_trial;
  for (int c = 0; c < 6; c++) {
    double deviator = sigma[c] + (c < 3 ? p : 0.0);
    double trial_deviator = trial[c] + (c < 3 ? p_trial : 0.0);
    ck_assert_msg(fabs(deviator - scale * trial_deviator) <= 1e-13 * q_trial,
                  "point %zu component %d not radial", i, c);
  }
  for (int c = 0; c < 6; c++)
    change[c] = sigma[c] - old_sigma[c];
  elastic_strain(change, elastic);
  for (int c = 0; c < 6; c++)
    plastic[c] = before->strain[c][i] - elastic[c];
  /* Stresses <= ~1e8 Pa give elastic strains <= 5e-4 with round-off
   * ~1e-19; 1e-16 is far above that and far below the increments (1e-4). */
  double volumetric = plastic[0] + plastic[1] + plastic[2];
  ck_assert_msg(fabs(volumetric) < 1e-16,
                "point %zu plastic volumetric strain %g", i, volumetric);
  double pp = plastic[0] * plastic[0] + plastic[1] * plastic[1] +
              plastic[2] * plastic[2] +
              2.0 * (plastic[3] * plastic[3] + plastic[4] * plastic[4] +
                     plastic[5] * plastic[5]);
  double equivalent = sqrt(2.0 / 3.0 * pp);
  double increment = after->plastic[i] - before->plastic[i];
  /* The state is ~0.1, so its own round-off is ~1e-17. */
  ck_assert_msg(fabs(increment - equivalent) <= 1e-15 + 1e-9 * equivalent,
                "point %zu plastic strain %.17g, expected %.17g", i, increment,
                equivalent);
}

START_TEST(test_random_trial_states) {
  test_points *before =
      test_points_create(RANDOM_POINTS, GM_VON_MISES_STATE_COUNT, DENSITY);
  fill_random(before, RANDOM_POINTS, 777u);
  test_points *after = test_points_clone(before);
  double(*trial)[MAX_POINTS] = malloc(6 * sizeof *trial);
  ck_assert_ptr_nonnull(trial);
  test_points_elastic_trial(before, YOUNGS, POISSON, trial);
  gm_von_mises_def def = vm_def();
  run_vm(after, &def);
  size_t elastic_count = 0, plastic_count = 0;
  for (size_t i = 0; i < RANDOM_POINTS; i++) {
    double point_trial[6];
    for (int c = 0; c < 6; c++)
      point_trial[c] = trial[c][i];
    if (equivalent_of(point_trial) <= YIELD_STRESS) {
      elastic_count++;
      for (int c = 0; c < 6; c++)
        ck_assert_msg(
            memcmp(&after->stress[c][i], &point_trial[c], sizeof(double)) == 0,
            "elastic point %zu component %d changed", i, c);
      ck_assert(after->plastic[i] == before->plastic[i]);
    } else {
      plastic_count++;
      check_plastic_return(before, after, i, point_trial);
    }
  }
  /* Both branches must be exercised substantially. */
  ck_assert_uint_ge(elastic_count, RANDOM_POINTS / 10);
  ck_assert_uint_ge(plastic_count, RANDOM_POINTS / 4);
  free(trial);
  free(after);
  free(before);
}
END_TEST

/* One step of uniaxial stress on point 0: axial (xx) strain increment
 * `axial`; the lateral (yy = zz) increment is solved by secant iteration so
 * that both lateral stresses stay 0 (to 1e-9 sigma_y). */
static double uniaxial_step(test_points *point, gm_von_mises_def *def,
                            double axial, double lateral_guess) {
  double start[6], start_plastic = point->plastic[0];
  point_stress(point, 0, start);
  double shear_modulus = YOUNGS / (2.0 * (1.0 + POISSON));
  double lame = YOUNGS * POISSON / ((1.0 + POISSON) * (1.0 - 2.0 * POISSON));
  double lateral_stiffness = 2.0 * (lame + shear_modulus); /* Pa */
  double x_prev = 0.0, r_prev = 0.0, x = lateral_guess;
  for (int iteration = 0; iteration < 60; iteration++) {
    for (int c = 0; c < 6; c++)
      point->stress[c][0] = start[c];
    point->plastic[0] = start_plastic;
    point->strain[GM_XX][0] = axial;
    point->strain[GM_YY][0] = point->strain[GM_ZZ][0] = x;
    run_vm(point, def);
    double r = point->stress[GM_YY][0];
    if (fmax(fabs(r), fabs(point->stress[GM_ZZ][0])) < 1e-9 * YIELD_STRESS)
      return x;
    double slope = iteration == 0 || x == x_prev ? lateral_stiffness
                                                 : (r - r_prev) / (x - x_prev);
    if (!(fabs(slope) > 1e-3 * lateral_stiffness))
      slope = lateral_stiffness; /* flat secant: fall back to elastic */
    x_prev = x;
    r_prev = r;
    x -= r / slope;
  }
  ck_abort_msg("uniaxial lateral stress did not converge");
  return x;
}

/* Loop index: tension (0) or compression (1). */
START_TEST(test_uniaxial_plateau) {
  double axial = _i == 0 ? 1e-6 : -1e-6; /* strain per step */
  const int steps = 300; /* yield at 100 steps: E 1e-4 = sigma_y */
  test_points *point = test_points_create(1, GM_VON_MISES_STATE_COUNT, DENSITY);
  gm_von_mises_def def = vm_def();
  double lateral = -POISSON * axial, plastic_before_last = 0.0;
  int first_plastic_step = -1;
  for (int step = 1; step <= steps; step++) {
    lateral = uniaxial_step(point, &def, axial, lateral);
    double sigma_axial = point->stress[GM_XX][0];
    if (first_plastic_step < 0 && point->plastic[0] > 0.0)
      first_plastic_step = step;
    if (first_plastic_step < 0) /* elastic: sigma = E eps (1e-9 solver) */
      ck_assert_msg(fabs(sigma_axial - YOUNGS * step * axial) <
                        1e-8 * YIELD_STRESS,
                    "step %d: sigma %.17g, E eps %.17g", step, sigma_axial,
                    YOUNGS * step * axial);
    if (step == steps - 100)
      plastic_before_last = point->plastic[0];
  }
  /* Yield onset where E eps first exceeds sigma_y: step 100 exactly in real
   * numbers, so allow the neighbouring step for the rounding of E eps. */
  double onset = YIELD_STRESS / (YOUNGS * fabs(axial));
  ck_assert_msg(fabs(first_plastic_step - onset) <= 1.0,
                "first plastic step %d, expected %g", first_plastic_step,
                onset);
  /* Plateau: |sigma_axial| = sigma_y with lateral stresses ~1e-9 sigma_y,
   * so 1e-8 relative is the solver's accuracy with margin. */
  double sigma_axial = point->stress[GM_XX][0];
  ck_assert_msg(fabs(fabs(sigma_axial) / YIELD_STRESS - 1.0) < 1e-8,
                "plateau %.17g Pa", sigma_axial);
  ck_assert(sigma_axial * axial > 0.0);
  /* Stationary stress on the plateau: isochoric plastic flow. */
  ck_assert_msg(fabs(lateral + 0.5 * axial) < 1e-8 * fabs(axial),
                "lateral increment %.17g", lateral);
  double plastic_rate = (point->plastic[0] - plastic_before_last) / 100.0;
  ck_assert_msg(fabs(plastic_rate / fabs(axial) - 1.0) < 1e-8,
                "plastic strain per step %.17g", plastic_rate);
  free(point);
}
END_TEST

static Suite *von_mises_suite(void) {
  Suite *suite = suite_create("von_mises");
  TCase *map = tcase_create("return_map");
  tcase_set_timeout(map, 60);
  tcase_add_test(map, test_random_trial_states);
  tcase_add_loop_test(map, test_uniaxial_plateau, 0, 2);
  suite_add_tcase(suite, map);
  return suite;
}

int main(void) {
  return test_run_suite(von_mises_suite()) ? EXIT_FAILURE : 0;
}
