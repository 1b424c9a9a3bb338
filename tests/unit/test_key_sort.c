/*
 * test_key_sort.c - the block-key sort (lib/core/key_sort.c) against the C
 * library's qsort. Each input is sorted twice, once by the function under
 * test and once by qsort on a copy, and the two arrays must be equal key for
 * key. The tolerance is zero: a sort is exact, and with distinct keys there
 * is exactly one ascending order, so any difference is a wrong answer (the
 * reference is checked to be strictly ascending, i.e. the inputs keep the
 * contract's distinct keys).
 *
 * Every path is forced on every input:
 *   - gm_key_sort as the block grid calls it (depth limit 2 floor(log2 n));
 *   - gm_key_introsort with depth limits 0 to 3: depth 0 heapsorts the
 *     whole array (n > GM_KEY_SORT_SMALL), 1 to 3 heapsort the ranges left
 *     after one to three partitions, at an offset into the array;
 *   - gm_key_insertion_sort alone, on the sizes up to 100 (its O(n^2) on
 *     100 000 reversed keys, ~5e9 moves, is the "slow" case below).
 * Sizes 0, 1, 2 (edges), 15, 16, 17 (around GM_KEY_SORT_SMALL = 16, where
 * the introsort hands over to insertion), 100 and 100 000. Inputs: random,
 * sorted, reversed, organ-pipe, sawtooth, negative keys spread from
 * INT64_MIN to INT64_MAX (both included), and Musser's median-of-three
 * killer, on which the depth limit is what keeps the introsort O(n log n):
 * with n = 100 000 an instrumented copy of the sort handed 99 936 of the
 * keys to heapsort: the 32 partitions the limit allows split off only 64
 * keys in all.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include <check.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/key_sort.h"
#include "test_random.h"

static const size_t SIZES[] = {0, 1, 2, 15, 16, 17, 100, 100000};
enum { SIZE_COUNT = sizeof SIZES / sizeof SIZES[0] };
/* The largest size gm_key_insertion_sort takes in the fast cases. */
static const size_t INSERTION_FAST_MAX = 100;

enum {
  INPUT_RANDOM,
  INPUT_SORTED,
  INPUT_REVERSED,
  INPUT_ORGAN_PIPE,
  INPUT_SAWTOOTH,
  INPUT_EXTREMES,
  INPUT_MEDIAN_KILLER,
  INPUT_COUNT
};
static const char *const INPUT_NAME[INPUT_COUNT] = {
    "random",   "sorted",   "reversed",          "organ-pipe",
    "sawtooth", "extremes", "median-of-3 killer"};

/* Successive states of the tests' LCG: its period is 2^64, so n < 2^64
 * states are distinct; as int64 about half are negative. */
static void fill_random(int64_t *keys, size_t n) {
  lcg_state = 0x5eed15u + n;
  for (size_t i = 0; i < n; i++) {
    lcg_uniform();
    keys[i] = (int64_t)lcg_state;
  }
}

/* 0, 2, 4, ... up, then ..., 5, 3, 1 down: distinct. */
static void fill_organ_pipe(int64_t *keys, size_t n) {
  size_t up = (n + 1) / 2;
  for (size_t i = 0; i < n; i++)
    keys[i] = i < up ? (int64_t)(2 * i) : (int64_t)(2 * (n - 1 - i) + 1);
}

/* Five ascending teeth; key (i mod tooth) * 5 + i / tooth is distinct as
 * i / tooth < 5. */
static void fill_sawtooth(int64_t *keys, size_t n) {
  size_t tooth = (n + 4) / 5;
  for (size_t i = 0; i < n; i++)
    keys[i] = (int64_t)((i % tooth) * 5 + i / tooth);
}

/* n keys evenly spread over the whole int64 range, INT64_MIN first and
 * INT64_MAX last, then shuffled (Fisher-Yates): half negative, both ends
 * in every array of two or more keys. */
static void fill_extremes(int64_t *keys, size_t n) {
  uint64_t step = n > 1 ? UINT64_MAX / (n - 1) : 0;
  for (size_t i = 0; i < n; i++) {
    uint64_t offset = i + 1 == n && n > 1 ? UINT64_MAX : i * step;
    /* Offset binary: 0 is INT64_MIN, UINT64_MAX is INT64_MAX. */
    keys[i] = (int64_t)(offset - (UINT64_MAX / 2 + 1));
  }
  lcg_state = 0xe57e3e5u + n;
  for (size_t i = n; i > 1; i--) {
    size_t j = (size_t)(lcg_uniform() * (double)i);
    int64_t kept = keys[i - 1];
    keys[i - 1] = keys[j];
    keys[j] = kept;
  }
}

/* Musser (1997), "Introspective sorting and selection algorithms", the
 * median-of-3 killer for n = 2k, k even: a[i] = i for odd i, k + i - 1 for
 * even i (i = 1..k), a[k + i] = 2 i: a permutation of 1..2k. Other sizes
 * take it on their largest multiple of 4, followed by the rest ascending. */
static void fill_median_killer(int64_t *keys, size_t n) {
  size_t m = n - n % 4, k = m / 2;
  for (size_t i = 1; i <= k; i++) {
    keys[i - 1] = (int64_t)(i % 2 ? i : k + i - 1);
    keys[k + i - 1] = (int64_t)(2 * i);
  }
  for (size_t i = m; i < n; i++)
    keys[i] = (int64_t)(i + 1);
}

static void fill_input(int input, int64_t *keys, size_t n) {
  switch (input) {
  case INPUT_RANDOM:
    fill_random(keys, n);
    break;
  case INPUT_SORTED:
    for (size_t i = 0; i < n; i++)
      keys[i] = 3 * (int64_t)i - (int64_t)n; /* some negative */
    break;
  case INPUT_REVERSED:
    for (size_t i = 0; i < n; i++)
      keys[i] = (int64_t)n - (int64_t)i;
    break;
  case INPUT_ORGAN_PIPE:
    fill_organ_pipe(keys, n);
    break;
  case INPUT_SAWTOOTH:
    fill_sawtooth(keys, n);
    break;
  case INPUT_EXTREMES:
    fill_extremes(keys, n);
    break;
  default:
    fill_median_killer(keys, n);
    break;
  }
}

static int compare_keys(const void *a, const void *b) {
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

enum { SORT_KEY_SORT = -1, SORT_INSERTION = -2 }; /* else: a depth >= 0 */

static void run_sort(int sort, int64_t *keys, size_t n) {
  if (sort == SORT_KEY_SORT)
    gm_key_sort(keys, n);
  else if (sort == SORT_INSERTION)
    gm_key_insertion_sort(keys, n);
  else
    gm_key_introsort(keys, n, sort);
}

/* Sorts input `input` of n keys with `sort` and with qsort; asserts the
 * reference strictly ascending and the two arrays equal key for key. */
static void check_against_qsort(int sort, int input, size_t n) {
  int64_t *keys = malloc((n ? n : 1) * sizeof *keys);
  int64_t *reference = malloc((n ? n : 1) * sizeof *reference);
  ck_assert_ptr_nonnull(keys);
  ck_assert_ptr_nonnull(reference);
  fill_input(input, keys, n);
  if (n)
    memcpy(reference, keys, n * sizeof *keys);
  qsort(reference, n, sizeof *reference, compare_keys);
  for (size_t i = 1; i < n; i++)
    REQUIRE(reference[i - 1] < reference[i],
            "%s, n = %zu: input keys %zu and %zu are equal (the contract "
            "wants distinct keys)",
            INPUT_NAME[input], n, i - 1, i);
  run_sort(sort, keys, n);
  for (size_t i = 0; i < n; i++)
    REQUIRE(keys[i] == reference[i],
            "sort %d, %s, n = %zu: key %zu is %lld, qsort's %lld", sort,
            INPUT_NAME[input], n, i, (long long)keys[i],
            (long long)reference[i]);
  free(keys);
  free(reference);
}

/* _i: the input. */
START_TEST(test_key_sort_every_size) {
  for (size_t s = 0; s < SIZE_COUNT; s++)
    check_against_qsort(SORT_KEY_SORT, _i, SIZES[s]);
}
END_TEST

START_TEST(test_forced_heapsort) {
  for (int depth = 0; depth <= 3; depth++)
    for (size_t s = 0; s < SIZE_COUNT; s++)
      check_against_qsort(depth, _i, SIZES[s]);
}
END_TEST

START_TEST(test_insertion_sort) {
  for (size_t s = 0; s < SIZE_COUNT; s++)
    if (SIZES[s] <= INSERTION_FAST_MAX)
      check_against_qsort(SORT_INSERTION, _i, SIZES[s]);
}
END_TEST

/* The insertion sort on the 100 000 keys too: the sizes up to 100 above
 * keep its path in the fast cases. */
START_TEST(test_insertion_sort_large) {
  for (size_t s = 0; s < SIZE_COUNT; s++)
    if (SIZES[s] > INSERTION_FAST_MAX)
      check_against_qsort(SORT_INSERTION, _i, SIZES[s]);
}
END_TEST

static Suite *key_sort_suite(void) {
  Suite *suite = suite_create("key_sort");
  TCase *paths = tcase_create("paths");
  tcase_add_loop_test(paths, test_key_sort_every_size, 0, INPUT_COUNT);
  tcase_add_loop_test(paths, test_forced_heapsort, 0, INPUT_COUNT);
  tcase_add_loop_test(paths, test_insertion_sort, 0, INPUT_COUNT);
  suite_add_tcase(suite, paths);
  TCase *large = tcase_create("insertion_large");
  /* O(n^2): ~5e9 key moves for the reversed input alone. */
  tcase_set_timeout(large, 600.0);
  tcase_set_tags(large, "slow");
  tcase_add_loop_test(large, test_insertion_sort_large, 0, INPUT_COUNT);
  suite_add_tcase(suite, large);
  return suite;
}

int main(void) {
  return test_run_suite(key_sort_suite()) == 0 ? 0 : 1;
}
