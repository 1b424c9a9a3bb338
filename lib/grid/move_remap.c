/*
 * move_remap.c - USL's move pass and its momentum re-map in one sweep over
 * the points (issue 15). The separate passes (g2p.c's flip-and-move, then
 * p2g.c's momentum scatter, step.c REMAP_MOMENTUM) each walk every point
 * and each compute its shape functions; here each block's points are
 * moved and their re-mapped momenta m_p v_p^{t+dt} summed into the
 * block's tile in the same loop, from the same weights: the re-map uses
 * the committed positions, as the move's gather does (Sulsky, Zhou &
 * Schreyer 1995; 004 sec 3.2).
 *
 * Every bit is that of the separate passes. A point's move is
 * gm_linear_move_point_2d, the arithmetic of the flip-and-move pass; its
 * momenta are summed into the tile as scatter_block_2d_kind sums them,
 * the block's points in order[] order; the tiles are flushed colour by
 * colour, the blocks of a colour in their order, so every node receives
 * ((0 + t_0) + t_1) + ... over the colours that reach it, as in gm_p2g,
 * for any worker count. The moves' order does not matter: each writes its
 * own point, and the first failure named is the lowest index
 * (gm_worker_error), whatever the order.
 *
 * The new momenta cannot go to the grid's momentum arrays while later
 * colours still gather the nodal velocities v_i^L stored there
 * (grid_update.c), so they are summed into a spare pair of node arrays
 * and copied over once every block has moved. The spare pair is the next
 * buffer's F_xx and F_xy: USL writes them only in its DEFORM stage, after
 * this one, and reads the committed F until then (MEASURE_WALL_GAPS), so
 * for the length of this stage they hold nothing; a plain 2D domain has
 * no bytes per point to spare for a pair of its own (docs/performance.md,
 * the 300-byte bound). A grid with more nodes than the buffers have point
 * slots, and every scene gm_move_remap_fits refuses, takes the separate
 * passes.
 *
 * The sweep also tells the next binning whether every point stayed in
 * its block (points.blocks_kept): a scene at rest, or one whose points
 * cross no block edge in a step, then keeps its grid (bins.c). In the
 * granular family a point of node layer L > 0 is binned in a block whose
 * key carries its layer (core/block_grid.h) while the move writes its
 * plain key, so a step with more than one layer never keeps its grid; a
 * connected body (one layer) keeps it as a plain one does, and its
 * granular phase then runs on that grid (granular/components.c).
 */
#include "grid/grid.h"

#include "grid/own_nodes.h"
#include "grid/transfer.h"

#define TILE       (GM_BLOCK_EDGE_2D + 1)
#define TILE_NODES (TILE * TILE)

/* A block's re-mapped momenta (kg m/s), x and y side by side per node,
 * over its 8 x 8 nodes and the one-node halo its cells reach, node (a, b)
 * of the tile at a + TILE b (as p2g.c's tile). */
typedef struct momentum_tile {
  double node[TILE_NODES][2];
} momentum_tile;

typedef struct move_remap_context {
  gm_domain *domain;
  linear_move_2d move;
  const uint32_t *blocks; /* blocks of the colour being swept */
  double *sum[2];         /* kg m/s, the new momenta, per grid node */
  bool left_block[256];   /* per worker (domain.c: at most 256): a point
                             moved out of its block */
} move_remap_context;

bool gm_move_remap_fits(const gm_domain *domain) {
  const gm_points *points = &domain->points;
  return domain->dim == 2 && domain->def.scheme == GM_SCHEME_USL &&
         domain->shape_grid.shape == GM_SHAPE_LINEAR &&
         domain->def.transfer != GM_TRANSFER_APIC && domain->rigid_count == 0 &&
         !gm_periodic_x(domain) &&
         domain->grid.block_count * GM_BLOCK_NODES <= points->capacity;
}

/* Adds the rows [y0, y1) x columns [x0, x1) of the tile to the block
 * `block`, whose node (0, 0) is tile node (base_x, base_y); with `store`,
 * a region only this tile reaches, stores them (p2g.c flush_region). */
static GM_ALWAYS_INLINE void flush_region(double *const sum[2], uint32_t block,
                                          const momentum_tile *tile, int x0,
                                          int x1, int y0, int y1, int base_x,
                                          int base_y, const bool store) {
  double *restrict sum_x = sum[0], *restrict sum_y = sum[1];
  size_t block_first = (size_t)block * GM_BLOCK_NODES;
  for (int ty = y0; ty < y1; ty++) {
    size_t row = block_first + GM_BLOCK_EDGE_2D * (size_t)(ty - base_y);
    for (int tx = x0; tx < x1; tx++) {
      size_t node = row + (size_t)(tx - base_x);
      sum_x[node] =
          gm_own_sum(store, sum_x[node], tile->node[tx + TILE * ty][0]);
      sum_y[node] =
          gm_own_sum(store, sum_y[node], tile->node[tx + TILE * ty][1]);
    }
  }
}

/* The block's own nodes (row 0 and column 0 added, the others stored:
 * own_nodes.h), then the halo column (+x), row (+y) and corner (+x+y)
 * through the links (p2g.c flush_tile). */
static void flush_tile(double *const sum[2], const uint32_t *links,
                       const momentum_tile *tile) {
  const int E = GM_BLOCK_EDGE_2D;
  flush_region(sum, links[0], tile, 0, E, 0, 1, 0, 0, false);
  flush_region(sum, links[0], tile, 0, 1, 1, E, 0, 0, false);
  flush_region(sum, links[0], tile, 1, E, 1, E, 0, 0, true);
  if (links[1] != GM_NO_BLOCK)
    flush_region(sum, links[1], tile, E, TILE, 0, E, E, 0, false);
  if (links[2] != GM_NO_BLOCK)
    flush_region(sum, links[2], tile, 0, E, E, TILE, 0, E, false);
  if (links[3] != GM_NO_BLOCK)
    flush_region(sum, links[3], tile, E, TILE, E, TILE, E, E, false);
}

/* Moves the points of one block and sums their re-mapped momenta into
 * its tile; returns false if a moved point left the grid or is not
 * finite. blend (pic_fraction > 0) is a constant in each specialisation
 * below. */
static GM_ALWAYS_INLINE bool
move_remap_block_kind(const gm_domain *domain, const linear_move_2d *shared,
                      uint32_t block, momentum_tile *tile, bool *kept,
                      const bool blend) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  const gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const double *restrict px = from->position[0], *restrict py =
                                                     from->position[1];
  const double *restrict pvx = from->velocity[0], *restrict pvy =
                                                      from->velocity[1];
  double *restrict next_x = to->position[0], *restrict next_y = to->position[1];
  double *restrict next_vx = to->velocity[0], *restrict next_vy =
                                                  to->velocity[1];
  const double *restrict point_mass = points->mass; /* kg */
  int64_t *restrict key = points->block_key;
  const uint32_t *restrict order = points->order;
  const uint32_t *links =
      domain->grid.neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  double(*restrict tn)[2] = tile->node;
  /* A local copy: its fields stay in registers across the stores. */
  const linear_move_2d local_move = *shared, *m = &local_move;
  double origin_x = m->origin[0], origin_y = m->origin[1];
  double inv_cell = m->inv_cell;
  for (int t = 0; t < TILE_NODES; t++)
    tn[t][0] = tn[t][1] = 0.0;
  bool inside = true, same = true;
  int64_t own_key = domain->grid.block_key[block];
  uint32_t end = domain->grid.point_start[block + 1];
  for (uint32_t k = domain->grid.point_start[block]; k < end; k++) {
    size_t p = order[k];
    double wx[2], dx[2], wy[2], dy[2], moved[4];
    size_t node[4];
    int64_t local[2];
    gm_linear_cell_2d(px[p], py[p], origin_x, origin_y, inv_cell, links, wx, dx,
                      wy, dy, node, local);
    double weight[4] = {wx[0] * wy[0], wx[1] * wy[0], wx[0] * wy[1],
                        wx[1] * wy[1]};
    inside &= gm_linear_move_point_2d(m, weight, node, px[p], py[p], pvx[p],
                                      pvy[p], blend, moved, &key[p]);
    next_vx[p] = moved[0];
    next_vy[p] = moved[1];
    next_x[p] = moved[2];
    next_y[p] = moved[3];
    same &= key[p] == own_key;
    /* m_i v_i += N_ip m_p v_p^{t+dt}: scatter_block_2d_kind's momentum,
     * the same products in the same order. */
    size_t t = (size_t)(local[0] + TILE * local[1]);
    double mass = point_mass[p];
    for (int b = 0; b < 2; b++) {
      size_t row = t + (size_t)(TILE * b);
      double mvx = mass * moved[0] * wy[b], mvy = mass * moved[1] * wy[b];
      tn[row][0] += wx[0] * mvx;
      tn[row + 1][0] += wx[1] * mvx;
      tn[row][1] += wx[0] * mvy;
      tn[row + 1][1] += wx[1] * mvy;
    }
  }
  *kept = same;
  return inside;
}

static void move_remap_blocks(void *context, size_t begin, size_t end,
                              int worker) {
  move_remap_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const linear_move_2d *m = &ctx->move;
  momentum_tile tile;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = ctx->blocks[item];
    bool kept;
    bool inside =
        m->pic == 0.0
            ? move_remap_block_kind(domain, m, block, &tile, &kept, false)
            : move_remap_block_kind(domain, m, block, &tile, &kept, true);
    ctx->left_block[worker] |= !kept;
    const uint32_t *links =
        domain->grid.neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
    flush_tile(ctx->sum, links, &tile);
    if (inside)
      continue;
    const gm_grid *grid = &domain->grid;
    for (uint32_t k = grid->point_start[block];
         k < grid->point_start[block + 1]; k++)
      gm_report_moved_point(domain, &domain->scratch[worker],
                            domain->points.order[k], m->dt);
  }
}

/* Clears the spare sums of a range of blocks (before the sweep) where
 * other blocks' halos reach them (own_nodes.h). */
static void clear_sums(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  move_remap_context *ctx = context;
  gm_clear_shared_nodes_2d(ctx->sum[0], begin, end);
  gm_clear_shared_nodes_2d(ctx->sum[1], begin, end);
}

/* Copies the new momenta of a range of blocks to the grid (after it). */
static void copy_sums(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  move_remap_context *ctx = context;
  gm_remap_sums_commit(&ctx->domain->grid, ctx->sum, begin, end);
}

void gm_move_remap(gm_domain *domain, double dt) {
  gm_grid *grid = &domain->grid;
  gm_points *points = &domain->points;
  move_remap_context ctx;
  ctx.domain = domain;
  for (int w = 0; w < domain->worker_count; w++)
    ctx.left_block[w] = false;
  gm_linear_move_2d_init(domain, dt, &ctx.move);
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  ctx.sum[0] = to->deformation[F_XX]; /* spare until DEFORM (above) */
  ctx.sum[1] = to->deformation[F_XY];
  gm_parallel_for(&domain->pool, grid->block_count, clear_sums, &ctx);
  for (int colour = 0; colour < 4; colour++) { /* 2D: 4 colours */
    size_t first = grid->color_start[colour];
    size_t count = grid->color_start[colour + 1] - first;
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, count, move_remap_blocks, &ctx);
  }
  gm_parallel_for(&domain->pool, grid->block_count, copy_sums, &ctx);
  bool kept = true;
  for (int w = 0; w < domain->worker_count; w++)
    kept = kept && !ctx.left_block[w];
  points->blocks_kept = kept; /* read by the next binning (bins.c) */
}
