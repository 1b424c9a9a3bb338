/*
 * bins.c - grouping points by grid block (a counting sort of indices, every
 * step) and the periodic physical reordering of the point arrays so that
 * memory order follows the grid (cache-friendly scatter and gather).
 */
#include "grid/grid.h"

#include <string.h>

static size_t chunk_begin(size_t count, size_t chunks, size_t chunk) {
  return count * chunk / chunks;
}

/* Chunks of this binning: GM_BIN_CHUNKS, fewer where the counters (4
 * bytes per block and chunk) would outnumber half the points, at least 2
 * (two workers still share the work). The granular cloud's node layers
 * hold 1-3 points per 3D block, where 32 counters per block took 20
 * bytes per point (docs/performance.md, "Gap records per block"). Any
 * number of consecutive chunks gives the same order[]: index order inside
 * each block. */
static size_t bin_chunks(size_t points, size_t blocks) {
  size_t chunks = blocks ? points / (2 * blocks) : GM_BIN_CHUNKS;
  return chunks < 2 ? 2 : chunks > GM_BIN_CHUNKS ? GM_BIN_CHUNKS : chunks;
}

/* Room for the counters of this binning: at first those and 4 blocks'
 * worth, then grown by an eighth more, as the grid's blocks
 * (block_grid.c, reserve_blocks). */
static gm_status reserve_chunks(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  grid->chunks = bin_chunks(domain->points.count, grid->block_count);
  size_t needed = grid->chunks * grid->block_count;
  if (needed <= grid->chunk_capacity)
    return GM_OK;
  size_t room =
      needed + 4 * GM_BIN_CHUNKS + (grid->chunk_capacity ? needed / 8 : 0);
  uint32_t *grown = gm_alloc(room * sizeof(uint32_t));
  if (!grown)
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "grid: out of memory for the binning's counters");
  gm_free(grid->chunk_counts);
  grid->chunk_counts = grown;
  grid->chunk_capacity = room;
  return GM_OK;
}

/* Block of every point of the chunks, and per-chunk counts per block. */
static void locate_chunks(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_grid *grid = &domain->grid;
  gm_points *points = &domain->points;
  const int64_t *point_key = points->block_key;
  size_t chunks = grid->chunks;
  for (size_t chunk = begin; chunk < end; chunk++) {
    uint32_t *counts = grid->chunk_counts;
    for (size_t b = 0; b < grid->block_count; b++)
      counts[b * chunks + chunk] = 0;
    int64_t cached_key = -1;
    uint32_t cached_block = GM_NO_BLOCK;
    size_t last = chunk_begin(points->count, chunks, chunk + 1);
    for (size_t i = chunk_begin(points->count, chunks, chunk); i < last; i++) {
      if (point_key[i] != cached_key) {
        cached_key = point_key[i];
        cached_block = gm_grid_find(grid, cached_key);
      }
      points->point_block[i] = cached_block;
      counts[(size_t)cached_block * chunks + chunk]++;
    }
  }
}

/* Writes each chunk's points into its slots of order[]. */
static void scatter_chunks(void *context, size_t begin, size_t end,
                           int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_points *points = &domain->points;
  uint32_t *counts = domain->grid.chunk_counts;
  size_t chunks = domain->grid.chunks;
  for (size_t chunk = begin; chunk < end; chunk++) {
    size_t last = chunk_begin(points->count, chunks, chunk + 1);
    for (size_t i = chunk_begin(points->count, chunks, chunk); i < last; i++) {
      size_t slot = (size_t)points->point_block[i] * chunks + chunk;
      points->order[counts[slot]++] = (uint32_t)i;
    }
  }
}

/* key_ranges in 3D: linear MPM by the point's cell, uGIMP and cpGIMP by
 * their support's lowest node (support_3d.h; the other shapes are refused
 * in 3D, domain.c). */
static void keys_3d(gm_domain *domain, int worker, size_t begin, size_t end) {
  gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  const double *const *position = (const double *const *)current->position;
  const double *origin = domain->shape_grid.origin;
  if (domain->shape_grid.shape == GM_SHAPE_LINEAR) {
    for (size_t i = begin; i < end; i++)
      points->block_key[i] =
          gm_block_key_inside_3d(&domain->grid, position[0][i], position[1][i],
                                 position[2][i], origin, domain->inv_cell);
    return;
  }
  for (size_t i = begin; i < end; i++) {
    int64_t lowest[3]; /* GIMP box, B-spline or CPDI parallelepiped */
    if (gm_wide_lowest_3d(&domain->shape_grid, position,
                          (const double *const *)points->domain_size,
                          gm_support_slots_3d(domain, current), i, lowest)) {
      points->block_key[i] = gm_block_key_of_node_3d(&domain->grid, lowest[0],
                                                     lowest[1], lowest[2]);
      continue;
    }
    points->block_key[i] = 0; /* never used: the step fails */
    gm_worker_error(&domain->scratch[worker], GM_ERR_OUT_OF_GRID, i,
                    "step: the domain of point id %lld reaches past the "
                    "ghost cell layer around the grid box or spans more "
                    "than %d cells along an axis",
                    (long long)points->id[i], GM_SUPPORT_3D_MAX_SPAN - 1);
  }
}

/* Block key of every committed point (all inside the grid: positions and
 * domains are validated when added and when moved). Needed only when the
 * keys the last move pass wrote are stale (after adding points, a failed
 * step or a reordering). Linear MPM keys by the point's cell, the wider
 * supports by their lowest node (support.h). */
static void key_ranges(void *context, size_t begin, size_t end, int worker) {
  gm_domain *domain = context;
  gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  int dim = domain->dim;
  const double *const position[2] = {current->position[0],
                                     current->position[dim > 1 ? 1 : 0]};
  const double *origin = domain->shape_grid.origin;
  if (dim == 3) {
    keys_3d(domain, worker, begin, end);
    return;
  }
  if (domain->shape_grid.shape == GM_SHAPE_LINEAR) {
    for (size_t i = begin; i < end; i++)
      points->block_key[i] =
          gm_block_key_inside(&domain->grid, position[0][i], position[1][i],
                              origin, domain->inv_cell);
    return;
  }
  const double *deformation[4];
  gm_support_tensor(domain, current, deformation);
  const double *const size[2] = {points->domain_size[0],
                                 points->domain_size[dim > 1 ? 1 : 0]};
  for (size_t i = begin; i < end; i++) {
    int64_t lowest[2], highest[2];
    if (gm_wide_support_bounds(&domain->shape_grid, dim, position, deformation,
                               size, i, lowest, highest)) {
      points->block_key[i] =
          gm_block_key_of_node(&domain->grid, lowest[0], lowest[1]);
      continue;
    }
    points->block_key[i] = 0; /* never used: the step fails */
    gm_worker_error(&domain->scratch[worker], GM_ERR_OUT_OF_GRID, i,
                    "step: the domain of point id %lld reaches past the "
                    "ghost cell layer around the grid box",
                    (long long)points->id[i]);
  }
}

gm_status gm_bin_points(gm_domain *domain) {
  /* No point left its block in the committed step (and nothing changed
   * the points since: every change clears keys_valid): the grid, order[]
   * and point_block of the last binning are what a binning would give
   * (gm_grid_build reads only the keys; the counting sort below keeps
   * index order in a block), so they are kept; not a sparse grid, which
   * depends on the points' cells too (block_grid.c). */
  bool kept = domain->points.keys_valid && domain->points.blocks_kept &&
              !domain->grid.sparse;
  domain->points.blocks_kept = false; /* until this step's move sets it */
  if (!domain->points.keys_valid) {
    gm_parallel_for(&domain->pool, domain->points.count, key_ranges, domain);
    gm_status keys = gm_collect_worker_errors(domain);
    if (keys != GM_OK)
      return keys;
  }
  domain->points.keys_valid = false; /* until this step's move pass ends */
  gm_status status = kept ? GM_OK : gm_grid_build(domain);
  if (status == GM_OK)
    status = gm_walls_reserve(domain);
  if (status == GM_OK)
    status = gm_rigid_reserve(domain);
  if (status == GM_OK)
    status = gm_volumetric_reserve(domain);
  if (status == GM_OK && !kept)
    status = reserve_chunks(domain);
  if (status != GM_OK || kept)
    return status;
  gm_grid *grid = &domain->grid;
  size_t chunks = grid->chunks;
  gm_parallel_for(&domain->pool, chunks, locate_chunks, domain);
  /* Exclusive prefix over (block, chunk): points keep index order inside
   * a block whatever the worker count. */
  uint32_t running = 0;
  for (size_t b = 0; b < grid->block_count; b++) {
    grid->point_start[b] = running;
    uint32_t *counts = grid->chunk_counts + b * chunks;
    for (size_t chunk = 0; chunk < chunks; chunk++) {
      uint32_t in_chunk = counts[chunk];
      counts[chunk] = running;
      running += in_chunk;
    }
  }
  grid->point_start[grid->block_count] = running;
  gm_parallel_for(&domain->pool, chunks, scatter_chunks, domain);
  return GM_OK;
}

/* ------------------------------------------------------------ reordering */

static void permute_doubles(double *target, const double *source,
                            const uint32_t *order, size_t begin, size_t end) {
  for (size_t k = begin; k < end; k++)
    target[k] = source[order[k]];
}

/* Permutes the committed double-buffered fields into the spare buffer. */
static void permute_buffers(void *context, size_t begin, size_t end,
                            int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const uint32_t *order = points->order;
  for (int k = 0; k < domain->dim; k++) {
    permute_doubles(to->position[k], from->position[k], order, begin, end);
    permute_doubles(to->velocity[k], from->velocity[k], order, begin, end);
  }
  for (int k = 0; k < GM_STRESS_SLOTS; k++)
    if (from->stress[k]) /* yz, zx: 3D only */
      permute_doubles(to->stress[k], from->stress[k], order, begin, end);
  for (int k = 0; k < GM_F_SLOTS; k++)
    if (from->deformation[k])
      permute_doubles(to->deformation[k], from->deformation[k], order, begin,
                      end);
  for (int k = 0; k < GM_F_SLOTS; k++) /* CPDI: 4 slots, 9 in 3D */
    if (from->domain_map[k])
      permute_doubles(to->domain_map[k], from->domain_map[k], order, begin,
                      end);
  permute_doubles(to->volume, from->volume, order, begin, end);
  if (from->granular_state) {
    for (size_t k = begin; k < end; k++) {
      to->granular_state[k] = from->granular_state[order[k]];
      to->component[k] = from->component[order[k]];
    }
  }
  for (int k = 0; k < GM_AFFINE_STORED; k++)
    if (from->affine[k])
      permute_doubles(to->affine[k], from->affine[k], order, begin, end);
  size_t stride = points->state_stride;
  for (size_t i = begin; stride && i < end; i++)
    memcpy(to->state + i * stride, from->state + (size_t)order[i] * stride,
           stride * sizeof(double));
}

/* Permutes one single-buffered array through scratch (count doubles). */
static void permute_in_place(gm_points *points, double *field,
                             double *scratch) {
  if (!field)
    return;
  permute_doubles(scratch, field, points->order, 0, points->count);
  memcpy(field, scratch, points->count * sizeof(double));
}

void gm_reorder_points(gm_domain *domain) {
  gm_points *points = &domain->points;
  /* point_block is free until the next binning */
  gm_granular_remap_forest(domain, points->point_block);
  domain->granular.boxes_valid = false;
  size_t count = points->count;
  gm_parallel_for(&domain->pool, count, permute_buffers, domain);
  points->cur ^= 1;
  /* The buffer just released holds nothing needed: its volume array is
   * the scratch for the single-buffered fields (8 bytes per point). */
  double *scratch = points->buffer[points->cur ^ 1].volume;
  permute_in_place(points, points->mass, scratch);
  permute_in_place(points, points->initial_volume, scratch);
  for (int k = 0; k < domain->dim; k++) {
    permute_in_place(points, points->domain_size[k], scratch);
    permute_in_place(points, points->external_force[k], scratch);
  }
  int64_t *id_scratch = (int64_t *)(void *)scratch;
  for (size_t k = 0; k < count; k++)
    id_scratch[k] = points->id[points->order[k]];
  memcpy(points->id, id_scratch, count * sizeof(int64_t));
  int32_t *material_scratch = (int32_t *)(void *)scratch;
  for (size_t k = 0; k < count; k++)
    material_scratch[k] = points->material[points->order[k]];
  memcpy(points->material, material_scratch, count * sizeof(int32_t));
  for (size_t k = 0; k < count; k++)
    points->index_of_id[points->id[k]] = (uint32_t)k;
  points->keys_valid = false; /* recomputed at the next binning */
}
