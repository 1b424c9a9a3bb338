/*
 * key_sort.h - the in-place sort of the block keys (core/block_grid.c,
 * gm_grid_build). Private to the library.
 *
 * The contract, all of it:
 *   - sorts `count` int64_t keys ascending, in place; the keys are
 *     distinct (block keys are), so the result is the one ascending order,
 *     whatever the algorithm: any correct sort gives the same bytes;
 *   - allocates nothing (it runs inside a step) and uses no callback;
 *   - O(n log n) comparisons in the worst case: an introsort (quicksort on
 *     the median of the first, middle and last keys, ranges of at most
 *     GM_KEY_SORT_SMALL keys finished by insertion) that falls back to
 *     heapsort past a depth limit of 2 floor(log2 count) partition levels;
 *   - its recursion goes into the smaller side of each partition only, so
 *     the stack stays below log2(count) frames.
 * tests/unit/test_key_sort.c checks every path against qsort.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_CORE_KEY_SORT_H
#define GM_CORE_KEY_SORT_H

#include <stddef.h>
#include <stdint.h>

/* Ranges of at most this many keys are finished by insertion. */
#define GM_KEY_SORT_SMALL 16

/* Sorts keys[0..count) ascending in place (the contract above). */
void gm_key_sort(int64_t *keys, size_t count);

/* The introsort of gm_key_sort with the given depth limit (>= 0): after
 * `depth` partition levels a range longer than GM_KEY_SORT_SMALL is
 * heapsorted (depth 0: the whole array, when count > GM_KEY_SORT_SMALL).
 * gm_key_sort passes 2 floor(log2 count); other depths are for the tests,
 * which force each path. */
void gm_key_introsort(int64_t *keys, size_t count, int depth);

/* Insertion sort, the introsort's finish of short ranges: O(count^2),
 * exposed for the tests. */
void gm_key_insertion_sort(int64_t *keys, size_t count);

#endif
