/*
 * invariants.h - stress invariants shared by the built-in plastic models
 * (Drucker-Prager, von Mises). Private to the library.
 *
 * Conventions (002 sec 2.2), stress in Pa, TENSION POSITIVE, Voigt order
 * GM_XX, GM_YY, GM_ZZ, GM_XY, GM_YZ, GM_ZX (all six, also in 2D):
 *   p = -(s_xx + s_yy + s_zz) / 3       pressure, compression positive
 *   s = sigma + p I                     deviator
 *   q = sqrt(3/2 s:s)                   equivalent (von Mises) stress,
 * where s:s counts each shear component twice (s_xy = s_yx).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_MATERIALS_INVARIANTS_H
#define GM_MATERIALS_INVARIANTS_H

#include "granmpm.h"

#include <math.h>
#include <stddef.h>

/* Stress of point i of a batch split into pressure (Pa) and deviator (Pa). */
typedef struct gm_stress_split {
  double pressure;    /* p, compression positive */
  double deviator[6]; /* s, Voigt order */
  double equivalent;  /* q = sqrt(3/2 s:s) */
} gm_stress_split;

static inline gm_stress_split gm_split_stress(double *const stress[6],
                                              size_t i) {
  gm_stress_split split;
  split.pressure =
      -(stress[GM_XX][i] + stress[GM_YY][i] + stress[GM_ZZ][i]) / 3.0;
  for (int c = 0; c < 3; c++)
    split.deviator[c] = stress[c][i] + split.pressure;
  for (int c = 3; c < 6; c++)
    split.deviator[c] = stress[c][i];
  const double *s = split.deviator;
  double normal = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
  double shear = s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
  split.equivalent = sqrt(1.5 * (normal + 2.0 * shear));
  return split;
}

/* Writes sigma = scale * s - p I into point i: a radial return of the
 * deviator that keeps the pressure (deviatoric plastic flow). */
static inline void gm_write_scaled_deviator(double *const stress[6], size_t i,
                                            const gm_stress_split *split,
                                            double scale) {
  for (int c = 0; c < 3; c++)
    stress[c][i] = scale * split->deviator[c] - split->pressure;
  for (int c = 3; c < 6; c++)
    stress[c][i] = scale * split->deviator[c];
}

/* Elastic shear modulus G (Pa) from E (Pa) and nu, as in elastic.c. */
static inline double gm_shear_modulus(double youngs_modulus,
                                      double poisson_ratio) {
  return youngs_modulus / (2.0 * (1.0 + poisson_ratio));
}

/* Constrained (P-wave) modulus K + 4G/3 = E(1-nu)/((1+nu)(1-2nu)), Pa: the
 * wave speed of the stable time step. */
static inline double gm_p_wave_modulus(double youngs_modulus,
                                       double poisson_ratio) {
  return youngs_modulus * (1.0 - poisson_ratio) /
         ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
}

#endif /* GM_MATERIALS_INVARIANTS_H */
