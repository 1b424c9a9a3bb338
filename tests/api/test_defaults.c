/*
 * test_defaults.c - the exported gm_*_init() functions (the defaults that
 * hosts in other languages call) and the inline gm_*_default() built on
 * them: the documented values, the struct_size contract (NULL, a size the
 * library does not know, a caller's larger structure) and the earlier
 * gm_domain_def layouts the library still accepts.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include <check.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

/* Values are compared exactly: the library stores the literals of the
 * documentation (granmpm.h and the granmpm/ headers), so any difference is a
 * wrong default, not rounding. */

START_TEST(test_domain_defaults) {
  gm_domain_def def;
  memset(&def, 0xff, sizeof def);
  ck_assert_int_eq(gm_domain_def_init(&def, sizeof def), GM_OK);
  ck_assert_uint_eq(def.struct_size, sizeof def);
  ck_assert_int_eq(def.geometry, GM_GEOMETRY_PLANE_STRAIN);
  for (int k = 0; k < 3; k++) {
    ck_assert(def.origin[k] == 0.0);
    ck_assert(def.extent[k] == 1.0);
    ck_assert(def.gravity[k] == 0.0);
  }
  ck_assert(def.cell_size == 0.1);
  ck_assert_int_eq(def.scheme, GM_SCHEME_USL);
  for (int face = 0; face < 6; face++)
    ck_assert_int_eq(def.walls[face], GM_WALL_OPEN);
  ck_assert(def.cfl == 0.5);
  ck_assert_int_eq(def.refuse_unstable_dt, 0);
  ck_assert_int_eq(def.max_retries, 4);
  ck_assert_int_eq(def.worker_count, 1);
  ck_assert(def.enqueue_task == NULL);
  ck_assert(def.finish_task == NULL);
  ck_assert_ptr_null(def.task_user);
  ck_assert(def.damping == 0.0);
  ck_assert_int_eq(def.shape, GM_SHAPE_LINEAR);
  ck_assert_int_eq(def.family, GM_FAMILY_PLAIN);
  ck_assert(def.pic_fraction == 0.0);
}
END_TEST

/* The inline initialisers return exactly what the exported ones write
 * (one source of the values): compared field by field where padding could
 * differ, here as whole structures of the built-in materials, which have
 * no padding on LP64 (size_t, a pointer, then doubles). */
START_TEST(test_inline_agrees_with_exported) {
  gm_mohr_coulomb_def inline_mc = gm_mohr_coulomb_def_default(), mc;
  ck_assert_int_eq(gm_mohr_coulomb_def_init(&mc, sizeof mc), GM_OK);
  ck_assert_mem_eq(&inline_mc, &mc, sizeof mc);
  ck_assert(mc.youngs_modulus == 1e9);
  ck_assert(mc.bagnold_viscosity == 0.15);
  ck_assert(mc.density == 2250.0);
  ck_assert_str_eq(mc.name, "mohr_coulomb");

  gm_elastic_def inline_elastic = gm_elastic_def_default(), elastic;
  ck_assert_int_eq(gm_elastic_def_init(&elastic, sizeof elastic), GM_OK);
  ck_assert_mem_eq(&inline_elastic, &elastic, sizeof elastic);
  ck_assert(elastic.youngs_modulus == 1e6);

  gm_domain_def inline_domain = gm_domain_def_default(), domain;
  ck_assert_int_eq(gm_domain_def_init(&domain, sizeof domain), GM_OK);
  ck_assert(inline_domain.cfl == domain.cfl);
  ck_assert(inline_domain.cell_size == domain.cell_size);
  ck_assert_int_eq(inline_domain.max_retries, domain.max_retries);

  gm_fill_def fill = gm_fill_def_default();
  ck_assert_uint_eq(fill.struct_size, sizeof fill);
  ck_assert_int_eq(fill.points_per_cell_axis, 2);
  gm_granular_def granular = gm_granular_def_default();
  ck_assert(granular.tolerance == 1e-6);
  gm_wall_def wall = gm_wall_def_default();
  ck_assert(wall.normal[1] == 1.0);
  gm_perzyna_def perzyna = gm_perzyna_def_default();
  ck_assert(perzyna.fluidity == 50.0);
  gm_filling_def filling = gm_filling_def_default();
  ck_assert(filling.max_pressure == 1e5);
  gm_drucker_prager_def dp = gm_drucker_prager_def_default();
  ck_assert(dp.density == 1500.0);
  gm_von_mises_def vm = gm_von_mises_def_default();
  ck_assert(vm.yield_stress == 2e7);
  gm_stress_free_def sf = gm_stress_free_def_default();
  ck_assert(fabs(sf.p_wave_modulus - 1e6 * 0.7 / (1.3 * 0.4)) <= 1e-9);
  gm_summary summary = gm_summary_default();
  ck_assert_uint_eq(summary.struct_size, sizeof summary);
  ck_assert(summary.mass == 0.0);
}
END_TEST

START_TEST(test_init_contract) {
  ck_assert_int_eq(gm_fill_def_init(NULL, sizeof(gm_fill_def)), GM_ERR_NULL);
  ck_assert_int_eq(gm_summary_init(NULL, sizeof(gm_summary)), GM_ERR_NULL);
  /* A structure shorter than the library's: refused, nothing written. */
  gm_fill_def fill;
  memset(&fill, 0xab, sizeof fill);
  ck_assert_int_eq(gm_fill_def_init(&fill, sizeof fill - 1),
                   GM_ERR_STRUCT_SIZE);
  ck_assert_uint_eq(fill.struct_size, (size_t)0xababababababababULL);
  /* A caller's larger structure (say a host language's padded record):
   * the library's layout is filled, the rest zeroed, and struct_size says
   * how much the library knows. */
  unsigned char buffer[sizeof(gm_elastic_def) + 16];
  memset(buffer, 0xab, sizeof buffer);
  ck_assert_int_eq(
      gm_elastic_def_init((gm_elastic_def *)(void *)buffer, sizeof buffer),
      GM_OK);
  gm_elastic_def elastic;
  memcpy(&elastic, buffer, sizeof elastic);
  ck_assert_uint_eq(elastic.struct_size, sizeof elastic);
  ck_assert(elastic.poisson_ratio == 0.3);
  for (size_t k = sizeof elastic; k < sizeof buffer; k++)
    ck_assert_uint_eq(buffer[k], 0);
}
END_TEST

/* An earlier gm_domain_def layout (ending before `damping`) is a size the
 * library knows: only that prefix is written, and gm_domain_create
 * accepts it. */
START_TEST(test_domain_earlier_layout) {
  gm_domain_def def;
  memset(&def, 0xab, sizeof def);
  size_t old_size = offsetof(gm_domain_def, damping);
  ck_assert_int_eq(gm_domain_def_init(&def, old_size), GM_OK);
  ck_assert_uint_eq(def.struct_size, old_size);
  ck_assert(def.cfl == 0.5);
  const unsigned char *bytes = (const unsigned char *)&def;
  for (size_t k = old_size; k < sizeof def; k++)
    ck_assert_uint_eq(bytes[k], 0xab);
  gm_domain *domain = NULL;
  TEST_ASSERT_OK(NULL, gm_domain_create(&def, &domain));
  gm_domain_destroy(domain);
  /* One byte short of a known layout is not one. */
  ck_assert_int_eq(gm_domain_def_init(&def, old_size - 1), GM_ERR_STRUCT_SIZE);
}
END_TEST

static Suite *defaults_suite(void) {
  Suite *suite = suite_create("defaults");
  TCase *tcase = tcase_create("init");
  tcase_add_test(tcase, test_domain_defaults);
  tcase_add_test(tcase, test_inline_agrees_with_exported);
  tcase_add_test(tcase, test_init_contract);
  tcase_add_test(tcase, test_domain_earlier_layout);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(defaults_suite()) == 0 ? 0 : 1;
}
