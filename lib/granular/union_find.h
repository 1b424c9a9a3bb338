/*
 * union_find.h - disjoint sets over point indices (path halving, union by
 * size) and deterministic component labels: components are numbered
 * 0, 1, ... in increasing order of their smallest point id, so the labels
 * depend neither on the point order nor on the order of the unions.
 */
#ifndef GM_UNION_FIND_H
#define GM_UNION_FIND_H

#include <stddef.h>
#include <stdint.h>

/* parent and size: count entries each, owned by the caller. */
void gm_union_find_init(uint32_t *parent, uint32_t *size, size_t count);
/* The root of element's set, halving the path on the way. Inline: the
 * pair search, the forest's rejoin and the labels call it a few times per
 * point and step (about 20 instructions per point-step of the granular
 * cloud went to the calls). */
static inline uint32_t gm_union_find_root(uint32_t *parent, uint32_t element) {
  while (parent[element] != element) {
    parent[element] = parent[parent[element]]; /* path halving */
    element = parent[element];
  }
  return element;
}
/* Joins the sets of a and b; returns 1 if they were separate, else 0. */
int gm_union_find_join(uint32_t *parent, uint32_t *size, uint32_t a,
                       uint32_t b);
/* Writes label[i] for every element and returns the component count.
 * id: count distinct keys (point ids). scratch_first: count entries, the
 * element of smallest id of each set, then each set's label;
 * scratch_order: count entries, those elements sorted by id (one per
 * component). Both overwritten; 8 bytes per element, where a table of
 * (smallest id, root) pairs took 24. */
size_t gm_union_find_labels(uint32_t *parent, const int64_t *id, size_t count,
                            int32_t *label, uint32_t *scratch_first,
                            uint32_t *scratch_order);

/* The same labels without sorting, for ids that are indices into a map:
 * walks index_of_id[0..id_count) (entries equal to `absent` skipped) in id
 * order, so the first element met of each set has its smallest id and the
 * labels come out in order. O(id_count + count), against the sort's
 * O(C log C) for C components; scratch_label: count int32, overwritten. */
size_t gm_union_find_labels_by_id(uint32_t *parent, const uint32_t *index_of_id,
                                  size_t id_count, uint32_t absent,
                                  size_t count, int32_t *label,
                                  int32_t *scratch_label);

#endif
