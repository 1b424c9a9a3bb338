/*
 * move_remap_3d.c - USL's move pass and its momentum re-map in one sweep
 * over the points, in 3D with linear shape functions (the 3D twin of
 * move_remap.c, issue 16 item 5). The separate passes (g2p_3d.c's
 * flip-and-move, then p2g_3d.c's momentum scatter, step.c
 * REMAP_MOMENTUM) each walk every point and each compute its 8 weights
 * and node indices; here each block's points are moved and their
 * re-mapped momenta m_p v_p^{t+dt} summed in the same loop, from the
 * same weights and nodes: the re-map uses the committed positions, as the
 * move's gather does (Sulsky, Zhou & Schreyer 1995; 004 sec 3.2).
 *
 * Every bit is that of the separate passes. A point's gather, FLIP update
 * and move are g2p_3d.c's expressions in its order (nodes c, b, a; the
 * weight (w_x w_y) w_z); its momenta are summed as scatter_block_3d_kind
 * sums them, (N_i m_p) v_p, straight into per-node sums through the
 * block's neighbour links, the blocks colour by colour (8 colours, the
 * parities of the block coordinates) in the grid's colour order and the
 * points of a block in order[] order, so every node receives the same
 * ((0 + t_0) + t_1) + ... as in gm_p2g_3d, for any worker count.
 *
 * The new momenta cannot go to the grid's momentum arrays while later
 * colours still gather the nodal velocities v_i^L stored there
 * (grid_update_3d.c), so they are summed into three spare node arrays
 * and copied over once every block has moved. The spare arrays are the
 * next buffer's F_xx, F_xy and F_xz: USL writes them only in its DEFORM
 * stage, after this one, and reads the committed F until then (step.c),
 * so for the length of this stage they hold nothing (as move_remap.c's
 * pair in 2D). A grid with more nodes than the buffers have point slots,
 * and every scene gm_move_remap_3d_fits refuses, takes the separate
 * passes.
 *
 * The sweep also tells the next binning whether every point stayed in its
 * block (points.blocks_kept; bins.c).
 */
#include "grid/grid.h"

#include <math.h>
#include <string.h>

typedef struct move_remap_3d_context {
  gm_domain *domain;
  double dt;              /* s */
  const uint32_t *blocks; /* blocks of the colour being swept */
  double *sum[3];         /* kg m/s, the new momenta, per grid node */
  bool left_block[256];   /* per worker (domain.c: at most 256): a point
                             left the block it was binned in */
} move_remap_3d_context;

bool gm_move_remap_3d_fits(const gm_domain *domain) {
  const gm_points *points = &domain->points;
  return domain->dim == 3 && domain->def.scheme == GM_SCHEME_USL &&
         domain->shape_grid.shape == GM_SHAPE_LINEAR &&
         domain->def.transfer != GM_TRANSFER_APIC &&
         domain->def.family == GM_FAMILY_PLAIN && domain->rigid_count == 0 &&
         !gm_periodic_x(domain) &&
         domain->grid.block_count * GM_BLOCK_NODES <= points->capacity;
}

/* Names point p if its moved position (next buffer) is outside the grid
 * box or not finite: g2p_3d.c move_chunk_3d's test and message. */
static void report_moved_point_3d(gm_domain *domain,
                                  gm_worker_scratch *scratch, size_t p,
                                  double dt) {
  const gm_point_buffers *to = &domain->points.buffer[domain->points.cur ^ 1];
  const double *origin = domain->shape_grid.origin;
  double moved[3];
  bool inside = true;
  for (int k = 0; k < 3; k++) {
    moved[k] = to->position[k][p];
    double scaled = (moved[k] - origin[k]) * domain->inv_cell;
    inside = inside && scaled >= GM_GHOST_LAYERS &&
             scaled < (double)(domain->cells[k] + GM_GHOST_LAYERS);
  }
  if (inside)
    return;
  bool finite = isfinite(moved[0]) && isfinite(moved[1]) && isfinite(moved[2]);
  gm_worker_error(scratch, finite ? GM_ERR_OUT_OF_GRID : GM_ERR_NOT_FINITE, p,
                  "step: point id %lld %s (x = %g, y = %g, z = %g m at t = "
                  "%g s); the step was not taken",
                  (long long)domain->points.id[p],
                  finite ? "would leave the grid box"
                         : "got a non-finite position",
                  moved[0], moved[1], moved[2], domain->time + dt);
}

/* Moves the points of one block and adds their re-mapped momenta to the
 * sums; false if a moved point left the grid or is not finite. blend
 * (pic_fraction > 0) is a constant in each specialisation below. */
static GM_ALWAYS_INLINE bool
move_remap_block_3d_kind(gm_domain *domain, double dt, double *const sum[3],
                         uint32_t block, bool *kept, const bool blend) {
  const gm_points *points = &domain->points;
  const gm_grid *grid = &domain->grid;
  const gm_point_buffers *from = &points->buffer[points->cur];
  const gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const double *restrict position[3] = {
      from->position[0], from->position[1], from->position[2]}; /* m */
  const double *restrict velocity[3] = {
      from->velocity[0], from->velocity[1], from->velocity[2]}; /* m/s */
  double *restrict next_position[3] = {to->position[0], to->position[1],
                                       to->position[2]};
  double *restrict next_velocity[3] = {to->velocity[0], to->velocity[1],
                                       to->velocity[2]};
  /* After GM_GRID_FULL the grid's momenta hold v_i^L and its forces a_i
   * (grid_update_3d.c). */
  const double *restrict nodal_velocity[3] = {
      grid->momentum[0], grid->momentum[1], grid->momentum[2]}; /* m/s */
  const double *restrict nodal_acceleration[3] = {
      grid->force[0], grid->force[1], grid->force[2]}; /* m/s^2 */
  double *restrict sum_x = sum[0], *restrict sum_y = sum[1],
                   *restrict sum_z = sum[2];
  const double *restrict point_mass = points->mass; /* kg */
  int64_t *restrict key = points->block_key;
  const uint32_t *restrict order = points->order;
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  const double *origin = domain->shape_grid.origin; /* m, node 0 */
  double inv_cell = domain->inv_cell;               /* 1/m */
  double pic = domain->def.pic_fraction, flip = 1.0 - pic; /* - */
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  int64_t own_key = grid->block_key[block];
  bool inside = true, same = true;
  uint32_t end = grid->point_start[block + 1];
  for (uint32_t k = grid->point_start[block]; k < end; k++) {
    size_t p = order[k];
    double w[3][2], d[3][2]; /* weights, gradients (1/m; unused) */
    int64_t local[3];
    for (int axis = 0; axis < 3; axis++)
      local[axis] =
          gm_shape_linear_axis_inside(position[axis][p], origin[axis],
                                      inv_cell, w[axis], d[axis]) &
          mask;
    size_t node[8];
    double weight[8];
    for (int n = 0; n < 8; n++) {
      int a = n & 1, b = (n >> 1) & 1, c = n >> 2;
      node[n] = gm_block_node_3d(links, local[0] + a, local[1] + b,
                                 local[2] + c);
      weight[n] = w[0][a] * w[1][b] * w[2][c];
    }
    /* g2p_3d.c: a = sum N a_i, v = sum N v_i over c, b, a. */
    double acc[3] = {0, 0, 0}, vel[3] = {0, 0, 0};
    for (int n = 0; n < 8; n++)
      for (int i = 0; i < 3; i++) {
        acc[i] += weight[n] * nodal_acceleration[i][node[n]];
        vel[i] += weight[n] * nodal_velocity[i][node[n]];
      }
    double moved_velocity[3]; /* m/s */
    bool in = true;
    for (int i = 0; i < 3; i++) {
      double flipped = velocity[i][p] + dt * acc[i];
      moved_velocity[i] = blend ? flip * flipped + pic * vel[i] : flipped;
      next_velocity[i][p] = moved_velocity[i];
      double moved = position[i][p] + dt * vel[i]; /* m */
      next_position[i][p] = moved;
      double scaled = (moved - origin[i]) * inv_cell;
      in = in && scaled >= GM_GHOST_LAYERS &&
           scaled < (double)(domain->cells[i] + GM_GHOST_LAYERS);
    }
    inside &= in;
    if (in) {
      key[p] = gm_block_key_inside_3d(grid, next_position[0][p],
                                      next_position[1][p], next_position[2][p],
                                      origin, inv_cell);
      same &= key[p] == own_key;
    }
    /* m_i v_i += (N_ip m_p) v_p^{t+dt}: scatter_block_3d_kind's momentum,
     * the same products in the same order. */
    double m = point_mass[p];
    for (int n = 0; n < 8; n++) {
      double weighted = weight[n] * m; /* kg */
      sum_x[node[n]] += weighted * moved_velocity[0];
      sum_y[node[n]] += weighted * moved_velocity[1];
      sum_z[node[n]] += weighted * moved_velocity[2];
    }
  }
  *kept = same;
  return inside;
}

static void move_remap_blocks_3d(void *context, size_t begin, size_t end,
                                 int worker) {
  move_remap_3d_context *ctx = context;
  gm_domain *domain = ctx->domain;
  bool blend = domain->def.pic_fraction != 0.0;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = ctx->blocks[item];
    bool kept;
    bool inside = blend ? move_remap_block_3d_kind(domain, ctx->dt, ctx->sum,
                                                   block, &kept, true)
                        : move_remap_block_3d_kind(domain, ctx->dt, ctx->sum,
                                                   block, &kept, false);
    ctx->left_block[worker] |= !kept;
    if (inside)
      continue;
    const gm_grid *grid = &domain->grid;
    for (uint32_t k = grid->point_start[block];
         k < grid->point_start[block + 1]; k++)
      report_moved_point_3d(domain, &domain->scratch[worker],
                            domain->points.order[k], ctx->dt);
  }
}

/* Clears the spare sums of a range of blocks (before the sweep). */
static void clear_sums_3d(void *context, size_t begin, size_t end,
                          int worker) {
  (void)worker;
  move_remap_3d_context *ctx = context;
  size_t first = begin * GM_BLOCK_NODES;
  size_t bytes = (end - begin) * GM_BLOCK_NODES * sizeof(double);
  for (int k = 0; k < 3; k++)
    memset(ctx->sum[k] + first, 0, bytes);
}

/* Copies the new momenta of a range of blocks to the grid (after it). */
static void copy_sums_3d(void *context, size_t begin, size_t end,
                         int worker) {
  (void)worker;
  move_remap_3d_context *ctx = context;
  gm_grid *grid = &ctx->domain->grid;
  size_t first = begin * GM_BLOCK_NODES;
  size_t bytes = (end - begin) * GM_BLOCK_NODES * sizeof(double);
  for (int k = 0; k < 3; k++)
    memcpy(grid->momentum[k] + first, ctx->sum[k] + first, bytes);
}

void gm_move_remap_3d(gm_domain *domain, double dt) {
  gm_grid *grid = &domain->grid;
  gm_points *points = &domain->points;
  move_remap_3d_context ctx;
  ctx.domain = domain;
  ctx.dt = dt;
  for (int w = 0; w < domain->worker_count; w++)
    ctx.left_block[w] = false;
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  ctx.sum[0] = to->deformation[F_XX]; /* spare until DEFORM (above) */
  ctx.sum[1] = to->deformation[F_XY];
  ctx.sum[2] = to->deformation[F_XZ];
  gm_parallel_for(&domain->pool, grid->block_count, clear_sums_3d, &ctx);
  for (int colour = 0; colour < GM_BLOCK_COLOURS; colour++) {
    size_t first = grid->color_start[colour];
    size_t count = grid->color_start[colour + 1] - first;
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, count, move_remap_blocks_3d, &ctx);
  }
  gm_parallel_for(&domain->pool, grid->block_count, copy_sums_3d, &ctx);
  bool kept = true;
  for (int w = 0; w < domain->worker_count; w++)
    kept = kept && !ctx.left_block[w];
  points->blocks_kept = kept; /* read by the next binning (bins.c) */
}
