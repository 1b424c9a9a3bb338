/*
 * filling.c - the pressure-volume model for silo filling of Wieckowski 2004
 * ("001") sec 5.1.2: eq 24 for the pressure (elastic log-volume law plus a
 * one-sided bulk viscosity) and, for the deviator, the Perzyna return of
 * sec 5.1.1 with the pressure-dependent shear modulus. Equations and
 * parameters are in include/granmpm/filling.h.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include <math.h>
#include <string.h>

/* pi/2, the upper bound of the friction angle (rad). */
#define FILLING_HALF_PI 1.57079632679489661923

/* The log volumetric strain (-) at which eq 24 reaches max_pressure:
 * p_el = p0 exp(c (1 - J)), J = exp(eps_vol), c = (1 + e0)/kappa. */
static double filling_cap_strain(const gm_filling_def *def) {
  double compressibility = (1.0 + def->void_ratio) / def->kappa; /* - */
  return log(1.0 - log(def->max_pressure / def->reference_pressure) /
                       compressibility);
}

/* Elastic part of eq 24 (Pa) at the log volumetric strain eps_vol (-).
 * Beyond max_pressure the law goes on linearly in eps_vol with its tangent
 * bulk modulus there, K* = c J* max_pressure <= max_pressure c: the bound
 * the stable time step was computed with keeps holding (an exponential
 * past it made impacts blow up: the wave speed outran dt). */
static double filling_elastic_pressure(const gm_filling_def *def,
                                       double volumetric_strain) {
  double compressibility = (1.0 + def->void_ratio) / def->kappa; /* - */
  double cap = filling_cap_strain(def);
  if (volumetric_strain < cap) {
    double bulk = compressibility * exp(cap) * def->max_pressure; /* Pa */
    return def->max_pressure + bulk * (cap - volumetric_strain);
  }
  return def->reference_pressure *
         exp(compressibility * (1.0 - exp(volumetric_strain)));
}

/* Shear modulus of sec 5.1.2 (Pa) at elastic pressure p_el (Pa); held at
 * its max_pressure value beyond the cap (see above). */
static double filling_shear_modulus(const gm_filling_def *def,
                                    double elastic_pressure,
                                    double volumetric_strain) {
  double nu = def->poisson_ratio;
  double cap = filling_cap_strain(def);
  if (volumetric_strain < cap) {
    elastic_pressure = def->max_pressure;
    volumetric_strain = cap;
  }
  return 1.5 * (1.0 - 2.0 * nu) / (1.0 + nu) * (1.0 + def->void_ratio) /
         def->kappa * elastic_pressure * exp(volumetric_strain);
}

/* The Perzyna parameters for a point with shear modulus G (Pa): the
 * deviatoric return only uses G, m, gamma, N and sigma_ref. */
static gm_perzyna_def filling_deviatoric_def(const gm_filling_def *def,
                                             double shear_modulus) {
  gm_perzyna_def perzyna = gm_perzyna_def_default();
  perzyna.youngs_modulus = 2.0 * shear_modulus * (1.0 + def->poisson_ratio);
  perzyna.poisson_ratio = def->poisson_ratio;
  perzyna.density = def->density;
  perzyna.friction_angle = def->friction_angle;
  perzyna.fluidity = def->fluidity;
  perzyna.exponent = def->exponent;
  perzyna.reference_stress = def->reference_stress;
  perzyna.max_iterations = def->max_iterations;
  return perzyna;
}

/* Updates point i of the batch; returns as gm_perzyna_update. */
static int filling_update_point(const gm_material_batch *batch,
                                const gm_filling_def *def, size_t i,
                                char *message, size_t message_size) {
  const double *const *increment = batch->strain_increment;
  double volumetric_increment =
      increment[GM_XX][i] + increment[GM_YY][i] + increment[GM_ZZ][i];
  /* eps_vol = ln(V/V0) = ln(rho0/rho) (001 sec 5.1.2: exp(eps_vol) = (1 +
   * e)/(1 + e0)), from the point's density rather than summed increments:
   * a point placed looser than rho0 starts with (almost) no pressure, as
   * 001's released portions do, and a volume the granular density control
   * returns carries its pressure with it. */
  double volumetric_strain = log(def->density / batch->density[i]);
  double elastic_pressure = filling_elastic_pressure(def, volumetric_strain);
  double rate = batch->dt > 0.0 ? volumetric_increment / batch->dt : 0.0;
  /* Eq 24: the viscous part only resists compaction, (-mu rate)^+. */
  double pressure =
      elastic_pressure + fmax(-def->bulk_viscosity * rate, 0.0); /* Pa */
  double shear =
      filling_shear_modulus(def, elastic_pressure, volumetric_strain);
  gm_perzyna_def perzyna = filling_deviatoric_def(def, shear);

  /* One-point batch for the Perzyna return: the old deviator with the new
   * pressure, and the deviatoric part of the increment (no volume change,
   * so its elastic pressure update is void). */
  double old_pressure = -(batch->stress[GM_XX][i] + batch->stress[GM_YY][i] +
                          batch->stress[GM_ZZ][i]) /
                        3.0;
  double stress[6], deviatoric_increment[6];
  double *stress_columns[6], *state_column = batch->state[1] + i;
  const double *increment_columns[6];
  for (int c = 0; c < 6; c++) {
    /* s_t - p I = sigma_t + (p_t - p) I */
    stress[c] = batch->stress[c][i] + (c < 3 ? old_pressure - pressure : 0.0);
    deviatoric_increment[c] =
        increment[c][i] - (c < 3 ? volumetric_increment / 3.0 : 0.0);
    stress_columns[c] = &stress[c];
    increment_columns[c] = &deviatoric_increment[c];
  }
  gm_material_batch point;
  memset(&point, 0, sizeof point);
  point.struct_size = sizeof point;
  point.count = 1;
  point.worker = batch->worker;
  point.material = batch->material;
  point.geometry = batch->geometry;
  point.dt = batch->dt;
  point.density = batch->density + i;
  point.state = &state_column;
  point.state_count = 1;
  point.point_id = batch->point_id + i;
  for (int c = 0; c < 6; c++) {
    point.stress[c] = stress_columns[c];
    point.strain_increment[c] = increment_columns[c];
  }
  int result = gm_perzyna_update(&point, &perzyna, message, message_size);
  if (result != 0)
    return result;
  for (int c = 0; c < 6; c++)
    batch->stress[c][i] = stress[c];
  batch->state[0][i] = volumetric_strain;
  return 0;
}

int gm_filling_update(const gm_material_batch *batch, void *user, char *message,
                      size_t message_size) {
  const gm_filling_def *def = user;
  for (size_t i = 0; i < batch->count; i++) {
    int result = filling_update_point(batch, def, i, message, message_size);
    if (result != 0)
      return result;
  }
  return 0;
}

/* Checks every field; sets the error naming the first bad one. */
static gm_status filling_check(gm_domain *domain, const void *parameters) {
  const gm_filling_def *def = parameters;
  const char *name = "gm_filling_def";
  gm_status status =
      gm_check_positive(domain, name, "density", def->density, "kg/m^3", false);
  if (status == GM_OK &&
      !(def->poisson_ratio > -1.0 && def->poisson_ratio < 0.5))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.poisson_ratio is %g, must be in (-1, 0.5)", name,
                        def->poisson_ratio);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "kappa", def->kappa, "(-)", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "void_ratio", def->void_ratio,
                               "(-)", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "reference_pressure",
                               def->reference_pressure, "Pa", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "bulk_viscosity",
                               def->bulk_viscosity, "Pa s", true);
  if (status == GM_OK &&
      !(def->friction_angle > 0.0 && def->friction_angle < FILLING_HALF_PI))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.friction_angle is %g rad, must be in (0, pi/2) "
                        "radians",
                        name, def->friction_angle);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "fluidity", def->fluidity, "1/s",
                               false);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "exponent", def->exponent, "(-)",
                               false);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "reference_stress",
                               def->reference_stress, "Pa", true);
  if (status == GM_OK && !(isfinite(def->max_pressure) &&
                           def->max_pressure >= def->reference_pressure))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.max_pressure is %g Pa, must be finite and >= "
                        "reference_pressure (%g Pa)",
                        name, def->max_pressure, def->reference_pressure);
  if (status == GM_OK &&
      !(def->max_iterations >= 1 && def->max_iterations <= 1000))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.max_iterations is %d, must be in 1..1000", name,
                        def->max_iterations);
  return status;
}

/* K + 4G/3 = K 3(1 - nu)/(1 + nu) (Pa) with K bounded by
 * max_pressure (1 + e0)/kappa: along eq 24, K = (1 + e) p_el / kappa
 * grows with p_el unless V/V0 = exp(eps_vol) < kappa/(1 + e0) (a
 * compaction to ~1% of the volume for the default data). */
static double filling_p_wave_modulus(const void *parameters) {
  const gm_filling_def *def = parameters;
  double nu = def->poisson_ratio;
  double bulk = def->max_pressure * (1.0 + def->void_ratio) / def->kappa;
  return bulk * 3.0 * (1.0 - nu) / (1.0 + nu);
}

const gm_builtin_model gm_filling_model = {
    .caller = "gm_domain_add_filling",
    .layout = GM_LAYOUT_FILLING_DEF,
    .default_name = "filling",
    .update = gm_filling_update,
    .state_count = GM_FILLING_STATE_COUNT, /* eps_vol = 0: pressure p0 */
    .check = filling_check,
    .p_wave_modulus = filling_p_wave_modulus,
    .density_offset = offsetof(gm_filling_def, density),
    .record_end = GM_FIELD_END(gm_filling_def, max_iterations),
};

gm_status gm_domain_add_filling(gm_domain *domain, const gm_filling_def *def,
                                int *material_id) {
  return gm_register_builtin(domain, &gm_filling_model, def, material_id);
}
