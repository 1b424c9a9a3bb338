/*
 * jaumann.c - the objective stress increment of one step for a general 3D
 * motion: the Jaumann rotation sigma + (W sigma - sigma W) dt and the
 * strain increment D dt, from the velocity gradient L (002 sec 4.1, 004
 * eqs 3.20-3.21: L = D + W, D = (L + L^T)/2, W = (L - L^T)/2). A material
 * then integrates its law over D dt from the rotated stress, and never sees
 * a rigid rotation.
 *
 * The domain's 1D/2D stress update (grid/stress_update.c) writes the same
 * arithmetic for its one spin component W_xy; with W_yz = W_zx = 0 and
 * yz = zx = 0 the formulas below reduce to it bit for bit (every extra
 * term is an exact zero), so a 3D stress update built on this function
 * agrees with the plane one on plane states.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

/* Row-major indices of L_ij = dv_i/dx_j. */
enum { L_XX, L_XY, L_XZ, L_YX, L_YY, L_YZ, L_ZX, L_ZY, L_ZZ };

void gm_jaumann_rotate(const double velocity_gradient[9], double dt,
                       double stress[6]) {
  const double *l = velocity_gradient;
  /* Spin increments W_xy dt, W_yz dt, W_zx dt (rad); W is antisymmetric. */
  double a = 0.5 * (l[L_XY] - l[L_YX]) * dt;
  double b = 0.5 * (l[L_YZ] - l[L_ZY]) * dt;
  double c = 0.5 * (l[L_ZX] - l[L_XZ]) * dt;
  double xx = stress[GM_XX], yy = stress[GM_YY], zz = stress[GM_ZZ];
  double xy = stress[GM_XY], yz = stress[GM_YZ], zx = stress[GM_ZX];
  /* W sigma - sigma W = M + M^T with M = W sigma (sigma W = -(W sigma)^T
   * for W antisymmetric and sigma symmetric), written out per component. */
  stress[GM_XX] = xx + 2.0 * (a * xy - c * zx);
  stress[GM_YY] = yy - 2.0 * (a * xy - b * yz);
  stress[GM_ZZ] = zz + 2.0 * (c * zx - b * yz);
  stress[GM_XY] = xy + (a * (yy - xx) + (b * zx - c * yz));
  stress[GM_YZ] = yz + (b * (zz - yy) + (c * xy - a * zx));
  stress[GM_ZX] = zx + (c * (xx - zz) + (a * yz - b * xy));
}

void gm_strain_increment(const double velocity_gradient[9], double dt,
                         double increment[6]) {
  const double *l = velocity_gradient;
  increment[GM_XX] = l[L_XX] * dt;
  increment[GM_YY] = l[L_YY] * dt;
  increment[GM_ZZ] = l[L_ZZ] * dt;
  /* Tensor shear components, D_ij = (L_ij + L_ji)/2. */
  increment[GM_XY] = 0.5 * (l[L_XY] + l[L_YX]) * dt;
  increment[GM_YZ] = 0.5 * (l[L_YZ] + l[L_ZY]) * dt;
  increment[GM_ZX] = 0.5 * (l[L_ZX] + l[L_XZ]) * dt;
}
