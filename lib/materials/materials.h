/*
 * materials.h - the materials folder: the registry (materials.c) and the
 * built-in materials, which are written against the public
 * gm_material_update_fn and reach the registry only through
 * gm_add_builtin_material. The record (gm_material) is in
 * core/domain_materials.h. Private to the library.
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
/* One built-in material model: what its registration and its checkpoint
 * record need. Each model defines its own next to its update function;
 * builtin_models.c registers through it and lists them all. */
typedef struct gm_builtin_model {
  const char *caller;       /* "gm_domain_add_X", for the preamble */
  gm_layout layout;         /* its def struct (gm_X_def), see api_check.h */
  const char *default_name; /* material name when def->name is NULL */
  gm_material_update_fn *update;
  size_t state_count; /* per-point state, zeros at insertion */
  /* Checks the completed def's parameters, setting a message naming
   * gm_X_def.field; GM_OK or GM_ERR_INVALID_ARGUMENT. */
  gm_status (*check)(gm_domain *domain, const void *def);
  /* Pa, the modulus K + 4G/3 that bounds the wave speed of the def. */
  double (*p_wave_modulus)(const void *def);
  size_t density_offset; /* offsetof(gm_X_def, density) */
  /* Bytes of the parameter copy a checkpoint compares: from after the name
   * pointer to the end of this last compared field (trailing padding,
   * whose contents C leaves unspecified, is skipped). */
  size_t record_end;
} gm_builtin_model;

/* The preamble (gm_api_take_def), model->check, then the copy of the def
 * (name cleared: the domain keeps its own) as the material's parameters. */
gm_status gm_register_builtin(gm_domain *domain, const gm_builtin_model *model,
                              const void *def, int *material_id);
/* The model whose update function this is, or NULL (a user material). */
const gm_builtin_model *gm_builtin_model_of(gm_material_update_fn *update);
/* Offset of the first compared parameter byte: every gm_X_def starts with
 * struct_size and the name pointer. */
#define GM_BUILTIN_RECORD_BEGIN (sizeof(size_t) + sizeof(const char *))
#define GM_FIELD_END(type, field)                                              \
  (offsetof(type, field) + sizeof(((type *)0)->field))

extern const gm_builtin_model gm_elastic_model, gm_mohr_coulomb_model,
    gm_drucker_prager_model, gm_perzyna_model, gm_filling_model,
    gm_von_mises_model, gm_stress_free_model, gm_mu_i_model;

/* The Mohr-Coulomb corrector of plane trial stresses (mohr_coulomb.c) for
 * the fused deformation pass (grid/deform_mohr_coulomb.c): rows xx, yy,
 * zz, xy of `count` points (Pa, in place; yz = zx = 0), each finite, with
 * a finite sum xx + yy + zz + xy (summed in that order), and already the
 * elastic predictor's; no rate term (bagnold_viscosity 0).
 * The screen and return of gm_mohr_coulomb_update, so the same bits; the
 * plastic shear strain of point i, plastic_shear[i * stride], grows by
 * the return's. `prepared` (GM_MOHR_COULOMB_PREPARED_BYTES, zeroed before
 * its first use, one per thread) keeps the constants derived from the
 * def between calls. Returns false if some returned stress is not finite
 * (or overflows when summed): the caller's check then names the point. */
bool gm_mohr_coulomb_plane_returns(const gm_mohr_coulomb_def *def,
                                   double *const stress[4], size_t count,
                                   double *plastic_shear, size_t stride,
                                   void *prepared);

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

/* The objective stress increment of one step of a general 3D motion
 * (jaumann.c; 002 sec 4.1, 004 eqs 3.20-3.21): velocity_gradient is L_ij =
 * dv_i/dx_j (1/s), row-major like GM_FIELD_DEFORMATION_GRADIENT, dt in s.
 * gm_jaumann_rotate replaces the stress (Pa, Voigt) by
 * sigma + (W sigma - sigma W) dt, W = (L - L^T)/2, which keeps its trace
 * exactly and its other invariants to O((|W| dt)^2); on a state with
 * W_yz = W_zx = 0 and yz = zx = 0 it is bitwise the plane rotation of
 * grid/stress_update.c. gm_strain_increment writes D dt = (L + L^T) dt / 2
 * (tensor shear components). */
void gm_jaumann_rotate(const double velocity_gradient[9], double dt,
                       double stress[6]);
void gm_strain_increment(const double velocity_gradient[9], double dt,
                         double increment[6]);

#endif
