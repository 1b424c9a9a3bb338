/*
 * mu_i.c - built-in mu(I) material: Jop, Forterre & Pouliquen (2006) in the
 * elasto-viscoplastic form of Dunatunga & Kamrin (2015, sec 3), with the
 * low-I regularisation of Barker & Gray (2017). Conventions, parameters and
 * the equations are in include/granmpm/mu_i.h.
 *
 * The return works with the friction x = tau / p (-) of the returned stress:
 * with k = G dt sqrt(p / rho_s) / (d p) (-), the backward-Euler equation
 *   h(x) = x_tr - x - k I(x) = 0,     x_tr = tau_tr / p,
 * has h decreasing (I(x) is nondecreasing), h(0) = x_tr > 0 and
 * h(min(x_tr, mu_2)) < 0 once the material flows, so its root is unique and
 * bracketed. On Jop's branch (x >= mu_s, or x >= mu(I_1^N) when
 * regularised) I(x) = I_0 (x - mu_s) / (mu_2 - x) and h = 0 is the
 * quadratic
 *   x^2 - (x_tr + mu_2 + b) x + (x_tr mu_2 + b mu_s) = 0,   b = k I_0,
 * whose smaller root is taken in the cancellation-free form 2c/(B + sqrt).
 * On the regularised branch I(x) = A exp(-alpha / x^2) and the root is found
 * by Newton's method, falling back to bisection when a step leaves the
 * bracket.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "granmpm/mu_i.h"
#include "materials/invariants.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char DEF_NAME[] = "gm_mu_i_def";

/* Iterations of the safeguarded Newton solve: each bisection halves the
 * bracket, so 200 reach round-off from any start. */
#define MU_I_MAX_ITERATIONS 200

/* Friction of Jop's curve at inertial number I (-). */
static double jop_friction(const gm_mu_i_def *def, double inertial) {
  return def->static_friction +
         (def->limit_friction - def->static_friction) /
             (def->inertial_number_scale / inertial + 1.0);
}

/* Barker & Gray (2017) eq 3.9 for Jop's curve: with c = I mu'(I) / mu(I),
 *   C(I) = 4 c^2 - 4 c + mu^2 (1 - c/2)^2,
 * the equations are well posed where C < 0. C(0) = mu_s^2 > 0: Jop's curve
 * is ill posed as I -> 0. */
static double jop_posedness(const gm_mu_i_def *def, double inertial) {
  double mu = jop_friction(def, inertial);
  double i0 = def->inertial_number_scale;
  double slope = i0 * (def->limit_friction - def->static_friction) /
                 ((i0 + inertial) * (i0 + inertial)); /* mu'(I) */
  double c = inertial * slope / mu;
  return 4.0 * c * c - 4.0 * c + mu * mu * (1.0 - 0.5 * c) * (1.0 - 0.5 * c);
}

/* The regularised low-I branch of one parameter set. */
typedef struct mu_i_branch {
  double inertial;  /* I_1^N, -: below it the regularised curve is used */
  double friction;  /* mu(I_1^N), - */
  double amplitude; /* A = I_1^N exp(alpha / mu(I_1^N)^2), - */
} mu_i_branch;

/* Finds I_1^N, the smallest I with C(I) = 0: scans I = 1e-12 .. 1e3 by
 * factors of 2 for the first C <= 0, then bisects. Returns 0, or -1 if C
 * stays positive (Jop's curve is nowhere well posed). */
static int mu_i_find_branch(const gm_mu_i_def *def, mu_i_branch *branch) {
  double lower = 1e-12, upper = 0.0;
  if (!(jop_posedness(def, lower) > 0.0))
    return -1;
  for (double inertial = 2e-12; inertial < 1e3; inertial *= 2.0) {
    if (jop_posedness(def, inertial) <= 0.0) {
      upper = inertial;
      break;
    }
    lower = inertial;
  }
  if (upper == 0.0)
    return -1;
  for (int iteration = 0; iteration < 200 && upper - lower > 1e-15 * upper;
       iteration++) {
    double middle = 0.5 * (lower + upper);
    if (jop_posedness(def, middle) > 0.0)
      lower = middle;
    else
      upper = middle;
  }
  branch->inertial = upper; /* C(upper) <= 0: well posed from here up */
  branch->friction = jop_friction(def, upper);
  branch->amplitude = upper * exp(def->regularisation_exponent /
                                  (branch->friction * branch->friction));
  return 0;
}

/* Root of x_tr - x - k A exp(-alpha/x^2) = 0 on (0, upper), upper <= x_tr,
 * with h(upper) < 0 <= h(0). Newton safeguarded by bisection. */
static double regularised_root(double trial, double k, double amplitude,
                               double alpha, double upper) {
  double lower = 0.0;
  double x = upper;
  for (int iteration = 0; iteration < MU_I_MAX_ITERATIONS; iteration++) {
    double rate = amplitude * exp(-alpha / (x * x)); /* I(x) */
    double residual = trial - x - k * rate;
    if (residual > 0.0)
      lower = x;
    else if (residual < 0.0)
      upper = x;
    else
      return x;
    /* h'(x) = -1 - k I(x) 2 alpha / x^3 < 0. */
    double slope = -1.0 - k * rate * 2.0 * alpha / (x * x * x);
    double next = x - residual / slope;
    if (!(next > lower && next < upper))
      next = 0.5 * (lower + upper);
    if (fabs(next - x) <= 1e-15 * next || upper - lower <= 1e-15 * upper)
      return next;
    x = next;
  }
  return x;
}

/* Smaller root of the quadratic of the Jop branch (file comment). */
static double jop_root(const gm_mu_i_def *def, double trial, double b) {
  double mu_s = def->static_friction, mu_2 = def->limit_friction;
  double linear = trial + mu_2 + b;
  double constant = trial * mu_2 + b * mu_s;
  /* The discriminant is positive when trial > mu_s (see the header); the
   * fmax only guards round-off. */
  double root = sqrt(fmax(linear * linear - 4.0 * constant, 0.0));
  return 2.0 * constant / (linear + root);
}

/* Inverse of the friction law, I(x), with the branch if regularised. */
static double mu_i_inertial(const gm_mu_i_def *def, const mu_i_branch *branch,
                            double x) {
  if (branch && x < branch->friction)
    return branch->amplitude * exp(-def->regularisation_exponent / (x * x));
  if (x <= def->static_friction)
    return 0.0;
  return def->inertial_number_scale * (x - def->static_friction) /
         (def->limit_friction - x);
}

/* Constants of one update call. */
typedef struct mu_i_constants {
  const gm_mu_i_def *def;
  const mu_i_branch *branch; /* NULL when not regularised */
  double shear;              /* G, Pa */
  double dt;                 /* s */
} mu_i_constants;

/* Returns the friction x = tau/p (-) of the returned stress for a trial
 * friction `trial` > 0 and k of the file comment. */
static double mu_i_return(const mu_i_constants *k, double trial,
                          double stiffness) {
  const gm_mu_i_def *def = k->def;
  if (!k->branch) {
    if (trial <= def->static_friction)
      return trial; /* elastic */
    return jop_root(def, trial, stiffness * def->inertial_number_scale);
  }
  const mu_i_branch *branch = k->branch;
  if (trial > branch->friction &&
      trial - branch->friction - stiffness * branch->inertial >= 0.0)
    return jop_root(def, trial, stiffness * def->inertial_number_scale);
  double upper = fmin(trial, branch->friction);
  if (stiffness == 0.0)
    return trial;
  return regularised_root(trial, stiffness, branch->amplitude,
                          def->regularisation_exponent, upper);
}

/* Updates point i after the elastic trial; returns 0 or -1 (not finite). */
static int mu_i_update_point(const gm_material_batch *batch,
                             const mu_i_constants *k, size_t i, double *strain,
                             double *inertial) {
  const gm_mu_i_def *def = k->def;
  gm_stress_split trial = gm_split_stress(batch->stress, i);
  double tau_trial = trial.equivalent / sqrt(3.0); /* sqrt(s:s/2), Pa */
  *strain = 0.0;
  *inertial = 0.0;
  if (!isfinite(tau_trial) || !isfinite(trial.pressure))
    return -1;
  double density = batch->density ? batch->density[i] : def->density;
  if (density < def->critical_density || !(trial.pressure > 0.0)) {
    /* Disconnected (Dunatunga & Kamrin) or in tension: stress-free. */
    for (int c = 0; c < 6; c++)
      batch->stress[c][i] = 0.0;
    *strain = tau_trial / k->shear;
    return 0;
  }
  if (tau_trial == 0.0)
    return 0;
  double pressure = trial.pressure; /* Pa */
  /* k = G dt sqrt(p/rho_s) / (d p) = G dt / (d sqrt(rho_s p)), - */
  double stiffness =
      k->shear * k->dt /
      (def->grain_diameter * sqrt(def->grain_density * pressure));
  double x_trial = tau_trial / pressure;
  double x = mu_i_return(k, x_trial, stiffness);
  if (x == x_trial)
    return 0; /* elastic: the trial is kept bit for bit */
  gm_write_scaled_deviator(batch->stress, i, &trial, x / x_trial);
  *strain = (x_trial - x) * pressure / k->shear; /* gammadot_p dt */
  *inertial = mu_i_inertial(def, k->branch, x);
  return 0;
}

int gm_mu_i_update(const gm_material_batch *batch, void *user, char *message,
                   size_t message_size) {
  const gm_mu_i_def *def = user;
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.name = NULL;
  elastic.youngs_modulus = def->youngs_modulus;
  elastic.poisson_ratio = def->poisson_ratio;
  elastic.density = def->density;
  int result = gm_elastic_update(batch, &elastic, message, message_size);
  if (result != 0)
    return result;
  mu_i_branch branch;
  mu_i_constants k;
  k.def = def;
  k.branch = NULL;
  if (def->regularise) {
    /* Validated at registration; a composing user may pass anything. */
    if (mu_i_find_branch(def, &branch) != 0) {
      snprintf(message, message_size,
               "mu_i: Jop's curve has no well-posed range to regularise");
      return -1;
    }
    k.branch = &branch;
  }
  k.shear = gm_shear_modulus(def->youngs_modulus, def->poisson_ratio);
  k.dt = batch->dt;
  bool has_state =
      batch->state != NULL && batch->state_count >= GM_MU_I_STATE_COUNT;
  for (size_t i = 0; i < batch->count; i++) {
    double strain, inertial;
    if (mu_i_update_point(batch, &k, i, &strain, &inertial) != 0) {
      snprintf(message, message_size,
               "mu_i: point %lld: non-finite trial stress",
               batch->point_id ? (long long)batch->point_id[i] : (long long)i);
      return -1;
    }
    if (has_state) {
      batch->state[GM_MU_I_PLASTIC_STRAIN][i] += strain;
      batch->state[GM_MU_I_INERTIAL_NUMBER][i] = inertial;
    }
  }
  return 0;
}

/* Checks the fields beyond the call itself; sets the error. */
static gm_status mu_i_check(gm_domain *domain, const void *parameters) {
  const gm_mu_i_def *def = parameters;
  gm_status status = gm_check_elastic_constants(
      domain, DEF_NAME, def->youngs_modulus, def->poisson_ratio);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "density", def->density,
                               "kg/m^3", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "grain_density",
                               def->grain_density, "kg/m^3", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "grain_diameter",
                               def->grain_diameter, "m", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "static_friction",
                               def->static_friction, "(-)", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "inertial_number_scale",
                               def->inertial_number_scale, "(-)", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, DEF_NAME, "critical_density",
                               def->critical_density, "kg/m^3", true);
  if (status != GM_OK)
    return status;
  if (!(def->limit_friction > def->static_friction) ||
      !isfinite(def->limit_friction))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.limit_friction is %g, must be finite and above "
                        "static_friction (%g)",
                        DEF_NAME, def->limit_friction, def->static_friction);
  if (!def->regularise)
    return GM_OK;
  double alpha = def->regularisation_exponent;
  if (!(alpha > 0.0 && alpha < 2.0))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.regularisation_exponent is %g, must be in (0, 2) "
                        "(the regularised curve is ill posed as I -> 0 "
                        "otherwise)",
                        DEF_NAME, alpha);
  mu_i_branch branch;
  if (mu_i_find_branch(def, &branch) != 0)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: mu_s %g, mu_2 %g, I_0 %g give a curve that is ill "
                        "posed at every I: nothing to regularise (set "
                        "regularise = 0)",
                        DEF_NAME, def->static_friction, def->limit_friction,
                        def->inertial_number_scale);
  return GM_OK;
}

/* The viscoplastic return only softens: the elastic K + 4G/3 bounds the
 * wave speed, and backward Euler adds no limit of its own. */
static double mu_i_p_wave_modulus(const void *parameters) {
  const gm_mu_i_def *def = parameters;
  return gm_p_wave_modulus(def->youngs_modulus, def->poisson_ratio);
}

/* The doubles up to critical_density are compared as bytes; regularise
 * (an int followed by padding) and the exponent are recorded as numbers by
 * the checkpoint (io/checkpoint.c). */
const gm_builtin_model gm_mu_i_model = {
    .caller = "gm_domain_add_mu_i",
    .layout = GM_LAYOUT_MU_I_DEF,
    .default_name = "mu_i",
    .update = gm_mu_i_update,
    .state_count = GM_MU_I_STATE_COUNT, /* no plastic strain, I = 0 */
    .check = mu_i_check,
    .p_wave_modulus = mu_i_p_wave_modulus,
    .density_offset = offsetof(gm_mu_i_def, density),
    .record_end = GM_FIELD_END(gm_mu_i_def, critical_density),
};

gm_status gm_domain_add_mu_i(gm_domain *domain, const gm_mu_i_def *def,
                             int *material_id) {
  return gm_register_builtin(domain, &gm_mu_i_model, def, material_id);
}
