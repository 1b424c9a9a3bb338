/*
 * test_util.h - small helpers shared by the Check test programs. Uses only
 * the public API (granmpm.h). Every helper is `static inline` so a test file
 * that does not use one gets no warning.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_TEST_UTIL_H
#define GM_TEST_UTIL_H

#include <check.h>
#include <stdint.h>
#include <stdlib.h>

#include "granmpm.h"

/* Asserts that `call` returns GM_OK; on failure prints the call, the status
 * text and the domain's last error message. `domain` may be NULL (then the
 * message of the last failed gm_domain_create() is printed). */
#define TEST_ASSERT_OK(domain, call)                                           \
  do {                                                                         \
    gm_status test_status_ = (call);                                           \
    ck_assert_msg(test_status_ == GM_OK, "%s failed: %s (%s)", #call,          \
                  gm_strerror(test_status_),                                   \
                  (domain) ? gm_domain_last_error(domain)                      \
                           : gm_last_create_error());                          \
  } while (0)

/* Fails the test with the printf-style message unless cond holds. Unlike
 * ck_assert_msg it does not report a passing check to the Check runner (one
 * pipe write per check), which would dominate the tests that make millions
 * of checks (shape, overlap and CPDI sampling). */
#define REQUIRE(cond, ...)                                                     \
  do {                                                                         \
    if (!(cond))                                                               \
      ck_abort_msg(__VA_ARGS__);                                               \
  } while (0)

/* Short name of an update scheme, for failure messages. */
static inline const char *test_shape_name(gm_shape shape) {
  switch (shape) {
  case GM_SHAPE_LINEAR:
    return "linear";
  case GM_SHAPE_UGIMP:
    return "uGIMP";
  case GM_SHAPE_CPGIMP:
    return "cpGIMP";
  case GM_SHAPE_CPDI:
    return "CPDI";
  case GM_SHAPE_BSPLINE2:
    return "B-spline2";
  case GM_SHAPE_BSPLINE3:
    return "B-spline3";
  }
  return "unknown";
}

static inline const char *test_scheme_name(gm_update_scheme scheme) {
  switch (scheme) {
  case GM_SCHEME_USL:
    return "USL";
  case GM_SCHEME_MUSL:
    return "MUSL";
  case GM_SCHEME_USF:
    return "USF";
  }
  return "unknown";
}

/* Creates a domain or fails the test. */
static inline gm_domain *test_create_domain(const gm_domain_def *def) {
  gm_domain *domain = NULL;
  TEST_ASSERT_OK((gm_domain *)NULL, gm_domain_create(def, &domain));
  ck_assert_ptr_nonnull(domain);
  return domain;
}

/* Registers the built-in elastic material; returns its id.
 * youngs_modulus in Pa, density in kg/m^3. */
static inline int test_add_elastic(gm_domain *domain, double youngs_modulus,
                                   double poisson_ratio, double density) {
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.youngs_modulus = youngs_modulus;
  elastic.poisson_ratio = poisson_ratio;
  elastic.density = density;
  int material = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_elastic(domain, &elastic, &material));
  return material;
}

/* Adds count points of `material` at position (m, count * dim) with
 * velocity (m/s, count * dim; NULL: at rest) and volume (per point, in
 * gm_points_def's units: m^2 per unit thickness in plane strain, m^3 in
 * 3D); fails the test if the library refuses them. */
static inline void test_add_points(gm_domain *domain, int material,
                                   size_t count, const double *position,
                                   const double *velocity,
                                   const double *volume) {
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
}

/* Fills the box [lower, upper] (m) with points of `material` at rest, n per
 * cell per axis; returns the number of points added, *first_id the first id
 * (may be NULL). Unused components of lower/upper are ignored by 1D/2D. */
static inline size_t test_fill_box(gm_domain *domain, int material,
                                   const double lower[3], const double upper[3],
                                   int points_per_cell_axis,
                                   int64_t *first_id) {
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  for (int k = 0; k < 3; ++k) {
    fill.lower[k] = lower[k];
    fill.upper[k] = upper[k];
  }
  fill.points_per_cell_axis = points_per_cell_axis;
  int64_t first = -1;
  size_t count = 0;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, &first, &count));
  ck_assert_uint_gt(count, 0);
  if (first_id)
    *first_id = first;
  return count;
}

/* Copies a field into out in id order: out[(id - first_id)*components + k].
 * Ids must be first_id .. first_id + point_count - 1. Returns components. */
static inline size_t test_get_field_by_id(const gm_domain *domain,
                                          gm_field field, int64_t first_id,
                                          double *out) {
  size_t components = 0;
  TEST_ASSERT_OK(domain,
                 gm_domain_field_components(domain, field, &components));
  size_t count = gm_domain_point_count(domain);
  double *by_index = malloc(count * components * sizeof *by_index);
  int64_t *ids = malloc(count * sizeof *ids);
  ck_assert(by_index != NULL && ids != NULL);
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, field, by_index, count * components));
  TEST_ASSERT_OK(domain, gm_domain_get_ids(domain, ids, count));
  for (size_t i = 0; i < count; ++i) {
    int64_t slot = ids[i] - first_id;
    ck_assert(slot >= 0 && (size_t)slot < count);
    for (size_t k = 0; k < components; ++k)
      out[(size_t)slot * components + k] = by_index[i * components + k];
  }
  free(by_index);
  free(ids);
  return components;
}

/* Runs a suite with CK_NORMAL output; returns the number of failures, so a
 * test program's main() can `return test_run_suite(...) ? 1 : 0;`. */
static inline int test_run_suite(Suite *suite) {
  SRunner *runner = srunner_create(suite);
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed;
}

#endif /* GM_TEST_UTIL_H */
