/*
 * materials.c - the material registry: user callbacks and the built-in
 * linear elastic material, both stored the same way.
 */
#include "materials/materials.h"

#include "materials/invariants.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static gm_status check_common(gm_domain *domain, const char *what,
                              double p_wave_modulus, double density) {
  if (!(p_wave_modulus > 0.0) || !isfinite(p_wave_modulus))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: p_wave_modulus is %g Pa, must be finite and > 0",
                        what, p_wave_modulus);
  if (!(density > 0.0) || !isfinite(density))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: density is %g kg/m^3, must be finite and > 0",
                        what, density);
  if (domain->material_count >= GM_MAX_MATERIALS)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: at most %d materials per domain", what,
                        GM_MAX_MATERIALS);
  return GM_OK;
}

/* Appends a material and widens the per-point state pool if needed. */
static gm_status append_material(gm_domain *domain, const gm_material *source,
                                 int *material_id) {
  size_t old_count = (size_t)domain->material_count;
  void *materials = domain->materials;
  if (!gm_grow(&materials, sizeof(gm_material), old_count, old_count + 1))
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "gm_domain_add_material: out of memory");
  domain->materials = materials;
  /* Built-in materials point at their own parameters: re-aim after a move. */
  for (size_t m = 0; m < old_count; m++)
    if (domain->materials[m].builtin)
      domain->materials[m].user = domain->materials[m].parameters;
  if (source->state_count > domain->points.state_stride) {
    gm_status status = gm_points_restride_state(domain, source->state_count);
    if (status != GM_OK)
      return status;
  }
  domain->materials[old_count] = *source;
  domain->material_count++;
  *material_id = (int)old_count;
  return GM_OK;
}

gm_status gm_domain_add_material(gm_domain *domain, const gm_material_def *def,
                                 int *material_id) {
  gm_material_def full;
  gm_status status =
      gm_api_take_def(domain, "gm_domain_add_material", GM_LAYOUT_MATERIAL_DEF,
                      def, &full, material_id, "material_id");
  if (status != GM_OK)
    return status;
  def = &full;
  if (!def->update)
    return gm_set_error(domain, GM_ERR_NULL, "gm_material_def.update is NULL");
  if (def->state_count > GM_MAX_STATE)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_material_def.state_count is %zu, at most %d",
                        def->state_count, GM_MAX_STATE);
  status = check_common(domain, "gm_material_def", def->p_wave_modulus,
                        def->density);
  if (status != GM_OK)
    return status;
  gm_material material;
  memset(&material, 0, sizeof material);
  snprintf(material.name, sizeof material.name, "%s",
           def->name ? def->name : "user");
  material.update = def->update;
  material.user = def->user;
  material.state_count = def->state_count;
  for (size_t k = 0; k < def->state_count; k++) {
    double value = def->initial_state ? def->initial_state[k] : 0.0;
    if (!isfinite(value))
      return gm_set_error(domain, GM_ERR_NOT_FINITE,
                          "gm_material_def.initial_state[%zu] is not finite",
                          k);
    material.initial_state[k] = value;
  }
  material.p_wave_modulus = def->p_wave_modulus;
  material.density = def->density;
  return append_material(domain, &material, material_id);
}

gm_status gm_check_positive(gm_domain *domain, const char *def_name,
                            const char *field, double value, const char *unit,
                            bool zero_allowed) {
  bool valid = isfinite(value) && (zero_allowed ? value >= 0.0 : value > 0.0);
  if (valid)
    return GM_OK;
  return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                      "%s.%s is %g %s, must be finite and %s", def_name, field,
                      value, unit, zero_allowed ? ">= 0" : "> 0");
}

gm_status gm_check_elastic_constants(gm_domain *domain, const char *def_name,
                                     double youngs_modulus,
                                     double poisson_ratio) {
  gm_status status = gm_check_positive(domain, def_name, "youngs_modulus",
                                       youngs_modulus, "Pa", false);
  if (status != GM_OK)
    return status;
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.poisson_ratio is %g, must be in (-1, 0.5)",
                        def_name, poisson_ratio);
  return GM_OK;
}

gm_status gm_add_builtin_material(gm_domain *domain,
                                  const gm_builtin_material *spec,
                                  int *material_id) {
  if (spec->parameter_size > GM_MAX_PARAMETER_BYTES ||
      spec->state_count > GM_MAX_STATE)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: built-in parameters too large", spec->name);
  /* Messages name the def struct the caller filled in (gm_elastic_def,
   * ...), as the models' own parameter checks do. */
  gm_status status =
      check_common(domain, spec->def_name, spec->p_wave_modulus, spec->density);
  if (status != GM_OK)
    return status;
  gm_material material;
  memset(&material, 0, sizeof material);
  snprintf(material.name, sizeof material.name, "%s", spec->name);
  material.update = spec->update;
  if (spec->parameter_size > 0) /* memcpy from NULL is undefined, even of 0 */
    memcpy(material.parameters, spec->parameters, spec->parameter_size);
  material.builtin = true;
  material.state_count = spec->state_count;
  for (size_t k = 0; k < spec->state_count; k++)
    material.initial_state[k] =
        spec->initial_state ? spec->initial_state[k] : 0.0;
  material.p_wave_modulus = spec->p_wave_modulus;
  material.density = spec->density;
  status = append_material(domain, &material, material_id);
  if (status == GM_OK) /* user points at the domain's own copy */
    domain->materials[*material_id].user =
        domain->materials[*material_id].parameters;
  return status;
}

static gm_status elastic_check(gm_domain *domain, const void *parameters) {
  const gm_elastic_def *def = parameters;
  return gm_check_elastic_constants(domain, "gm_elastic_def",
                                    def->youngs_modulus, def->poisson_ratio);
}

/* Constrained (P-wave) modulus M = K + 4G/3 = E(1-nu)/((1+nu)(1-2nu)). */
static double elastic_p_wave_modulus(const void *parameters) {
  const gm_elastic_def *def = parameters;
  return gm_p_wave_modulus(def->youngs_modulus, def->poisson_ratio);
}

const gm_builtin_model gm_elastic_model = {
    .caller = "gm_domain_add_elastic",
    .layout = GM_LAYOUT_ELASTIC_DEF,
    .default_name = "elastic",
    .update = gm_elastic_update,
    .state_count = 0,
    .check = elastic_check,
    .p_wave_modulus = elastic_p_wave_modulus,
    .density_offset = offsetof(gm_elastic_def, density),
    .record_end = GM_FIELD_END(gm_elastic_def, density),
};

gm_status gm_domain_add_elastic(gm_domain *domain, const gm_elastic_def *def,
                                int *material_id) {
  return gm_register_builtin(domain, &gm_elastic_model, def, material_id);
}
