/*
 * granmpm/stress_free.h - built-in stress-free material: every update sets
 * the stress to zero whatever the strain increment. The granular
 * algorithms of Seyedan & Solowski 2021 (000) treat disconnected points
 * (density below critical) this way; it also models debris that only
 * carries mass.
 *
 * The library still needs a wave speed for the stable time step: set
 * p_wave_modulus to the constrained modulus K + 4G/3 the material will have
 * when it reconnects (e.g. E(1-nu)/((1+nu)(1-2nu)) of the granular model it
 * switches to), so dt stays valid across the switch.
 *
 * Included from the end of granmpm.h; also works included on its own.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GRANMPM_STRESS_FREE_H
#define GRANMPM_STRESS_FREE_H

#include "../granmpm.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gm_stress_free_def {
  size_t struct_size;    /* set by gm_stress_free_def_default() */
  const char *name;      /* copied; for messages and VTU */
  double density;        /* kg/m^3, finite > 0: default for new points */
  double p_wave_modulus; /* Pa, finite > 0: K + 4G/3 used only for the
                            stable time step (see above) */
} gm_stress_free_def;

/* Defaults: density 1500 kg/m^3 and p_wave_modulus 1.35e6 Pa, the
 * constrained modulus of the default gm_drucker_prager_def (E = 1 MPa,
 * nu = 0.3). */
/** gm_stress_free_def_init(&d, sizeof d) writes these defaults (gm_*_init
 * convention, granmpm.h); gm_stress_free_def_default() returns them. */
GM_API gm_status gm_stress_free_def_init(gm_stress_free_def *out,
                                         size_t struct_size);

static inline gm_stress_free_def gm_stress_free_def_default(void) {
  gm_stress_free_def value;
  (void)gm_stress_free_def_init(&value, sizeof value);
  return value;
}

/** Registers a stress-free material (no state). Invalid parameters give
 * GM_ERR_INVALID_ARGUMENT with a message naming the field. */
GM_API gm_status gm_domain_add_stress_free(gm_domain *domain,
                                           const gm_stress_free_def *def,
                                           int *material_id);

/** The update itself: sets all six stress components of every point to 0.
 * `user` is not read (may be NULL). Always returns 0. */
GM_API int gm_stress_free_update(const gm_material_batch *batch, void *user,
                                 char *message, size_t message_size);

#ifdef __cplusplus
}
#endif

#endif /* GRANMPM_STRESS_FREE_H */
