/*
 * von_mises.c - built-in von Mises material (001 sec 5.3): elastic -
 * perfectly plastic, yield f = q - sigma_y, associated flow
 * d_eps_p = lambda (3/2) s / q. With the library's Jaumann-rotated stress
 * the elastic trial is sigma_e = sigma_t + A : d_eps (gm_elastic_update);
 * a trial outside is returned radially: the corrector -2 G d_eps_p is
 * parallel to s_e, so sigma = (sigma_y / q_e) s_e - p_e I exactly, and
 * dlambda = (q_e - sigma_y) / (3 G) is the equivalent plastic strain.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "granmpm/von_mises.h"
#include "materials/invariants.h"

#include <string.h>

static const char DEF_NAME[] = "gm_von_mises_def";

/* Returns the elastic trial stress of point i to q <= yield_stress (Pa);
 * returns the equivalent plastic strain increment (-), 0 when elastic. */
static double von_mises_return(double *const stress[6], size_t i,
                               double yield_stress, double shear_modulus) {
  gm_stress_split trial = gm_split_stress(stress, i);
  double yield = trial.equivalent - yield_stress; /* Pa */
  /* Inside or on the surface (or a NaN trial, left for the library to
   * report): keep the trial bit for bit. */
  if (!(yield > 0.0))
    return 0.0;
  /* yield > 0 implies q_e > sigma_y > 0: no division by zero. */
  gm_write_scaled_deviator(stress, i, &trial, yield_stress / trial.equivalent);
  return yield / (3.0 * shear_modulus);
}

int gm_von_mises_update(const gm_material_batch *batch, void *user,
                        char *message, size_t message_size) {
  const gm_von_mises_def *def = user;
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.name = NULL;
  elastic.youngs_modulus = def->youngs_modulus;
  elastic.poisson_ratio = def->poisson_ratio;
  elastic.density = def->density;
  /* Elastic trial stress, identical to the built-in elastic material. */
  int result = gm_elastic_update(batch, &elastic, message, message_size);
  if (result != 0)
    return result;
  double shear_modulus =
      gm_shear_modulus(def->youngs_modulus, def->poisson_ratio); /* Pa */
  bool has_state =
      batch->state_count > GM_VON_MISES_PLASTIC_STRAIN && batch->state != NULL;
  for (size_t i = 0; i < batch->count; i++) {
    double plastic_strain =
        von_mises_return(batch->stress, i, def->yield_stress, shear_modulus);
    if (has_state)
      batch->state[GM_VON_MISES_PLASTIC_STRAIN][i] += plastic_strain;
  }
  return 0;
}

static gm_status von_mises_check(gm_domain *domain, const void *parameters) {
  const gm_von_mises_def *def = parameters;
  gm_status status = gm_check_elastic_constants(
      domain, DEF_NAME, def->youngs_modulus, def->poisson_ratio);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "density", def->density,
                               "kg/m^3", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "yield_stress",
                               def->yield_stress, "Pa", false);
  return status;
}

/* Plasticity only softens: the elastic K + 4G/3 bounds the wave speed. */
static double von_mises_p_wave_modulus(const void *parameters) {
  const gm_von_mises_def *def = parameters;
  return gm_p_wave_modulus(def->youngs_modulus, def->poisson_ratio);
}

const gm_builtin_model gm_von_mises_model = {
    .caller = "gm_domain_add_von_mises",
    .layout = GM_LAYOUT_VON_MISES_DEF,
    .default_name = "von_mises",
    .update = gm_von_mises_update,
    .state_count = GM_VON_MISES_STATE_COUNT, /* no plastic strain yet */
    .check = von_mises_check,
    .p_wave_modulus = von_mises_p_wave_modulus,
    .density_offset = offsetof(gm_von_mises_def, density),
    .record_end = GM_FIELD_END(gm_von_mises_def, yield_stress),
};

gm_status gm_domain_add_von_mises(gm_domain *domain,
                                  const gm_von_mises_def *def,
                                  int *material_id) {
  return gm_register_builtin(domain, &gm_von_mises_model, def, material_id);
}
