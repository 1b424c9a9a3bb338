/*
 * materials.h - the materials folder: the registry (materials.c) and the
 * built-in materials, which are written against the public
 * gm_material_update_fn and reach the registry only through
 * gm_add_builtin_material. The record (gm_material) is in core/core.h.
 * Private to the library.
 */
#ifndef GM_MATERIALS_H
#define GM_MATERIALS_H

#include "points/points.h"

/* A built-in material (written against the public callback interface):
 * its parameters are copied into the domain and passed to update as
 * `user` (materials.c). */
typedef struct gm_builtin_material {
  const char *def_name; /* the public def struct, for messages */
  const char *name;
  gm_material_update_fn *update;
  const void *parameters; /* copied, at most GM_MAX_PARAMETER_BYTES */
  size_t parameter_size;
  size_t state_count;
  const double *initial_state; /* state_count values, NULL = zeros */
  double p_wave_modulus;       /* Pa, K + 4G/3 */
  double density;              /* kg/m^3 */
} gm_builtin_material;
gm_status gm_add_builtin_material(gm_domain *domain,
                                  const gm_builtin_material *spec,
                                  int *material_id);
/* Young's modulus finite > 0 and Poisson ratio in (-1, 0.5); sets the
 * message naming def_name's fields. */
gm_status gm_check_elastic_constants(gm_domain *domain, const char *def_name,
                                     double youngs_modulus,
                                     double poisson_ratio);
/* value finite and > 0 (or >= 0 when zero_allowed); message names
 * def_name.field and the unit. */
gm_status gm_check_positive(gm_domain *domain, const char *def_name,
                            const char *field, double value, const char *unit,
                            bool zero_allowed);

#endif
