/*
 * granmpm/mohr_coulomb.h - built-in Mohr-Coulomb material with the Bagnold
 * rate term and a non-associated flow rule (000 sec 4.2, eqs 16-17).
 * Included from the end of granmpm.h; do not include it directly.
 *
 * Conventions: stress in Pa, TENSION POSITIVE, Voigt order GM_XX..GM_ZX
 * (all six components, also in plane strain and axisymmetry, where zz is
 * the out-of-plane / hoop stress and plasticity sees the full 3D stress).
 * Principal stresses are sorted sigma_1 >= sigma_2 >= sigma_3 (sigma_3 the
 * most compressive). Pressure p = -(s_xx + s_yy + s_zz)/3 (compression
 * positive), deviator s = sigma + p I, q = sqrt(3/2 s:s).
 *
 * Yield function, eq 16 of 000 rewritten for tension-positive stress (the
 * paper's sigma_1 is the most compressive stress, compression positive):
 *   f = (sigma_1 - sigma_3) + (sigma_1 + sigma_3) sin(phi)
 *       - 2 eta gammadot^2 cos(phi)
 * Plastic potential, eq 17: the same with the dilation angle psi and no rate
 * term. eta gammadot^2 acts as a rate-dependent cohesion (Pa); gammadot
 * (1/s) is the shear rate sqrt(2 d':d') of the step's deviatoric rate of
 * deformation d' = dev(strain_increment)/dt, which equals the rate of
 * simple shear dv_x/dy in simple shear. Triaxial compression (c = 0) gives
 * the plateau q/p = 6 sin(phi) / (3 - sin(phi)).
 *
 * Per-point state: GM_MOHR_COULOMB_PLASTIC_SHEAR_STRAIN, the accumulated
 * plastic shear strain, sum of sqrt(2 de_p:de_p) over the steps (de_p the
 * deviatoric plastic strain increment; same measure as gammadot dt).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GRANMPM_MOHR_COULOMB_H
#define GRANMPM_MOHR_COULOMB_H

#ifdef __cplusplus
extern "C" {
#endif

/** Index of the state variables in gm_material_batch.state. */
enum {
  GM_MOHR_COULOMB_PLASTIC_SHEAR_STRAIN = 0, /* -, accumulated */
  GM_MOHR_COULOMB_STATE_COUNT = 1
};

typedef struct gm_mohr_coulomb_def {
  size_t struct_size;
  const char *name;         /* copied; for messages and VTU */
  double youngs_modulus;    /* E, Pa, > 0 */
  double poisson_ratio;     /* nu, -1 < nu < 0.5 */
  double density;           /* kg/m^3, > 0 */
  double friction_angle;    /* phi, rad, 0 < phi < pi/2 */
  double dilation_angle;    /* psi, rad, 0 <= psi <= friction_angle */
  double bagnold_viscosity; /* eta, Pa s^2, >= 0 (0: rate independent) */
} gm_mohr_coulomb_def;

/** Defaults: the granular material of 000 Table 3 (E = 1 GPa, nu = 0.3,
 * phi = 30 deg, psi = 0, eta = 0.15, taken as Pa s^2, rho = 2250 kg/m^3). */
/** gm_mohr_coulomb_def_init(&d, sizeof d) writes these defaults (gm_*_init
 * convention, granmpm.h); gm_mohr_coulomb_def_default() returns them. */
GM_API gm_status gm_mohr_coulomb_def_init(gm_mohr_coulomb_def *out,
                                          size_t struct_size);

static inline gm_mohr_coulomb_def gm_mohr_coulomb_def_default(void) {
  gm_mohr_coulomb_def value;
  (void)gm_mohr_coulomb_def_init(&value, sizeof value);
  return value;
}

/** Registers the built-in Mohr-Coulomb material (the domain keeps a copy of
 * def); GM_ERR_INVALID_ARGUMENT names the offending field. */
GM_API gm_status gm_domain_add_mohr_coulomb(gm_domain *domain,
                                            const gm_mohr_coulomb_def *def,
                                            int *material_id);

/** The update itself, for users composing materials: `user` must point to a
 * valid gm_mohr_coulomb_def; the batch needs state_count >= 1 (state[0] is
 * the plastic shear strain). Returns 0, or < 0 (fatal, message names the
 * point or the cause) for a non-finite trial stress or a missing state. */
GM_API int gm_mohr_coulomb_update(const gm_material_batch *batch, void *user,
                                  char *message, size_t message_size);

#ifdef __cplusplus
}
#endif

#endif /* GRANMPM_MOHR_COULOMB_H */
