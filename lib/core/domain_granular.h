/*
 * domain_granular.h - the per-step work arrays of the granular family
 * (gm_granular_work) that the domain embeds. What works on them is declared
 * in granular/granular.h. Private to core/: included through
 * core/domain.h.
 */
#ifndef GM_DOMAIN_GRANULAR_H
#define GM_DOMAIN_GRANULAR_H

#include "core/core.h"

/* Declared in granular/interaction.h; the work arrays only point to it. */
typedef struct gm_interaction_domain gm_interaction_domain;
typedef struct gm_interaction_domain3 gm_interaction_domain3;

/* ----------------------------------------------------- granular scratch */
/* Per-step work arrays of the granular family (components.c), sized with
 * the points and the blocks outside the step's hot path. */
typedef struct gm_granular_work {
  size_t capacity; /* points */
  /* Node box of each point's support. 32 bits suffice: a domain has at
   * most 1e9 cells per axis (domain.c), so node indices stay below
   * 1e9 + 2 ghost layers + 1 < INT32_MAX; half the bytes of int64_t
   * (16 B per point). */
  int32_t *support_low[3]; /* z: 3D only */
  /* Highest node, stored only for the variants whose span varies (GIMP,
   * CPDI); NULL for linear MPM and the B-splines, whose support always
   * spans support_reach + 1 nodes per axis (8 B per point fewer). */
  int32_t *support_high[3];
  int32_t support_reach; /* nodes past the lowest: 1 linear, 2 or 3 B-spline;
                            0 with support_high stored */
  gm_interaction_domain *interaction;   /* per point; CPDI only (NULL
                                           otherwise) */
  gm_interaction_domain3 *interaction3; /* the same in 3D (parallelepipeds) */
  /* The same for the rectangle variants, SoA for the pair search: centre
   * (the committed positions, not owned) and half edges (m; not CPDI:
   * NULL there); and whether the point's material is granular. */
  const double *box_centre[3];
  double *box_half[3]; /* z: 3D only */
  uint8_t *granular;
  uint32_t *parent; /* union-find */
  uint32_t *set_size;
  /* Component of each point: not owned, the component array of the next
   * point buffer, where the step commits it (components.c). */
  int32_t *label;
  uint32_t *component_size; /* points per component */
  /* Node layer of each component; before the layers, the labelling's
   * scratch (union_find.h), with layer_stamp. */
  int32_t *component_layer;
  int32_t *layer_stamp; /* greedy colouring: last component per layer */
  uint32_t *cell_order; /* points by block, then local cell */
  uint32_t *cell_start; /* per block, GM_BLOCK_NODES + 1 offsets */
  size_t cell_capacity; /* blocks cell_start holds */
  uint64_t *conflict;   /* candidate point pairs of the search, then the
                           pairs of components sharing a node */
  size_t conflict_count, conflict_capacity;
  /* CSR of the conflicts per component (components + 1 offsets); 8 bytes
   * per point, so that between steps it also holds the kept forest's
   * edges while gm_granular_remap_forest sorts them. */
  uint32_t *adjacency_start;
  int32_t *adjacency;
  size_t adjacency_capacity;
  /* Spanning forest of the last search (edges p << 32 | q by point index):
   * valid while the committed points keep their indices (no reordering,
   * addition or removal), it lets the next step re-check N - C pairs
   * instead of searching all of them (components.c). */
  uint64_t *forest;
  size_t forest_count;
  bool forest_valid;
  /* The points of the union-find (parent, set_size) the last search left,
   * whose sets are the kept forest's (0: none, or renamed since by a
   * reordering): a step whose kept edges all hold starts from them
   * (components.c). */
  size_t sets_count;
  /* Whether the component array of point buffer labels_buffer holds the
   * labels of the kept forest's sets (labels_components of them): a step
   * whose sets did not change copies them instead of labelling again. */
  bool labels_kept;
  int labels_buffer;
  size_t labels_components;
  uint8_t *visit;    /* points to search from when the forest is reused */
  bool cells_sorted; /* cell_start marks this step's unsorted blocks */
  /* box_half depends only on per-point constants for linear MPM and uGIMP
   * (the initial domain scaled to V_cr): kept while the points keep their
   * indices, and recomputed after any addition, removal or reordering. */
  bool boxes_valid;
  /* Linear MPM with cached boxes, every point granular, and every box's
   * half edge below 0.45 cell per axis: two interaction boxes that
   * overlap are then less than 0.9 cell apart per axis, so the points'
   * cells differ by at most one and their supports share a node
   * (components.c, box_edges_hold_2d), and the supports are computed
   * only when a search follows the check. Set with the boxes. */
  bool overlap_shares_node;
  /* Of the step in progress, committed with it. */
  gm_granular_summary summary;
} gm_granular_work;

#endif
