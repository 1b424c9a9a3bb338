/*
 * pair_rules.h - the two tests of a candidate pair of the granular method
 * (000 sec 3.4, Tables A1-A2): do the points' supports share a grid node,
 * and do they interact. Inline: the search (pair_search.c) and the check
 * of the kept forest (components.c) run them once per pair or edge.
 */
#ifndef GRANMPM_PAIR_RULES_H
#define GRANMPM_PAIR_RULES_H

#include "granular/granular.h"

#include <math.h>

/* Do the supports of p and q share a node? With a fixed span (no highest
 * node stored, core/domain_granular.h) the lowest nodes are at most
 * support_reach apart: the same test, since high = low + support_reach exactly.
 */
static inline bool gm_supports_share_node(const gm_granular_work *work, int dim,
                                          uint32_t p, uint32_t q) {
  if (!work->support_high[0]) {
    int32_t reach = work->support_reach;
    for (int k = 0; k < dim; k++) {
      int32_t apart = work->support_low[k][p] - work->support_low[k][q];
      if (apart > reach || -apart > reach)
        return false;
    }
    return true;
  }
  for (int k = 0; k < dim; k++)
    if (work->support_low[k][p] > work->support_high[k][q] ||
        work->support_low[k][q] > work->support_high[k][p])
      return false;
  return true;
}

/* Task 1 for one candidate pair (rules at the top of components.c). Domains
 * of the rectangle variants are axis-aligned: interval tests decide. */
static inline bool gm_pair_interacts(const gm_domain *domain, uint32_t p,
                                     uint32_t q) {
  const gm_granular_work *work = &domain->granular;
  if (!work->granular[p] && !work->granular[q])
    return true;
  if (domain->shape_grid.shape == GM_SHAPE_CPDI && domain->dim == 3)
    return gm_interaction_overlap3(&work->interaction3[p],
                                   &work->interaction3[q]); /* 15 axes */
  if (domain->shape_grid.shape == GM_SHAPE_CPDI)
    return gm_interaction_overlap(domain->dim, &work->interaction[p],
                                  &work->interaction[q]);
  for (int k = 0; k < domain->dim; k++)
    if (!(fabs(work->box_centre[k][q] - work->box_centre[k][p]) <
          work->box_half[k][p] + work->box_half[k][q]))
      return false;
  return true;
}

#endif
