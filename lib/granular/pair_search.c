/*
 * pair_search.c - the pre-task and task 1 of the granular method (000 sec
 * 3.4, Tables A1-A2): the pairs of points whose supports share a grid node,
 * and which of them interact.
 *
 * Points are bucketed by block (the plain binning) and, inside a block, by
 * the cell of their support's lowest node (on a window's first visit of
 * the block in the step). A partner q of p shares a node
 * only if q's lowest node lies within [low_p - span + 1, high_p] per axis,
 * span being the widest support of the step, so p looks at those few cells
 * only: O(N), never all pairs. Interaction rules are at the top of
 * components.c.
 */
#include "granular/granular.h"

#include "granular/pair_rules.h"

#include <math.h>
#include <string.h>

/* Number of local cells of a block (64 in every dimension: 64, 8 x 8,
 * 4 x 4 x 4). */
#define BLOCK_CELLS GM_BLOCK_NODES

/* Local cell of point p's lowest node in its block: x + y << shift (+ z
 * << 2 shift in 3D). */
static int64_t local_cell(const gm_granular_work *work, int dim, int shift,
                          uint32_t p) {
  int64_t mask = ((int64_t)1 << shift) - 1;
  int64_t cell = (work->support_low[0][p] & mask) +
                 ((work->support_low[1][p] & mask) << shift);
  if (dim == 3)
    cell += (work->support_low[2][p] & mask) << (2 * shift);
  return cell;
}

/* A block whose cells are not grouped yet: its first offset (a point
 * index, below UINT32_MAX) holds this mark until sort_block_cells runs. */
#define UNSORTED UINT32_MAX

/* Marks every block unsorted, once per step before the first search: only
 * the blocks a searching point's window reaches are then sorted (the
 * searching points are often a few, the disconnected ones). */
static void mark_blocks_unsorted(void *context, size_t begin, size_t end,
                                 int worker) {
  (void)worker;
  gm_granular_work *work = context;
  for (size_t b = begin; b < end; b++)
    work->cell_start[b * (BLOCK_CELLS + 1)] = UNSORTED;
}

/* Groups a block's points by the local cell of their support's lowest node
 * (a counting sort), on the first visit of the step; returns its offsets. */
static const uint32_t *sorted_block_cells(gm_domain *domain, uint32_t b) {
  gm_grid *grid = &domain->grid;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  int shift = grid->shift, dim = domain->dim;
  uint32_t *start = work->cell_start + (size_t)b * (BLOCK_CELLS + 1);
  if (start[0] != UNSORTED)
    return start;
  memset(start, 0, (BLOCK_CELLS + 1) * sizeof(uint32_t));
  uint32_t first = grid->point_start[b], last = grid->point_start[b + 1];
  for (uint32_t k = first; k < last; k++) {
    uint32_t p = points->order[k];
    start[local_cell(work, dim, shift, p) + 1]++;
  }
  start[0] = first;
  for (int c = 0; c < BLOCK_CELLS; c++)
    start[c + 1] += start[c];
  uint32_t fill[BLOCK_CELLS];
  memcpy(fill, start, sizeof fill);
  for (uint32_t k = first; k < last; k++) {
    uint32_t p = points->order[k];
    work->cell_order[fill[local_cell(work, dim, shift, p)]++] = p;
  }
  return start;
}

/* Each pair sharing a node lies in both points' candidate windows, so it
 * is visited only from its first point in (lowest node z, y, x, index)
 * order (z in 3D only). */
static bool later_in_raster(const gm_granular_work *work, int dim, uint32_t p,
                            uint32_t q) {
  if (dim == 3) {
    int64_t pz = work->support_low[2][p], qz = work->support_low[2][q];
    if (pz != qz)
      return qz > pz;
  }
  int64_t py = work->support_low[1][p], qy = work->support_low[1][q];
  if (py != qy)
    return qy > py;
  int64_t px = work->support_low[0][p], qx = work->support_low[0][q];
  return qx != px ? qx > px : q > p;
}

/* Whether p's search takes the candidate q. Every pair whose two ends
 * search is taken once, from its first point in raster order: every pair
 * of a full search (subset NULL) and, in a subset search, every pair of
 * two points outside the largest kept set (the union-find gives the same
 * sets in any order of the joins, and the conflicts are kept as a set:
 * layers.c). A pair with one searching end is taken from that end. */
static inline bool takes_partner(const gm_granular_work *work, int dim,
                                 const uint8_t *subset, uint32_t p,
                                 uint32_t q) {
  return q != p && ((subset && !subset[q]) || later_in_raster(work, dim, p, q));
}

/* Appends a b to work->conflict: two points that share a node but did not
 * interact (JOIN pass of a subset search: components.c keeps those of
 * different components), or two components that share a node (CONFLICTS
 * pass, as low << 32 | high). */
static gm_status add_pair(gm_domain *domain, uint32_t a, uint32_t b) {
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
  work->conflict[work->conflict_count++] = (uint64_t)a << 32 | b;
  return GM_OK;
}

/* One pair sharing a node. JOIN: nothing if the two are already joined
 * through others; joined if they interact; else, in a subset search, a
 * candidate conflict. CONFLICTS: the pair of their components if those
 * differ. Inline: once per candidate pair, the call cost more than the
 * tests of a pair that does not interact. */
static GM_ALWAYS_INLINE gm_status handle_pair(gm_domain *domain,
                                              gm_pair_pass pass, uint32_t p,
                                              uint32_t q, uint32_t *root_p,
                                              const uint8_t *subset) {
  gm_granular_work *work = &domain->granular;
  if (pass == GM_PASS_CONFLICTS) {
    int32_t a = work->label[p], b = work->label[q];
    return a == b ? GM_OK
                  : add_pair(domain, (uint32_t)(a < b ? a : b),
                             (uint32_t)(a < b ? b : a));
  }
  if (*root_p == gm_union_find_root(work->parent, q))
    return GM_OK;
  if (!gm_pair_interacts(domain, p, q))
    return subset ? add_pair(domain, p, q) : GM_OK;
  gm_union_find_join(work->parent, work->set_size, *root_p, q);
  *root_p = gm_union_find_root(work->parent, p);
  work->forest[work->forest_count++] = (uint64_t)p << 32 | q;
  return GM_OK;
}

/* The partners of p among the points of one block whose lowest node lies
 * in the window [from, to] (node indices per axis). */
static gm_status visit_block(gm_domain *domain, gm_pair_pass pass, uint32_t p,
                             uint32_t *root_p, const uint8_t *subset,
                             uint32_t block, const int64_t base[3],
                             const int64_t from[3], const int64_t to[3]) {
  gm_granular_work *work = &domain->granular;
  int dim = domain->dim, shift = domain->grid.shift;
  int64_t last = ((int64_t)1 << shift) - 1; /* local index of a block edge */
  const uint32_t *start = sorted_block_cells(domain, block);
  /* With a fixed span (no highest node stored) every support spans
   * support_reach + 1 nodes, the window is [low_p - reach, low_p + reach]
   * per axis (cut at 0 and, with half windows, at low_p along the last
   * axis), and a lowest node in it is one at most reach from p's: every
   * point of the window shares a node with p (gm_supports_share_node). */
  bool window_shares = !work->support_high[0];
  int64_t low[3] = {0, 0, 0}, high[3] = {0, 0, 0};
  for (int k = 0; k < dim; k++) {
    low[k] = from[k] > base[k] ? from[k] - base[k] : 0;
    high[k] = to[k] - base[k] < last ? to[k] - base[k] : last;
  }
  /* The cells low[0]..high[0] of one row are consecutive local cells, so
   * their points are one run of cell_order: a row at a time, the same
   * points in the same order as cell by cell. */
  for (int64_t z = low[2]; z <= high[2]; z++) {
    for (int64_t y = low[1]; y <= high[1]; y++) {
      int64_t row = (y << shift) + (z << (2 * shift));
      uint32_t run_first = start[row + low[0]];
      uint32_t run_end = start[row + high[0] + 1];
      for (uint32_t k = run_first; k < run_end; k++) {
        uint32_t q = work->cell_order[k];
        if (!takes_partner(work, dim, subset, p, q) ||
            (!window_shares && !gm_supports_share_node(work, dim, p, q)))
          continue;
        gm_status status = handle_pair(domain, pass, p, q, root_p, subset);
        if (status != GM_OK)
          return status;
      }
    }
  }
  return GM_OK;
}

/* The blocks (of the plain binning) holding p's candidate window
 * [from, to], each searched by visit_block. */
static gm_status visit_window(gm_domain *domain, gm_pair_pass pass, uint32_t p,
                              uint32_t *root_p, const uint8_t *subset,
                              const int64_t from[3], const int64_t to[3]) {
  const gm_grid *grid = &domain->grid;
  int dim = domain->dim, shift = grid->shift;
  int64_t blocks_x = grid->blocks_per_axis[0];
  int64_t blocks_y = dim > 1 ? grid->blocks_per_axis[1] : 1;
  for (int64_t bz = from[2] >> shift; bz <= to[2] >> shift; bz++) {
    if (dim == 3 && bz >= grid->blocks_per_axis[2])
      continue;
    for (int64_t by = from[1] >> shift; by <= to[1] >> shift; by++) {
      for (int64_t bx = from[0] >> shift; bx <= to[0] >> shift; bx++) {
        if (bx >= blocks_x || (dim > 1 && by >= blocks_y))
          continue;
        uint32_t block =
            gm_grid_find(grid, (bz * blocks_y + by) * blocks_x + bx);
        if (block == GM_NO_BLOCK)
          continue;
        int64_t base[3] = {bx << shift, dim > 1 ? by << shift : 0,
                           dim == 3 ? bz << shift : 0};
        gm_status status =
            visit_block(domain, pass, p, root_p, subset, block, base, from, to);
        if (status != GM_OK)
          return status;
      }
    }
  }
  return GM_OK;
}

/* visit_window for a plane domain whose supports have a fixed span (no
 * highest node stored): every point of the window shares a node with p
 * (visit_block), so only the raster test is left per partner. The same
 * blocks, rows and points in the same order as visit_window's, without
 * its third axis and per-block set-up: the cloud's disconnected points
 * each search every step (bench/results/2026-11-30-cloud22.md). */
static gm_status visit_window_2d(gm_domain *domain, gm_pair_pass pass,
                                 uint32_t p, uint32_t *root_p,
                                 const uint8_t *subset, const int64_t from[3],
                                 const int64_t to[3]) {
  const gm_grid *grid = &domain->grid;
  const gm_granular_work *work = &domain->granular;
  const uint32_t *cell_order = work->cell_order;
  int shift = grid->shift;
  int64_t mask = ((int64_t)1 << shift) - 1;
  int64_t blocks_x = grid->blocks_per_axis[0];
  int64_t last_bx = to[0] >> shift, last_by = to[1] >> shift;
  last_bx = last_bx < blocks_x ? last_bx : blocks_x - 1;
  if (last_by >= grid->blocks_per_axis[1])
    last_by = grid->blocks_per_axis[1] - 1;
  for (int64_t by = from[1] >> shift; by <= last_by; by++) {
    int64_t base_y = by << shift;
    int64_t y0 = from[1] > base_y ? from[1] - base_y : 0;
    int64_t y1 = to[1] - base_y < mask ? to[1] - base_y : mask;
    for (int64_t bx = from[0] >> shift; bx <= last_bx; bx++) {
      uint32_t block = gm_grid_find(grid, by * blocks_x + bx);
      if (block == GM_NO_BLOCK)
        continue;
      int64_t base_x = bx << shift;
      int64_t x0 = from[0] > base_x ? from[0] - base_x : 0;
      int64_t x1 = to[0] - base_x < mask ? to[0] - base_x : mask;
      const uint32_t *start = sorted_block_cells(domain, block);
      for (int64_t y = y0; y <= y1; y++) {
        const uint32_t *row = start + (y << shift);
        for (uint32_t k = row[x0]; k < row[x1 + 1]; k++) {
          uint32_t q = cell_order[k];
          if (!takes_partner(work, 2, subset, p, q))
            continue;
          gm_status status = handle_pair(domain, pass, p, q, root_p, subset);
          if (status != GM_OK)
            return status;
        }
      }
    }
  }
  return GM_OK;
}

gm_status gm_pair_search(gm_domain *domain, const int max_span[3],
                         gm_pair_pass pass, const uint8_t *subset) {
  gm_grid *grid = &domain->grid;
  gm_granular_work *work = &domain->granular;
  int dim = domain->dim;
  bool half = subset == NULL; /* every pair from its first point only */
  for (size_t p = 0; p < domain->points.count; p++) {
    if (subset && !subset[p])
      continue;
    if (!work->cells_sorted) { /* only when some point searches */
      gm_parallel_for(&domain->pool, grid->block_count, mark_blocks_unsorted,
                      work);
      work->cells_sorted = true;
    }
    /* A partner's lowest node lies in [low - span + 1, high] per axis;
     * with half windows, rows (2D) or planes (3D) below p's hold no
     * partner later in raster order. */
    int64_t from[3] = {0, 0, 0}, to[3] = {0, 0, 0};
    for (int k = 0; k < dim; k++) {
      from[k] = work->support_low[k][p] - max_span[k] + 1;
      from[k] = from[k] < 0 ? 0 : from[k];
      to[k] = gm_support_high(work, k, p);
    }
    if (half && dim > 1)
      from[dim - 1] = work->support_low[dim - 1][p];
    uint32_t root_p = gm_union_find_root(work->parent, (uint32_t)p);
    gm_status status = dim == 2 && !work->support_high[0]
                           ? visit_window_2d(domain, pass, (uint32_t)p, &root_p,
                                             subset, from, to)
                           : visit_window(domain, pass, (uint32_t)p, &root_p,
                                          subset, from, to);
    if (status != GM_OK)
      return status;
  }
  return GM_OK;
}
