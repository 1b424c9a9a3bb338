/*
 * builtin_models.c - the built-in material models in one table, and the one
 * registration they all go through: the checked preamble, the model's own
 * parameter check, and the copy of its def as the material's parameters.
 * A model is a gm_builtin_model defined beside its update function; adding
 * one means adding it to BUILTIN_MODELS, and its checkpoint record follows.
 */
#include "materials/materials.h"

#include <stdalign.h>
#include <string.h>

static const gm_builtin_model *const BUILTIN_MODELS[] = {
    &gm_elastic_model,     &gm_mohr_coulomb_model, &gm_drucker_prager_model,
    &gm_perzyna_model,     &gm_filling_model,      &gm_von_mises_model,
    &gm_stress_free_model, &gm_mu_i_model,
};

const gm_builtin_model *gm_builtin_model_of(gm_material_update_fn *update) {
  size_t count = sizeof BUILTIN_MODELS / sizeof BUILTIN_MODELS[0];
  for (size_t k = 0; k < count; k++)
    if (BUILTIN_MODELS[k]->update == update)
      return BUILTIN_MODELS[k];
  return NULL;
}

gm_status gm_register_builtin(gm_domain *domain, const gm_builtin_model *model,
                              const void *def, int *material_id) {
  /* The completed def (the library's layout of it), aligned for any of
   * the gm_X_def structs. */
  alignas(max_align_t) unsigned char full[GM_MAX_PARAMETER_BYTES];
  size_t size = gm_layout_size(model->layout);
  if (size > sizeof full)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: built-in parameters too large", model->caller);
  gm_status status = gm_api_take_def(domain, model->caller, model->layout, def,
                                     full, material_id, "material_id");
  if (status == GM_OK)
    status = model->check(domain, full);
  if (status != GM_OK)
    return status;
  const char *name;
  memcpy(&name, full + sizeof(size_t), sizeof name);
  const char *no_name = NULL; /* the domain keeps its own copy of the name */
  memcpy(full + sizeof(size_t), &no_name, sizeof no_name);
  double density; /* kg/m^3 */
  memcpy(&density, full + model->density_offset, sizeof density);
  gm_builtin_material spec;
  memset(&spec, 0, sizeof spec);
  spec.def_name = gm_layout_name(model->layout);
  spec.name = name ? name : model->default_name;
  spec.update = model->update;
  spec.parameters = full;
  spec.parameter_size = size;
  spec.state_count = model->state_count;
  spec.initial_state = NULL; /* every model starts from zeros */
  spec.p_wave_modulus = model->p_wave_modulus(full);
  spec.density = density;
  return gm_add_builtin_material(domain, &spec, material_id);
}
