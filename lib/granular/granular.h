/*
 * granular.h - the granular folder: the granular phase of a step
 * (components.c: domains of interaction, components, node layers), the
 * pair search (pair_search.c), union-find (union_find.h), the layers
 * (layers.c), the density control after the stress update
 * (density_control.c), and gm_domain_set_granular (granular.c). Private
 * to the library.
 */
#ifndef GM_GRANULAR_H
#define GM_GRANULAR_H

#include "granular/interaction.h"
#include "granular/union_find.h"
#include "materials/materials.h"
#include "points/points.h"

/* Granular family (components.c, density_control.c, granular.c). */
/* After the plain binning: domains of interaction, components by
 * union-find, node layers; re-keys the points by layer (block_key, with
 * keys_valid set). With summary.layer_count > 1 the caller (step.c) bins
 * them again: the binning is in grid/, above this folder. */
gm_status gm_granular_prepare(gm_domain *domain);
/* After the stress update of a chunk: stress-free and density-control
 * rules of the stress_free and granular families (000 eqs 13-15, 18). */
void gm_density_control_chunk(gm_domain *domain, size_t first, size_t count);
/* Pair search (pair_search.c) and layers (layers.c). */
typedef enum gm_pair_pass { GM_PASS_JOIN, GM_PASS_CONFLICTS } gm_pair_pass;
/* Every pair sharing a node: from every point with half windows (subset
 * NULL), or from the points with subset[p] != 0 with full windows. JOIN
 * unites interacting pairs and records the forest; a subset search also
 * appends the pairs of different sets that do not interact to
 * work->conflict (point indices p << 32 | q: the candidates for the
 * conflicts of the layers, kept by components.c). CONFLICTS appends the
 * pairs of components that share a node (label low << 32 | high). */
gm_status gm_pair_search(gm_domain *domain, const int max_span[3],
                         gm_pair_pass pass, const uint8_t *subset);
gm_status gm_assign_layers(gm_domain *domain, size_t components,
                           size_t *layer_count);
/* Follows a reordering (points->order: new index k holds old order[k])
 * in the kept spanning forest; scratch: count entries. */
void gm_granular_remap_forest(gm_domain *domain, uint32_t *scratch);
/* Nodes past the lowest one that a support of `shape` always spans per
 * axis (linear 1, quadratic B-spline 2, cubic 3), or 0 where it varies
 * (GIMP, CPDI: the highest node is then stored). */
static inline int32_t gm_fixed_support_reach(gm_shape shape) {
  switch (shape) {
  case GM_SHAPE_LINEAR:
    return 1;
  case GM_SHAPE_BSPLINE2:
    return 2;
  case GM_SHAPE_BSPLINE3:
    return 3;
  default:
    return 0;
  }
}
/* Highest node of point p's support along axis k. */
static inline int32_t gm_support_high(const gm_granular_work *work, int k,
                                      size_t p) {
  return work->support_high[k] ? work->support_high[k][p]
                               : work->support_low[k][p] + work->support_reach;
}
/* Sizes the granular work arrays for the points and blocks. */
gm_status gm_granular_reserve(gm_domain *domain);
void gm_granular_free(gm_domain *domain);

#endif
