/*
 * test_material_contract.c - the registration contract every built-in
 * material keeps, checked from one table (issue 14 item 4) instead of a copy
 * per model:
 *  - the default def (gm_X_def_init) is accepted, and ids are consecutive;
 *  - NULL domain, def or id pointer: GM_ERR_NULL; a struct_size the library
 *    does not know: GM_ERR_STRUCT_SIZE;
 *  - every listed invalid value, and NaN in every double parameter, gives
 *    GM_ERR_INVALID_ARGUMENT with a message naming the field and the def
 *    struct, leaves *material as it was, and takes no id (the next valid
 *    registration gets the next id).
 * The ranges are the ones each man page states (gm_plasticity(3),
 * gm_materials(3)); a model's own physics is tested in its own file.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "granmpm.h"
#include "granmpm/drucker_prager.h"
#include "granmpm/filling.h"
#include "granmpm/mohr_coulomb.h"
#include "granmpm/mu_i.h"
#include "granmpm/perzyna.h"
#include "granmpm/stress_free.h"
#include "granmpm/von_mises.h"
#include "test_util.h"

/* One refused value: the field, where it is in the def, what is written. */
typedef struct bad_value {
  const char *field;
  size_t offset;
  int is_int; /* 0: a double field, 1: an int field */
  double value;
} bad_value;

enum { MAX_BAD = 16, MAX_DOUBLES = 12, MAX_DEF_BYTES = 256 };

typedef struct material_model {
  const char *def_name; /* the struct name the messages must carry */
  size_t size;          /* sizeof the def */
  gm_status (*init)(void *def, size_t size);
  gm_status (*add)(gm_domain *domain, const void *def, int *material);
  size_t doubles[MAX_DOUBLES]; /* offsets of every double parameter */
  size_t double_count;
  bad_value bad[MAX_BAD];
  size_t bad_count;
} material_model;

/* Typed wrappers: calling gm_X_def_init through a void * signature would
 * be undefined behaviour, so each model gets its own pair. */
#define MODEL_CALLS(model)                                                     \
  static gm_status init_##model(void *def, size_t size) {                      \
    return gm_##model##_def_init(def, size);                                   \
  }                                                                            \
  static gm_status add_##model(gm_domain *domain, const void *def,             \
                               int *material) {                                \
    return gm_domain_add_##model(domain, def, material);                       \
  }
MODEL_CALLS(elastic)
MODEL_CALLS(mohr_coulomb)
MODEL_CALLS(drucker_prager)
MODEL_CALLS(perzyna)
MODEL_CALLS(filling)
MODEL_CALLS(von_mises)
MODEL_CALLS(stress_free)
MODEL_CALLS(mu_i)

#define D(type, field) offsetof(type, field)
#define BAD(type, field, value)                                                \
  { #field, offsetof(type, field), 0, value }
#define BAD_INT(type, field, value)                                            \
  { #field, offsetof(type, field), 1, value }
#define COUNT(array) (sizeof(array) / sizeof((array)[0]))

static const material_model MODELS[] = {
    {"gm_elastic_def",
     sizeof(gm_elastic_def),
     init_elastic,
     add_elastic,
     {D(gm_elastic_def, youngs_modulus), D(gm_elastic_def, poisson_ratio),
      D(gm_elastic_def, density)},
     3,
     {BAD(gm_elastic_def, youngs_modulus, 0.0),
      BAD(gm_elastic_def, youngs_modulus, INFINITY),
      BAD(gm_elastic_def, poisson_ratio, 0.5),
      BAD(gm_elastic_def, poisson_ratio, -1.0),
      BAD(gm_elastic_def, density, 0.0)},
     5},
    {"gm_mohr_coulomb_def",
     sizeof(gm_mohr_coulomb_def),
     init_mohr_coulomb,
     add_mohr_coulomb,
     {D(gm_mohr_coulomb_def, youngs_modulus),
      D(gm_mohr_coulomb_def, poisson_ratio), D(gm_mohr_coulomb_def, density),
      D(gm_mohr_coulomb_def, friction_angle),
      D(gm_mohr_coulomb_def, dilation_angle),
      D(gm_mohr_coulomb_def, bagnold_viscosity)},
     6,
     {BAD(gm_mohr_coulomb_def, youngs_modulus, -1.0),
      BAD(gm_mohr_coulomb_def, poisson_ratio, 0.5),
      BAD(gm_mohr_coulomb_def, density, 0.0),
      BAD(gm_mohr_coulomb_def, friction_angle, 0.0),
      BAD(gm_mohr_coulomb_def, friction_angle, -0.3),
      BAD(gm_mohr_coulomb_def, friction_angle, 1.5707963267948966),
      /* psi above the default phi (0.52 rad), still below pi/2 */
      BAD(gm_mohr_coulomb_def, dilation_angle, 1.5),
      BAD(gm_mohr_coulomb_def, dilation_angle, -0.1),
      BAD(gm_mohr_coulomb_def, bagnold_viscosity, -1e-3)},
     9},
    {"gm_drucker_prager_def",
     sizeof(gm_drucker_prager_def),
     init_drucker_prager,
     add_drucker_prager,
     {D(gm_drucker_prager_def, youngs_modulus),
      D(gm_drucker_prager_def, poisson_ratio),
      D(gm_drucker_prager_def, density),
      D(gm_drucker_prager_def, friction_angle)},
     4,
     {BAD(gm_drucker_prager_def, youngs_modulus, 0.0),
      BAD(gm_drucker_prager_def, youngs_modulus, -1e6),
      BAD(gm_drucker_prager_def, poisson_ratio, 0.5),
      BAD(gm_drucker_prager_def, poisson_ratio, -1.0),
      BAD(gm_drucker_prager_def, density, 0.0),
      BAD(gm_drucker_prager_def, density, INFINITY),
      BAD(gm_drucker_prager_def, friction_angle, 0.0),
      BAD(gm_drucker_prager_def, friction_angle, -0.1),
      BAD(gm_drucker_prager_def, friction_angle, 1.5707963267948966),
      BAD(gm_drucker_prager_def, friction_angle, 2.0)},
     10},
    {"gm_perzyna_def",
     sizeof(gm_perzyna_def),
     init_perzyna,
     add_perzyna,
     {D(gm_perzyna_def, youngs_modulus), D(gm_perzyna_def, poisson_ratio),
      D(gm_perzyna_def, density), D(gm_perzyna_def, friction_angle),
      D(gm_perzyna_def, fluidity), D(gm_perzyna_def, exponent),
      D(gm_perzyna_def, reference_stress)},
     7,
     {BAD(gm_perzyna_def, youngs_modulus, -1.0),
      BAD(gm_perzyna_def, poisson_ratio, 0.5),
      BAD(gm_perzyna_def, density, 0.0),
      /* degrees given where radians are expected */
      BAD(gm_perzyna_def, friction_angle, 30.0),
      BAD(gm_perzyna_def, fluidity, 0.0),
      BAD(gm_perzyna_def, reference_stress, -1.0),
      BAD_INT(gm_perzyna_def, max_iterations, 0)},
     7},
    {"gm_filling_def",
     sizeof(gm_filling_def),
     init_filling,
     add_filling,
     {D(gm_filling_def, density), D(gm_filling_def, poisson_ratio),
      D(gm_filling_def, kappa), D(gm_filling_def, void_ratio),
      D(gm_filling_def, reference_pressure), D(gm_filling_def, bulk_viscosity),
      D(gm_filling_def, friction_angle), D(gm_filling_def, fluidity),
      D(gm_filling_def, exponent), D(gm_filling_def, reference_stress),
      D(gm_filling_def, max_pressure)},
     11,
     {BAD(gm_filling_def, density, -1.0),
      BAD(gm_filling_def, poisson_ratio, -1.0), BAD(gm_filling_def, kappa, 0.0),
      BAD(gm_filling_def, void_ratio, -0.1),
      BAD(gm_filling_def, reference_pressure, 0.0),
      BAD(gm_filling_def, bulk_viscosity, -1.0),
      BAD(gm_filling_def, friction_angle, 0.0),
      BAD(gm_filling_def, friction_angle, 2.0),
      BAD(gm_filling_def, fluidity, INFINITY),
      BAD(gm_filling_def, exponent, 0.0),
      /* below the reference pressure p0 */
      BAD(gm_filling_def, max_pressure, 100.0),
      BAD_INT(gm_filling_def, max_iterations, 5000)},
     12},
    {"gm_von_mises_def",
     sizeof(gm_von_mises_def),
     init_von_mises,
     add_von_mises,
     {D(gm_von_mises_def, youngs_modulus), D(gm_von_mises_def, poisson_ratio),
      D(gm_von_mises_def, density), D(gm_von_mises_def, yield_stress)},
     4,
     {BAD(gm_von_mises_def, youngs_modulus, 0.0),
      BAD(gm_von_mises_def, poisson_ratio, 0.5),
      BAD(gm_von_mises_def, poisson_ratio, -1.5),
      BAD(gm_von_mises_def, density, -1.0),
      BAD(gm_von_mises_def, yield_stress, 0.0),
      BAD(gm_von_mises_def, yield_stress, -1e6),
      BAD(gm_von_mises_def, yield_stress, INFINITY)},
     7},
    {"gm_stress_free_def",
     sizeof(gm_stress_free_def),
     init_stress_free,
     add_stress_free,
     {D(gm_stress_free_def, density), D(gm_stress_free_def, p_wave_modulus)},
     2,
     {BAD(gm_stress_free_def, density, 0.0),
      BAD(gm_stress_free_def, density, -1000.0),
      BAD(gm_stress_free_def, p_wave_modulus, 0.0),
      BAD(gm_stress_free_def, p_wave_modulus, -1e6),
      BAD(gm_stress_free_def, p_wave_modulus, INFINITY)},
     5},
    {"gm_mu_i_def",
     sizeof(gm_mu_i_def),
     init_mu_i,
     add_mu_i,
     {D(gm_mu_i_def, youngs_modulus), D(gm_mu_i_def, poisson_ratio),
      D(gm_mu_i_def, density), D(gm_mu_i_def, grain_density),
      D(gm_mu_i_def, grain_diameter), D(gm_mu_i_def, static_friction),
      D(gm_mu_i_def, limit_friction), D(gm_mu_i_def, inertial_number_scale),
      D(gm_mu_i_def, critical_density),
      D(gm_mu_i_def, regularisation_exponent)},
     10,
     {BAD(gm_mu_i_def, youngs_modulus, 0.0),
      BAD(gm_mu_i_def, poisson_ratio, 0.5), BAD(gm_mu_i_def, density, -1.0),
      BAD(gm_mu_i_def, grain_density, 0.0),
      BAD(gm_mu_i_def, static_friction, 0.0),
      /* mu_2 below mu_s */
      BAD(gm_mu_i_def, limit_friction, 0.3),
      BAD(gm_mu_i_def, inertial_number_scale, -0.1),
      BAD(gm_mu_i_def, critical_density, -1.0),
      BAD(gm_mu_i_def, regularisation_exponent, 2.0),
      BAD(gm_mu_i_def, regularisation_exponent, 0.0)},
     10},
};

/* A def of model m at its defaults, in a buffer big enough for any. */
static void default_def(const material_model *model,
                        unsigned char def[MAX_DEF_BYTES]) {
  ck_assert_uint_le(model->size, MAX_DEF_BYTES);
  memset(def, 0, MAX_DEF_BYTES);
  ck_assert_int_eq(model->init(def, model->size), GM_OK);
}

static void write_value(unsigned char *def, const bad_value *bad) {
  if (bad->is_int) {
    int value = (int)bad->value;
    memcpy(def + bad->offset, &value, sizeof value);
  } else {
    memcpy(def + bad->offset, &bad->value, sizeof bad->value);
  }
}

/* A refused registration: the status, a message naming field and struct,
 * *material untouched. */
static void expect_refused(const material_model *model, gm_domain *domain,
                           const unsigned char *def, const char *field,
                           const char *what) {
  int material = -7;
  gm_status status = model->add(domain, def, &material);
  ck_assert_msg(status == GM_ERR_INVALID_ARGUMENT,
                "%s %s: status %d (%s), expected GM_ERR_INVALID_ARGUMENT",
                model->def_name, what, (int)status, gm_strerror(status));
  const char *message = gm_domain_last_error(domain);
  ck_assert_msg(strstr(message, field) && strstr(message, model->def_name),
                "%s %s: message '%s' does not name %s and %s", model->def_name,
                what, message, field, model->def_name);
  ck_assert_msg(material == -7, "%s %s: *material changed to %d",
                model->def_name, what, material);
}

START_TEST(test_defaults_accepted) {
  const material_model *model = &MODELS[_i];
  gm_domain_def domain_def = gm_domain_def_default();
  gm_domain *domain = test_create_domain(&domain_def);
  unsigned char def[MAX_DEF_BYTES];
  default_def(model, def);
  for (int expected = 0; expected < 3; expected++) {
    int material = -1;
    TEST_ASSERT_OK(domain, model->add(domain, def, &material));
    ck_assert_int_eq(material, expected);
  }
  gm_domain_destroy(domain);
}
END_TEST

START_TEST(test_null_and_struct_size) {
  const material_model *model = &MODELS[_i];
  gm_domain_def domain_def = gm_domain_def_default();
  gm_domain *domain = test_create_domain(&domain_def);
  unsigned char def[MAX_DEF_BYTES];
  default_def(model, def);
  int material = -1;
  ck_assert_int_eq(model->add(NULL, def, &material), GM_ERR_NULL);
  ck_assert_int_eq(model->add(domain, NULL, &material), GM_ERR_NULL);
  ck_assert_int_eq(model->add(domain, def, NULL), GM_ERR_NULL);
  const size_t unknown_sizes[] = {0, 4, 8, model->size - 1};
  for (size_t k = 0; k < COUNT(unknown_sizes); k++) {
    default_def(model, def);
    memcpy(def, &unknown_sizes[k], sizeof unknown_sizes[k]);
    gm_status status = model->add(domain, def, &material);
    ck_assert_msg(status == GM_ERR_STRUCT_SIZE,
                  "%s: struct_size %zu gave %d (%s)", model->def_name,
                  unknown_sizes[k], (int)status, gm_strerror(status));
  }
  ck_assert_int_eq(material, -1);
  gm_domain_destroy(domain);
}
END_TEST

START_TEST(test_invalid_values_refused) {
  const material_model *model = &MODELS[_i];
  gm_domain_def domain_def = gm_domain_def_default();
  gm_domain *domain = test_create_domain(&domain_def);
  unsigned char def[MAX_DEF_BYTES];
  char what[64];
  for (size_t b = 0; b < model->bad_count; b++) {
    default_def(model, def);
    write_value(def, &model->bad[b]);
    snprintf(what, sizeof what, "%s = %g", model->bad[b].field,
             model->bad[b].value);
    expect_refused(model, domain, def, model->bad[b].field, what);
  }
  /* NaN is out of every range: each double parameter refuses it. The
   * field's name is not in the table for these, only its offset: the
   * message must name the struct. */
  for (size_t d = 0; d < model->double_count; d++) {
    default_def(model, def);
    bad_value nan_value = {"", model->doubles[d], 0, NAN};
    write_value(def, &nan_value);
    snprintf(what, sizeof what, "NaN at offset %zu", model->doubles[d]);
    expect_refused(model, domain, def, "", what);
  }
  /* No refused call took an id. */
  default_def(model, def);
  int material = -1;
  TEST_ASSERT_OK(domain, model->add(domain, def, &material));
  ck_assert_int_eq(material, 0);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *contract_suite(void) {
  Suite *suite = suite_create("material_contract");
  TCase *registration = tcase_create("registration");
  int models = (int)COUNT(MODELS);
  tcase_add_loop_test(registration, test_defaults_accepted, 0, models);
  tcase_add_loop_test(registration, test_null_and_struct_size, 0, models);
  tcase_add_loop_test(registration, test_invalid_values_refused, 0, models);
  suite_add_tcase(suite, registration);
  return suite;
}

int main(void) {
  SRunner *runner = srunner_create(contract_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
