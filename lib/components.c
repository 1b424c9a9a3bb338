/*
 * components.c - parallel grids of the granular method (000 sec 3.3-3.4,
 * Tables A1-A3), run after the plain binning of each step:
 *
 *  1. each point's support (the node box it sends data to) and domain of
 *     interaction (interaction.h);
 *  2. the pre-task: candidate pairs are the points whose supports share a
 *     node. Points are bucketed by block and, inside it, by the cell of
 *     their support's lowest node, so a point looks only at the few cells
 *     whose points can reach its nodes: O(N), never all pairs;
 *  3. task 1: a candidate pair interacts if its domains of interaction
 *     overlap (both granular), if the granular point's domain of
 *     interaction overlaps the other point's own domain (one granular), or
 *     always (neither granular: plain MPM between them);
 *  4. task 2: connected components of the interaction graph by union-find,
 *     labelled in order of their smallest point id (deterministic);
 *  5. every component must behave as if alone on its grid. Components that
 *     share no node cannot affect each other on one grid, so only the
 *     components that do share a node are kept apart: a greedy colouring
 *     (in label order) gives each a node layer, and the points are re-keyed
 *     into their layer's blocks (grid.h) and binned again. With one
 *     component, or none sharing nodes, nothing is re-binned.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Number of local cells of a block (64 in 1D and 2D). */
#define BLOCK_CELLS GM_BLOCK_NODES

/* Support box and domain of interaction of every point (committed state). */
static void point_geometry(void *context, size_t begin, size_t end,
                           int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  const gm_point_buffers *current = &points->buffer[points->cur];
  int dim = domain->dim;
  const double *const position[2] = {current->position[0],
                                     current->position[dim > 1 ? 1 : 0]};
  const double *const deformation[4] = {
      current->deformation[F_XX], current->deformation[F_XY],
      current->deformation[F_YX], current->deformation[F_YY]};
  const double *const size[2] = {points->domain_size[0],
                                 points->domain_size[dim > 1 ? 1 : 0]};
  for (size_t p = begin; p < end; p++) {
    gm_point_domain point;
    gm_load_point_domain(dim, position, deformation, size, p, &point);
    int64_t low[2], high[2];
    /* Cannot fail: the binning checked the same support. */
    gm_support_bounds(&domain->shape_grid, &point, low, high);
    for (int k = 0; k < 2; k++) {
      work->support_low[k][p] = low[k];
      work->support_high[k][p] = high[k];
    }
    const gm_material *material = &domain->materials[points->material[p]];
    double measure = 0.0; /* non-granular: its own domain */
    if (material->granular) {
      /* The initial domain's area (length in 1D) scaled to V_cr:
       * A0 V_cr / V0 = A0 (m / V0) / rho_cr (000 sec 3.3, Table A2). */
      double initial = size[0][p] * (dim > 1 ? size[1][p] : 1.0);
      measure = initial * points->mass[p] / points->initial_volume[p] /
                material->critical_density;
    }
    gm_interaction_domain *interaction = &work->interaction[p];
    gm_interaction_domain_of(domain->shape_grid.shape, dim, &point, measure,
                             interaction);
    work->granular[p] = material->granular;
    for (int k = 0; k < 2; k++) { /* r1 = (hx, 0), r2 = (0, hy) if a box */
      work->box_centre[k][p] = interaction->centre[k];
      work->box_half[k][p] = fabs(interaction->half_edge[k][k]);
    }
  }
}

/* Groups each block's points by the local cell of their support's lowest
 * node (a counting sort per block). */
static void sort_cells(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_grid *grid = &domain->grid;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  int shift = grid->shift;
  int64_t mask = ((int64_t)1 << shift) - 1;
  for (size_t b = begin; b < end; b++) {
    uint32_t *start = work->cell_start + b * (BLOCK_CELLS + 1);
    memset(start, 0, (BLOCK_CELLS + 1) * sizeof(uint32_t));
    uint32_t first = grid->point_start[b], last = grid->point_start[b + 1];
    for (uint32_t k = first; k < last; k++) {
      uint32_t p = points->order[k];
      int64_t cell = (work->support_low[0][p] & mask) +
                     ((work->support_low[1][p] & mask) << shift);
      start[cell + 1]++;
    }
    start[0] = first;
    for (int c = 0; c < BLOCK_CELLS; c++)
      start[c + 1] += start[c];
    uint32_t fill[BLOCK_CELLS];
    memcpy(fill, start, sizeof fill);
    for (uint32_t k = first; k < last; k++) {
      uint32_t p = points->order[k];
      int64_t cell = (work->support_low[0][p] & mask) +
                     ((work->support_low[1][p] & mask) << shift);
      work->cell_order[fill[cell]++] = p;
    }
  }
}

/* Do the supports of p and q share a node? */
static bool supports_share_node(const gm_granular_work *work, int dim,
                                uint32_t p, uint32_t q) {
  for (int k = 0; k < dim; k++)
    if (work->support_low[k][p] > work->support_high[k][q] ||
        work->support_low[k][q] > work->support_high[k][p])
      return false;
  return true;
}

/* Each pair sharing a node lies in both points' candidate windows, so it
 * is visited only from its first point in (lowest node y, x, index) order. */
static bool later_in_raster(const gm_granular_work *work, uint32_t p,
                            uint32_t q) {
  int64_t py = work->support_low[1][p], qy = work->support_low[1][q];
  if (py != qy)
    return qy > py;
  int64_t px = work->support_low[0][p], qx = work->support_low[0][q];
  return qx != px ? qx > px : q > p;
}

/* Task 1 for one candidate pair (rules at the top of this file). Domains
 * of the rectangle variants are axis-aligned: interval tests decide. */
static bool pair_interacts(const gm_domain *domain, uint32_t p, uint32_t q) {
  const gm_granular_work *work = &domain->granular;
  if (!work->granular[p] && !work->granular[q])
    return true;
  if (domain->shape_grid.shape == GM_SHAPE_CPDI)
    return gm_interaction_overlap(domain->dim, &work->interaction[p],
                                  &work->interaction[q]);
  for (int k = 0; k < domain->dim; k++)
    if (!(fabs(work->box_centre[k][q] - work->box_centre[k][p]) <
          work->box_half[k][p] + work->box_half[k][q]))
      return false;
  return true;
}

/* What to do with each candidate pair (sharing a node). */
typedef enum pair_pass { PASS_JOIN, PASS_CONFLICTS } pair_pass;

static gm_status add_conflict(gm_domain *domain, int32_t a, int32_t b) {
  gm_granular_work *work = &domain->granular;
  if (work->conflict_count == work->conflict_capacity) {
    size_t capacity =
        work->conflict_capacity ? 2 * work->conflict_capacity : 1024;
    if (!gm_grow((void **)&work->conflict, sizeof(uint64_t),
                 work->conflict_capacity, capacity))
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "granular: out of memory for grid conflicts");
    work->conflict_capacity = capacity;
  }
  uint32_t low = (uint32_t)(a < b ? a : b), high = (uint32_t)(a < b ? b : a);
  work->conflict[work->conflict_count++] = (uint64_t)low << 32 | high;
  return GM_OK;
}

/* One pair in one pass: join if it interacts (skipping the test when the
 * two are already joined through others), or record the conflict of two
 * components that share a node. */
static gm_status handle_pair(gm_domain *domain, pair_pass pass, uint32_t p,
                             uint32_t q, uint32_t *root_p) {
  gm_granular_work *work = &domain->granular;
  if (pass == PASS_CONFLICTS)
    return work->label[p] == work->label[q]
               ? GM_OK
               : add_conflict(domain, work->label[p], work->label[q]);
  if (*root_p != gm_union_find_root(work->parent, q) &&
      pair_interacts(domain, p, q)) {
    gm_union_find_join(work->parent, work->set_size, *root_p, q);
    *root_p = gm_union_find_root(work->parent, p);
    work->interaction_count++;
  }
  return GM_OK;
}

/* The partners of p among the points of one block whose lowest node lies
 * in the window [from, to] (node indices per axis). */
static gm_status visit_block(gm_domain *domain, pair_pass pass, uint32_t p,
                             uint32_t *root_p, uint32_t block,
                             const int64_t base[2], const int64_t from[2],
                             const int64_t to[2]) {
  gm_granular_work *work = &domain->granular;
  int dim = domain->dim, shift = domain->grid.shift;
  int64_t last = ((int64_t)1 << shift) - 1; /* local index of a block edge */
  const uint32_t *start = work->cell_start + block * (BLOCK_CELLS + 1);
  int64_t low[2] = {0, 0}, high[2] = {0, 0};
  for (int k = 0; k < dim; k++) {
    low[k] = from[k] > base[k] ? from[k] - base[k] : 0;
    high[k] = to[k] - base[k] < last ? to[k] - base[k] : last;
  }
  for (int64_t y = low[1]; y <= high[1]; y++) {
    for (int64_t x = low[0]; x <= high[0]; x++) {
      int64_t cell = x + (y << shift);
      for (uint32_t k = start[cell]; k < start[cell + 1]; k++) {
        uint32_t q = work->cell_order[k];
        if (!later_in_raster(work, p, q) ||
            !supports_share_node(work, dim, p, q))
          continue;
        gm_status status = handle_pair(domain, pass, p, q, root_p);
        if (status != GM_OK)
          return status;
      }
    }
  }
  return GM_OK;
}

/* The pre-task: every pair of points whose supports share a node, found
 * from the cells that can hold such a partner, handed to the pass. */
static gm_status visit_pairs(gm_domain *domain, const int max_span[2],
                             pair_pass pass) {
  gm_grid *grid = &domain->grid;
  gm_granular_work *work = &domain->granular;
  int dim = domain->dim, shift = grid->shift;
  int64_t blocks_x = grid->blocks_per_axis[0];
  for (size_t p = 0; p < domain->points.count; p++) {
    /* A partner's lowest node lies in [low - span + 1, high] per axis;
     * rows below p's hold no partner later in raster order. */
    int64_t from[2] = {0, 0}, to[2] = {0, 0};
    for (int k = 0; k < dim; k++) {
      from[k] = work->support_low[k][p] - max_span[k] + 1;
      from[k] = from[k] < 0 ? 0 : from[k];
      to[k] = work->support_high[k][p];
    }
    if (dim > 1)
      from[1] = work->support_low[1][p];
    uint32_t root_p = gm_union_find_root(work->parent, (uint32_t)p);
    for (int64_t by = from[1] >> shift; by <= to[1] >> shift; by++) {
      for (int64_t bx = from[0] >> shift; bx <= to[0] >> shift; bx++) {
        if (bx >= blocks_x || (dim > 1 && by >= grid->blocks_per_axis[1]))
          continue;
        uint32_t block = gm_grid_find(grid, by * blocks_x + bx);
        if (block == GM_NO_BLOCK)
          continue;
        int64_t base[2] = {bx << shift, dim > 1 ? by << shift : 0};
        gm_status status = visit_block(domain, pass, (uint32_t)p, &root_p,
                                       block, base, from, to);
        if (status != GM_OK)
          return status;
      }
    }
  }
  return GM_OK;
}

static int compare_conflicts(const void *left, const void *right) {
  uint64_t a = *(const uint64_t *)left, b = *(const uint64_t *)right;
  return (a > b) - (a < b);
}

/* Greedy colouring of the components that share nodes, in label order;
 * returns the number of layers. */
static gm_status assign_layers(gm_domain *domain, size_t components,
                               size_t *layer_count) {
  gm_granular_work *work = &domain->granular;
  qsort(work->conflict, work->conflict_count, sizeof(uint64_t),
        compare_conflicts);
  size_t unique = 0;
  for (size_t i = 0; i < work->conflict_count; i++)
    if (unique == 0 || work->conflict[i] != work->conflict[unique - 1])
      work->conflict[unique++] = work->conflict[i];
  /* CSR of the lower neighbours of each component (the ones coloured
   * before it): conflicts are (low << 32 | high), sorted by low. */
  if (unique > work->adjacency_capacity) {
    if (!gm_grow((void **)&work->adjacency, sizeof(int32_t),
                 work->adjacency_capacity, unique))
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "granular: out of memory for grid conflicts");
    work->adjacency_capacity = unique;
  }
  uint32_t *start = work->adjacency_start;
  memset(start, 0, (components + 1) * sizeof(uint32_t));
  for (size_t i = 0; i < unique; i++)
    start[(work->conflict[i] & 0xffffffffu) + 1]++;
  for (size_t c = 0; c < components; c++)
    start[c + 1] += start[c];
  for (size_t i = 0; i < unique; i++) {
    uint32_t high = (uint32_t)(work->conflict[i] & 0xffffffffu);
    work->adjacency[start[high]++] = (int32_t)(work->conflict[i] >> 32);
  }
  for (size_t c = components; c > 0; c--) /* undo the fill shift */
    start[c] = start[c - 1];
  start[0] = 0;
  size_t layers = 1;
  for (size_t c = 0; c < components; c++)
    work->layer_stamp[c] = -1;
  for (size_t c = 0; c < components; c++) {
    for (uint32_t k = start[c]; k < start[c + 1]; k++)
      work->layer_stamp[work->component_layer[work->adjacency[k]]] = (int32_t)c;
    int32_t layer = 0;
    while (work->layer_stamp[layer] == (int32_t)c)
      layer++;
    work->component_layer[c] = layer;
    if ((size_t)layer + 1 > layers)
      layers = (size_t)layer + 1;
  }
  *layer_count = layers;
  return GM_OK;
}

gm_status gm_granular_prepare(gm_domain *domain) {
  gm_status status = gm_granular_reserve(domain);
  if (status != GM_OK)
    return status;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  size_t count = points->count;
  int dim = domain->dim;
  gm_parallel_for(&domain->pool, count, point_geometry, domain);
  gm_parallel_for(&domain->pool, domain->grid.block_count, sort_cells, domain);
  int max_span[2] = {1, 1};
  for (size_t p = 0; p < count; p++)
    for (int k = 0; k < dim; k++) {
      int span = (int)(work->support_high[k][p] - work->support_low[k][p] + 1);
      max_span[k] = span > max_span[k] ? span : max_span[k];
    }
  gm_union_find_init(work->parent, work->set_size, count);
  work->interaction_count = 0;
  status = visit_pairs(domain, max_span, PASS_JOIN);
  if (status != GM_OK)
    return status;
  size_t components = gm_union_find_labels(
      work->parent, points->id, count, work->label, work->min_id, work->roots);
  memset(work->component_size, 0, components * sizeof(uint32_t));
  for (size_t p = 0; p < count; p++)
    work->component_size[work->label[p]]++;
  work->conflict_count = 0;
  size_t layers = 1;
  memset(work->component_layer, 0, components * sizeof(int32_t));
  if (components > 1) {
    status = visit_pairs(domain, max_span, PASS_CONFLICTS);
    if (status == GM_OK)
      status = assign_layers(domain, components, &layers);
    if (status != GM_OK)
      return status;
  }
  double *label_out = points->buffer[points->cur ^ 1].component;
  for (size_t p = 0; p < count; p++)
    label_out[p] = (double)work->label[p];
  work->component_count = components;
  work->layer_count = layers;
  if (layers == 1)
    return GM_OK;
  int64_t stride = gm_grid_layer_stride(&domain->grid);
  for (size_t p = 0; p < count; p++)
    points->block_key[p] +=
        (int64_t)work->component_layer[work->label[p]] * stride;
  points->keys_valid = true;
  return gm_bin_points(domain);
}
