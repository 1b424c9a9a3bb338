/*
 * test_batch.h - a hand-built gm_material_batch for testing built-in
 * material update functions directly (SoA storage for up to MAX_POINTS
 * points, one state variable), and the stress invariants recomputed
 * independently of the library: p = -tr(sigma)/3 (compression positive),
 * q = sqrt(3/2 s:s) with the shear terms counted twice.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_TEST_BATCH_H
#define GM_TEST_BATCH_H

#include <check.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "granmpm.h"

enum { MAX_POINTS = 8192 };

/* Storage for a hand-built batch of up to MAX_POINTS points. */
typedef struct test_points {
  double strain[6][MAX_POINTS]; /* - , tensor shear components */
  double stress[6][MAX_POINTS]; /* Pa */
  double density[MAX_POINTS];   /* kg/m^3 */
  double plastic[MAX_POINTS];   /* state 0: equivalent plastic strain */
  int64_t id[MAX_POINTS];
  double *state_columns[1];
  gm_material_batch batch;
} test_points;

static inline test_points *test_points_create(size_t count, size_t state_count,
                                              double density) {
  test_points *points = calloc(1, sizeof *points);
  ck_assert_ptr_nonnull(points);
  ck_assert_uint_le(count, MAX_POINTS);
  gm_material_batch *batch = &points->batch;
  batch->struct_size = sizeof *batch;
  batch->count = count;
  batch->geometry = GM_GEOMETRY_PLANE_STRAIN;
  batch->dt = 1e-4; /* s; the model does not use it */
  for (int c = 0; c < 6; c++) {
    batch->strain_increment[c] = points->strain[c];
    batch->stress[c] = points->stress[c];
  }
  for (size_t i = 0; i < count; i++) {
    points->density[i] = density;
    points->id[i] = (int64_t)i;
  }
  batch->density = points->density;
  points->state_columns[0] = points->plastic;
  batch->state = points->state_columns;
  batch->state_count = state_count;
  batch->point_id = points->id;
  return points;
}

/* A copy whose batch points at the copy's own arrays. */
static inline test_points *test_points_clone(const test_points *source) {
  test_points *copy = malloc(sizeof *copy);
  ck_assert_ptr_nonnull(copy);
  memcpy(copy, source, sizeof *copy);
  gm_material_batch *batch = &copy->batch;
  for (int c = 0; c < 6; c++) {
    batch->strain_increment[c] = copy->strain[c];
    batch->stress[c] = copy->stress[c];
  }
  batch->density = copy->density;
  copy->state_columns[0] = copy->plastic;
  batch->state = copy->state_columns;
  batch->point_id = copy->id;
  return copy;
}

/* The elastic trial of every point (a plastic model's documented first
 * stage, gm_elastic_update with E (Pa) and nu) into trial[c][i]. */
static inline void test_points_elastic_trial(const test_points *points,
                                             double youngs, double poisson,
                                             double (*trial)[MAX_POINTS]) {
  test_points *copy = test_points_clone(points);
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.youngs_modulus = youngs;
  elastic.poisson_ratio = poisson;
  ck_assert_int_eq(gm_elastic_update(&copy->batch, &elastic, NULL, 0), 0);
  for (int c = 0; c < 6; c++)
    memcpy(trial[c], copy->stress[c], sizeof copy->stress[c]);
  free(copy);
}

/* ------------------------------------------------------------- invariants */

static inline double pressure_of(const double sigma[6]) {
  return -(sigma[0] + sigma[1] + sigma[2]) / 3.0;
}

static inline double equivalent_of(const double sigma[6]) {
  double p = pressure_of(sigma);
  double sxx = sigma[0] + p, syy = sigma[1] + p, szz = sigma[2] + p;
  double ss =
      sxx * sxx + syy * syy + szz * szz +
      2.0 * (sigma[3] * sigma[3] + sigma[4] * sigma[4] + sigma[5] * sigma[5]);
  return sqrt(1.5 * ss);
}

static inline void point_stress(const test_points *points, size_t i,
                                double out[6]) {
  for (int c = 0; c < 6; c++)
    out[c] = points->stress[c][i];
}

#endif /* GM_TEST_BATCH_H */
