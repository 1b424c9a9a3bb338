/*
 * test_allocation.c - "no allocation inside a step after warm-up": every
 * library allocation goes through the gm_set_allocator hook, so a counting
 * allocator sees them all. After a few warm-up steps (the grid and the
 * per-step work arrays reach their size), further steps of a scene whose
 * occupied region stays the same must not allocate at all, with one or two
 * workers and with each update scheme. Also checks that every allocation is
 * freed by gm_domain_destroy (the counts balance).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <stdatomic.h>
#include <stdlib.h>

#include "test_util.h"

static atomic_long allocations; /* calls to the hook's malloc */
static atomic_long releases;    /* calls to the hook's free (non-NULL) */

static void *counting_malloc(size_t size, void *user) {
  (void)user;
  atomic_fetch_add(&allocations, 1);
  return malloc(size);
}

static void counting_free(void *pointer, void *user) {
  (void)user;
  if (pointer)
    atomic_fetch_add(&releases, 1);
  free(pointer);
}

static void install_counting_allocator(void) {
  gm_allocator allocator = {sizeof(gm_allocator), counting_malloc,
                            counting_free, NULL};
  ck_assert_int_eq(gm_set_allocator(&allocator), GM_OK);
  atomic_store(&allocations, 0);
  atomic_store(&releases, 0);
}

/* An elastic block resting on a fixed floor under gravity: it compresses
 * and oscillates but stays in the same cells, so after warm-up the set of
 * grid blocks, hence every work array, keeps its size. */
static gm_domain *resting_block(gm_update_scheme scheme, int workers) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = 0.05;
  def.extent[0] = def.extent[1] = 2.0;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double lower[3] = {0.5, 0.0, 0.0}, upper[3] = {1.5, 0.6, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  return domain;
}

START_TEST(test_no_allocation_after_warm_up) {
  static const gm_update_scheme schemes[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                              GM_SCHEME_USF};
  gm_update_scheme scheme = schemes[_i % 3];
  int workers = 1 + _i / 3;
  install_counting_allocator();
  gm_domain *domain = resting_block(scheme, workers);
  enum { WARM_UP_STEPS = 5, MEASURED_STEPS = 200 };
  for (int step = 0; step < WARM_UP_STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, -1.0));
  long before = atomic_load(&allocations);
  for (int step = 0; step < MEASURED_STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, -1.0));
  long during = atomic_load(&allocations) - before;
  ck_assert_msg(during == 0,
                "%s, %d workers: %ld allocations in %d steps after warm-up",
                test_scheme_name(scheme), workers, during, MEASURED_STEPS);
  gm_domain_destroy(domain);
  ck_assert_msg(atomic_load(&allocations) == atomic_load(&releases),
                "allocations %ld != frees %ld after destroy",
                atomic_load(&allocations), atomic_load(&releases));
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("allocation");
  TCase *tcase = tcase_create("steady_state");
  tcase_set_timeout(tcase, 60);
  tcase_add_loop_test(tcase, test_no_allocation_after_warm_up, 0, 6);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
