/*
 * test_cpdi_reset.c - the reset of over-distorted CPDI domains
 * (lib/points/cpdi_reset.c):
 *  - gm_cpdi_domain_reset on given domain maps: a map whose singular
 *    values differ by more than GM_CPDI_MAX_DISTORTION becomes
 *    sqrt(det D) I (same area, no distortion); one within the bound is
 *    left bitwise alone; an inverted one is left for the step to refuse;
 *  - a free block sheared far beyond the bound (through the public API):
 *    every domain stays a parallelogram of area det F x initial area and
 *    distortion at most the bound, domains are reset along the way, and
 *    the total mass and momentum stay what they were, to round-off, across
 *    every step (resets included): a reset changes the interpolation
 *    domain only.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "points/points.h"
#include "test_util.h"

#include <check.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Ratio of the singular values of the 2x2 matrix (a b; c d). */
static double distortion(double a, double b, double c, double d) {
  double norm_squared = a * a + b * b + c * c + d * d;
  double determinant = fabs(a * d - b * c);
  double q = norm_squared / (2.0 * determinant); /* (rho + 1/rho) / 2 */
  return q + sqrt(fmax(q * q - 1.0, 0.0));
}

/* Maps far beyond the bound are reset to sqrt(det) I; those within are
 * untouched. det is compared to 1e-15 relative: one sqrt and one square
 * of rounding. */
START_TEST(test_reset_of_given_maps) {
  static const double distorted[][4] = {
      {1.0, 5.0, 0.0, 1.0},   /* simple shear 5: ratio 26 */
      {2.0, 0.0, 0.0, 0.5},   /* stretch: ratio 4 */
      {0.3, 1.4, -0.4, 0.9}}; /* general, ratio 3.34 */
  for (size_t m = 0; m < sizeof distorted / sizeof distorted[0]; m++) {
    double map[4];
    memcpy(map, distorted[m], sizeof map);
    double before = map[0] * map[3] - map[1] * map[2];
    ck_assert_double_gt(distortion(map[0], map[1], map[2], map[3]),
                        GM_CPDI_MAX_DISTORTION);
    ck_assert(gm_cpdi_domain_reset(map, GM_CPDI_MAX_DISTORTION));
    double after = map[0] * map[3] - map[1] * map[2];
    ck_assert_msg(fabs(after - before) <= 1e-15 * before,
                  "map %zu: det %.17g after the reset, %.17g before", m, after,
                  before);
    ck_assert(map[1] == 0.0 && map[2] == 0.0 && map[0] == map[3]);
  }
  static const double kept[][4] = {
      {1.0, 1.0, 0.0, 1.0},   /* shear 1: ratio 2.62 */
      {1.7, 0.0, 0.0, 0.6},   /* ratio 2.83 */
      {-1.0, 0.0, 0.0, -2.0}, /* rotated by pi, ratio 2 */
      {1.0, 0.0, 0.0, -5.0}}; /* inverted: the step refuses it */
  for (size_t m = 0; m < sizeof kept / sizeof kept[0]; m++) {
    double map[4];
    memcpy(map, kept[m], sizeof map);
    ck_assert(!gm_cpdi_domain_reset(map, GM_CPDI_MAX_DISTORTION));
    ck_assert(memcmp(map, kept[m], sizeof map) == 0);
  }
}
END_TEST

/* A field of every point, in point-index order (caller frees). */
static double *get_field(const gm_domain *domain, gm_field field,
                         size_t *components) {
  TEST_ASSERT_OK(domain, gm_domain_field_components(domain, field, components));
  size_t length = gm_domain_point_count(domain) * *components;
  double *values = malloc((length + 1) * sizeof *values);
  ck_assert_ptr_nonnull(values);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, field, values, length));
  return values;
}

/* Total mass (kg per unit thickness) and momentum (kg m/s), and the sum
 * of |m v| that sets the scale of their rounding. */
static void totals(const gm_domain *domain, double *mass, double momentum[2],
                   double *scale) {
  size_t count = gm_domain_point_count(domain), nm, nv;
  double *m = get_field(domain, GM_FIELD_MASS, &nm);
  double *v = get_field(domain, GM_FIELD_VELOCITY, &nv);
  *mass = *scale = momentum[0] = momentum[1] = 0.0;
  for (size_t i = 0; i < count; i++) {
    *mass += m[i];
    for (int k = 0; k < 2; k++) {
      momentum[k] += m[i] * v[i * nv + k];
      *scale += fabs(m[i] * v[i * nv + k]);
    }
  }
  free(m);
  free(v);
}

/* Box 2 m x 2 m, open faces, no gravity, cells 0.05 m; a block 0.6 m x
 * 0.4 m of a very soft elastic solid (E = 10 Pa: shear wave speed 0.06
 * m/s, so the block barely resists) with 2 x 2 points per cell, given the
 * simple shear v_x = 0.05 + 2 (y - 1) m/s, v_y = 0.02 m/s: the points
 * move nearly ballistically, F -> (1 2t; 0 1), and the distortion of F
 * passes GM_CPDI_MAX_DISTORTION = 3 at t ~ 0.58 s. The uniform part makes
 * the total momentum non-zero, so that its conservation is not 0 = 0. */
static gm_domain *create_sheared_block(void) {
  gm_domain_def def = gm_domain_def_default();
  def.shape = GM_SHAPE_CPDI;
  def.extent[0] = def.extent[1] = 2.0; /* m */
  def.cell_size = 0.05;                /* m */
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 10.0, 0.3, 1000.0);
  const double lower[3] = {0.7, 0.8, 0.0}, upper[3] = {1.3, 1.2, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  size_t count = gm_domain_point_count(domain);
  const double *y = NULL;
  double *vx = NULL, *vy = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &vx));
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 1, &vy));
  for (size_t i = 0; i < count; i++) {
    vx[i] = 0.05 + 2.0 * (y[i] - 1.0); /* m/s */
    vy[i] = 0.02;                      /* m/s */
  }
  return domain;
}

/* Shoelace area (m^2) of 4 corners (x, y interleaved). */
static double polygon_area(const double corner[8]) {
  double area = 0.0;
  for (int c = 1; c + 1 < 4; c++) {
    double ax = corner[2 * c] - corner[0], ay = corner[2 * c + 1] - corner[1];
    double bx = corner[2 * c + 2] - corner[0];
    double by = corner[2 * c + 3] - corner[1];
    area += 0.5 * (ax * by - ay * bx);
  }
  return area;
}

/* Per step: every domain's area is det F x its initial area (1e-9
 * relative: D and F take the same increments and a reset keeps det D, so
 * they part only by rounding, ~1e-16 per step over ~500 steps) and its
 * distortion (edge vectors r1 = (c1 - c0)/2, r2 = (c3 - c0)/2 of square
 * initial domains) at most the bound (1e-9 slack for the rounding of the
 * corners); a domain that is an axis-aligned square while F is distorted
 * beyond the bound was reset. Mass and momentum: equal before and after
 * each step to 1e-13 of sum |m v| (the transfers sum ~400 points' terms,
 * each rounded to 1e-16 relative; a momentum error of a reset would be of
 * the order of the velocity differences across a domain, 0.1 m/s in 0.3
 * m/s, i.e. 1e-1 relative). */
START_TEST(test_sheared_block_resets_conserving) {
  gm_domain *domain = create_sheared_block();
  size_t count = gm_domain_point_count(domain);
  double mass0, momentum0[2], scale0;
  totals(domain, &mass0, momentum0, &scale0);
  int resets_seen = 0, steps = 0;
  double time = 0.0, max_f_distortion = 0.0;
  while (time < 0.9) { /* F_xy ~ 1.8: distortion ~ 5.8 */
    double mass_before, before[2], scale;
    totals(domain, &mass_before, before, &scale);
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &time, NULL));
    steps++;
    double mass_after, after[2], unused;
    totals(domain, &mass_after, after, &unused);
    ck_assert_msg(mass_after == mass_before, "mass %.17g -> %.17g kg",
                  mass_before, mass_after);
    for (int k = 0; k < 2; k++)
      ck_assert_msg(fabs(after[k] - before[k]) <= 1e-13 * scale,
                    "step %d: momentum %d %.17g -> %.17g kg m/s", steps, k,
                    before[k], after[k]);
    size_t nc, nf, ns;
    double *corners = get_field(domain, GM_FIELD_DOMAIN_CORNERS, &nc);
    double *f = get_field(domain, GM_FIELD_DEFORMATION_GRADIENT, &nf);
    double *size = get_field(domain, GM_FIELD_DOMAIN_SIZE, &ns);
    for (size_t i = 0; i < count; i++) {
      const double *c = corners + i * nc, *fi = f + i * nf;
      double initial_area = size[i * ns] * size[i * ns + 1];
      double jacobian = fi[0] * fi[4] - fi[1] * fi[3];
      double area = polygon_area(c);
      ck_assert_msg(fabs(area - jacobian * initial_area) <=
                        1e-9 * jacobian * initial_area,
                    "step %d point %zu: area %.17g m^2, det F A0 %.17g", steps,
                    i, area, jacobian * initial_area);
      double r1[2] = {0.5 * (c[2] - c[0]), 0.5 * (c[3] - c[1])};
      double r2[2] = {0.5 * (c[6] - c[0]), 0.5 * (c[7] - c[1])};
      double domain_distortion = distortion(r1[0], r2[0], r1[1], r2[1]);
      ck_assert_msg(domain_distortion <= GM_CPDI_MAX_DISTORTION * (1.0 + 1e-9),
                    "step %d point %zu: domain distortion %.6g", steps, i,
                    domain_distortion);
      double f_distortion = distortion(fi[0], fi[1], fi[3], fi[4]);
      max_f_distortion = fmax(max_f_distortion, f_distortion);
      bool square =
          r1[1] == 0.0 && r2[0] == 0.0 && fabs(r1[0] - r2[1]) <= 1e-12 * r1[0];
      if (square && f_distortion > GM_CPDI_MAX_DISTORTION)
        resets_seen++;
    }
    free(corners);
    free(f);
    free(size);
  }
  printf("sheared block: %d steps, F distortion up to %.3g, %d domains "
         "seen just reset\n",
         steps, max_f_distortion, resets_seen);
  ck_assert_double_gt(max_f_distortion, 1.5 * GM_CPDI_MAX_DISTORTION);
  ck_assert_int_gt(resets_seen, 0);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *cpdi_reset_suite(void) {
  Suite *suite = suite_create("cpdi_reset");
  TCase *tcase = tcase_create("reset");
  tcase_set_timeout(tcase, 120);
  tcase_add_test(tcase, test_reset_of_given_maps);
  tcase_add_test(tcase, test_sheared_block_resets_conserving);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(cpdi_reset_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
