/*
 * collapse_material.h - the Drucker-Prager cone of the collapse scenes'
 * Perzyna material, matched to a Mohr-Coulomb friction angle: one home for
 * the planar/axisymmetric and 3D examples and the convergence probes
 * (bench/convergence/collapse_scene.c), so that every run of "the
 * recommended setting" builds the same material.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_EXAMPLES_COLLAPSE_MATERIAL_H
#define GM_EXAMPLES_COLLAPSE_MATERIAL_H

#include <math.h>

/* The friction angle (rad) of the Drucker-Prager cone with psi = 0 that
 * flows in plane strain at the friction of Mohr-Coulomb phi (rad) with
 * psi = 0. Once the elastic strain rate vanishes, g = q makes s_zz = 0, so
 * the cone q = m p reads R = (m / sqrt 3) p on Mohr's circle (R its radius,
 * p its centre), and Mohr-Coulomb flows at R = sin(phi) p
 * (docs/convergence.md sec. 10). So m = sqrt(3) sin(phi), and with
 * m = 18 s / (9 - s^2) (include/granmpm/drucker_prager.h) s = sin(phi_dp)
 * is the positive root of m s^2 + 18 s - 9 m = 0. phi = 37 deg: m = 1.0424.
 * In axisymmetry and 3D the same cone is kept (one material for every
 * geometry; there it is not matched to Mohr-Coulomb's flow). A phi that is
 * not positive is returned as it is, for gm_domain_add_perzyna to name. */
static inline double collapse_matched_cone_friction(double phi) {
  if (!(phi > 0.0))
    return phi;
  double slope = sqrt(3.0) * sin(phi);
  return asin((-18.0 + sqrt(324.0 + 36.0 * slope * slope)) / (2.0 * slope));
}

#endif
