/*
 * volumetric_mean.c - the cell-mean volumetric strain rate against
 * volumetric locking (gm_domain_set_volumetric, GM_VOLUMETRIC_CELL_MEAN).
 *
 * Why: a plastically incompressible flow (psi = 0) or a nearly
 * incompressible elastic solid asks tr L = 0 at every point; with 2 x 2 or
 * more points per cell linear MPM imposes more such constraints than a
 * cell's nodal velocities can satisfy, and the flow locks (stiffens):
 * docs/convergence.md section 25 measured it in the slot silo, whose
 * orifice width then grows with every halving of the cell. The B-bar
 * method (Hughes 1980, IJNME 15:1413) keeps the deviatoric part of the
 * strain rate at each quadrature point and takes the dilatational part
 * from a lower-order field, for bilinear elements its mean over the
 * element; Coombs, Charlton, Cortis & Augarde (2018, CMAME 333:1,
 * "Overcoming volumetric locking in material point methods") carry that
 * over to MPM with the background cell as the element and the material
 * points as its quadrature points. In rate form, for the points p of a
 * cell c:
 *
 *   mean_c = sum_p V_p tr L_p / sum_p V_p                      (1/s)
 *   L_p   <- L_p + (mean_c - tr L_p) / n I                     (1/s)
 *
 * the cell integral of div v over the volume the points carry (V_p: the
 * committed volume, the quadrature weight of the step), with n = 2 (xx,
 * yy) in plane strain, where L_zz = 0 stays 0, n = 3 (xx, yy and the
 * hoop rate v_r / r) in axisymmetry, where tr L includes the hoop rate,
 * and n = 3 (xx, yy, zz) in GM_GEOMETRY_3D, whose cells have 8 nodes. The
 * trace of the new L is mean_c, its deviator is the point's own; F, V =
 * det F V0 and the stress then follow it (g2p.c, g2p_3d.c). docs/convergence.md
 * section 25's experiment took the mean by mass; the volume is the cell
 * integral's own weight (the two differ by the points' density ratio).
 *
 * How, without allocation in a pass and bitwise for any worker count: a
 * deformation pass first gathers every point's tr L (g2p.c) and stores it
 * with its cell (gm_volumetric_store_chunk); the cell sums are then formed
 * block by block in the scatter's colour order (p2g.c: 4 colours in 2D,
 * p2g_3d.c: 8 in 3D), each block by one worker, its points in binning
 * order (gm_volumetric_sum), so every sum is added in one fixed order; the
 * pass then gathers again and shifts each point's L
 * (gm_volumetric_apply_chunk, gm_volumetric_apply_chunk_3d). The arrays
 * grow with the grid and the points at binning (gm_volumetric_reserve),
 * outside the passes. In the granular family the points of each component
 * sit on its own node layer (block_grid.h), so a cell's mean is taken over
 * the points of one component, in 2D and 3D alike.
 */
#include "grid/grid.h"

#include "grid/transfer.h"

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#define NO_CELL SIZE_MAX

/* Two new arrays of count elements of the given sizes in *first and
 * *second; false, with nothing allocated, when either fails. */
static bool alloc_pair(size_t count, size_t first_size, size_t second_size,
                       void **first, void **second) {
  *first = gm_alloc(count * first_size);
  *second = gm_alloc(count * second_size);
  if (*first && *second)
    return true;
  gm_free(*first);
  gm_free(*second);
  return false;
}

gm_status gm_volumetric_reserve(gm_domain *domain) {
  if (domain->volumetric != GM_VOLUMETRIC_CELL_MEAN)
    return GM_OK;
  gm_grid *grid = &domain->grid;
  void *first = NULL, *second = NULL;
  size_t nodes = grid->block_capacity * GM_BLOCK_NODES;
  if (nodes > grid->cell_capacity) { /* scratch: nothing to keep */
    if (!alloc_pair(nodes, sizeof(double), sizeof(double), &first, &second))
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "volumetric averaging: out of memory for %zu "
                          "nodes",
                          nodes);
    gm_free(grid->cell_rate_volume);
    gm_free(grid->cell_volume);
    grid->cell_rate_volume = first;
    grid->cell_volume = second;
    grid->cell_capacity = nodes;
  }
  /* The points' capacity, not their count: a scene that gains points
   * (sources) reallocates as rarely as the points' own arrays. */
  size_t points = domain->points.capacity;
  if (points > grid->point_capacity) {
    if (!alloc_pair(points, sizeof(double), sizeof(size_t), &first, &second))
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "volumetric averaging: out of memory for %zu "
                          "points",
                          points);
    gm_free(grid->point_rate);
    gm_free(grid->point_cell);
    grid->point_rate = first;
    grid->point_cell = second;
    grid->point_capacity = points;
  }
  return GM_OK;
}

/* Node index of the lowest node of point p's cell (the cell the linear
 * shape functions use, gm_shape_linear_axis_inside), reached from the
 * point's block through its neighbour links, as the scatter reaches its
 * nodes; NO_CELL if the links do not reach it (a wide support whose
 * lowest block is more than a block below the point: the point then keeps
 * its own rate). */
static size_t cell_node(const gather_view *v, size_t p) {
  double w[2], d[2];
  int64_t cx = gm_shape_linear_axis_inside(v->position[0][p], v->origin[0],
                                           v->inv_cell, w, d);
  int64_t cy = gm_shape_linear_axis_inside(v->position[1][p], v->origin[1],
                                           v->inv_cell, w, d);
  uint32_t block = v->point_block[p];
  int64_t base[2];
  gm_block_base(v->grid, v->grid->block_key[block], base);
  int64_t x = cx - base[0], y = cy - base[1];
  const int64_t reach = 2 * GM_BLOCK_EDGE_2D;
  if (x < 0 || y < 0 || x >= reach || y >= reach)
    return NO_CELL;
  const uint32_t *links = v->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int neighbour =
      (int)(x >> GM_BLOCK_SHIFT_2D) + 2 * (int)(y >> GM_BLOCK_SHIFT_2D);
  if (links[neighbour] == GM_NO_BLOCK)
    return NO_CELL;
  return gm_block_node(links, GM_BLOCK_SHIFT_2D, x, y);
}

/* tr L of a gathered point (1/s): the in-plane trace, plus the hoop rate
 * in axisymmetry. */
static inline double gathered_trace(const chunk_gather *g, size_t j,
                                    bool axisymmetric) {
  double trace = g->gradient[0][j] + g->gradient[3][j];
  return axisymmetric ? trace + g->gradient[4][j] : trace;
}

void gm_volumetric_store_chunk(const gm_domain *domain, const gather_view *v,
                               size_t first, size_t count,
                               const chunk_gather *g) {
  const gm_grid *grid = &domain->grid;
  double *restrict rate = grid->point_rate;
  size_t *restrict cell = grid->point_cell;
  const int32_t *material = domain->points.material;
  bool rigid = domain->rigid_count > 0;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    rate[p] = gathered_trace(g, j, v->axisymmetric);
    /* Rigid points move as prescribed (rigid.c): no part in the mean. */
    cell[p] = rigid && domain->materials[material[p]].rigid ? NO_CELL
                                                            : cell_node(v, p);
  }
}

/* Node index of the lowest node of 3D point p's cell (the 8 nodes of the
 * linear shape functions), reached from its block (whose lowest corner
 * is at most a support below the point, g2p_3d.c) through the neighbour
 * links, as the 3D gather reaches its nodes; NO_CELL if they do not reach
 * it (the point then keeps its own rate). */
static size_t cell_node_3d(const gm_domain *domain, size_t p) {
  const gm_grid *grid = &domain->grid;
  const gm_point_buffers *current = &domain->points.buffer[domain->points.cur];
  uint32_t block = domain->points.point_block[p];
  int64_t base[3];
  gm_block_coordinates_3d(grid, grid->block_key[block], base);
  int64_t local[3];
  const int64_t reach = 2 * GM_BLOCK_EDGE_3D;
  for (int axis = 0; axis < 3; axis++) {
    double w[2], d[2];
    int64_t cell = gm_shape_linear_axis_inside(current->position[axis][p],
                                               domain->shape_grid.origin[axis],
                                               domain->inv_cell, w, d);
    local[axis] = cell - (base[axis] << GM_BLOCK_SHIFT_3D);
    if (local[axis] < 0 || local[axis] >= reach)
      return NO_CELL;
  }
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int neighbour = (int)(local[0] >> GM_BLOCK_SHIFT_3D) +
                  2 * (int)(local[1] >> GM_BLOCK_SHIFT_3D) +
                  4 * (int)(local[2] >> GM_BLOCK_SHIFT_3D);
  if (links[neighbour] == GM_NO_BLOCK)
    return NO_CELL;
  return gm_block_node_3d(links, local[0], local[1], local[2]);
}

void gm_volumetric_store_chunk_3d(const gm_domain *domain, size_t first,
                                  size_t count,
                                  const double (*gradient)[GM_BATCH_SIZE]) {
  const gm_grid *grid = &domain->grid;
  double *restrict rate = grid->point_rate;
  size_t *restrict cell = grid->point_cell;
  const int32_t *material = domain->points.material;
  bool rigid = domain->rigid_count > 0;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    /* tr L = L_xx + L_yy + L_zz (1/s; L row-major, g2p_3d.c) */
    rate[p] = gradient[0][j] + gradient[4][j] + gradient[8][j];
    cell[p] = rigid && domain->materials[material[p]].rigid
                  ? NO_CELL
                  : cell_node_3d(domain, p);
  }
}

typedef struct sum_context {
  gm_domain *domain;
  const uint32_t *blocks; /* blocks of the colour being summed */
  const double *volume;   /* m^3, committed */
} sum_context;

static void clear_cells(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  sum_context *ctx = context;
  gm_grid *grid = &ctx->domain->grid;
  size_t first = begin * GM_BLOCK_NODES;
  size_t bytes = (end - begin) * GM_BLOCK_NODES * sizeof(double);
  memset(grid->cell_rate_volume + first, 0, bytes);
  memset(grid->cell_volume + first, 0, bytes);
}

/* A point's cell is its block's or one of its upper neighbours' (+x, +y,
 * +x+y; in 3D also +z and the +z combinations: cell_node, cell_node_3d):
 * blocks of one colour, two apart along each axis, never share a cell, as
 * in the scatter (p2g.c, p2g_3d.c). */
static void sum_blocks(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  sum_context *ctx = context;
  gm_grid *grid = &ctx->domain->grid;
  const uint32_t *order = ctx->domain->points.order;
  const double *restrict rate = grid->point_rate;
  const size_t *restrict cell = grid->point_cell;
  const double *restrict volume = ctx->volume;
  double *restrict rate_volume = grid->cell_rate_volume;
  double *restrict cell_volume = grid->cell_volume;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = ctx->blocks[item];
    for (uint32_t k = grid->point_start[block];
         k < grid->point_start[block + 1]; k++) {
      size_t p = order[k];
      size_t c = cell[p];
      if (c == NO_CELL)
        continue;
      rate_volume[c] += volume[p] * rate[p];
      cell_volume[c] += volume[p];
    }
  }
}

void gm_volumetric_sum(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  sum_context ctx;
  ctx.domain = domain;
  ctx.volume = domain->points.buffer[domain->points.cur].volume;
  gm_parallel_for(&domain->pool, grid->block_count, clear_cells, &ctx);
  /* The scatter's colours: 4 in 2D (p2g.c), 8 in 3D (p2g_3d.c). */
  int colours = domain->dim == 3 ? GM_BLOCK_COLOURS : 4;
  for (int colour = 0; colour < colours; colour++) {
    size_t first = grid->color_start[colour];
    size_t count = grid->color_start[colour + 1] - first;
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, count, sum_blocks, &ctx);
  }
}

void gm_volumetric_apply_chunk(const gm_domain *domain, const gather_view *v,
                               size_t first, size_t count, chunk_gather *g) {
  const gm_grid *grid = &domain->grid;
  const size_t *restrict cell = grid->point_cell + first;
  const double *restrict rate_volume = grid->cell_rate_volume;
  const double *restrict cell_volume = grid->cell_volume;
  bool axisymmetric = v->axisymmetric;
  for (size_t j = 0; j < count; j++) {
    size_t c = cell[j];
    if (c == NO_CELL)
      continue;
    double mean = rate_volume[c] / cell_volume[c]; /* 1/s */
    double own = gathered_trace(g, j, axisymmetric);
    if (axisymmetric) { /* xx, yy and the hoop rate take a third each */
      double third = (mean - own) / 3.0;
      g->gradient[0][j] += third;
      g->gradient[3][j] += third;
      g->gradient[4][j] += third;
    } else { /* plane strain: L_zz = 0 stays */
      double half = 0.5 * (mean - own);
      g->gradient[0][j] += half;
      g->gradient[3][j] += half;
    }
  }
}

void gm_volumetric_apply_chunk_3d(const gm_domain *domain, size_t first,
                                  size_t count,
                                  double (*gradient)[GM_BATCH_SIZE]) {
  const gm_grid *grid = &domain->grid;
  const size_t *restrict cell = grid->point_cell + first;
  const double *restrict rate_volume = grid->cell_rate_volume;
  const double *restrict cell_volume = grid->cell_volume;
  for (size_t j = 0; j < count; j++) {
    size_t c = cell[j];
    if (c == NO_CELL)
      continue;
    double mean = rate_volume[c] / cell_volume[c]; /* 1/s */
    double own = gradient[0][j] + gradient[4][j] + gradient[8][j];
    double third = (mean - own) / 3.0; /* xx, yy and zz take a third each */
    gradient[0][j] += third;
    gradient[4][j] += third;
    gradient[8][j] += third;
  }
}
