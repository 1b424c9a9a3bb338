/*
 * perzyna.c - elastic-viscoplastic Drucker-Prager material (Perzyna
 * overstress), Wieckowski 2004 ("001") sec 5.1.1, eqs 15-23, integrated by
 * the backward Euler rule of eqs 19-22. Conventions and parameters are in
 * include/granmpm/perzyna.h.
 *
 * The return (eqs 19-22): with the trial deviator s_e = s_t + 2 G de
 * (eq 20), its invariant q_e, the trial overstress f_e = q_e - m p > 0 and
 * the normalising stress sigma_n, the equivalent viscoplastic strain
 * increment x = Delta e_vp solves (eq 22)
 *   x = gamma dt ((f_e - 3 G x) / sigma_n)^N,
 * then q = q_e - 3 G x (eq 21) and s = s_e q / q_e (eq 19). We solve for the
 * fraction of the trial overstress that remains, z = (q - m p) / f_e in
 * [0, 1], because it stays well scaled in the rate-independent limit
 * (z -> 0) as well as in the elastic one (z -> 1). With
 *   a = (3 G gamma dt / sigma_n) (f_e / sigma_n)^(N - 1)
 * eq 22 becomes h(z) = z + a z^N - 1 = 0: h is increasing, h(0) = -1 and
 * h(1) = a >= 0, so the root is unique and bracketed by [0, 1]. For N = 1,
 * z = 1 / (1 + a), which is the closed form printed after eq 22 (with the
 * paper's typo nu for gamma). Also z < a^(-1/N) since h(a^(-1/N)) > 0.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "materials/invariants.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Relative step at which the iteration for z is converged: the root is then
 * known to round-off (Newton converges quadratically near it). */
#define PERZYNA_RELATIVE_TOLERANCE 1e-14

/* pi/2, the upper bound of the friction angle (rad). */
#define PERZYNA_HALF_PI 1.57079632679489661923

/* m of f = q - m p for a friction angle phi (rad), 001 sec 5.1.1. */
static double perzyna_slope(double friction_angle) {
  double sine = sin(friction_angle);
  return 18.0 * sine / (9.0 - sine * sine);
}

/* Splits sigma (Pa) into pressure (returned, compression positive) and
 * deviator s (Pa). */
static double perzyna_split(const double sigma[6], double deviator[6]) {
  double pressure = -(sigma[GM_XX] + sigma[GM_YY] + sigma[GM_ZZ]) / 3.0;
  for (int c = 0; c < 6; c++)
    deviator[c] = sigma[c];
  for (int c = 0; c < 3; c++)
    deviator[c] += pressure;
  return pressure;
}

/* q = sqrt(3/2 s:s) (Pa); the shear components appear twice in s:s. */
static double perzyna_mises(const double deviator[6]) {
  double normal = deviator[GM_XX] * deviator[GM_XX] +
                  deviator[GM_YY] * deviator[GM_YY] +
                  deviator[GM_ZZ] * deviator[GM_ZZ];
  double shear = deviator[GM_XY] * deviator[GM_XY] +
                 deviator[GM_YZ] * deviator[GM_YZ] +
                 deviator[GM_ZX] * deviator[GM_ZX];
  return sqrt(1.5 * (normal + 2.0 * shear));
}

/* Solves z + a z^N = 1 on [0, 1] by Newton's method safeguarded by the
 * bracket (a bisection step whenever Newton leaves it). Returns 0 and *z,
 * or 1 if not converged within max_iterations. */
static int perzyna_solve_fraction(double a, double exponent, int max_iterations,
                                  double *z) {
  double lower = 0.0, upper = 1.0;
  /* Exact for N = 1, and ~a^(-1/N) for large a: a good start either way. */
  double guess = pow(1.0 + a, -1.0 / exponent);
  for (int iteration = 0; iteration < max_iterations; iteration++) {
    double power = pow(guess, exponent);
    double residual = guess + a * power - 1.0;
    if (residual == 0.0) {
      *z = guess;
      return 0;
    }
    if (residual > 0.0)
      upper = guess;
    else
      lower = guess;
    /* h'(z) = 1 + a N z^(N-1); infinite at z = 0 for N < 1 (then the
     * step is 0 and the bracket test below sends us to bisection). */
    double slope = 1.0 + a * exponent * (guess > 0.0 ? power / guess : 0.0);
    double next = guess - residual / slope;
    if (!(next > lower && next < upper))
      next = 0.5 * (lower + upper);
    double step = fabs(next - guess);
    guess = next;
    if (step <= PERZYNA_RELATIVE_TOLERANCE * guess ||
        upper - lower <= PERZYNA_RELATIVE_TOLERANCE * upper) {
      *z = guess;
      return 0;
    }
  }
  *z = guess;
  return 1;
}

/* Constants of one update, from the def. */
typedef struct perzyna_constants {
  double shear;       /* G, Pa */
  double bulk;        /* K, Pa */
  double slope;       /* m, - */
  double fluidity_dt; /* gamma dt, - */
  const gm_perzyna_def *def;
} perzyna_constants;

/* Remaining overstress fraction z for a trial overstress f_e > 0 (Pa) and
 * normalising stress sigma_n >= 0 (Pa). Returns 0 or 1 (not converged). */
static int perzyna_fraction(const perzyna_constants *k, double overstress,
                            double normaliser, double *a_out, double *z) {
  const gm_perzyna_def *def = k->def;
  double stiffness = 3.0 * k->shear * k->fluidity_dt; /* Pa */
  double a;
  if (stiffness == 0.0)
    a = 0.0; /* no time or no stiffness: no viscoplastic return */
  else if (normaliser == 0.0)
    a = INFINITY; /* Phi unbounded: rate-independent return */
  else
    a = stiffness / normaliser *
        pow(overstress / normaliser, def->exponent - 1.0);
  *a_out = a;
  if (a == 0.0) {
    *z = 1.0;
    return 0;
  }
  if (isinf(a)) {
    *z = 0.0;
    return 0;
  }
  if (def->exponent == 1.0 && !def->always_iterate) {
    *z = 1.0 / (1.0 + a); /* closed form after eq 22 */
    return 0;
  }
  return perzyna_solve_fraction(a, def->exponent, def->max_iterations, z);
}

/* Updates point i; returns 0, 1 (not converged) or -1 (not finite). */
static int perzyna_update_point(const gm_material_batch *batch,
                                const perzyna_constants *k, size_t i,
                                char *message, size_t message_size) {
  double sigma[6], deviator[6], increment[6];
  for (int c = 0; c < 6; c++) {
    sigma[c] = batch->stress[c][i];
    increment[c] = batch->strain_increment[c][i];
  }
  double volumetric = increment[GM_XX] + increment[GM_YY] + increment[GM_ZZ];
  double pressure = perzyna_split(sigma, deviator);
  /* Eq 23 (compression-positive p falls when the volume grows; eq 15 as
   * printed lacks the minus sign), with the tension cut-off at p = 0. */
  pressure = fmax(pressure - k->bulk * volumetric, 0.0);
  for (int c = 0; c < 6; c++) /* eq 20: de = deviator of the increment */
    deviator[c] +=
        2.0 * k->shear * (increment[c] - (c < 3 ? volumetric / 3.0 : 0.0));
  double trial_q = perzyna_mises(deviator);
  if (!isfinite(trial_q) || !isfinite(pressure)) {
    snprintf(message, message_size,
             "perzyna: point %lld: non-finite trial stress",
             (long long)batch->point_id[i]);
    return -1;
  }
  double overstress = trial_q - k->slope * pressure; /* f_e, Pa */
  if (overstress > 0.0) {
    double normaliser = fmax(k->slope * pressure, k->def->reference_stress);
    double a, z;
    if (perzyna_fraction(k, overstress, normaliser, &a, &z) != 0) {
      snprintf(message, message_size,
               "perzyna: point %lld: overstress iteration (N = %g) did not "
               "converge in %d iterations",
               (long long)batch->point_id[i], k->def->exponent,
               k->def->max_iterations);
      return 1;
    }
    double q = k->slope * pressure + z * overstress; /* eq 21 */
    /* Delta e_vp: from eq 22 directly while little of f_e is returned
     * (a <= 1, where 1 - z would cancel), otherwise from eq 21. */
    double strain = 0.0;
    if (a <= 1.0 && normaliser > 0.0)
      strain =
          k->fluidity_dt * pow(z * overstress / normaliser, k->def->exponent);
    else if (k->shear > 0.0)
      strain = (1.0 - z) * overstress / (3.0 * k->shear);
    double scale = q / trial_q; /* eq 19: 1 + 3 G x / q = q_e / q */
    for (int c = 0; c < 6; c++)
      deviator[c] *= scale;
    batch->state[0][i] += strain;
  }
  for (int c = 0; c < 6; c++)
    batch->stress[c][i] = deviator[c] - (c < 3 ? pressure : 0.0);
  return 0;
}

int gm_perzyna_update(const gm_material_batch *batch, void *user, char *message,
                      size_t message_size) {
  const gm_perzyna_def *def = user;
  double young = def->youngs_modulus; /* Pa */
  double nu = def->poisson_ratio;     /* - */
  perzyna_constants k;
  k.shear = young / (2.0 * (1.0 + nu));
  k.bulk = young / (3.0 * (1.0 - 2.0 * nu));
  k.slope = perzyna_slope(def->friction_angle);
  k.fluidity_dt = def->fluidity * batch->dt;
  k.def = def;
  for (size_t i = 0; i < batch->count; i++) {
    int result = perzyna_update_point(batch, &k, i, message, message_size);
    if (result != 0)
      return result;
  }
  return 0;
}

/* Checks the fields beyond the elastic constants; sets the error. */
static gm_status perzyna_check(gm_domain *domain, const void *parameters) {
  const gm_perzyna_def *def = parameters;
  const char *name = "gm_perzyna_def";
  gm_status status = gm_check_elastic_constants(
      domain, name, def->youngs_modulus, def->poisson_ratio);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "density", def->density, "kg/m^3",
                               false);
  if (status == GM_OK &&
      !(def->friction_angle > 0.0 && def->friction_angle < PERZYNA_HALF_PI))
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
  if (status == GM_OK &&
      !(def->max_iterations >= 1 && def->max_iterations <= 1000))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.max_iterations is %d, must be in 1..1000", name,
                        def->max_iterations);
  return status;
}

/* M = K + 4G/3 = E (1 - nu) / ((1 + nu)(1 - 2 nu)), Pa: the viscoplastic
 * flow only softens the response, so the elastic value bounds it. */
static double perzyna_p_wave_modulus(const void *parameters) {
  const gm_perzyna_def *def = parameters;
  return gm_p_wave_modulus(def->youngs_modulus, def->poisson_ratio);
}

const gm_builtin_model gm_perzyna_model = {
    .caller = "gm_domain_add_perzyna",
    .layout = GM_LAYOUT_PERZYNA_DEF,
    .default_name = "perzyna",
    .update = gm_perzyna_update,
    .state_count = GM_PERZYNA_STATE_COUNT, /* zeros initially */
    .check = perzyna_check,
    .p_wave_modulus = perzyna_p_wave_modulus,
    .density_offset = offsetof(gm_perzyna_def, density),
    .record_end = GM_FIELD_END(gm_perzyna_def, always_iterate),
};

gm_status gm_domain_add_perzyna(gm_domain *domain, const gm_perzyna_def *def,
                                int *material_id) {
  return gm_register_builtin(domain, &gm_perzyna_model, def, material_id);
}
