/*
 * union_find.c - disjoint sets and deterministic labels (see union_find.h).
 */
#include "granular/granular.h"

#include <stdlib.h>

void gm_union_find_init(uint32_t *parent, uint32_t *size, size_t count) {
  for (size_t i = 0; i < count; i++) {
    parent[i] = (uint32_t)i;
    size[i] = 1;
  }
}

uint32_t gm_union_find_root(uint32_t *parent, uint32_t element) {
  while (parent[element] != element) {
    parent[element] = parent[parent[element]]; /* path halving */
    element = parent[element];
  }
  return element;
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

/* qsort order of components: by smallest id (ids are distinct). */
static int compare_roots(const void *left, const void *right) {
  int64_t a = ((const gm_root_order *)left)->min_id;
  int64_t b = ((const gm_root_order *)right)->min_id;
  return (a > b) - (a < b);
}

size_t gm_union_find_labels(uint32_t *parent, const int64_t *id, size_t count,
                            int32_t *label, int64_t *scratch_min,
                            gm_root_order *scratch_roots) {
  for (size_t i = 0; i < count; i++)
    scratch_min[i] = INT64_MAX;
  for (size_t i = 0; i < count; i++) {
    uint32_t root = gm_union_find_root(parent, (uint32_t)i);
    if (id[i] < scratch_min[root])
      scratch_min[root] = id[i];
  }
  size_t components = 0;
  for (size_t i = 0; i < count; i++)
    if (parent[i] == i)
      scratch_roots[components++] =
          (gm_root_order){scratch_min[i], (uint32_t)i};
  qsort(scratch_roots, components, sizeof *scratch_roots, compare_roots);
  /* The label of each root, kept in scratch_min (minima no longer needed). */
  for (size_t c = 0; c < components; c++)
    scratch_min[scratch_roots[c].root] = (int64_t)c;
  for (size_t i = 0; i < count; i++)
    label[i] = (int32_t)scratch_min[gm_union_find_root(parent, (uint32_t)i)];
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
