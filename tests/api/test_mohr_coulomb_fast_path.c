/*
 * test_mohr_coulomb_fast_path.c - the deformation pass of Mohr-Coulomb
 * plane points has a fused fast path (lib/grid/deform_mohr_coulomb.c: F,
 * V, the Jaumann rotation and the elastic predictor in chunk loops, then
 * the material's screen and closed-form plane return) taken when a
 * chunk's material is the built-in Mohr-Coulomb model without the rate
 * term. It promises the general path's arithmetic bit for bit. The general
 * path is forced here by registering the same law as a user material whose
 * callback calls gm_mohr_coulomb_update itself (one state variable, the
 * plastic shear strain): the two domains must then agree in every bit of
 * every field, and in the failures they report. (The plastic shear strain
 * itself is not readable through the API; the stress it comes with is.)
 *
 * Scenes (plane strain, h = 0.01 m, 2 x 2 points per cell, E = 1 MPa,
 * phi = 30 degrees): a column of sand collapsing against a slip wall on a
 * slip floor (about half its point updates return, a quarter of those to
 * the apex at the free surface), with USL, MUSL blended with PIC, a
 * dilation angle, uGIMP and CPDI; a block spinning at 10 rad/s (the
 * Jaumann spin under plasticity); Mohr-Coulomb beside an elastic block,
 * whose shared chunks mix materials (general path in both domains); and a
 * column squeezed so fast that F inverts; and a column of E = 1e308 Pa
 * stretched until its elastic trial stress overflows (the fused pass hands
 * that chunk to the general stress update, which reports it).
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
#define PI   3.14159265358979323846

/* The general path: the same law through a user callback. */
static int wrapped_mohr_coulomb(const gm_material_batch *batch, void *user,
                                char *message, size_t message_size) {
  return gm_mohr_coulomb_update(batch, user, message, message_size);
}

typedef struct scene {
  gm_update_scheme scheme;
  double pic_fraction; /* - */
  double spin;         /* rad/s about the block's centre */
  double squeeze;      /* 1/s: v_x = -squeeze (x - x_c) */
  double dilation;     /* rad */
  bool with_elastic;   /* an elastic block beside the column */
  gm_wall_type floor;
  gm_shape shape;
  double young; /* Pa, 0: 1 MPa */
} scene;

static gm_mohr_coulomb_def sand(double dilation, double young) {
  gm_mohr_coulomb_def law = gm_mohr_coulomb_def_default();
  law.youngs_modulus = young > 0.0 ? young : 1e6; /* Pa */
  law.poisson_ratio = 0.3;                        /* - */
  law.density = 1800.0;                           /* kg/m^3 */
  law.friction_angle = 30.0 * PI / 180.0;         /* rad */
  law.dilation_angle = dilation;                  /* rad */
  law.bagnold_viscosity = 0.0; /* Pa s^2: the fast path's case */
  return law;
}

static double p_wave_modulus(double young, double nu) { /* Pa */
  return young * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

static int add_sand(gm_domain *domain, const gm_mohr_coulomb_def *law,
                    bool builtin) {
  int id = -1;
  if (builtin) {
    TEST_ASSERT_OK(domain, gm_domain_add_mohr_coulomb(domain, law, &id));
    return id;
  }
  gm_material_def def = gm_material_def_default();
  def.name = "mohr_coulomb"; /* the built-in one's: messages compare equal */
  def.update = wrapped_mohr_coulomb;
  def.user = (void *)law;
  def.state_count = GM_MOHR_COULOMB_STATE_COUNT;
  def.p_wave_modulus = p_wave_modulus(law->youngs_modulus, law->poisson_ratio);
  def.density = law->density;
  TEST_ASSERT_OK(domain, gm_domain_add_material(domain, &def, &id));
  return id;
}

/* The two laws of the pair live as long as the domains (user pointer). */
static gm_mohr_coulomb_def laws[2];

static gm_domain *make_domain(const scene *s, bool builtin) {
  gm_domain_def def = gm_domain_def_default();
  def.extent[0] = 0.4;
  def.extent[1] = 0.4;
  def.cell_size = CELL;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_YMIN] = s->floor;
  def.walls[GM_FACE_XMIN] = GM_WALL_SLIP;
  def.scheme = s->scheme;
  def.pic_fraction = s->pic_fraction;
  def.shape = s->shape;
  def.max_retries = 0; /* a failed step fails: no halved dt */
  gm_domain *domain = NULL;
  TEST_ASSERT_OK(NULL, gm_domain_create(&def, &domain));
  laws[builtin] = sand(s->dilation, s->young);
  int column = add_sand(domain, &laws[builtin], builtin);
  gm_fill_def fill = gm_fill_def_default();
  fill.points_per_cell_axis = 2;
  fill.material = column;
  /* A squeezed column stands off the wall (it moves towards its centre
   * line x_c = left + 0.0465 m). */
  double left = s->squeeze > 0.0 ? 0.05 : 0.0, bottom = 0.0; /* m */
  if (s->squeeze < 0.0) /* a stretched one stands mid-grid */
    left = 0.1535;
  fill.lower[0] = left;
  fill.upper[0] = left + 0.093; /* not a block boundary: shared chunks */
  fill.lower[1] = bottom;
  fill.upper[1] = bottom + 0.17;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  if (s->with_elastic) {
    gm_elastic_def elastic = gm_elastic_def_default();
    elastic.youngs_modulus = 1e6; /* Pa */
    elastic.poisson_ratio = 0.3;
    elastic.density = 1800.0; /* kg/m^3 */
    int block = -1;
    TEST_ASSERT_OK(domain, gm_domain_add_elastic(domain, &elastic, &block));
    fill.material = block;
    fill.lower[0] = 0.093;
    fill.upper[0] = 0.143;
    TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  }
  if (s->spin != 0.0 || s->squeeze != 0.0) {
    /* v = omega x (x - c) about the column's centre c, plus the squeeze */
    double cx = left + 0.0465, cy = bottom + 0.085; /* m */
    size_t n = gm_domain_point_count(domain);
    double *x = malloc(2 * n * sizeof *x), *v = malloc(2 * n * sizeof *v);
    TEST_ASSERT_OK(domain,
                   gm_domain_get_field(domain, GM_FIELD_POSITION, x, 2 * n));
    for (size_t p = 0; p < n; p++) {
      v[2 * p] = -s->spin * (x[2 * p + 1] - cy) - s->squeeze * (x[2 * p] - cx);
      v[2 * p + 1] = s->spin * (x[2 * p] - cx);
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
                  "fused and the general Mohr-Coulomb path",
                  what, (int)fields[f], differ, length);
    free(x);
    free(y);
  }
}

static double fixed_dt(void) { /* s, half the CFL bound */
  return 0.5 * CELL / sqrt(p_wave_modulus(1e6, 0.3) / 1800.0);
}

/* Points whose stress lies on the yield surface (returned this step, to
 * within round-off): the scene must exercise the return, not only the
 * elastic predictor. f = (s1 - s3) + (s1 + s3) sin(phi) for tension
 * positive and no cohesion (000 eq 16); on the surface f = 0 up to a
 * relative 1e-9 of the stress (the return is exact in one step). */
static size_t yielded_points(gm_domain *domain) {
  size_t n = gm_domain_point_count(domain);
  double *s = malloc(6 * n * sizeof *s);
  TEST_ASSERT_OK(domain,
                 gm_domain_get_field(domain, GM_FIELD_STRESS, s, 6 * n));
  double sine = sin(30.0 * PI / 180.0);
  size_t on = 0;
  for (size_t p = 0; p < n; p++) {
    const double *t = s + 6 * p;
    double centre = 0.5 * (t[0] + t[1]);
    double radius = sqrt(0.25 * (t[0] - t[1]) * (t[0] - t[1]) + t[3] * t[3]);
    double high = fmax(centre + radius, t[2]);
    double low = fmin(centre - radius, t[2]);
    double f = (high - low) + (high + low) * sine;
    double size = fabs(high) + fabs(low);
    on += size > 0.0 && fabs(f) <= 1e-9 * size;
  }
  free(s);
  return on;
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
  /* At least a fifth of the points on the surface at the end: measured
   * 0.26 (the spinning column) to 0.85 of them in these scenes. */
  size_t yielded = yielded_points(fused);
  ck_assert_msg(yielded * 5 >= gm_domain_point_count(fused),
                "%s: only %zu points on the yield surface", what, yielded);
  gm_domain_destroy(fused);
  gm_domain_destroy(general);
}

START_TEST(collapse_usl) {
  scene s = {GM_SCHEME_USL,   0.0, 0.0, 0.0, 0.0, false, GM_WALL_SLIP,
             GM_SHAPE_LINEAR, 0.0};
  run_pair(&s, 300, "collapse, USL");
}
END_TEST

START_TEST(collapse_musl_pic_dilation) {
  scene s = {GM_SCHEME_MUSL,  0.2, 0.0, 0.0, 0.17, false, GM_WALL_SLIP,
             GM_SHAPE_LINEAR, 0.0};
  run_pair(&s, 300, "collapse, MUSL, PIC 0.2, psi 0.17 rad");
}
END_TEST

/* The fast path starts from the gathered gradient, whatever the shape. */
START_TEST(collapse_ugimp) {
  scene s = {GM_SCHEME_USL,  0.0, 0.0, 0.0, 0.0, false, GM_WALL_SLIP,
             GM_SHAPE_UGIMP, 0.0};
  run_pair(&s, 200, "collapse, uGIMP");
}
END_TEST

START_TEST(collapse_cpdi) {
  scene s = {GM_SCHEME_USL, 0.0,          0.0,           0.0, 0.0,
             false,         GM_WALL_SLIP, GM_SHAPE_CPDI, 0.0};
  run_pair(&s, 200, "collapse, CPDI");
}
END_TEST

START_TEST(spinning_column) {
  scene s = {GM_SCHEME_USL,   0.0, 10.0, 0.0, 0.0, false, GM_WALL_SLIP,
             GM_SHAPE_LINEAR, 0.0};
  run_pair(&s, 200, "spinning column");
}
END_TEST

START_TEST(beside_elastic_mixed_chunks) {
  scene s = {GM_SCHEME_USL,   0.0, 0.0, 0.0, 0.0, true, GM_WALL_SLIP,
             GM_SHAPE_LINEAR, 0.0};
  run_pair(&s, 300, "beside an elastic block");
}
END_TEST

/* A column squeezed along x at 1.5 / dt: 1 + L_xx dt < 0 inverts F in the
 * first step. Both paths fail it with the same status and message and
 * leave the committed state as it was. */
START_TEST(inversion_fails_alike) {
  scene s = {
      GM_SCHEME_USL,   0.0, 0.0, 1.5 / fixed_dt(), 0.0, false, GM_WALL_SLIP,
      GM_SHAPE_LINEAR, 0.0};
  gm_domain *fused = make_domain(&s, true);
  gm_domain *general = make_domain(&s, false);
  double dt = fixed_dt();
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
    assert_same_state(fused, general, "inversion");
  }
  ck_assert_msg(failed, "inversion: no step failed");
  gm_domain_destroy(fused);
  gm_domain_destroy(general);
}
END_TEST

/* A column stretched along x by 1.5 per step (v_x = 1.5 / dt (x - x_c))
 * with E = 1e308 Pa: F stays positive (det F = 2.5), but the elastic trial
 * xx, about (lambda + 2 G) 1.5 = 2e308 Pa, overflows. The fused pass hands
 * such a chunk to the general stress update: both domains fail the step
 * with the material's message. dt is the domain's stable one (the fixed
 * one of the soft law would be refused). */
START_TEST(overflow_fails_alike) {
  scene s = {GM_SCHEME_USL,   0.0,  0.0, -1.0, 0.0, false, GM_WALL_SLIP,
             GM_SHAPE_LINEAR, 1e308};
  gm_domain *fused = make_domain(&s, true);
  double dt = 0.0;
  TEST_ASSERT_OK(fused, gm_domain_stable_dt(fused, &dt));
  gm_domain_destroy(fused);
  s.squeeze = -1.5 / dt;
  fused = make_domain(&s, true);
  gm_domain *general = make_domain(&s, false);
  gm_status a = gm_domain_step(fused, dt);
  gm_status b = gm_domain_step(general, dt);
  ck_assert_int_eq(a, b);
  ck_assert_int_ne(a, GM_OK);
  ck_assert_str_eq(gm_domain_last_error(fused), gm_domain_last_error(general));
  ck_assert_msg(strstr(gm_domain_last_error(fused), "not finite") != NULL,
                "overflow: %s", gm_domain_last_error(fused));
  assert_same_state(fused, general, "overflow");
  gm_domain_destroy(fused);
  gm_domain_destroy(general);
}
END_TEST

static Suite *suite(void) {
  Suite *s = suite_create("mohr_coulomb_fast_path");
  TCase *tc = tcase_create("bitwise");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, collapse_usl);
  tcase_add_test(tc, collapse_musl_pic_dilation);
  tcase_add_test(tc, collapse_ugimp);
  tcase_add_test(tc, collapse_cpdi);
  tcase_add_test(tc, spinning_column);
  tcase_add_test(tc, beside_elastic_mixed_chunks);
  tcase_add_test(tc, inversion_fails_alike);
  tcase_add_test(tc, overflow_fails_alike);
  suite_add_tcase(s, tc);
  return s;
}

int main(void) {
  return test_run_suite(suite()) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
