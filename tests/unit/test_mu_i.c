/*
 * test_mu_i.c - the built-in mu(I) material at the constitutive level,
 * driven directly through gm_mu_i_update with hand-built batches: steady
 * simple shear at a prescribed shear rate and pressure reaches
 * tau / p = mu(I), I = gammadot d / sqrt(p / rho_s) (Jop, Forterre &
 * Pouliquen 2006; on the low-I branch the curve of Barker & Gray 2017);
 * below mu_s the unregularised material stays exactly elastic; the
 * stress-free states; argument checks.
 *
 * The regularised branch is recomputed here independently of the library:
 * I_1^N from the sign change of Barker & Gray's eq 3.9 by bisection, then
 * A = I_1^N exp(alpha / mu(I_1^N)^2).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "granmpm/mu_i.h"
#include "test_mu_i_law.h"
#include "test_util.h"

enum { CASES = 4 };

/* A batch of CASES points with two state columns. */
typedef struct shear_batch {
  double strain[6][CASES];
  double stress[6][CASES];
  double density[CASES];
  double plastic[CASES], inertial[CASES];
  int64_t id[CASES];
  double *state[2];
  gm_material_batch batch;
} shear_batch;

static void batch_init(shear_batch *b, size_t count, double dt,
                       double density) {
  memset(b, 0, sizeof *b);
  gm_material_batch *batch = &b->batch;
  batch->struct_size = sizeof *batch;
  batch->count = count;
  batch->geometry = GM_GEOMETRY_PLANE_STRAIN;
  batch->dt = dt;
  for (int c = 0; c < 6; c++) {
    batch->strain_increment[c] = b->strain[c];
    batch->stress[c] = b->stress[c];
  }
  for (size_t i = 0; i < count; i++) {
    b->density[i] = density;
    b->id[i] = (int64_t)i;
  }
  batch->density = b->density;
  b->state[0] = b->plastic;
  b->state[1] = b->inertial;
  batch->state = b->state;
  batch->state_count = GM_MU_I_STATE_COUNT;
  batch->point_id = b->id;
}

static void update(shear_batch *b, gm_mu_i_def *def) {
  char message[160] = "";
  int result = gm_mu_i_update(&b->batch, def, message, sizeof message);
  ck_assert_msg(result == 0, "update returned %d: %s", result, message);
}

/* ------------------------------------------------ the friction law, here */

/* jop_mu() and posedness(): tests/common/test_mu_i_law.h */

typedef struct branch {
  double inertial, friction, amplitude; /* I_1^N, mu(I_1^N), A */
} branch;

static branch low_branch(const gm_mu_i_def *def) {
  ck_assert(posedness(def, 1e-9) > 0.0 &&
            posedness(def, def->inertial_number_scale) < 0.0);
  double upper = posedness_onset(def);
  branch b;
  b.inertial = upper;
  b.friction = jop_mu(def, upper);
  b.amplitude =
      upper * exp(def->regularisation_exponent / (b.friction * b.friction));
  return b;
}

/* mu(I) of the material: Jop's curve, or the regularised one below I_1^N. */
static double model_mu(const gm_mu_i_def *def, double inertial) {
  if (def->regularise) {
    branch b = low_branch(def);
    if (inertial < b.inertial)
      return sqrt(def->regularisation_exponent / log(b.amplitude / inertial));
  }
  return jop_mu(def, inertial);
}

/* ----------------------------------------------------------- simple shear */

/* Loop index: 0 = Jop's curve, 1 = regularised. Each case is sheared at a
 * rate gammadot (du/dy, 1/s) under a pressure p, from an isotropic stress
 * -p I, with a dt that loads 1 % of the expected tau per step (so that
 * creeping and fast cases take a few hundred steps alike); the run stops
 * when tau changes by no more than 1e-15 relative in a step. The fixed
 * point of the backward-Euler return has gammadot_p = gammadot exactly, so
 * tau / p = mu(I) holds there to round-off: the brief's 1e-6 relative is
 * loose by orders (measured below 1e-10). */
START_TEST(test_steady_simple_shear) {
  gm_mu_i_def def = gm_mu_i_def_default();
  def.regularise = _i;
  const double pressures[3] = {100.0, 1e3, 1e4}; /* Pa */
  /* From the creeping branch (1e-6, 1e-4: below I_1^N when regularised,
   * where Jop's curve is barely above mu_s) to above I_0. */
  const double targets[5] = {1e-6, 1e-4, 0.02, 0.2, 1.0};
  const double shear_modulus =
      def.youngs_modulus / (2.0 * (1.0 + def.poisson_ratio)); /* Pa */
  branch low = low_branch(&def);
  shear_batch *b = malloc(sizeof *b);
  ck_assert_ptr_nonnull(b);
  for (int pi = 0; pi < 3; pi++) {
    for (int ti = 0; ti < 5; ti++) {
      double p = pressures[pi], inertial = targets[ti];
      double expected = model_mu(&def, inertial);
      /* gammadot = I sqrt(p/rho_s) / d */
      double rate = inertial * sqrt(p / def.grain_density) / def.grain_diameter;
      double dt = 0.01 * expected * p / (shear_modulus * rate); /* s */
      batch_init(b, 1, dt, def.density);
      for (int c = 0; c < 3; c++)
        b->stress[c][0] = -p;
      b->strain[GM_XY][0] = 0.5 * rate * dt; /* tensor shear strain */
      long step = 0;
      for (double before = -1.0;
           fabs(b->stress[GM_XY][0] - before) > 1e-15 * fabs(before); step++) {
        ck_assert_msg(step < 100000, "no steady state after %ld steps", step);
        before = b->stress[GM_XY][0];
        update(b, &def);
      }
      /* p is unchanged: the strain increment and the flow are deviatoric */
      double mean = -(b->stress[0][0] + b->stress[1][0] + b->stress[2][0]) / 3;
      ck_assert_msg(fabs(mean - p) <= 1e-12 * p, "p moved: %g -> %g", p, mean);
      double friction = b->stress[GM_XY][0] / p;
      ck_assert_msg(fabs(friction - expected) <= 1e-6 * expected,
                    "regularise %d, p %g Pa, I %g: tau/p %.12g, mu(I) %.12g "
                    "after %ld steps",
                    def.regularise, p, inertial, friction, expected, step);
      /* The state holds the inertial number of the last step. */
      ck_assert_msg(fabs(b->inertial[0] - inertial) <= 1e-6 * inertial,
                    "state I %.12g, expected %.12g", b->inertial[0], inertial);
      if (def.regularise && inertial < low.inertial)
        ck_assert(friction < def.static_friction); /* creeps below mu_s */
    }
  }
  free(b);
}
END_TEST

/* Barker & Gray's well-posedness condition (eq 3.9 with c = I mu'/mu) holds
 * on the whole regularised branch for the default alpha = 1.9: on
 * mu = sqrt(alpha / ln(A/I)), c = mu^2 / (2 alpha) exactly. Also the match
 * point: Jop's curve is ill posed just below I_1^N and well posed above. */
START_TEST(test_regularised_branch_well_posed) {
  gm_mu_i_def def = gm_mu_i_def_default();
  branch low = low_branch(&def);
  ck_assert(posedness(&def, 0.99 * low.inertial) > 0.0);
  ck_assert(posedness(&def, 1.01 * low.inertial) < 0.0);
  double alpha = def.regularisation_exponent;
  for (double inertial = 1e-30; inertial < low.inertial; inertial *= 1.5) {
    double mu = sqrt(alpha / log(low.amplitude / inertial));
    double c = mu * mu / (2.0 * alpha);
    double condition =
        4.0 * c * c - 4.0 * c + mu * mu * (1.0 - c / 2.0) * (1.0 - c / 2.0);
    ck_assert_msg(condition < 0.0, "ill posed at I = %g (mu %g): %g", inertial,
                  mu, condition);
  }
}
END_TEST

/* Unregularised, a trial below mu_s p is kept bit for bit (the elastic
 * trial of gm_elastic_update) and the state records I = 0; regularised,
 * the same trial creeps, at exactly the rate of the regularised curve. */
START_TEST(test_below_yield) {
  gm_mu_i_def def = gm_mu_i_def_default();
  def.regularise = 0;
  shear_batch *b = malloc(sizeof *b), *e = malloc(sizeof *e);
  ck_assert(b && e);
  const double p = 2000.0; /* Pa */
  batch_init(b, 3, 1e-4, def.density);
  /* tau/p after the increment, below mu_s = 0.382 */
  const double friction[3] = {0.2, 0.3, 0.37};
  double shear_modulus = def.youngs_modulus / (2 * (1 + def.poisson_ratio));
  for (size_t i = 0; i < 3; i++) {
    for (int c = 0; c < 3; c++)
      b->stress[c][i] = -p;
    b->stress[GM_XY][i] = friction[i] * p - 10.0;
    b->strain[GM_XY][i] = 10.0 / (2.0 * shear_modulus); /* +10 Pa */
    b->strain[GM_XX][i] = 1e-5 * (double)i;             /* some volume */
  }
  batch_init(e, 3, 1e-4, def.density);
  memcpy(e->stress, b->stress, sizeof e->stress);
  memcpy(e->strain, b->strain, sizeof e->strain);
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.youngs_modulus = def.youngs_modulus;
  elastic.poisson_ratio = def.poisson_ratio;
  ck_assert_int_eq(gm_elastic_update(&e->batch, &elastic, NULL, 0), 0);
  update(b, &def);
  for (size_t i = 0; i < 3; i++) {
    for (int c = 0; c < 6; c++)
      ck_assert_msg(
          memcmp(&b->stress[c][i], &e->stress[c][i], sizeof(double)) == 0,
          "point %zu component %d not elastic", i, c);
    ck_assert(b->inertial[i] == 0.0 && b->plastic[i] == 0.0);
  }
  free(b);
  free(e);
}
END_TEST

/* Below the critical density, or with a tensile trial, the stress is 0
 * (Dunatunga & Kamrin's disconnected state; no cohesion). */
START_TEST(test_stress_free_states) {
  gm_mu_i_def def = gm_mu_i_def_default();
  def.critical_density = 1500.0;
  shear_batch *b = malloc(sizeof *b);
  ck_assert_ptr_nonnull(b);
  batch_init(b, 3, 1e-4, 1499.0);
  b->density[2] = 1501.0;
  for (size_t i = 0; i < 3; i++)
    for (int c = 0; c < 3; c++)
      b->stress[c][i] = -1000.0; /* compressed, but too loose (0) */
  b->stress[GM_XY][0] = 100.0;
  b->density[1] = 1501.0; /* dense enough, but in tension: */
  for (int c = 0; c < 3; c++)
    b->stress[c][1] = 500.0;
  b->stress[GM_XY][2] = 100.0; /* dense, compressed: keeps its stress */
  update(b, &def);
  for (int c = 0; c < 6; c++) {
    ck_assert(b->stress[c][0] == 0.0);
    ck_assert(b->stress[c][1] == 0.0);
  }
  ck_assert(b->stress[GM_XX][2] < 0.0 && b->stress[GM_XY][2] > 0.0);
  free(b);
}
END_TEST

START_TEST(test_registration) {
  gm_domain_def domain_def = gm_domain_def_default();
  gm_domain *domain = test_create_domain(&domain_def);
  gm_mu_i_def def = gm_mu_i_def_default();
  int material = -1;
  /* mu_2 barely above mu_s: Jop's curve is ill posed at every I, so the
   * regularisation has no match point; unregularised it is accepted. */
  def.limit_friction = def.static_friction + 1e-3;
  ck_assert_int_eq(gm_domain_add_mu_i(domain, &def, &material),
                   GM_ERR_INVALID_ARGUMENT);
  def.regularise = 0;
  TEST_ASSERT_OK(domain, gm_domain_add_mu_i(domain, &def, &material));
  ck_assert_int_eq(material, 0);
  def = gm_mu_i_def_default();
  TEST_ASSERT_OK(domain, gm_domain_add_mu_i(domain, &def, &material));
  ck_assert_int_eq(material, 1);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("mu_i");
  TCase *tcase = tcase_create("constitutive");
  tcase_set_timeout(tcase, 60);
  tcase_add_loop_test(tcase, test_steady_simple_shear, 0, 2);
  tcase_add_test(tcase, test_regularised_branch_well_posed);
  tcase_add_test(tcase, test_below_yield);
  tcase_add_test(tcase, test_stress_free_states);
  tcase_add_test(tcase, test_registration);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
