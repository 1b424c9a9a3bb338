/*
 * key_sort.c - the block keys sorted ascending in place, without allocation
 * or callback, in O(n log n) at worst: an introsort (quicksort, insertion
 * for short ranges, heapsort past the depth limit). The contract is in
 * key_sort.h. Moved unchanged from block_grid.c (issue 15), where it had
 * replaced qsort (docs/performance.md, "The granular cloud").
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "core/core.h"

#include "core/key_sort.h"

static void swap_keys(int64_t *keys, size_t a, size_t b) {
  int64_t kept = keys[a];
  keys[a] = keys[b];
  keys[b] = kept;
}

void gm_key_insertion_sort(int64_t *keys, size_t count) {
  for (size_t i = 1; i < count; i++) {
    int64_t key = keys[i];
    size_t j = i;
    for (; j > 0 && keys[j - 1] > key; j--)
      keys[j] = keys[j - 1];
    keys[j] = key;
  }
}

/* Heapsort: the fallback that bounds the introsort at O(n log n). */
static void sift_down_keys(int64_t *keys, size_t root, size_t count) {
  for (size_t child = 2 * root + 1; child < count; child = 2 * root + 1) {
    if (child + 1 < count && keys[child + 1] > keys[child])
      child++;
    if (keys[root] >= keys[child])
      return;
    swap_keys(keys, root, child);
    root = child;
  }
}

static void heap_sort_keys(int64_t *keys, size_t count) {
  for (size_t root = count / 2; root-- > 0;)
    sift_down_keys(keys, root, count);
  for (size_t end = count; end-- > 1;) {
    swap_keys(keys, 0, end);
    sift_down_keys(keys, 0, end);
  }
}

/* Partitions around the median of the first, middle and last keys (moved
 * to the front); returns the pivot's final index. */
static size_t partition_keys(int64_t *keys, size_t count) {
  size_t middle = count / 2, last = count - 1;
  if (keys[middle] < keys[0])
    swap_keys(keys, middle, 0);
  if (keys[last] < keys[0])
    swap_keys(keys, last, 0);
  if (keys[last] < keys[middle])
    swap_keys(keys, last, middle);
  swap_keys(keys, 0, middle); /* the median as the pivot, at 0 */
  int64_t pivot = keys[0];
  size_t low = 1, high = last; /* keys[last] >= pivot: a sentinel */
  for (;;) {
    while (keys[low] < pivot)
      low++;
    while (keys[high] > pivot)
      high--;
    if (low >= high)
      break;
    swap_keys(keys, low++, high--);
  }
  swap_keys(keys, 0, high);
  return high;
}

/* Sorts keys ascending in place: quicksort down to small ranges, heapsort
 * past depth partition levels (gm_key_sort: 2 floor(log2 count)). */
void gm_key_introsort(int64_t *keys, size_t count, int depth) {
  while (count > GM_KEY_SORT_SMALL) {
    if (depth-- == 0) {
      heap_sort_keys(keys, count);
      return;
    }
    size_t pivot = partition_keys(keys, count);
    /* Recurse into the smaller side, loop on the larger: the depth of
     * the recursion stays below log2(count). */
    if (pivot < count - pivot - 1) {
      gm_key_introsort(keys, pivot, depth);
      keys += pivot + 1;
      count -= pivot + 1;
    } else {
      gm_key_introsort(keys + pivot + 1, count - pivot - 1, depth);
      count = pivot;
    }
  }
  gm_key_insertion_sort(keys, count);
}

/* The depth limit 2 floor(log2 count): twice the levels of perfectly
 * balanced partitions, so quicksort finishes unless its pivots are poor
 * for long, and heapsort then bounds the rest at O(n log n). */
void gm_key_sort(int64_t *keys, size_t count) {
  int depth = 0;
  for (size_t n = count; n > 1; n >>= 1)
    depth += 2;
  gm_key_introsort(keys, count, depth);
}
