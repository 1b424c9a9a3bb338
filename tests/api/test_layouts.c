/*
 * test_layouts.c - the struct_size contract of every public call that
 * takes a definition or result structure (api_check.h): for each
 * structure, its current size is accepted; one byte short is refused with
 * GM_ERR_STRUCT_SIZE and a message naming the structure, the size given
 * and the size expected, leaving the domain as it was; and the earlier
 * layouts of the structures that grew (gm_domain_def, gm_wall_force) are
 * accepted, a definition's missing fields taking their defaults and a
 * result's missing fields left unwritten. gm_allocator, which
 * gm_set_allocator takes without a domain, is refused the same way, its
 * message in gm_last_create_error().
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include <check.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int no_stress(const gm_material_batch *batch, void *user, char *message,
                     size_t message_size) {
  (void)batch;
  (void)user;
  (void)message;
  (void)message_size;
  return 0;
}

/* A 2D domain 1 m x 1 m, cells of 0.1 m, with an elastic material 0 of
 * density 1000 kg/m^3. */
static gm_domain *fresh_domain(void) {
  gm_domain_def def = gm_domain_def_default();
  def.extent[0] = def.extent[1] = 1.0; /* m */
  gm_domain *domain = test_create_domain(&def);
  (void)test_add_elastic(domain, 1e6, 0.3, 1000.0);
  return domain;
}

static const double point[2] = {0.55, 0.55}; /* m, a cell centre */
static const double volume[1] = {0.0025};    /* m^2, a quarter cell */

/* One call per structure: builds a valid argument from its defaults with
 * the given struct_size and calls the entry point. */
typedef gm_status call_fn(gm_domain *domain, size_t size);

static gm_status call_material(gm_domain *domain, size_t size) {
  gm_material_def def = gm_material_def_default();
  def.update = no_stress;
  def.p_wave_modulus = 1e6; /* Pa */
  def.density = 1000.0;     /* kg/m^3 */
  def.struct_size = size;
  int id;
  return gm_domain_add_material(domain, &def, &id);
}

#define CALL_ADD(type, function)                                               \
  static gm_status call_##type(gm_domain *domain, size_t size) {               \
    gm_##type##_def def = gm_##type##_def_default();                           \
    def.struct_size = size;                                                    \
    int id;                                                                    \
    return function(domain, &def, &id);                                        \
  }
CALL_ADD(elastic, gm_domain_add_elastic)
CALL_ADD(wall, gm_domain_add_wall)
CALL_ADD(rigid, gm_domain_add_rigid)
CALL_ADD(drucker_prager, gm_domain_add_drucker_prager)
CALL_ADD(filling, gm_domain_add_filling)
CALL_ADD(mohr_coulomb, gm_domain_add_mohr_coulomb)
CALL_ADD(perzyna, gm_domain_add_perzyna)
CALL_ADD(stress_free, gm_domain_add_stress_free)
CALL_ADD(von_mises, gm_domain_add_von_mises)
CALL_ADD(mu_i, gm_domain_add_mu_i)

static gm_status call_source(gm_domain *domain, size_t size) {
  gm_source_def def = gm_source_def_default();
  def.material = 0;
  def.count = 1;
  def.position = point;
  def.point_size = 0.05; /* m */
  def.struct_size = size;
  int id;
  return gm_domain_add_source(domain, &def, &id);
}

static gm_status call_sink(gm_domain *domain, size_t size) {
  gm_sink_def def = gm_sink_def_default();
  def.upper[0] = def.upper[1] = 0.1; /* m */
  def.struct_size = size;
  int id;
  return gm_domain_add_sink(domain, &def, &id);
}

static gm_status call_granular(gm_domain *domain, size_t size) {
  gm_granular_def def = gm_granular_def_default();
  def.critical_density = 990.0; /* kg/m^3, below the material's 1000 */
  def.struct_size = size;
  return gm_domain_set_granular(domain, 0, &def);
}

static gm_status call_points(gm_domain *domain, size_t size) {
  gm_points_def def = gm_points_def_default();
  def.count = 1;
  def.material = 0;
  def.position = point;
  def.volume = volume;
  def.struct_size = size;
  return gm_domain_add_points(domain, &def, NULL);
}

static gm_status call_fill(gm_domain *domain, size_t size) {
  gm_fill_def def = gm_fill_def_default();
  def.material = 0;
  def.lower[0] = def.lower[1] = 0.2; /* m */
  def.upper[0] = def.upper[1] = 0.4; /* m */
  def.struct_size = size;
  return gm_domain_fill_box(domain, &def, NULL, NULL);
}

static gm_status call_wall_force(gm_domain *domain, size_t size) {
  gm_wall_def wall = gm_wall_def_default();
  int id;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &id));
  gm_wall_force force = gm_wall_force_default();
  force.struct_size = size;
  return gm_domain_get_wall_force(domain, id, &force);
}

static gm_status call_rigid_load(gm_domain *domain, size_t size) {
  gm_rigid_def rigid = gm_rigid_def_default();
  int id;
  TEST_ASSERT_OK(domain, gm_domain_add_rigid(domain, &rigid, &id));
  gm_rigid_load load = gm_rigid_load_default();
  load.struct_size = size;
  return gm_domain_get_rigid_load(domain, id, &load);
}

static gm_status call_source_totals(gm_domain *domain, size_t size) {
  TEST_ASSERT_OK(domain, call_source(domain, sizeof(gm_source_def)));
  gm_flow_totals totals = gm_flow_totals_default();
  totals.struct_size = size;
  return gm_domain_get_source_totals(domain, 0, &totals);
}

static gm_status call_sink_totals(gm_domain *domain, size_t size) {
  TEST_ASSERT_OK(domain, call_sink(domain, sizeof(gm_sink_def)));
  gm_flow_totals totals = gm_flow_totals_default();
  totals.struct_size = size;
  return gm_domain_get_sink_totals(domain, 0, &totals);
}

static gm_status call_granular_summary(gm_domain *domain, size_t size) {
  gm_granular_summary summary = gm_granular_summary_default();
  summary.struct_size = size;
  return gm_domain_get_granular_summary(domain, &summary);
}

static gm_status call_summary(gm_domain *domain, size_t size) {
  gm_summary summary = gm_summary_default();
  summary.struct_size = size;
  return gm_domain_get_summary(domain, &summary);
}

typedef struct layout_case {
  const char *structure; /* named in the refusal */
  size_t size;           /* sizeof, this header */
  call_fn *call;
} layout_case;

#define CASE(type, call)                                                       \
  { #type, sizeof(type), call }
static const layout_case cases[] = {
    CASE(gm_material_def, call_material),
    CASE(gm_elastic_def, call_elastic),
    CASE(gm_wall_def, call_wall),
    CASE(gm_rigid_def, call_rigid),
    CASE(gm_source_def, call_source),
    CASE(gm_sink_def, call_sink),
    CASE(gm_granular_def, call_granular),
    CASE(gm_points_def, call_points),
    CASE(gm_fill_def, call_fill),
    CASE(gm_drucker_prager_def, call_drucker_prager),
    CASE(gm_filling_def, call_filling),
    CASE(gm_mohr_coulomb_def, call_mohr_coulomb),
    CASE(gm_perzyna_def, call_perzyna),
    CASE(gm_stress_free_def, call_stress_free),
    CASE(gm_von_mises_def, call_von_mises),
    CASE(gm_mu_i_def, call_mu_i),
    CASE(gm_wall_force, call_wall_force),
    CASE(gm_rigid_load, call_rigid_load),
    CASE(gm_flow_totals, call_source_totals),
    CASE(gm_flow_totals, call_sink_totals),
    CASE(gm_granular_summary, call_granular_summary),
    CASE(gm_summary, call_summary),
};
#define CASE_COUNT ((int)(sizeof cases / sizeof cases[0]))

/* Current size: accepted. */
START_TEST(test_current_size_accepted) {
  const layout_case *c = &cases[_i];
  gm_domain *domain = fresh_domain();
  gm_status status = c->call(domain, c->size);
  ck_assert_msg(status == GM_OK, "%s of %zu bytes: %s (%s)", c->structure,
                c->size, gm_strerror(status), gm_domain_last_error(domain));
  gm_domain_destroy(domain);
}
END_TEST

/* One byte short of the current layout, and a bare size_t: refused with a
 * message naming the structure and both sizes, and nothing registered (the
 * material count and point count unchanged). */
START_TEST(test_short_size_refused) {
  const layout_case *c = &cases[_i];
  const size_t shorts[2] = {c->size - 1, sizeof(size_t)};
  for (int k = 0; k < 2; k++) {
    gm_domain *domain = fresh_domain();
    size_t points_before = gm_domain_point_count(domain);
    gm_status status = c->call(domain, shorts[k]);
    ck_assert_msg(status == GM_ERR_STRUCT_SIZE, "%s of %zu bytes: %s",
                  c->structure, shorts[k], gm_strerror(status));
    char expected[160];
    snprintf(expected, sizeof expected, "%s.struct_size is %zu, expected %zu",
             c->structure, shorts[k], c->size);
    const char *message = gm_domain_last_error(domain);
    ck_assert_msg(strstr(message, expected), "message '%s' lacks '%s'", message,
                  expected);
    ck_assert_uint_eq(gm_domain_point_count(domain), points_before);
    /* The domain still takes the same call with the right size: nothing
     * of the refused one was kept (a second material or wall fits). */
    ck_assert_int_eq(c->call(domain, c->size), GM_OK);
    gm_domain_destroy(domain);
  }
}
END_TEST

/* Every earlier gm_domain_def layout: the caller's bytes past it are
 * garbage (0xab, which as `shape`, `family` or `transfer` is no enum value
 * and as `damping` or `pic_fraction` a negative number), so the create
 * succeeds only if those fields took their defaults. The same bytes in a
 * full-size definition are refused, which shows they would be. */
START_TEST(test_domain_def_earlier_layouts) {
  const size_t earlier[] = {
      offsetof(gm_domain_def, damping), offsetof(gm_domain_def, shape),
      offsetof(gm_domain_def, family), offsetof(gm_domain_def, pic_fraction),
      offsetof(gm_domain_def, transfer)};
  for (size_t k = 0; k < sizeof earlier / sizeof earlier[0]; k++) {
    gm_domain_def def;
    memset(&def, 0xab, sizeof def);
    ck_assert_int_eq(gm_domain_def_init(&def, earlier[k]), GM_OK);
    gm_domain *domain = NULL;
    gm_status status = gm_domain_create(&def, &domain);
    ck_assert_msg(status == GM_OK, "earlier layout of %zu bytes: %s",
                  earlier[k], gm_last_create_error());
    gm_domain_destroy(domain);
    def.struct_size = sizeof def; /* the garbage is now the caller's */
    ck_assert_int_eq(gm_domain_create(&def, &domain), GM_ERR_INVALID_ARGUMENT);
    /* One byte short of the earlier layout is none. */
    def.struct_size = earlier[k] - 1;
    ck_assert_int_eq(gm_domain_create(&def, &domain), GM_ERR_STRUCT_SIZE);
    char expected[160];
    snprintf(expected, sizeof expected,
             "gm_domain_def.struct_size is %zu, expected %zu", earlier[k] - 1,
             sizeof def);
    ck_assert_msg(strstr(gm_last_create_error(), expected),
                  "message '%s' lacks '%s'", gm_last_create_error(), expected);
  }
  gm_domain_def def = gm_domain_def_default();
  def.struct_size = sizeof def - 1;
  gm_domain *domain = NULL;
  ck_assert_int_eq(gm_domain_create(&def, &domain), GM_ERR_STRUCT_SIZE);
  ck_assert_ptr_null(domain);
  ck_assert_ptr_nonnull(strstr(gm_last_create_error(), "gm_domain_def"));
}
END_TEST

/* The gm_wall_force layout before the impulse fields: the force fields are
 * those of a full-size call after the same step, the bytes past the
 * layout are not written, and struct_size stays the caller's. A block of
 * material resting on a floor wall gives a nonzero force to compare. */
START_TEST(test_wall_force_earlier_layout) {
  gm_domain_def def = gm_domain_def_default();
  def.gravity[1] = -9.81; /* m/s^2 */
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  gm_wall_def wall = gm_wall_def_default();
  wall.point[1] = 0.1; /* m, a node row */
  int wall_id;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  const double lower[3] = {0.3, 0.1, 0.0}, upper[3] = {0.7, 0.5, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-4));

  gm_wall_force full = gm_wall_force_default();
  TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, wall_id, &full));
  ck_assert(full.normal > 0.0); /* the floor pushes up on the block */

  size_t old_size = offsetof(gm_wall_force, impulse);
  gm_wall_force old;
  memset(&old, 0xab, sizeof old);
  old.struct_size = old_size;
  TEST_ASSERT_OK(domain, gm_domain_get_wall_force(domain, wall_id, &old));
  ck_assert_uint_eq(old.struct_size, old_size);
  for (int k = 0; k < 3; k++)
    ck_assert(old.force[k] == full.force[k]);
  ck_assert(old.normal == full.normal);
  ck_assert(old.tangential == full.tangential);
  const unsigned char *bytes = (const unsigned char *)&old;
  for (size_t k = old_size; k < sizeof old; k++)
    ck_assert_uint_eq(bytes[k], 0xab);

  old.struct_size = old_size - 1;
  ck_assert_int_eq(gm_domain_get_wall_force(domain, wall_id, &old),
                   GM_ERR_STRUCT_SIZE);
  ck_assert_ptr_nonnull(
      strstr(gm_domain_last_error(domain), "gm_wall_force.struct_size"));
  gm_domain_destroy(domain);
}
END_TEST

/* gm_allocator, taken by gm_set_allocator without a domain: one byte short
 * and a bare size_t are refused with the message in
 * gm_last_create_error() (naming the structure and both sizes), and the
 * allocator in force stays the one installed before (a domain created
 * after the refusals allocates through it, never through the refused
 * hook); the current size and a larger one are accepted. */
static long refused_calls; /* calls to the refused hook: must stay 0 */
static long kept_calls;    /* calls to the hook installed first */
static void *refused_malloc(size_t size, void *user) {
  (void)user;
  refused_calls++;
  return malloc(size);
}
static void *kept_malloc(size_t size, void *user) {
  (void)user;
  kept_calls++;
  return malloc(size);
}
static void plain_free(void *pointer, void *user) {
  (void)user;
  free(pointer);
}

START_TEST(test_allocator_size) {
  gm_allocator kept = {sizeof(gm_allocator), kept_malloc, plain_free, NULL};
  ck_assert_int_eq(gm_set_allocator(&kept), GM_OK);
  gm_allocator refused = {sizeof(gm_allocator), refused_malloc, plain_free,
                          NULL};
  const size_t shorts[2] = {sizeof(gm_allocator) - 1, sizeof(size_t)};
  for (int k = 0; k < 2; k++) {
    refused.struct_size = shorts[k];
    ck_assert_int_eq(gm_set_allocator(&refused), GM_ERR_STRUCT_SIZE);
    char expected[160];
    snprintf(expected, sizeof expected,
             "gm_allocator.struct_size is %zu, expected %zu", shorts[k],
             sizeof(gm_allocator));
    ck_assert_msg(strstr(gm_last_create_error(), expected),
                  "message '%s' lacks '%s'", gm_last_create_error(), expected);
  }
  kept_calls = refused_calls = 0;
  gm_domain *domain = fresh_domain();
  gm_domain_destroy(domain);
  ck_assert_int_eq(refused_calls, 0);
  ck_assert_int_gt(kept_calls, 0);
  /* The current size, and a larger one (its extra bytes ignored). */
  refused.struct_size = sizeof(gm_allocator);
  ck_assert_int_eq(gm_set_allocator(&refused), GM_OK);
  refused.struct_size = sizeof(gm_allocator) + 8;
  ck_assert_int_eq(gm_set_allocator(&refused), GM_OK);
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
}
END_TEST

static Suite *layouts_suite(void) {
  Suite *suite = suite_create("layouts");
  TCase *tcase = tcase_create("struct_size");
  tcase_add_loop_test(tcase, test_current_size_accepted, 0, CASE_COUNT);
  tcase_add_loop_test(tcase, test_short_size_refused, 0, CASE_COUNT);
  tcase_add_test(tcase, test_domain_def_earlier_layouts);
  tcase_add_test(tcase, test_wall_force_earlier_layout);
  tcase_add_test(tcase, test_allocator_size);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(layouts_suite()) == 0 ? 0 : 1;
}
