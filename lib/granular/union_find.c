/*
 * union_find.c - disjoint sets and deterministic labels (see union_find.h).
 */
#include "granular/granular.h"

void gm_union_find_init(uint32_t *parent, uint32_t *size, size_t count) {
  for (size_t i = 0; i < count; i++) {
    parent[i] = (uint32_t)i;
    size[i] = 1;
  }
}

int gm_union_find_join(uint32_t *parent, uint32_t *size, uint32_t a,
                       uint32_t b) {
  a = gm_union_find_root(parent, a);
  b = gm_union_find_root(parent, b);
  if (a == b)
    return 0;
  if (size[a] < size[b]) { /* the larger set's root stays: shallow trees */
    uint32_t swap = a;
    a = b;
    b = swap;
  }
  parent[b] = a;
  size[a] += size[b];
  return 1;
}

/* Restores the heap order of order[0..count) below position `at`, the
 * largest id on top. */
static void sift_down(uint32_t *order, size_t at, size_t count,
                      const int64_t *id) {
  for (;;) {
    size_t child = 2 * at + 1;
    if (child >= count)
      return;
    if (child + 1 < count && id[order[child + 1]] > id[order[child]])
      child++;
    if (id[order[child]] <= id[order[at]])
      return;
    uint32_t swap = order[at];
    order[at] = order[child];
    order[child] = swap;
    at = child;
  }
}

/* Heapsort of order[0..count) by increasing id[order[k]]: in place (no
 * scratch, no recursion; qsort would need the ids in the sorted records).
 * The ids are distinct, so every sort gives this one order. */
static void sort_by_id(uint32_t *order, size_t count, const int64_t *id) {
  for (size_t k = count / 2; k > 0; k--)
    sift_down(order, k - 1, count, id);
  for (size_t end = count; end > 1; end--) {
    uint32_t swap = order[0];
    order[0] = order[end - 1];
    order[end - 1] = swap;
    sift_down(order, 0, end - 1, id);
  }
}

size_t gm_union_find_labels(uint32_t *parent, const int64_t *id, size_t count,
                            int32_t *label, uint32_t *scratch_first,
                            uint32_t *scratch_order) {
  for (size_t i = 0; i < count; i++) /* path halving keeps roots roots */
    if (parent[i] == i)
      scratch_first[i] = (uint32_t)i;
  for (size_t i = 0; i < count; i++) {
    uint32_t root = gm_union_find_root(parent, (uint32_t)i);
    if (id[i] < id[scratch_first[root]])
      scratch_first[root] = (uint32_t)i;
  }
  size_t components = 0;
  for (size_t i = 0; i < count; i++)
    if (parent[i] == i)
      scratch_order[components++] = scratch_first[i];
  sort_by_id(scratch_order, components, id);
  /* The label of each root, kept in scratch_first (no longer needed). */
  for (size_t c = 0; c < components; c++)
    scratch_first[gm_union_find_root(parent, scratch_order[c])] = (uint32_t)c;
  for (size_t i = 0; i < count; i++)
    label[i] = (int32_t)scratch_first[gm_union_find_root(parent, (uint32_t)i)];
  return components;
}

size_t gm_union_find_labels_by_id(uint32_t *parent, const uint32_t *index_of_id,
                                  size_t id_count, uint32_t absent,
                                  size_t count, int32_t *label,
                                  int32_t *scratch_label) {
  for (size_t i = 0; i < count; i++)
    scratch_label[i] = -1;
  size_t components = 0;
  for (size_t id = 0; id < id_count; id++) {
    uint32_t element = index_of_id[id];
    if (element == absent)
      continue;
    uint32_t root = gm_union_find_root(parent, element);
    if (scratch_label[root] < 0)
      scratch_label[root] = (int32_t)components++;
  }
  for (size_t i = 0; i < count; i++)
    label[i] = scratch_label[gm_union_find_root(parent, (uint32_t)i)];
  return components;
}
