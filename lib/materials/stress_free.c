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

gm_status gm_domain_add_stress_free(gm_domain *domain,
                                    const gm_stress_free_def *def,
                                    int *material_id) {
  gm_stress_free_def full;
  gm_status status = gm_api_take_def(domain, "gm_domain_add_stress_free",
                                     GM_LAYOUT_STRESS_FREE_DEF, def, &full,
                                     material_id, "material_id");
  if (status != GM_OK)
    return status;
  def = &full;
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "density", def->density,
                               "kg/m^3", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "p_wave_modulus",
                               def->p_wave_modulus, "Pa", false);
  if (status != GM_OK)
    return status;
  gm_stress_free_def parameters = *def;
  parameters.struct_size = sizeof parameters;
  parameters.name = NULL; /* the domain keeps its own copy of the name */
  gm_builtin_material spec;
  memset(&spec, 0, sizeof spec);
  spec.def_name = DEF_NAME;
  spec.name = def->name ? def->name : "stress_free";
  spec.update = gm_stress_free_update;
  spec.parameters = &parameters;
  spec.parameter_size = sizeof parameters;
  spec.state_count = 0;
  spec.p_wave_modulus = def->p_wave_modulus;
  spec.density = def->density;
  return gm_add_builtin_material(domain, &spec, material_id);
}
