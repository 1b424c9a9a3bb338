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

gm_status gm_domain_add_von_mises(gm_domain *domain,
                                  const gm_von_mises_def *def,
                                  int *material_id) {
  gm_von_mises_def full;
  gm_status status = gm_api_take_def(domain, "gm_domain_add_von_mises",
                                     GM_LAYOUT_VON_MISES_DEF, def, &full,
                                     material_id, "material_id");
  if (status != GM_OK)
    return status;
  def = &full;
  if (status == GM_OK)
    status = gm_check_elastic_constants(domain, DEF_NAME, def->youngs_modulus,
                                        def->poisson_ratio);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "density", def->density,
                               "kg/m^3", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "yield_stress",
                               def->yield_stress, "Pa", false);
  if (status != GM_OK)
    return status;
  gm_von_mises_def parameters = *def;
  parameters.struct_size = sizeof parameters;
  parameters.name = NULL; /* the domain keeps its own copy of the name */
  gm_builtin_material spec;
  memset(&spec, 0, sizeof spec);
  spec.def_name = DEF_NAME;
  spec.name = def->name ? def->name : "von_mises";
  spec.update = gm_von_mises_update;
  spec.parameters = &parameters;
  spec.parameter_size = sizeof parameters;
  spec.state_count = GM_VON_MISES_STATE_COUNT;
  spec.initial_state = NULL; /* no plastic strain yet */
  /* Plasticity only softens: the elastic K + 4G/3 bounds the wave speed. */
  spec.p_wave_modulus =
      gm_p_wave_modulus(def->youngs_modulus, def->poisson_ratio);
  spec.density = def->density;
  return gm_add_builtin_material(domain, &spec, material_id);
}
