/*
 * stress_free.c - built-in stress-free material: sigma = 0 after every
 * update (000: disconnected granular points carry no stress). The strain
 * increment is ignored; the p-wave modulus only feeds the stable dt.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "granmpm/stress_free.h"

#include <string.h>

static const char DEF_NAME[] = "gm_stress_free_def";

int gm_stress_free_update(const gm_material_batch *batch, void *user,
                          char *message, size_t message_size) {
  (void)user;
  (void)message;
  (void)message_size;
  for (int c = 0; c < 6; c++)
    for (size_t i = 0; i < batch->count; i++)
      batch->stress[c][i] = 0.0;
  return 0;
}

static gm_status stress_free_check(gm_domain *domain, const void *parameters) {
  const gm_stress_free_def *def = parameters;
  gm_status status = gm_check_positive(domain, DEF_NAME, "density",
                                       def->density, "kg/m^3", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "p_wave_modulus",
                               def->p_wave_modulus, "Pa", false);
  return status;
}

/* The modulus the caller chose for the stable time step (see the header). */
static double stress_free_p_wave_modulus(const void *parameters) {
  return ((const gm_stress_free_def *)parameters)->p_wave_modulus;
}

const gm_builtin_model gm_stress_free_model = {
    .caller = "gm_domain_add_stress_free",
    .layout = GM_LAYOUT_STRESS_FREE_DEF,
    .default_name = "stress_free",
    .update = gm_stress_free_update,
    .state_count = 0,
    .check = stress_free_check,
    .p_wave_modulus = stress_free_p_wave_modulus,
    .density_offset = offsetof(gm_stress_free_def, density),
    .record_end = GM_FIELD_END(gm_stress_free_def, p_wave_modulus),
};

gm_status gm_domain_add_stress_free(gm_domain *domain,
                                    const gm_stress_free_def *def,
                                    int *material_id) {
  return gm_register_builtin(domain, &gm_stress_free_model, def, material_id);
}
