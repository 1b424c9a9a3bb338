/*
 * drucker_prager.c - built-in Drucker-Prager material (002 sec 2.2, 4.1):
 * elastic - perfectly plastic, cohesionless, yield f = q - m p, plastic
 * potential g = q (non-associated, plastically incompressible).
 *
 * The update is the paper's forward-Euler projection (002 sec 4.1): the
 * library has already rotated the stress by the Jaumann spin, so the
 * elastic trial is sigma_e = sigma_t + A : d_eps (gm_elastic_update), and
 *   sigma = sigma_e                   if f(sigma_e) <= 0
 *   sigma = (m p_e / q_e) s_e - p_e I if f(sigma_e) > 0 and p_e > 0
 *   sigma = 0                         if f(sigma_e) > 0 and p_e <= 0.
 * The second line is exact for g = q: the plastic strain rate is
 * lambda (3/2) s / q, deviatoric and parallel to s, so the corrector
 * -2 G d_eps_p keeps p and scales the deviator radially onto q = m p.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "granmpm/drucker_prager.h"
#include "materials/invariants.h"

#include <math.h>
#include <string.h>

static const char DEF_NAME[] = "gm_drucker_prager_def";

/* Slope m of the yield line q = m p for friction angle phi (rad), 002 sec
 * 2.2: the mean of the triaxial compression and extension matches. */
static double drucker_prager_slope(double friction_angle) {
  double sin_phi = sin(friction_angle);
  return 18.0 * sin_phi / (9.0 - sin_phi * sin_phi);
}

/* Projects the elastic trial stress of point i onto the admissible set;
 * returns the equivalent plastic strain increment (-), 0 when elastic. */
static double drucker_prager_return(double *const stress[6], size_t i,
                                    double slope, double shear_modulus) {
  gm_stress_split trial = gm_split_stress(stress, i);
  double yield = trial.equivalent - slope * trial.pressure; /* Pa */
  /* Inside or on the surface: keep the trial bit for bit. A NaN trial also
   * lands here and is passed on for the library to report. */
  if (!(yield > 0.0))
    return 0.0;
  if (trial.pressure > 0.0) {
    /* yield > 0 and p > 0 imply q > m p > 0: no division by zero. */
    double scale = slope * trial.pressure / trial.equivalent;
    gm_write_scaled_deviator(stress, i, &trial, scale);
    /* Radial return: q drops by 3 G dlambda, dlambda = equivalent strain. */
    return yield / (3.0 * shear_modulus);
  }
  /* Tension outside the cone: the cohesionless material separates. */
  for (int c = 0; c < 6; c++)
    stress[c][i] = 0.0;
  return trial.equivalent / (3.0 * shear_modulus);
}

int gm_drucker_prager_update(const gm_material_batch *batch, void *user,
                             char *message, size_t message_size) {
  const gm_drucker_prager_def *def = user;
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.name = NULL;
  elastic.youngs_modulus = def->youngs_modulus;
  elastic.poisson_ratio = def->poisson_ratio;
  elastic.density = def->density;
  /* Elastic trial stress, identical to the built-in elastic material. */
  int result = gm_elastic_update(batch, &elastic, message, message_size);
  if (result != 0)
    return result;
  double slope = drucker_prager_slope(def->friction_angle);
  double shear_modulus =
      gm_shear_modulus(def->youngs_modulus, def->poisson_ratio); /* Pa */
  bool has_state = batch->state_count > GM_DRUCKER_PRAGER_PLASTIC_STRAIN &&
                   batch->state != NULL;
  for (size_t i = 0; i < batch->count; i++) {
    double plastic_strain =
        drucker_prager_return(batch->stress, i, slope, shear_modulus);
    if (has_state)
      batch->state[GM_DRUCKER_PRAGER_PLASTIC_STRAIN][i] += plastic_strain;
  }
  return 0;
}

static gm_status drucker_prager_check(gm_domain *domain,
                                      const void *parameters) {
  const gm_drucker_prager_def *def = parameters;
  gm_status status = gm_check_elastic_constants(
      domain, DEF_NAME, def->youngs_modulus, def->poisson_ratio);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "density", def->density,
                               "kg/m^3", false);
  if (status != GM_OK)
    return status;
  double phi = def->friction_angle; /* rad */
  if (!(phi > 0.0 && phi < 0.5 * GM_PI))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.friction_angle is %g rad, must be in (0, pi/2) "
                        "radians, i.e. strictly between 0 and 90 degrees",
                        DEF_NAME, phi);
  return GM_OK;
}

/* Plasticity only softens: the elastic K + 4G/3 bounds the wave speed. */
static double drucker_prager_p_wave_modulus(const void *parameters) {
  const gm_drucker_prager_def *def = parameters;
  return gm_p_wave_modulus(def->youngs_modulus, def->poisson_ratio);
}

const gm_builtin_model gm_drucker_prager_model = {
    .caller = "gm_domain_add_drucker_prager",
    .layout = GM_LAYOUT_DRUCKER_PRAGER_DEF,
    .default_name = "drucker_prager",
    .update = gm_drucker_prager_update,
    .state_count = GM_DRUCKER_PRAGER_STATE_COUNT, /* no plastic strain yet */
    .check = drucker_prager_check,
    .p_wave_modulus = drucker_prager_p_wave_modulus,
    .density_offset = offsetof(gm_drucker_prager_def, density),
    .record_end = GM_FIELD_END(gm_drucker_prager_def, friction_angle),
};

gm_status gm_domain_add_drucker_prager(gm_domain *domain,
                                       const gm_drucker_prager_def *def,
                                       int *material_id) {
  return gm_register_builtin(domain, &gm_drucker_prager_model, def,
                             material_id);
}
