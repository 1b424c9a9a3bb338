/*
 * thin_slide.c - a layer of thickness t, 0.15 m long, launched at 1 m/s
 * along a Coulomb floor wall of friction mu under gravity, for
 * docs/convergence.md section 17: a rigid slider stops after
 * v0^2 / (2 mu g), whatever its thickness, so the ratio printed (centre of
 * mass travel over that) tells whether a layer thinner than a cell feels
 * the wall's whole friction. tests/physics/test_friction.c asserts it for
 * linear and B-spline2 shapes.
 *
 * usage: thin_slide CELL THICKNESS MU PPC SHAPE [MATERIAL [FLOOR_Y]]
 *   CELL, THICKNESS, FLOOR_Y in m (FLOOR_Y: the wall's height above the
 *   box face, default 0); SHAPE linear|ugimp|bspline2; MATERIAL elastic
 *   (E 20 MPa, the test's, default) | mc (Mohr-Coulomb phi 37, E 0.5 MPa)
 *   | granular (the same in the granular family)
 * Build and run from the worktree after `make`:
 *   gcc -std=c11 -O2 -Iinclude bench/convergence/thin_slide.c \
 *     -Lbuild/lib/.libs -lgranmpm -lm -o thin_slide
 *   LD_LIBRARY_PATH=build/lib/.libs ./thin_slide 0.015 0.0075 0.4 2 ugimp
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81; /* m/s^2 */

static int fail(gm_domain *domain, const char *what) {
  fprintf(stderr, "%s: %s\n", what,
          domain ? gm_domain_last_error(domain) : gm_last_create_error());
  return 1;
}

int main(int argc, char **argv) {
  if (argc < 6) {
    fprintf(stderr,
            "usage: %s CELL THICKNESS MU PPC SHAPE "
            "[elastic|mc|granular [FLOOR_Y]]\n",
            argv[0]);
    return 2;
  }
  double cell = atof(argv[1]), thickness = atof(argv[2]); /* m */
  double mu = atof(argv[3]);
  int ppc = atoi(argv[4]);
  const char *shape = argv[5];
  const char *material = argc > 6 ? argv[6] : "elastic";
  double floor_y = argc > 7 ? atof(argv[7]) : 0.0; /* m */
  if (!(cell > 0.0) || !(thickness > 0.0) || !(mu > 0.0) || ppc < 1 ||
      !(floor_y >= 0.0)) {
    fprintf(stderr, "CELL, THICKNESS and MU must be > 0, PPC >= 1, "
                    "FLOOR_Y >= 0\n");
    return 2;
  }
  const double speed = 1.0, length = 0.15; /* m/s, m */
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = cell;
  def.extent[0] = 0.6;
  def.extent[1] = floor_y + thickness + 0.1;
  def.gravity[1] = -GRAVITY;
  def.shape = strcmp(shape, "bspline2") == 0 ? GM_SHAPE_BSPLINE2
              : strcmp(shape, "linear") == 0 ? GM_SHAPE_LINEAR
                                             : GM_SHAPE_UGIMP;
  int granular = strcmp(material, "granular") == 0;
  def.family = granular ? GM_FAMILY_GRANULAR : GM_FAMILY_PLAIN;
  gm_domain *domain = NULL;
  if (gm_domain_create(&def, &domain) != GM_OK)
    return fail(NULL, "gm_domain_create");
  int id = -1;
  if (granular || strcmp(material, "mc") == 0) {
    gm_mohr_coulomb_def mc = gm_mohr_coulomb_def_default();
    mc.youngs_modulus = 5e5; /* Pa, the column collapse's */
    mc.poisson_ratio = 0.3;
    mc.density = 1800.0; /* kg/m^3 */
    mc.friction_angle = 37.0 * PI / 180.0;
    mc.dilation_angle = 0.0;
    mc.bagnold_viscosity = 0.0;
    if (gm_domain_add_mohr_coulomb(domain, &mc, &id) != GM_OK)
      return fail(domain, "gm_domain_add_mohr_coulomb");
    if (granular) {
      gm_granular_def settings = gm_granular_def_default();
      settings.critical_density = 0.98 * mc.density;
      if (gm_domain_set_granular(domain, id, &settings) != GM_OK)
        return fail(domain, "gm_domain_set_granular");
    }
  } else {
    gm_elastic_def elastic = gm_elastic_def_default();
    elastic.youngs_modulus = 2e7; /* Pa, tests/physics/test_friction.c's */
    elastic.poisson_ratio = 0.3;
    elastic.density = 2000.0; /* kg/m^3 */
    if (gm_domain_add_elastic(domain, &elastic, &id) != GM_OK)
      return fail(domain, "gm_domain_add_elastic");
  }
  gm_wall_def wall = gm_wall_def_default();
  wall.point[1] = floor_y;
  wall.friction_static = wall.friction_kinetic = mu;
  int wall_id = -1;
  if (gm_domain_add_wall(domain, &wall, &wall_id) != GM_OK)
    return fail(domain, "gm_domain_add_wall");
  gm_fill_def fill = gm_fill_def_default();
  fill.points_per_cell_axis = ppc;
  fill.material = id;
  fill.lower[0] = 0.05;
  fill.upper[0] = 0.05 + length;
  fill.lower[1] = floor_y;
  fill.upper[1] = floor_y + thickness;
  fill.velocity[0] = speed;
  if (gm_domain_fill_box(domain, &fill, NULL, NULL) != GM_OK)
    return fail(domain, "gm_domain_fill_box");
  gm_summary summary = gm_summary_default();
  gm_domain_get_summary(domain, &summary);
  double start = summary.centre_of_mass[0];  /* m */
  double stop_time = speed / (mu * GRAVITY); /* s */
  double expected = speed * stop_time / 2.0; /* m, v0^2 / (2 mu g) */
  if (gm_domain_advance(domain, 1.6 * stop_time, 0.0, NULL, NULL) != GM_OK)
    return fail(domain, "gm_domain_advance");
  gm_domain_get_summary(domain, &summary);
  printf("RESULT cell=%g thickness_cells=%.3g ppc=%d shape=%s material=%s "
         "floor_y=%g points=%zu travel_over_rigid=%.4f kinetic_J=%.3g\n",
         cell, thickness / cell, ppc, shape, material, floor_y,
         gm_domain_point_count(domain),
         (summary.centre_of_mass[0] - start) / expected,
         summary.kinetic_energy);
  gm_domain_destroy(domain);
  return 0;
}
