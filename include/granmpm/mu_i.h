/*
 * granmpm/mu_i.h - built-in mu(I) material: the local rheology of Jop,
 * Forterre & Pouliquen (2006, Nature 441:727) in the elasto-viscoplastic
 * form of Dunatunga & Kamrin (2015, JFM 779:483, sec 3), with the partial
 * regularisation of the low-I branch by Barker & Gray (2017, JFM 828:5).
 *
 * Stress in Pa, tension positive; p = -(s_xx + s_yy + s_zz)/3 (pressure,
 * compression positive), s = sigma + p I, and the equivalent shear stress
 *   tau = sqrt(s:s / 2)        (= |sigma_xy| in simple shear),
 * the full 3D stress in every geometry. The inertial number of a plastic
 * shear rate gammadot_p = sqrt(2 D_p:D_p) (1/s, = du/dy in simple shear) is
 *   I = gammadot_p d / sqrt(p / rho_s),
 * d the grain diameter (m), rho_s the density of the grains (kg/m^3, not
 * the bulk density of the packing). The friction law (Jop et al. 2006):
 *   mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1),     tau = mu(I) p.
 *
 * Update of one point (Dunatunga & Kamrin 2015 sec 3): the elastic trial
 * sigma_tr = sigma_t + C : D dt (Jaumann-rotated sigma_t, gm_elastic_update),
 * then
 *   - stress-free (sigma = 0) if the point's density is below
 *     critical_density (the disconnected state of their model) or the
 *     trial pressure is p_tr <= 0 (cohesionless: no mean tension);
 *   - otherwise the plastic shear rate gammadot_p, deviatoric and along s_tr
 *     (no plastic volume change), solves the backward-Euler equation
 *       tau = tau_tr - G dt gammadot_p,  gammadot_p = I(tau/p) sqrt(p/rho_s)/d
 *     with I(mu) the inverse of the friction law, and s = s_tr tau / tau_tr
 *     while p = p_tr. Without regularisation I(mu) = 0 for mu <= mu_s (the
 *     point stays exactly elastic) and I_0 (mu - mu_s)/(mu_2 - mu) above:
 *     the equation is a quadratic in tau, solved in closed form.
 *
 * Regularisation (Barker & Gray 2017): the equations are ill posed for I
 * below I_1^N, the smallest I at which the growth-rate condition (their
 * eq 3.9) changes sign for Jop's curve. There mu(I) is replaced by
 *   mu(I) = sqrt(alpha / ln(A / I)),   A = I_1^N exp(alpha / mu(I_1^N)^2),
 * continuous at I_1^N (their eq 6.4 for A); mu -> 0 as I -> 0, so there is
 * no yield stress: below mu_s the material creeps at I = A exp(-alpha/mu^2).
 * For the defaults I_1^N = 0.0194, mu(I_1^N) = 0.3988, A = 2980, so at
 * mu = 0.3 I = 2.0e-6: a 20 mm layer of 0.5 mm grains on a slope of
 * tan = 0.3 creeps at 2e-5 m/s at its surface (1.2 m/s at tan = 0.466). The
 * curve is well posed as I -> 0 only for alpha < 2 (their alpha = 1.9). The
 * high-I ill-posedness is not removed (Barker & Gray show no choice of
 * mu(I) alone can remove it). The equation for tau is then solved by a
 * Newton iteration safeguarded by bisection on the bracket (0, tau_tr).
 *
 * Time step: the viscoplastic correction is backward Euler, so it adds no
 * stability limit; the stable dt is the elastic one, cell / sqrt(M / rho)
 * with M = K + 4G/3 of youngs_modulus and poisson_ratio. Choose E so that
 * the elastic strains rho g h / M stay small (say <= 1 %) but not larger:
 * dt scales as 1/sqrt(E).
 *
 * Included from the end of granmpm.h; also works included on its own.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GRANMPM_MU_I_H
#define GRANMPM_MU_I_H

#include "../granmpm.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Per-point state of the mu(I) material (batch->state[k]). */
enum {
  /* Accumulated plastic shear strain (-): the sum of gammadot_p dt =
   * (tau_tr - tau) / G over the steps (tau_tr / G at a stress-free one). */
  GM_MU_I_PLASTIC_STRAIN = 0,
  /* Inertial number I (-) of the last update: gammadot_p d / sqrt(p/rho_s),
   * 0 when elastic or stress-free. */
  GM_MU_I_INERTIAL_NUMBER = 1,
  GM_MU_I_STATE_COUNT = 2
};

typedef struct gm_mu_i_def {
  size_t struct_size;             /* set by gm_mu_i_def_default() */
  const char *name;               /* copied; for messages and VTU */
  double youngs_modulus;          /* E, Pa, finite > 0 (elastic part) */
  double poisson_ratio;           /* nu, -, in (-1, 0.5) */
  double density;                 /* bulk density of new points, kg/m^3, > 0 */
  double grain_density;           /* rho_s, kg/m^3, > 0 (in I) */
  double grain_diameter;          /* d, m, > 0 (in I) */
  double static_friction;         /* mu_s, > 0 */
  double limit_friction;          /* mu_2, > mu_s */
  double inertial_number_scale;   /* I_0, -, > 0 */
  double critical_density;        /* kg/m^3, >= 0: stress-free below it
                                     (Dunatunga & Kamrin's rho_c); 0 = no
                                     density criterion */
  int regularise;                 /* nonzero (default): Barker & Gray low-I
                                     branch; 0: Jop's curve with a yield
                                     stress mu_s p */
  double regularisation_exponent; /* alpha, in (0, 2); default 1.9 */
} gm_mu_i_def;

/* Defaults: the glass beads of Jop, Forterre & Pouliquen (2006):
 * mu_s = tan 20.9 deg, mu_2 = tan 32.76 deg, I_0 = 0.279, d = 0.5 mm;
 * grain density 2500 kg/m^3 (glass), bulk density 1500 kg/m^3 (solid
 * fraction 0.6), no density criterion, E = 1 MPa and nu = 0.3 (the
 * elastic part is a numerical stiffness, see above), regularised with
 * alpha = 1.9 (Barker & Gray 2017). gm_*_init convention (granmpm.h):
 * gm_mu_i_def_init(&d, sizeof d) writes them, gm_mu_i_def_default()
 * returns them. */
GM_API gm_status gm_mu_i_def_init(gm_mu_i_def *out, size_t struct_size);

static inline gm_mu_i_def gm_mu_i_def_default(void) {
  gm_mu_i_def value;
  (void)gm_mu_i_def_init(&value, sizeof value);
  return value;
}

/** Registers a mu(I) material (GM_MU_I_STATE_COUNT state values per point,
 * initially 0). Invalid parameters give GM_ERR_INVALID_ARGUMENT with a
 * message naming the field; with regularise set, also parameters for which
 * Jop's curve has no well-posed range (no I_1^N). */
GM_API gm_status gm_domain_add_mu_i(gm_domain *domain, const gm_mu_i_def *def,
                                    int *material_id);

/** The update itself, for users composing materials: `user` must point to a
 * valid gm_mu_i_def (as gm_domain_add_mu_i accepts). Elastic trial stress
 * (gm_elastic_update), then the return above; the state is written when
 * batch->state_count >= GM_MU_I_STATE_COUNT. Returns 0, or -1 for a
 * non-finite trial stress (message names the point). */
GM_API int gm_mu_i_update(const gm_material_batch *batch, void *user,
                          char *message, size_t message_size);

#ifdef __cplusplus
}
#endif

#endif /* GRANMPM_MU_I_H */
