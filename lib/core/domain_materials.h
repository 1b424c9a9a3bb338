/*
 * domain_materials.h - the record of a material (gm_material) that the
 * domain holds in its material array. The registry and the built-in
 * models are declared in materials/materials.h. Private to core/: included
 * through core/domain.h.
 */
#ifndef GM_DOMAIN_MATERIALS_H
#define GM_DOMAIN_MATERIALS_H

#include "core/core.h"
#include "core/domain_boundaries.h" /* gm_force_report */

#define GM_MAX_MATERIALS       256
#define GM_MAX_PARAMETER_BYTES 256

/* ------------------------------------------------------------ materials */
typedef struct gm_material {
  char name[64];
  gm_material_update_fn *update;
  void *user;
  size_t state_count;
  double initial_state[GM_MAX_STATE];
  double p_wave_modulus; /* Pa, K + 4G/3 bound for the stable dt */
  double density;        /* kg/m^3, default for new points */
  /* Parameters of a built-in material, owned by the domain; `user` points
   * here (re-aimed whenever the material array moves). */
  _Alignas(max_align_t) unsigned char parameters[GM_MAX_PARAMETER_BYTES];
  bool builtin;
  /* Rigid material (rigid.c): prescribed velocity, and the force the
   * deformable material exerted on it (impulse of the call in progress,
   * force of the last successful call). */
  bool rigid;
  double rigid_velocity[3]; /* m/s (z: 3D, else 0) */
  double rigid_impulse[3];  /* N s, of the call in progress (z: 3D) */
  gm_force_report rigid_report;
  /* Granular material (gm_domain_set_granular). */
  bool granular;
  double critical_density; /* kg/m^3, rho_cr */
  double tolerance;        /* kg/m^3, TOL */
  gm_density_control density_control;
} gm_material;

#endif
