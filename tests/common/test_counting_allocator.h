/*
 * test_counting_allocator.h - a gm_set_allocator hook that counts the
 * library's allocations and frees, for the tests of "no allocation inside a
 * step after warm-up" (tests/api/test_allocation.c and the 3D and option
 * tests that repeat it for their paths), and that can fail the n-th
 * allocation to inject an out-of-memory. Every test file that includes it
 * gets its own counters.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_TEST_COUNTING_ALLOCATOR_H
#define GM_TEST_COUNTING_ALLOCATOR_H

#include <check.h>
#include <stdatomic.h>
#include <stdlib.h>

#include "granmpm.h"

static atomic_long test_allocations; /* calls to the hook's malloc */
static atomic_long test_releases;    /* calls to the hook's free (non-NULL) */
/* >= 0: that many more allocations succeed, then one fails; -1: none fails */
static atomic_long test_fail_countdown = -1;

static inline void *test_counting_malloc(size_t size, void *user) {
  (void)user;
  if (atomic_load(&test_fail_countdown) >= 0 &&
      atomic_fetch_sub(&test_fail_countdown, 1) == 0)
    return NULL; /* the injected out-of-memory */
  atomic_fetch_add(&test_allocations, 1);
  return malloc(size);
}

static inline void test_counting_free(void *pointer, void *user) {
  (void)user;
  if (pointer)
    atomic_fetch_add(&test_releases, 1);
  free(pointer);
}

/* Installs the hook for the whole process (gm_set_allocator) and zeroes the
 * counters; gm_set_allocator(NULL) puts the default allocator back. */
static inline void test_install_counting_allocator(void) {
  gm_allocator allocator = {sizeof(gm_allocator), test_counting_malloc,
                            test_counting_free, NULL};
  ck_assert_int_eq(gm_set_allocator(&allocator), GM_OK);
  atomic_store(&test_allocations, 0);
  atomic_store(&test_releases, 0);
  atomic_store(&test_fail_countdown, -1);
}

#endif /* GM_TEST_COUNTING_ALLOCATOR_H */
