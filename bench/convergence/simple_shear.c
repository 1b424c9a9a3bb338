/*
 * simple_shear.c - one Mohr-Coulomb point (psi = 0, no rate term) driven
 * through gm_mohr_coulomb_update in plane-strain simple shear at constant
 * volume from an isotropic 1 kPa: prints the steady stress ratio on the shear
 * plane, tau_xy / -sigma_yy, against sin(phi) and tan(phi)
 * (docs/convergence.md, section 10). No Jaumann spin: the material update
 * alone. Build and run from the worktree after `make`:
 *   gcc -std=c11 -Iinclude bench/convergence/simple_shear.c \
 *     -Lbuild/lib/.libs -lgranmpm -lm -o simple_shear
 *   LD_LIBRARY_PATH=build/lib/.libs ./simple_shear 35
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
int main(int argc, char **argv) {
  double phi_deg = argc > 1 ? atof(argv[1]) : 35.0;
  gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
  def.youngs_modulus = 5e5;
  def.poisson_ratio = 0.3;
  def.density = 1800;
  def.friction_angle = phi_deg * 3.14159265358979 / 180.0;
  def.dilation_angle = 0;
  def.bagnold_viscosity = 0;
  double inc[6] = {0}, s[6] = {-1000, -1000, -1000, 0, 0, 0}, rho = 1800;
  int64_t id = 0;
  gm_material_batch b = {0};
  b.struct_size = sizeof b;
  b.count = 1;
  b.geometry = GM_GEOMETRY_PLANE_STRAIN;
  b.dt = 1e-4;
  for (int c = 0; c < 6; c++) {
    b.strain_increment[c] = &inc[c];
    b.stress[c] = &s[c];
  }
  b.density = &rho;
  b.point_id = &id;
  double st0 = 0, st1 = 0, st2 = 0, st3 = 0;
  double *const states[4] = {&st0, &st1, &st2, &st3};
  b.state = states;
  b.state_count = 4;
  inc[GM_XY] = 0.5e-4; /* tensor shear strain per step: gamma = 1e-4 */
  char msg[256];
  for (int k = 0; k < 20000; k++)
    if (gm_mohr_coulomb_update(&b, &def, msg, sizeof msg) != 0) {
      puts(msg);
      return 1;
    }
  printf("phi %.1f: tau/sigma_n on the shear plane %.4f, sin phi %.4f, tan phi "
         "%.4f "
         "(sxx %.1f syy %.1f szz %.1f sxy %.1f)\n",
         phi_deg, s[GM_XY] / -s[GM_YY], sin(def.friction_angle),
         tan(def.friction_angle), s[0], s[1], s[2], s[3]);
  return 0;
}
