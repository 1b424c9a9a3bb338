/*
 * test_cpdi_reset_3d.c - the reset of over-distorted CPDI domains in 3D
 * (lib/points/cpdi_reset.c, docs/3d.md "CPDI domain reset in 3D"):
 *  - gm_cpdi_domain_reset_3d on given domain maps (rotated, so that no
 *    map is diagonal): a map whose singular values differ by more than
 *    GM_CPDI_MAX_DISTORTION becomes cbrt(det D) I (same volume), on both
 *    sides of the root-free pre-tests and in the band between them where
 *    the singular values decide; one within the bound is left bitwise
 *    alone; an inverted one is left for the step to refuse;
 *  - a free block given the simple shear v_x = gamma (y - y_c), no
 *    gravity, a very soft solid (nearly ballistic, F -> I + gamma t e_x
 *    e_y): before the 3D reset existed the step failed with
 *    GM_ERR_OUT_OF_GRID at step 153 (gamma t = 6.1), a domain following
 *    F spanning more than GM_SUPPORT_3D_MAX_SPAN node planes. It now runs
 *    to gamma t = 12 with the total mass bitwise and the momentum to
 *    round-off across every step (resets included), every domain of
 *    volume det F V0 and distortion at most the bound, domains reset along
 *    the way (to cbrt(det D) I), and GM_FIELD_DOMAIN_CORNERS showing D's
 *    parallelepiped;
 *  - below the bound D = F bitwise (so a 3D CPDI run that never resets
 *    is the one it was before D existed), in every scheme;
 *  - the sheared run bitwise the same with 1 and 2 workers, D included;
 *  - a checkpoint written after resets restarts bitwise, D included,
 *    also with APIC and the granular family (the longest array list), and
 *    a format-version-2 file (no 3D map) loads with D = F;
 *  - no allocation in a step after warm-up, across resets.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "core/domain.h" /* white box: the domain map D next to F */
#include "points/points.h"

#include "test_counting_allocator.h"
#include "test_restart.h"
#include "test_util.h"

#include <check.h>
#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Slot of component ij (row-major) of F and D (core.h). */
static const int SLOT[9] = {F_XX, F_XY, F_XZ, F_YX, F_YY,
                            F_YZ, F_ZX, F_ZY, F_ZZ};

static double det3(const double f[9]) {
  return f[0] * (f[4] * f[8] - f[5] * f[7]) -
         f[1] * (f[3] * f[8] - f[5] * f[6]) +
         f[2] * (f[3] * f[7] - f[4] * f[6]);
}

/* sigma_max / sigma_min of f (row-major), independently of the library:
 * the eigenvalues of f^T f by cyclic Jacobi rotations (converged to
 * rounding well within 50 sweeps for 3 x 3). */
static double distortion(const double f[9]) {
  double c[3][3];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      c[i][j] = f[i] * f[j] + f[3 + i] * f[3 + j] + f[6 + i] * f[6 + j];
  for (int sweep = 0; sweep < 50; sweep++) {
    double off = c[0][1] * c[0][1] + c[0][2] * c[0][2] + c[1][2] * c[1][2];
    if (off == 0.0)
      break;
    for (int p = 0; p < 2; p++)
      for (int q = p + 1; q < 3; q++) {
        if (c[p][q] == 0.0)
          continue;
        double theta = (c[q][q] - c[p][p]) / (2.0 * c[p][q]);
        double t = (theta >= 0 ? 1.0 : -1.0) /
                   (fabs(theta) + sqrt(theta * theta + 1.0));
        double cs = 1.0 / sqrt(t * t + 1.0), sn = t * cs;
        for (int k = 0; k < 3; k++) { /* columns p, q */
          double a = c[k][p], b = c[k][q];
          c[k][p] = cs * a - sn * b;
          c[k][q] = sn * a + cs * b;
        }
        for (int k = 0; k < 3; k++) { /* rows p, q */
          double a = c[p][k], b = c[q][k];
          c[p][k] = cs * a - sn * b;
          c[q][k] = sn * a + cs * b;
        }
      }
  }
  double high = fmax(c[0][0], fmax(c[1][1], c[2][2]));
  double low = fmin(c[0][0], fmin(c[1][1], c[2][2]));
  return sqrt(high / low);
}

/* q R diag(s) with R the rotation by angle about (1, 2, 2) / 3. */
static void rotated_diagonal(const double s[3], double angle, double out[9]) {
  double axis[3] = {1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0};
  double c = cos(angle), sn = sin(angle), r[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      r[3 * i + j] = (i == j ? c : 0.0) + (1.0 - c) * axis[i] * axis[j];
  r[1] -= sn * axis[2];
  r[2] += sn * axis[1];
  r[3] += sn * axis[2];
  r[5] -= sn * axis[0];
  r[6] -= sn * axis[1];
  r[7] += sn * axis[0];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      out[3 * i + j] = r[3 * i + j] * s[j];
}

/* The pre-tests of cpdi_reset.c read q = |D|_F^2 |D^-1|_F^2: below
 * (T + 1 + 1/T)^2 = 18.8 no reset, above 5 + 2 T^2 + 2 / T^2 = 23.2 a
 * reset, between them the singular values decide. Cases on each side
 * (singular values s, q noted). det is compared to 1e-15 relative: one
 * cube root and one cube of rounding. */
START_TEST(test_reset_of_given_maps_3d) {
  static const double distorted[][3] = {
      {4.0, 1.0, 0.5},           /* ratio 8, q 87: above */
      {3.02, 1.0, 1.0},          /* ratio 3.02, q 23.5: above */
      {3.1, 1.76068168616, 1.0}, /* ratio 3.1, s2^2 = s1 s3, q 19.6: band */
      {3.3, 2.5, 1.0}};          /* ratio 3.3, q 22.7: the band */
  static const double kept[][3] = {
      {2.9, 1.70293863659, 1.0}, /* ratio 2.9, q 18.0: below */
      {2.98, 1.0, 1.0},          /* ratio 2.98, q 23.0: the band */
      {1.2, 1.1, 0.9}};          /* ratio 1.33, q 9.5: below */
  for (size_t m = 0; m < 4; m++) {
    double map[9];
    rotated_diagonal(distorted[m], 0.7 + (double)m, map);
    double before = det3(map);
    ck_assert_double_gt(distortion(map), GM_CPDI_MAX_DISTORTION);
    ck_assert(gm_cpdi_domain_reset_3d(map, GM_CPDI_MAX_DISTORTION));
    double after = det3(map);
    ck_assert_msg(fabs(after - before) <= 1e-15 * before,
                  "map %zu: det %.17g after the reset, %.17g before", m, after,
                  before);
    for (int k = 0; k < 9; k++)
      ck_assert(k % 4 == 0 ? map[k] == map[0] : map[k] == 0.0);
  }
  for (size_t m = 0; m < 3; m++) {
    double map[9], copy[9];
    rotated_diagonal(kept[m], 0.3 + (double)m, map);
    memcpy(copy, map, sizeof map);
    ck_assert_double_lt(distortion(map), GM_CPDI_MAX_DISTORTION);
    ck_assert(!gm_cpdi_domain_reset_3d(map, GM_CPDI_MAX_DISTORTION));
    ck_assert(memcmp(map, copy, sizeof map) == 0);
  }
  double inverted[9] = {4.0, 0, 0, 0, 1.0, 0, 0, 0, -0.5}, copy[9];
  memcpy(copy, inverted, sizeof copy);
  ck_assert(!gm_cpdi_domain_reset_3d(inverted, GM_CPDI_MAX_DISTORTION));
  ck_assert(memcmp(inverted, copy, sizeof copy) == 0);
}
END_TEST

/* ------------------------------------------------- the sheared block */
static const double SHEAR_RATE = 4.0;  /* 1/s, gamma = dv_x/dy */
static const double SHEAR_DT = 0.01;   /* s */
static const double SHEAR_CELL = 0.1;  /* m */
static const double SHEAR_Y_MID = 0.4; /* m, the block's centre height */

/* Box 3.2 x 0.8 x 0.8 m, cells 0.1 m, open faces, no gravity; a block
 * 0.4 x 0.2 x 0.4 m (2 points per cell per axis: 256 points, edges 0.05
 * m) of a very soft elastic solid (E = 10 Pa, shear wave speed 0.06 m/s:
 * the block barely resists) given v_x = 0.05 + gamma (y - 0.4) m/s, so
 * that the points move nearly ballistically and F -> (1 gamma t 0; 0 1 0;
 * 0 0 1), whose distortion passes GM_CPDI_MAX_DISTORTION = 3 at gamma t
 * = 8/3. The drift makes the total momentum non-zero. */
static gm_domain *sheared_block(gm_update_scheme scheme, int workers) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = SHEAR_CELL;
  def.extent[0] = 3.2; /* m */
  def.extent[1] = def.extent[2] = 0.8;
  for (int k = 0; k < 3; k++)
    def.gravity[k] = 0.0;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 10.0, 0.3, 1000.0);
  const double lower[3] = {1.4, 0.3, 0.2}, upper[3] = {1.8, 0.5, 0.6};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  size_t count = gm_domain_point_count(domain);
  const double *y = NULL;
  double *vx = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &vx));
  for (size_t i = 0; i < count; i++)
    vx[i] = 0.05 + SHEAR_RATE * (y[i] - SHEAR_Y_MID); /* m/s */
  return domain;
}

static void run(gm_domain *domain, int steps) {
  for (int k = 0; k < steps; k++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, SHEAR_DT));
}

/* Point p's F or D (committed buffer), row-major. */
static void read_tensor(const gm_domain *domain, bool map, size_t p,
                        double out[9]) {
  const gm_point_buffers *b = &domain->points.buffer[domain->points.cur];
  for (int k = 0; k < 9; k++)
    out[k] = map ? b->domain_map[SLOT[k]][p] : b->deformation[SLOT[k]][p];
}

/* A field of every point, in point-index order (caller frees). */
static double *get_field(const gm_domain *domain, gm_field field,
                         size_t components) {
  size_t length = gm_domain_point_count(domain) * components;
  double *values = malloc((length + 1) * sizeof *values);
  ck_assert_ptr_nonnull(values);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, field, values, length));
  return values;
}

/* Total mass (kg) and momentum (kg m/s), and the sum of |m v| that sets
 * the scale of their rounding. */
static void totals(const gm_domain *domain, double *mass, double momentum[3],
                   double *scale) {
  size_t count = gm_domain_point_count(domain);
  double *m = get_field(domain, GM_FIELD_MASS, 1);
  double *v = get_field(domain, GM_FIELD_VELOCITY, 3);
  *mass = *scale = momentum[0] = momentum[1] = momentum[2] = 0.0;
  for (size_t i = 0; i < count; i++) {
    *mass += m[i];
    for (int k = 0; k < 3; k++) {
      momentum[k] += m[i] * v[3 * i + k];
      *scale += fabs(m[i] * v[3 * i + k]);
    }
  }
  free(m);
  free(v);
}

/* What one step of the sheared block is checked for (per point, the
 * committed state): */
typedef struct shear_record {
  double worst_volume;     /* |det D - det F| / det F */
  double worst_corners;    /* |D from the corners - D| */
  double worst_distortion; /* of D */
  double max_f_distortion; /* of F */
  double max_f_reach;      /* cells, x extent of F's parallelepiped */
  int reset_seen;          /* points whose D is c I while F is distorted */
} shear_record;

/* The corners of VTK_HEXAHEDRON's order (fields.c): r_k = (c_k' - c_0) / 2
 * for c_1 (+x), c_3 (+y), c_4 (+z), so D's column k = r_k / (l_k / 2). */
static void check_point(const gm_domain *domain, size_t p,
                        const double *corners, const double *size,
                        shear_record *record) {
  double f[9], d[9];
  read_tensor(domain, false, p, f);
  read_tensor(domain, true, p, d);
  double det_f = det3(f);
  record->worst_volume =
      fmax(record->worst_volume, fabs(det3(d) - det_f) / det_f);
  static const int corner_of_edge[3] = {1, 3, 4};
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < 3; i++) {
      const double *c = corners + 24 * p;
      double r = 0.5 * (c[3 * corner_of_edge[k] + i] - c[i]); /* m */
      double column = r / (0.5 * size[3 * p + k]);
      record->worst_corners =
          fmax(record->worst_corners, fabs(column - d[3 * i + k]));
    }
  record->worst_distortion = fmax(record->worst_distortion, distortion(d));
  double f_distortion = distortion(f);
  record->max_f_distortion = fmax(record->max_f_distortion, f_distortion);
  double reach = 0.0; /* m, x extent of F's parallelepiped */
  for (int k = 0; k < 3; k++)
    reach += fabs(f[k]) * size[3 * p + k];
  record->max_f_reach = fmax(record->max_f_reach, reach / SHEAR_CELL);
  bool scaled_identity = true;
  for (int k = 0; k < 9; k++)
    scaled_identity =
        scaled_identity && (k % 4 == 0 ? d[k] == d[0] : d[k] == 0.0);
  if (scaled_identity && f_distortion > GM_CPDI_MAX_DISTORTION)
    record->reset_seen++;
}

/* gamma t = 12 (1200 steps would be 12 s; 300 steps of 0.01 s at gamma =
 * 4/s), MUSL. Per step: mass bitwise (per point, never changed) and
 * momentum equal before and after each step to 1e-13 of sum |m v| (the
 * transfers sum 256 points' terms of up to 27 node contributions, each
 * rounded to 1e-16 relative; a momentum error of a reset would be of the
 * order of the velocity differences across a domain, gamma l = 0.2 m/s
 * in sum |m v| / M ~ 0.25 m/s, i.e. 1e-1 relative). Per point: det D =
 * det F to 1e-12 (they take the same increments and a reset keeps det D:
 * a cube root and a cube, 4e-16, then ~1e-16 per step over 300 steps),
 * D's distortion at most the bound (1e-12 slack for the independent
 * eigenvalue solver's rounding), the corners' D equal to D to 4e-14
 * (corners at x up to 3.2 m, each rounded to half an ulp, 2.2e-16 m,
 * subtracted and divided by half edges of 0.025 m: 2 x 2.2e-16 / 0.025
 * = 1.8e-14, with a factor 2 for the sum of three terms). */
START_TEST(test_sheared_block_runs_past_the_span) {
  gm_domain *domain = sheared_block(GM_SCHEME_MUSL, 1);
  size_t count = gm_domain_point_count(domain);
  shear_record record = {0};
  int steps = 0, first_reset_step = -1;
  double mass0, momentum0[3], scale0;
  totals(domain, &mass0, momentum0, &scale0);
  double worst_momentum = 0.0; /* relative to sum |m v| */
  for (; steps < 300; steps++) {
    double mass_before, before[3], scale;
    totals(domain, &mass_before, before, &scale);
    TEST_ASSERT_OK(domain, gm_domain_step(domain, SHEAR_DT));
    double mass_after, after[3], unused;
    totals(domain, &mass_after, after, &unused);
    ck_assert_msg(mass_after == mass_before, "mass %.17g -> %.17g kg",
                  mass_before, mass_after);
    for (int k = 0; k < 3; k++)
      worst_momentum = fmax(worst_momentum, fabs(after[k] - before[k]) / scale);
    double *corners = get_field(domain, GM_FIELD_DOMAIN_CORNERS, 24);
    double *size = get_field(domain, GM_FIELD_DOMAIN_SIZE, 3);
    int seen = record.reset_seen;
    for (size_t p = 0; p < count; p++)
      check_point(domain, p, corners, size, &record);
    if (first_reset_step < 0 && record.reset_seen > seen)
      first_reset_step = steps + 1;
    free(corners);
    free(size);
  }
  double mass1, momentum1[3], scale1;
  totals(domain, &mass1, momentum1, &scale1);
  printf("CPDI 3D sheared block: %d steps (gamma t = %.3g), first reset seen "
         "at step %d, %d domains seen just reset; F distortion up to %.3g, "
         "F's parallelepiped up to %.3g cells along x; D distortion up to "
         "%.6g, |det D - det F| / det F up to %.2g, corners' D off by %.2g, "
         "momentum per step %.2g of sum |m v| (drift %.2g over the run)\n",
         steps, SHEAR_RATE * SHEAR_DT * steps, first_reset_step,
         record.reset_seen, record.max_f_distortion, record.max_f_reach,
         record.worst_distortion, record.worst_volume, record.worst_corners,
         worst_momentum, fabs(momentum1[0] - momentum0[0]) / scale0);
  ck_assert_double_le(worst_momentum, 1e-13);
  ck_assert_double_le(record.worst_volume, 1e-12);
  ck_assert_double_le(record.worst_corners, 4e-14);
  ck_assert_double_le(record.worst_distortion,
                      GM_CPDI_MAX_DISTORTION * (1.0 + 1e-12));
  ck_assert_int_gt(record.reset_seen, 0);
  /* Without the reset the domains would follow F: a parallelepiped
   * reaching over more than GM_SUPPORT_3D_MAX_SPAN - 1 = 4 cells along x
   * is refused (support_cpdi_3d.h), which is how the step failed. */
  ck_assert_double_gt(record.max_f_reach, 4.0 + 1.0);
  gm_domain_destroy(domain);
}
END_TEST

/* _i: scheme. 30 steps (gamma t = 1.2: F's distortion up to about 2.2,
 * printed): no domain reaches the bound, so D = F bitwise, point by point,
 * and the run is the one of F-following domains (the state of a 3D CPDI
 * run that never resets does not change). */
START_TEST(test_below_the_bound_map_is_f) {
  gm_update_scheme scheme = (gm_update_scheme)_i;
  gm_domain *domain = sheared_block(scheme, 1);
  run(domain, 30);
  size_t count = gm_domain_point_count(domain);
  double largest = 0.0;
  for (size_t p = 0; p < count; p++) {
    double f[9], d[9];
    read_tensor(domain, false, p, f);
    read_tensor(domain, true, p, d);
    ck_assert_msg(memcmp(f, d, sizeof f) == 0, "%s: point %zu: D is not F",
                  test_scheme_name(scheme), p);
    largest = fmax(largest, distortion(f));
  }
  printf("CPDI 3D below the bound, %s: F distortion up to %.3g, D = F\n",
         test_scheme_name(scheme), largest);
  ck_assert_double_gt(largest, 1.5);
  ck_assert_double_lt(largest, GM_CPDI_MAX_DISTORTION);
  gm_domain_destroy(domain);
}
END_TEST

/* ------------------------------------ workers, restart, allocation */
/* Every point's D, 9 per point, row-major (white box: the snapshots of
 * test_restart.h carry it next to every field the API shows). */
static double *domain_maps(const gm_domain *domain, size_t *length,
                           void *context) {
  (void)context;
  size_t count = gm_domain_point_count(domain);
  *length = 9 * count;
  double *map = malloc((*length + 1) * sizeof *map);
  ck_assert_ptr_nonnull(map);
  for (size_t p = 0; p < count; p++)
    read_tensor(domain, true, p, map + 9 * p);
  return map;
}

static test_snapshot observe(const gm_domain *domain) {
  return test_snapshot_take(domain, domain_maps, NULL);
}

/* Points whose D is no longer F: reset at least once. */
static size_t reset_points(const gm_domain *domain) {
  size_t count = gm_domain_point_count(domain), reset = 0;
  for (size_t p = 0; p < count; p++) {
    double f[9], d[9];
    read_tensor(domain, false, p, f);
    read_tensor(domain, true, p, d);
    reset += memcmp(f, d, sizeof f) != 0;
  }
  return reset;
}

/* _i: scheme. 150 steps: gamma t = 6, past the first resets. */
START_TEST(test_workers_bitwise_with_resets) {
  gm_update_scheme scheme = (gm_update_scheme)_i;
  test_snapshot result[2];
  for (int workers = 1; workers <= 2; workers++) {
    gm_domain *domain = sheared_block(scheme, workers);
    run(domain, 150);
    ck_assert_uint_gt(reset_points(domain), 0);
    result[workers - 1] = observe(domain);
    gm_domain_destroy(domain);
  }
  test_snapshot_assert_same(&result[0], &result[1], "1 against 2 workers");
  test_snapshot_free(&result[0]);
  test_snapshot_free(&result[1]);
}
END_TEST

static void step_sheared(gm_domain *domain, test_restart_phase phase, int steps,
                         void *context) {
  (void)phase;
  (void)context;
  run(domain, steps);
}

static void assert_reset(gm_domain *domain, void *context) {
  (void)context;
  ck_assert_uint_gt(reset_points(domain), 0);
}

static gm_domain *build_sheared(int workers, void *context) {
  return sheared_block(*(const gm_update_scheme *)context, workers);
}

/* _i: scheme; saved on 1 worker after resets (step 100, gamma t = 4),
 * continued on 1 (_i < 3) or 2 workers for 100 more steps; the restarted
 * domain runs 3 steps first (stale caches). D compared too. */
START_TEST(test_restart_bitwise_with_resets) {
  gm_update_scheme scheme = (gm_update_scheme)(_i % 3);
  test_restart_run restart = {.what = "sheared CPDI block",
                              .build = build_sheared,
                              .context = &scheme,
                              .workers_before = 1,
                              .workers_after = _i < 3 ? 1 : 2,
                              .steps_before = 100,
                              .steps_after = 100,
                              .stale_steps = 3,
                              .step = step_sheared,
                              .before_save = assert_reset,
                              .extra = domain_maps};
  test_restart_check(&restart);
}
END_TEST

/* FNV-1a 64 (gm_checkpoint(3)), to re-seal a file altered on purpose. */
static uint64_t fnv1a64(const unsigned char *bytes, size_t size,
                        uint64_t hash) {
  for (size_t k = 0; k < size; k++) {
    hash ^= bytes[k];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

static unsigned char *read_whole(const char *path, size_t *size) {
  FILE *file = fopen(path, "rb");
  ck_assert_ptr_nonnull(file);
  fseek(file, 0, SEEK_END);
  *size = (size_t)ftell(file);
  fseek(file, 0, SEEK_SET);
  unsigned char *data = malloc(*size + 1);
  ck_assert_ptr_nonnull(data);
  ck_assert_uint_eq(fread(data, 1, *size, file), *size);
  fclose(file);
  return data;
}

/* A format-version-2 file of a 3D CPDI domain (written before the 3D
 * domain map existed) has no D arrays. Made here from a version-3 file
 * saved before any reset, where D = F bitwise: the nine D arrays (each a
 * u64 byte count and the bytes) repeat the nine F arrays right before
 * them, and are cut out; the header then says version 2 and is re-sealed.
 * The load must start D = F, and the run continue bitwise as the saved
 * one, through its first resets. */
START_TEST(test_version_2_file_starts_map_at_f) {
  char path[64], old_path[64];
  snprintf(path, sizeof path, "/tmp/gm_cpdi_reset3d_v3_%ld.ckpt",
           (long)getpid());
  snprintf(old_path, sizeof old_path, "/tmp/gm_cpdi_reset3d_v2_%ld.ckpt",
           (long)getpid());
  gm_domain *a = sheared_block(GM_SCHEME_MUSL, 1);
  run(a, 20);
  ck_assert_uint_eq(reset_points(a), 0);
  TEST_ASSERT_OK(a, gm_domain_save(a, path));
  test_snapshot at_save = observe(a);
  size_t size = 0, count = gm_domain_point_count(a);
  unsigned char *data = read_whole(path, &size);
  size_t block = 9 * (8 + 8 * count); /* bytes of nine point arrays */
  uint64_t array_bytes = 8 * count;
  size_t at = 0; /* offset of the F arrays */
  for (size_t i = 32; at == 0 && i + 2 * block <= size; i++)
    if (memcmp(data + i, &array_bytes, 8) == 0 &&
        memcmp(data + i, data + i + block, block) == 0)
      at = i;
  ck_assert_uint_gt(at, 0);
  memmove(data + at + block, data + at + 2 * block, size - at - 2 * block);
  size -= block;
  uint32_t version = 2;
  uint64_t payload = size - 32;
  memcpy(data + 8, &version, 4);
  memcpy(data + 16, &payload, 8);
  uint64_t hash = fnv1a64(data, 24, 0xcbf29ce484222325ull);
  hash = fnv1a64(data + 32, size - 32, hash);
  memcpy(data + 24, &hash, 8);
  FILE *file = fopen(old_path, "wb");
  ck_assert_ptr_nonnull(file);
  ck_assert_uint_eq(fwrite(data, 1, size, file), size);
  ck_assert_int_eq(fclose(file), 0);
  free(data);
  gm_domain *b = sheared_block(GM_SCHEME_MUSL, 1);
  run(b, 3); /* D no longer F: the load must set it */
  TEST_ASSERT_OK(b, gm_domain_load(b, old_path));
  test_snapshot loaded = observe(b);
  test_snapshot_assert_same(&at_save, &loaded,
                            "a version-2 file, right after the load");
  run(a, 100);
  run(b, 100);
  ck_assert_uint_gt(reset_points(a), 0);
  test_snapshot end_a = observe(a), end_b = observe(b);
  test_snapshot_assert_same(&end_a, &end_b,
                            "a version-2 file, after the restarted steps");
  remove(path);
  remove(old_path);
  test_snapshot_free(&at_save);
  test_snapshot_free(&loaded);
  test_snapshot_free(&end_a);
  test_snapshot_free(&end_b);
  gm_domain_destroy(a);
  gm_domain_destroy(b);
}
END_TEST

/* The longest list of point arrays a checkpoint holds (checkpoint.c):
 * CPDI's domain map with APIC's affine matrix and the granular family's
 * state and label in 3D, 50 arrays. The sheared block of a granular
 * material (rho_cr below the density: connected, stressed) with APIC,
 * saved after resets at step 100 and restarted bitwise. */
static gm_domain *granular_apic_block(void) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  def.family = GM_FAMILY_GRANULAR;
  def.transfer = GM_TRANSFER_APIC;
  def.cell_size = SHEAR_CELL;
  def.extent[0] = 3.2; /* m */
  def.extent[1] = def.extent[2] = 0.8;
  for (int k = 0; k < 3; k++)
    def.gravity[k] = 0.0;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 10.0, 0.3, 1000.0);
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = 900.0; /* kg/m^3 */
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &granular));
  const double lower[3] = {1.4, 0.3, 0.2}, upper[3] = {1.8, 0.5, 0.6};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  size_t count = gm_domain_point_count(domain);
  const double *y = NULL;
  double *vx = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &vx));
  for (size_t i = 0; i < count; i++)
    vx[i] = 0.05 + SHEAR_RATE * (y[i] - SHEAR_Y_MID); /* m/s */
  return domain;
}

static gm_domain *build_granular_apic(int workers, void *context) {
  (void)workers; /* 1: granular_apic_block's default */
  (void)context;
  return granular_apic_block();
}

START_TEST(test_restart_granular_apic_with_resets) {
  test_restart_run restart = {.what = "granular APIC",
                              .build = build_granular_apic,
                              .workers_before = 1,
                              .workers_after = 1,
                              .steps_before = 100,
                              .steps_after = 50,
                              .stale_steps = 0,
                              .step = step_sheared,
                              .before_save = assert_reset,
                              .extra = domain_maps};
  test_restart_check(&restart);
}
END_TEST

/* _i: workers - 1. Steps 80 to 120 reset domains (the first at about
 * step 60, printed by the sheared case) and allocate nothing once warm:
 * a reset writes the next buffer in place. The block spreads over more
 * blocks of the grid as it shears, so warm-up runs to step 80 and the
 * count covers 40 steps within which no new block is reached (measured;
 * a new block would be a legitimate allocation of the grid). */
START_TEST(test_no_allocation_with_resets) {
  test_install_counting_allocator();
  gm_domain *domain = sheared_block(GM_SCHEME_MUSL, _i + 1);
  run(domain, 80);
  size_t reset_before = reset_points(domain);
  long before = atomic_load(&test_allocations);
  run(domain, 40);
  long after = atomic_load(&test_allocations);
  size_t reset_after = reset_points(domain);
  gm_domain_destroy(domain);
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
  ck_assert_uint_gt(reset_after, reset_before);
  ck_assert_msg(after == before, "%d workers: %ld allocations in 40 steps",
                _i + 1, after - before);
}
END_TEST

static Suite *cpdi_reset_3d_suite(void) {
  Suite *suite = suite_create("cpdi_reset_3d");
  TCase *tcase = tcase_create("reset");
  tcase_set_timeout(tcase, 300);
  tcase_add_test(tcase, test_reset_of_given_maps_3d);
  tcase_add_test(tcase, test_sheared_block_runs_past_the_span);
  tcase_add_loop_test(tcase, test_below_the_bound_map_is_f, 0, 3);
  tcase_add_loop_test(tcase, test_workers_bitwise_with_resets, 0, 3);
  tcase_add_loop_test(tcase, test_restart_bitwise_with_resets, 0, 6);
  tcase_add_test(tcase, test_restart_granular_apic_with_resets);
  tcase_add_test(tcase, test_version_2_file_starts_map_at_f);
  tcase_add_loop_test(tcase, test_no_allocation_with_resets, 0, 2);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(cpdi_reset_3d_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
