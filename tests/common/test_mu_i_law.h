/*
 * test_mu_i_law.h - the mu(I) friction law recomputed independently of the
 * library, for tests/unit/test_mu_i.c and tests/physics/test_bagnold.c:
 * Jop, Forterre & Pouliquen's (2006) curve and Barker & Gray's (2017)
 * eq 3.9 well-posedness function for it.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_TEST_MU_I_LAW_H
#define GM_TEST_MU_I_LAW_H

#include "granmpm/mu_i.h"

/* Jop's curve: mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1) (-). */
static inline double jop_mu(const gm_mu_i_def *def, double inertial) {
  return def->static_friction +
         (def->limit_friction - def->static_friction) /
             (def->inertial_number_scale / inertial + 1.0);
}

/* Barker & Gray (2017) eq 3.9 for Jop's curve: well posed where < 0. */
static inline double posedness(const gm_mu_i_def *def, double inertial) {
  double i0 = def->inertial_number_scale;
  double mu = jop_mu(def, inertial);
  double c = inertial * i0 * (def->limit_friction - def->static_friction) /
             ((i0 + inertial) * (i0 + inertial) * mu);
  return 4.0 * c * c - 4.0 * c + mu * mu * (1.0 - c / 2.0) * (1.0 - c / 2.0);
}

/* I_1^N, the lowest I where Jop's curve is well posed (posedness < 0),
 * by bisection on [1e-9, I_0] to round-off (-). */
static inline double posedness_onset(const gm_mu_i_def *def) {
  double lower = 1e-9, upper = def->inertial_number_scale;
  for (int k = 0; k < 200; k++) {
    double middle = 0.5 * (lower + upper);
    if (posedness(def, middle) > 0.0)
      lower = middle;
    else
      upper = middle;
  }
  return upper;
}

#endif /* GM_TEST_MU_I_LAW_H */
