/*
 * granmpm/drucker_prager.h - built-in Drucker-Prager material: elastic -
 * perfectly plastic, cohesionless, non-associated and plastically
 * incompressible (Wieckowski, Youn & Yeon 1999, sec 2.2 and 4.1).
 *
 * Stress in Pa, tension positive; p = -(s_xx + s_yy + s_zz)/3 (pressure,
 * compression positive), s = sigma + p I, q = sqrt(3/2 s:s) (shear terms
 * counted twice in s:s). Plasticity always uses the full 3D stress (in plane
 * strain s_zz is sigma_zz, in axisymmetry the hoop stress).
 *
 *   yield surface      f = q - m p,   m = 18 sin(phi) / (9 - sin^2(phi))
 *   plastic potential  g = q          (no plastic volume change, psi = 0)
 *
 * m is the mean of the Mohr-Coulomb matches in triaxial compression,
 * 6 sin(phi)/(3 - sin(phi)), and extension, 6 sin(phi)/(3 + sin(phi)).
 * The material has no cohesion, as in the three source papers: it carries
 * no tension, and a trial stress outside the surface with p <= 0 returns to
 * the apex sigma = 0 (the point has separated). A cohesion field may be
 * appended to the def later (struct_size keeps that compatible).
 *
 * Included from the end of granmpm.h; also works included on its own.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GRANMPM_DRUCKER_PRAGER_H
#define GRANMPM_DRUCKER_PRAGER_H

#include "../granmpm.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Per-point state of the Drucker-Prager material (batch->state[k]). */
enum {
  /* Accumulated equivalent plastic strain (-), sum of
   * sqrt(2/3 de_p:de_p) = (q_trial - q) / (3 G) over the plastic returns;
   * at the apex return the deviatoric part q_trial / (3 G) is added. */
  GM_DRUCKER_PRAGER_PLASTIC_STRAIN = 0,
  GM_DRUCKER_PRAGER_STATE_COUNT = 1
};

typedef struct gm_drucker_prager_def {
  size_t struct_size;    /* set by gm_drucker_prager_def_default() */
  const char *name;      /* copied; for messages and VTU */
  double youngs_modulus; /* Pa, finite > 0 */
  double poisson_ratio;  /* -, in (-1, 0.5) */
  double density;        /* kg/m^3, finite > 0: default for new points */
  double friction_angle; /* phi, radians, in (0, pi/2) exclusive */
} gm_drucker_prager_def;

/* Defaults: the stored granular material of Wieckowski 2004 (001 sec 5.1.1):
 * E = 1 MPa, nu = 0.3, phi = 25 degrees, density 1500 kg/m^3. */
/** gm_drucker_prager_def_init(&d, sizeof d) writes these defaults (gm_*_init
 * convention, granmpm.h); gm_drucker_prager_def_default() returns them. */
GM_API gm_status gm_drucker_prager_def_init(gm_drucker_prager_def *out,
                                            size_t struct_size);

static inline gm_drucker_prager_def gm_drucker_prager_def_default(void) {
  gm_drucker_prager_def value;
  (void)gm_drucker_prager_def_init(&value, sizeof value);
  return value;
}

/** Registers a Drucker-Prager material (GM_DRUCKER_PRAGER_STATE_COUNT state
 * values per point, initially 0). Invalid parameters give
 * GM_ERR_INVALID_ARGUMENT with a message naming the field. */
GM_API gm_status gm_domain_add_drucker_prager(gm_domain *domain,
                                              const gm_drucker_prager_def *def,
                                              int *material_id);

/** The update itself, for users composing materials: `user` must point to a
 * gm_drucker_prager_def. Elastic trial stress (gm_elastic_update), then the
 * return map of 002 sec 4.1. The plastic strain is accumulated in
 * batch->state[GM_DRUCKER_PRAGER_PLASTIC_STRAIN] when batch->state_count >= 1.
 * Always returns 0; a non-finite trial stress is passed through unchanged
 * (the library reports it). */
GM_API int gm_drucker_prager_update(const gm_material_batch *batch, void *user,
                                    char *message, size_t message_size);

#ifdef __cplusplus
}
#endif

#endif /* GRANMPM_DRUCKER_PRAGER_H */
