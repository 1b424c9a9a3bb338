/*
 * test_stress_free.c - the built-in stress-free material: the update
 * leaves exactly +0 in every stress component whatever it is given, and
 * the p_wave_modulus it registers is the one the stable time step uses
 * (004 eqs 3.11-3.12). Its registration checks are in
 * test_material_contract.c, with every built-in model's.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "granmpm/stress_free.h"
#include "test_util.h"

enum { POINTS = 64 };

/* Knuth's MMIX LCG; uniform double in [lo, hi) from the top 53 bits. */
static double lcg_uniform(uint64_t *seed, double lo, double hi) {
  *seed = *seed * 6364136223846793005ULL + 1442695040888963407ULL;
  return lo + (hi - lo) * (double)(*seed >> 11) * 0x1.0p-53;
}

/* Input stress and strain: random over many decades of both signs, with
 * some non-finite values and -0 mixed in. */
static double awkward_value(uint64_t *seed, size_t i, int c) {
  switch ((i + (size_t)c) % 8) {
  case 0:
    return NAN;
  case 1:
    return -INFINITY;
  case 2:
    return -0.0;
  default:
    return lcg_uniform(seed, -1.0, 1.0) * pow(10.0, lcg_uniform(seed, -6, 9));
  }
}

START_TEST(test_stress_is_zero) {
  double strain[6][POINTS], stress[6][POINTS], density[POINTS];
  int64_t id[POINTS];
  uint64_t seed = 99;
  gm_material_batch batch;
  memset(&batch, 0, sizeof batch);
  batch.struct_size = sizeof batch;
  batch.count = POINTS;
  batch.geometry = (gm_geometry)(_i + 1);
  batch.dt = 1e-3; /* s */
  for (int c = 0; c < 6; c++) {
    for (size_t i = 0; i < POINTS; i++) {
      strain[c][i] = awkward_value(&seed, i, c);
      stress[c][i] = awkward_value(&seed, i + 3, c);
    }
    batch.strain_increment[c] = strain[c];
    batch.stress[c] = stress[c];
  }
  for (size_t i = 0; i < POINTS; i++) {
    density[i] = 1000.0;
    id[i] = (int64_t)i;
  }
  batch.density = density;
  batch.point_id = id;
  gm_stress_free_def def = gm_stress_free_def_default();
  /* Through the def and with a NULL user: `user` is documented unused. */
  void *users[2] = {&def, NULL};
  for (int u = 0; u < 2; u++) {
    ck_assert_int_eq(gm_stress_free_update(&batch, users[u], NULL, 0), 0);
    const double positive_zero = 0.0;
    for (int c = 0; c < 6; c++)
      for (size_t i = 0; i < POINTS; i++)
        ck_assert_msg(memcmp(&stress[c][i], &positive_zero, sizeof(double)) ==
                          0,
                      "point %zu component %d is %g", i, c, stress[c][i]);
    for (int c = 0; c < 6; c++) /* dirty it again for the second call */
      for (size_t i = 0; i < POINTS; i++)
        stress[c][i] = awkward_value(&seed, i, c);
  }
}
END_TEST

/* A block at rest of the registered material: the stable dt is
 * cfl h / sqrt(M / rho) with the registered M and rho (004 eqs 3.11-3.12),
 * and after a step under gravity in a closed box the stress is still 0. */
START_TEST(test_in_a_domain) {
  const double modulus = 4e6;                         /* Pa */
  const double density = 900.0;                       /* kg/m^3 */
  gm_domain_def domain_def = gm_domain_def_default(); /* 1 m box, h 0.1 m */
  domain_def.gravity[1] = -9.81;                      /* m/s^2 */
  for (int face = 0; face < 4; face++)
    domain_def.walls[face] = GM_WALL_SLIP;
  gm_domain *domain = test_create_domain(&domain_def);
  gm_stress_free_def def = gm_stress_free_def_default();
  def.density = density;
  def.p_wave_modulus = modulus;
  int material = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_stress_free(domain, &def, &material));
  const double lower[3] = {0.3, 0.3, 0.0}, upper[3] = {0.7, 0.7, 0.0};
  size_t count = test_fill_box(domain, material, lower, upper, 2, NULL);
  double dt = 0.0;
  TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
  double expected =
      domain_def.cfl * domain_def.cell_size / sqrt(modulus / density);
  /* Round-off of volume / mass and one square root: a few ulp. */
  ck_assert_msg(fabs(dt / expected - 1.0) < 1e-12, "dt %.17g, expected %.17g",
                dt, expected);
  TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
  double *stress = malloc(count * 6 * sizeof *stress);
  ck_assert_ptr_nonnull(stress);
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_STRESS, stress, count * 6));
  for (size_t k = 0; k < count * 6; k++)
    ck_assert_msg(stress[k] == 0.0, "stress value %zu is %g", k, stress[k]);
  free(stress);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *stress_free_suite(void) {
  Suite *suite = suite_create("stress_free");
  TCase *update = tcase_create("update");
  /* Loop index + 1: geometry 1D, plane strain, axisymmetric. */
  tcase_add_loop_test(update, test_stress_is_zero, 0, 3);
  tcase_add_test(update, test_in_a_domain);
  suite_add_tcase(suite, update);
  return suite;
}

int main(void) {
  return test_run_suite(stress_free_suite()) ? EXIT_FAILURE : 0;
}
