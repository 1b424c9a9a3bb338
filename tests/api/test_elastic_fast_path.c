/*
 * test_elastic_fast_path.c - the deformation pass of linear elastic plane
 * points has a fused fast path (lib/grid/deform_elastic.c: F, V, the
 * Jaumann rotation and Hooke's law in one chunk pass) taken when a chunk's
 * material is the built-in elastic one. It promises the general path's
 * arithmetic bit for bit. The general path is forced here by registering
 * the same law as a user material whose callback calls gm_elastic_update
 * itself: the two domains must then agree in every bit of every field,
 * in the failures they report, and in what a failed step leaves behind.
 *
 * Scenes (plane strain, linear shapes, h = 0.01 m, 2 x 2 points per cell):
 * a block spinning at 20 rad/s on a slip floor under gravity (Jaumann spin
 * and large rotations), with USL, MUSL and FLIP blended with PIC, and with
 * uGIMP and quadratic B-splines instead of linear shapes; two
 * elastic materials side by side, whose shared chunks mix materials; and
 * a block thrown at 10 m/s into a fixed floor with a dt that inverts F
 * (the step fails, or with retries halves dt and succeeds).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include <check.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CELL 0.01 /* m */

/* The general path: the same law through a user callback. */
static int wrapped_elastic(const gm_material_batch *batch, void *user,
                           char *message, size_t message_size) {
  return gm_elastic_update(batch, user, message, message_size);
}

typedef struct scene {
  gm_update_scheme scheme;
  double pic_fraction;   /* - */
  double spin;           /* rad/s about the block's centre */
  double throw_velocity; /* m/s along -y */
  bool two_materials;
  gm_wall_type floor;
  int max_retries;
  gm_shape shape;
} scene;

static const gm_elastic_def *elastic_law(int which) {
  static gm_elastic_def laws[2];
  for (int k = 0; k < 2; k++) {
    laws[k] = gm_elastic_def_default();
    laws[k].youngs_modulus = k == 0 ? 1e6 : 4e6; /* Pa */
    laws[k].poisson_ratio = k == 0 ? 0.3 : 0.25;
    laws[k].density = 1800.0; /* kg/m^3 */
  }
  return &laws[which];
}

static int add_law(gm_domain *domain, int which, bool builtin) {
  const gm_elastic_def *law = elastic_law(which);
  int id = -1;
  if (builtin) {
    TEST_ASSERT_OK(domain, gm_domain_add_elastic(domain, law, &id));
    return id;
  }
  double young = law->youngs_modulus, nu = law->poisson_ratio;
  gm_material_def def = gm_material_def_default();
  def.name = "wrapped elastic";
  def.update = wrapped_elastic;
  def.user = (void *)law;
  def.p_wave_modulus = young * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
  def.density = law->density;
  TEST_ASSERT_OK(domain, gm_domain_add_material(domain, &def, &id));
  return id;
}

static gm_domain *make_domain(const scene *s, bool builtin) {
  gm_domain_def def = gm_domain_def_default();
  def.extent[0] = 0.4;
  def.extent[1] = 0.4;
  def.cell_size = CELL;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_YMIN] = s->floor;
  def.scheme = s->scheme;
  def.pic_fraction = s->pic_fraction;
  def.max_retries = s->max_retries;
  def.shape = s->shape;
  gm_domain *domain = NULL;
  TEST_ASSERT_OK(NULL, gm_domain_create(&def, &domain));
  int first = add_law(domain, 0, builtin);
  int second = s->two_materials ? add_law(domain, 1, builtin) : first;
  gm_fill_def fill = gm_fill_def_default();
  fill.points_per_cell_axis = 2;
  fill.lower[1] = 0.0;
  fill.upper[1] = 0.15;
  fill.velocity[1] = -s->throw_velocity;
  /* Two boxes sharing the edge x = 0.155 (not a block boundary): the
   * chunks around it hold points of both materials. */
  fill.material = first;
  fill.lower[0] = 0.05;
  fill.upper[0] = 0.155;
  int64_t first_id = 0;
  size_t count = 0;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, &first_id, &count));
  fill.material = second;
  fill.lower[0] = 0.155;
  fill.upper[0] = 0.25;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, &first_id, &count));
  if (s->spin != 0.0) { /* v = omega x (x - c) about the block's centre */
    size_t n = gm_domain_point_count(domain);
    double *x = malloc(2 * n * sizeof *x), *v = malloc(2 * n * sizeof *v);
    TEST_ASSERT_OK(domain,
                   gm_domain_get_field(domain, GM_FIELD_POSITION, x, 2 * n));
    for (size_t p = 0; p < n; p++) {
      v[2 * p] = -s->spin * (x[2 * p + 1] - 0.075);
      v[2 * p + 1] = s->spin * (x[2 * p] - 0.15) - s->throw_velocity;
    }
    TEST_ASSERT_OK(domain,
                   gm_domain_set_field(domain, GM_FIELD_VELOCITY, v, 2 * n));
    free(x);
    free(v);
  }
  return domain;
}

/* Every field of the two domains, bit for bit. */
static void assert_same_state(gm_domain *a, gm_domain *b, const char *what) {
  static const gm_field fields[] = {GM_FIELD_POSITION,
                                    GM_FIELD_VELOCITY,
                                    GM_FIELD_VOLUME,
                                    GM_FIELD_STRESS,
                                    GM_FIELD_DEFORMATION_GRADIENT,
                                    GM_FIELD_ID};
  size_t n = gm_domain_point_count(a);
  ck_assert_uint_eq(n, gm_domain_point_count(b));
  for (size_t f = 0; f < sizeof fields / sizeof fields[0]; f++) {
    size_t components = 0;
    TEST_ASSERT_OK(a, gm_domain_field_components(a, fields[f], &components));
    size_t length = n * components;
    double *x = malloc(length * sizeof *x), *y = malloc(length * sizeof *y);
    TEST_ASSERT_OK(a, gm_domain_get_field(a, fields[f], x, length));
    TEST_ASSERT_OK(b, gm_domain_get_field(b, fields[f], y, length));
    size_t differ = 0;
    for (size_t i = 0; i < length; i++)
      differ += memcmp(&x[i], &y[i], sizeof x[i]) != 0;
    ck_assert_msg(differ == 0,
                  "%s: field %d differs in %zu of %zu values between the "
                  "fused and the general elastic path",
                  what, (int)fields[f], differ, length);
    free(x);
    free(y);
  }
}

static double fixed_dt(void) { /* s, half the CFL bound of the stiffer law */
  const gm_elastic_def *law = elastic_law(1);
  double nu = law->poisson_ratio;
  double modulus = law->youngs_modulus * (1.0 - nu) /
                   ((1.0 + nu) * (1.0 - 2.0 * nu)); /* Pa */
  return 0.5 * CELL / sqrt(modulus / law->density);
}

static void run_pair(const scene *s, int steps, const char *what) {
  gm_domain *fused = make_domain(s, true);
  gm_domain *general = make_domain(s, false);
  double dt = fixed_dt();
  for (int step = 0; step < steps; step++) {
    TEST_ASSERT_OK(fused, gm_domain_step(fused, dt));
    TEST_ASSERT_OK(general, gm_domain_step(general, dt));
  }
  assert_same_state(fused, general, what);
  gm_domain_destroy(fused);
  gm_domain_destroy(general);
}

START_TEST(spinning_block_usl) {
  scene s = {GM_SCHEME_USL, 0.0,          20.0, 0.0,
             false,         GM_WALL_SLIP, 3,    GM_SHAPE_LINEAR};
  run_pair(&s, 300, "spinning block, USL");
}
END_TEST

START_TEST(spinning_block_musl_pic) {
  scene s = {GM_SCHEME_MUSL, 0.2,          20.0, 0.0,
             false,          GM_WALL_SLIP, 3,    GM_SHAPE_LINEAR};
  run_pair(&s, 300, "spinning block, MUSL, PIC 0.2");
}
END_TEST

/* The fast path starts from the gathered gradient, whatever the shape:
 * GIMP's and the B-splines' deformation passes take it too. */
START_TEST(spinning_block_ugimp) {
  scene s = {GM_SCHEME_USL, 0.0,          20.0, 0.0,
             false,         GM_WALL_SLIP, 3,    GM_SHAPE_UGIMP};
  run_pair(&s, 200, "spinning block, uGIMP");
}
END_TEST

START_TEST(spinning_block_bspline2) {
  scene s = {GM_SCHEME_USL, 0.0,          20.0, 0.0,
             false,         GM_WALL_SLIP, 3,    GM_SHAPE_BSPLINE2};
  run_pair(&s, 200, "spinning block, quadratic B-splines");
}
END_TEST

START_TEST(two_materials_mixed_chunks) {
  scene s = {GM_SCHEME_USL, 0.0,          5.0, 0.0,
             true,          GM_WALL_SLIP, 3,   GM_SHAPE_LINEAR};
  run_pair(&s, 300, "two elastic materials");
}
END_TEST

/* A block at 10 m/s into a fixed floor, stepped at 10x the fixed dt: F
 * inverts at the impact. Without retries both paths fail the same step
 * with the same status and message and leave the committed state as it
 * was; with retries both halve dt the same way and agree afterwards. */
static void impact(int max_retries) {
  scene s = {GM_SCHEME_USL, 0.0,           0.0,         10.0,
             false,         GM_WALL_FIXED, max_retries, GM_SHAPE_LINEAR};
  gm_domain *fused = make_domain(&s, true);
  gm_domain *general = make_domain(&s, false);
  double dt = 10.0 * fixed_dt();
  bool failed = false;
  for (int step = 0; step < 4 && !failed; step++) {
    gm_status a = gm_domain_step(fused, dt);
    gm_status b = gm_domain_step(general, dt);
    ck_assert_int_eq(a, b);
    if (a != GM_OK) {
      failed = true;
      ck_assert_int_eq(a, GM_ERR_NOT_FINITE);
      ck_assert_str_eq(gm_domain_last_error(fused),
                       gm_domain_last_error(general));
      ck_assert_ptr_nonnull(strstr(gm_domain_last_error(fused), "det F"));
    }
    assert_same_state(fused, general, "impact");
  }
  /* Measured: without retries the second step inverts F (det F = -0.08 at
   * one point); with 8 halvings allowed all four steps succeed (a fifth
   * would throw a point out of the grid). */
  ck_assert_msg(failed == (max_retries == 0), "impact with max_retries %d: %s",
                max_retries, failed ? "a step failed" : "no step failed");
  gm_domain_destroy(fused);
  gm_domain_destroy(general);
}

START_TEST(impact_fails_alike) {
  impact(0);
}
END_TEST

START_TEST(impact_retries_alike) {
  impact(8);
}
END_TEST

static Suite *suite(void) {
  Suite *s = suite_create("elastic_fast_path");
  TCase *tc = tcase_create("bitwise");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, spinning_block_usl);
  tcase_add_test(tc, spinning_block_musl_pic);
  tcase_add_test(tc, spinning_block_ugimp);
  tcase_add_test(tc, spinning_block_bspline2);
  tcase_add_test(tc, two_materials_mixed_chunks);
  tcase_add_test(tc, impact_fails_alike);
  tcase_add_test(tc, impact_retries_alike);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  return test_run_suite(suite()) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
