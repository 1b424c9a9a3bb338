/*
 * granmpm/von_mises.h - built-in von Mises (Huber-von Mises) material:
 * elastic - perfectly plastic with associated (deviatoric) flow, for the
 * plastic forming examples of Wieckowski 2004 (001 sec 5.3).
 *
 * Stress in Pa, tension positive; p = -(s_xx + s_yy + s_zz)/3, s = sigma +
 * p I, q = sqrt(3/2 s:s) (shear terms counted twice in s:s); the full 3D
 * stress is used in every geometry.
 *
 *   yield surface  f = q - yield_stress
 *   return map     sigma = (yield_stress / q_e) s_e - p_e I  if f(sigma_e) > 0
 *
 * (radial return of the elastic trial deviator; the pressure is elastic).
 *
 * Included from the end of granmpm.h; also works included on its own.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GRANMPM_VON_MISES_H
#define GRANMPM_VON_MISES_H

#include "../granmpm.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Per-point state of the von Mises material (batch->state[k]). */
enum {
  /* Accumulated equivalent plastic strain (-), sum of
   * sqrt(2/3 de_p:de_p) = (q_e - yield_stress) / (3 G) over the returns. */
  GM_VON_MISES_PLASTIC_STRAIN = 0,
  GM_VON_MISES_STATE_COUNT = 1
};

typedef struct gm_von_mises_def {
  size_t struct_size;    /* set by gm_von_mises_def_default() */
  const char *name;      /* copied; for messages and VTU */
  double youngs_modulus; /* Pa, finite > 0 */
  double poisson_ratio;  /* -, in (-1, 0.5) */
  double density;        /* kg/m^3, finite > 0: default for new points */
  double yield_stress;   /* sigma_y, Pa, finite > 0: uniaxial yield stress */
} gm_von_mises_def;

/* Defaults: the steel of the extrusion example of Wieckowski 2004 (001 sec
 * 5.3.1): E = 2e5 MPa, nu = 0.3, sigma_0 = 20 MPa, density 7800 kg/m^3. */
/** gm_von_mises_def_init(&d, sizeof d) writes these defaults (gm_*_init
 * convention, granmpm.h); gm_von_mises_def_default() returns them. */
GM_API gm_status gm_von_mises_def_init(gm_von_mises_def *out,
                                       size_t struct_size);

static inline gm_von_mises_def gm_von_mises_def_default(void) {
  gm_von_mises_def value;
  (void)gm_von_mises_def_init(&value, sizeof value);
  return value;
}

/** Registers a von Mises material (GM_VON_MISES_STATE_COUNT state values
 * per point, initially 0). Invalid parameters give GM_ERR_INVALID_ARGUMENT
 * with a message naming the field. */
GM_API gm_status gm_domain_add_von_mises(gm_domain *domain,
                                         const gm_von_mises_def *def,
                                         int *material_id);

/** The update itself, for users composing materials: `user` must point to a
 * gm_von_mises_def. Elastic trial stress (gm_elastic_update), then the
 * radial return. The plastic strain is accumulated in
 * batch->state[GM_VON_MISES_PLASTIC_STRAIN] when batch->state_count >= 1.
 * Always returns 0; a non-finite trial stress is passed through unchanged
 * (the library reports it). */
GM_API int gm_von_mises_update(const gm_material_batch *batch, void *user,
                               char *message, size_t message_size);

#ifdef __cplusplus
}
#endif

#endif /* GRANMPM_VON_MISES_H */
