/*
 * move_remap_wide.c - USL's move pass and its momentum re-map in one sweep
 * over the points for uGIMP, cpGIMP and CPDI in 2D, as move_remap.c does
 * for linear MPM (issue 15): each block's points are moved (FLIP or
 * blended velocity, 004 eq 3.17; x' = x + dt sum S_i v_i^L) and their
 * re-mapped momenta m_p v_p^{t+dt} summed into the block's tile from the
 * same support, which the separate passes (g2p.c's flip-and-move, then the
 * REMAP_MOMENTUM scatter of p2g_wide.c) each compute: the re-map uses the
 * committed positions and domains, as the move's gather does (Sulsky, Zhou
 * & Schreyer 1995; 004 sec 3.2). One support per point instead of two, one
 * sweep instead of two.
 *
 * Every bit is that of the separate passes: a point's gather is
 * gather_wide.h's (the short support where the domain is no longer than a
 * cell, the general one otherwise; CPDI's corners of support_cpdi.h),
 * its velocity and position follow
 * flip_chunk and move_chunk expression by expression, its momenta go into
 * the tile as scatter_product sums them (weight S_a S_b times m_p v'; CPDI
 * corner by corner as scatter_cpdi), the
 * block's points in order[] order, and the tiles are flushed colour by
 * colour, the blocks of a colour in their order, over the nodes the
 * separate scatter flushes, into sums that start at zero as the cleared
 * grid does. The new momenta go to the spare pair of node arrays of
 * move_remap.c (the next buffer's F_xx and F_xy, dead until DEFORM: for
 * cpGIMP the next F is read only by the DEFORM stage's keys, after it
 * writes F; CPDI's domains follow the domain map D, not F) and are copied
 * to the grid's momenta once every block has
 * moved. The block keys of the moved points stay DEFORM's (a GIMP support
 * follows F in cpGIMP, a CPDI one D). A CPDI point's corner cells come
 * from the scatter of the same step where it kept them (cpdi_cache.h),
 * the fractions from the corners with support_cpdi.h's expressions.
 */
#include "grid/grid.h"

#include "grid/gather_wide.h"
#include "grid/transfer.h"

#include <string.h>

/* The block and its +x, +y, +x+y neighbours: every node a point binned in
 * the block reaches (p2g_wide.c). */
#define EDGE       (2 * GM_BLOCK_EDGE_2D)
#define TILE_NODES (EDGE * EDGE)

/* A block's re-mapped momenta (kg m/s), x and y side by side per node. */
typedef struct momentum_tile {
  double node[TILE_NODES][2];
} momentum_tile;

typedef struct move_remap_wide_context {
  gm_domain *domain;
  linear_move_2d move; /* dt, the blend, the box bounds (g2p.c) */
  gather_view view;    /* the nodal arrays and shape grid gather_wide.h reads */
  const uint32_t *blocks; /* blocks of the colour being swept */
  double *sum[2];         /* kg m/s, the new momenta, per grid node */
  bool cpdi;              /* CPDI corners, else the GIMP axes */
  gm_cpdi_cache cache;    /* CPDI: the cells the scatter kept */
} move_remap_wide_context;

bool gm_move_remap_wide_fits(const gm_domain *domain) {
  const gm_points *points = &domain->points;
  gm_shape shape = domain->shape_grid.shape;
  return domain->dim == 2 && domain->def.scheme == GM_SCHEME_USL &&
         (shape == GM_SHAPE_UGIMP || shape == GM_SHAPE_CPGIMP ||
          shape == GM_SHAPE_CPDI) &&
         domain->def.transfer != GM_TRANSFER_APIC &&
         domain->def.family == GM_FAMILY_PLAIN && domain->rigid_count == 0 &&
         !gm_periodic_x(domain) &&
         domain->grid.block_count * GM_BLOCK_NODES <= points->capacity;
}

bool gm_cpdi_cache_fits(const gm_domain *domain) {
  return domain->shape_grid.shape == GM_SHAPE_CPDI &&
         gm_move_remap_wide_fits(domain);
}

void gm_cpdi_cache_arrays(gm_domain *domain, gm_cpdi_cache *out) {
  out->packed = domain->points.block_key; /* keyed again by the deformation */
}

/* Adds the tile's first `rows` x `columns` nodes to the sums (p2g_wide.c
 * flush_wide_tile, the same nodes in the same order). */
static void flush_tile(double *const sum[2], const uint32_t *links,
                       const momentum_tile *tile, int64_t columns,
                       int64_t rows) {
  const int shift = GM_BLOCK_SHIFT_2D;
  for (int64_t y = 0; y < rows; y++) {
    for (int64_t x = 0; x < columns; x++) {
      int neighbour = (int)(x >> shift) + 2 * (int)(y >> shift);
      if (links[neighbour] == GM_NO_BLOCK)
        continue; /* past the grid's last node: never reached */
      size_t node = gm_block_node(links, shift, x, y);
      sum[0][node] += tile->node[x + EDGE * y][0];
      sum[1][node] += tile->node[x + EDGE * y][1];
    }
  }
}

/* Point p's support: the short one into axis (true in *is_short), else the
 * general one into product; x0, y0 its lowest node from the block's base
 * and reach its farthest node past that. False (the error recorded, as
 * the separate passes record it) if it cannot be computed or does not fit
 * the block's neighbours. */
static GM_ALWAYS_INLINE bool
point_support(const gm_domain *domain, const gather_view *v,
              const gm_shape_grid *shape_grid, size_t p, const int64_t base[2],
              gm_short_axis axis[2], gm_product_support *product,
              bool *is_short, int64_t *x0, int64_t *y0, int64_t reach[2],
              gm_worker_scratch *scratch) {
  double half[2]; /* m */
  gm_rectangle_half_edges(v->shape_grid->shape, 2, v->domain_size,
                          v->support_tensor, p, half);
  if (gm_short_support_2d(shape_grid, v->position[0][p], v->position[1][p],
                          half[0], half[1], axis)) {
    *x0 = axis[0].lowest - base[0];
    *y0 = axis[1].lowest - base[1];
    reach[0] = axis[0].reach;
    reach[1] = axis[1].reach;
    if (gm_wide_support_fits(2, *x0, *y0, reach, EDGE)) {
      *is_short = true;
      return true;
    }
  }
  *is_short = false;
  bool found = gm_product_support_rectangle(v->shape_grid, v->position[0][p],
                                            v->position[1][p], half[0], half[1],
                                            product);
  *x0 = product->lowest[0] - base[0];
  *y0 = product->lowest[1] - base[1];
  reach[0] = product->span[0] - 1;
  reach[1] = product->span[1] - 1;
  if (found && gm_wide_support_fits(2, *x0, *y0, reach, EDGE))
    return true;
  gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                  "step: the support of point id %lld cannot be "
                  "computed or does not fit the block it was binned in "
                  "(a degenerate domain, e.g. an edge far below a cell); "
                  "the step was not taken",
                  (long long)domain->points.id[p]);
  return false;
}

/* Point p's CPDI support (support_cpdi.h; the committed domain map),
 * with its reach per axis; false (the error recorded as the separate
 * passes record it) as point_support. */
static GM_ALWAYS_INLINE bool
cpdi_point_support(const gm_domain *domain, const gather_view *v,
                   const gm_shape_grid *shape_grid, size_t p,
                   const int64_t base[2], gm_cpdi_support *corners,
                   int64_t reach[2], gm_worker_scratch *scratch) {
  if (gm_cpdi_point_support_2d(shape_grid, v->position, v->support_tensor,
                               v->domain_size, p, corners, reach) &&
      gm_wide_support_fits(2, corners->lowest[0] - base[0],
                           corners->lowest[1] - base[1], reach, EDGE))
    return true;
  gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                  "step: the support of point id %lld cannot be "
                  "computed or does not fit the block it was binned in "
                  "(a degenerate domain, e.g. an edge far below a cell); "
                  "the step was not taken",
                  (long long)domain->points.id[p]);
  return false;
}

/* CPDI's re-mapped momentum, corner by corner as p2g_wide.c's scatter_cpdi
 * sums it (share of m_p v' times N_i(x_c)), the same products in the same
 * order. */
static GM_ALWAYS_INLINE void scatter_cpdi_momentum(momentum_tile *tile,
                                                   const gm_cpdi_kept *s,
                                                   double momentum_x,
                                                   double momentum_y) {
  double share = 0.25; /* gm_cpdi_support_2d's */
  double share_x = share * momentum_x, share_y = share * momentum_y;
  for (int c = 0; c < 4; c++) {
    /* the corner cell's lower left node; the others at fixed offsets */
    double(*cell)[2] = &tile->node[s->tile[c]]; /* EDGE = 16 */
    for (int b = 0; b < 2; b++) {
      for (int a = 0; a < 2; a++) {
        double value = s->axis[c][0][a] * s->axis[c][1][b];
        double *node = cell[a + EDGE * b];
#if defined(__GNUC__) /* x and y as one pair, the same operation per lane */
        gm_pair w = {value, value}, part = {share_x, share_y}, sum;
        memcpy(&sum, node, sizeof sum);
        sum += w * part;
        memcpy(node, &sum, sizeof sum);
#else
        node[0] += value * share_x;
        node[1] += value * share_y;
#endif
      }
    }
  }
}

/* Moves the points of one block and sums their re-mapped momenta into
 * its tile (rows x columns nodes touched); returns false if a moved point
 * left the grid or is not finite. blend (pic_fraction > 0) is a constant
 * in each specialisation below. */
static GM_ALWAYS_INLINE bool
move_remap_block_kind(const gm_domain *domain, const move_remap_wide_context *c,
                      uint32_t block, momentum_tile *tile, int64_t *columns,
                      int64_t *rows, gm_worker_scratch *scratch,
                      const bool blend, const bool cpdi) {
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
  const uint32_t *restrict order = points->order;
  const uint32_t *links =
      domain->grid.neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  const gather_view *v = &c->view;
  const linear_move_2d local_move = c->move, *m = &local_move;
  /* A local copy: the tile's stores would otherwise reload it per point. */
  const gm_shape_grid shape_grid = *v->shape_grid;
  double dt = m->dt;
  int64_t base[2];
  gm_block_base(&domain->grid, domain->grid.block_key[block], base);
  gm_tile_values tile_values; /* the corners' nodal values (tile_values.h) */
  if (cpdi) {
    gm_tile_values_start(links, &tile_values);
  }
  memset(tile, 0, sizeof *tile);
  *columns = 0;
  *rows = 1;
  bool inside = true;
  uint32_t end = domain->grid.point_start[block + 1];
  for (uint32_t k = domain->grid.point_start[block]; k < end; k++) {
    size_t p = order[k];
    gm_short_axis axis[2];
    gm_product_support product;
    gm_cpdi_support corners;
    gm_cpdi_kept kept;
    bool is_short = false;
    int64_t x0, y0, reach[2];
    bool found;
    if (cpdi) {
      /* the cells the scatter kept (cpdi_cache.h) and the fractions
       * from them, else the whole support */
      found = gm_cpdi_kept_load(&c->cache, p, &kept);
      if (found) {
        double corner_position[4][2]; /* m */
        gather_cpdi_kept_rows(v, &tile_values, &kept, true, false);
        gm_cpdi_kept_fractions(&shape_grid, v->position, v->support_tensor,
                               v->domain_size, p, base, &kept, corner_position);
      } else if (cpdi_point_support(domain, v, &shape_grid, p, base, &corners,
                                    reach, scratch)) {
        gm_cpdi_kept_from_support(&corners, base, reach, &kept);
        gather_cpdi_kept_rows(v, &tile_values, &kept, true, false);
        found = true;
      }
      x0 = found ? kept.lowest[0] : 0;
      y0 = found ? kept.lowest[1] : 0;
      reach[0] = found ? kept.reach[0] : 0;
      reach[1] = found ? kept.reach[1] : 0;
    } else {
      found = point_support(domain, v, &shape_grid, p, base, axis, &product,
                            &is_short, &x0, &y0, reach, scratch);
    }
    /* A point without a support gathers nothing and is moved by zero, as
     * in the separate passes; the step fails anyway. */
    point_gather sum = {
        {0.0, 0.0}, {0.0, 0.0}, {{0.0, 0.0}, {0.0, 0.0}}, {0.0, 0.0}};
    if (found && cpdi)
      gather_cpdi_kept_2d(&tile_values, &kept, NULL, &sum, true,
                          false); /* no g_c read */
    else if (found && is_short)
      gather_short_2d(v, links, x0, y0, axis, &sum, true, false);
    else if (found)
      gather_product(v, links, x0, y0, &product, &sum, 2);
    /* flip_chunk, then move_chunk, expression by expression. */
    double vx, vy; /* m/s */
    if (blend) {
      vx = m->flip * (pvx[p] + dt * sum.acceleration[0]) +
           m->pic * sum.velocity[0];
      vy = m->flip * (pvy[p] + dt * sum.acceleration[1]) +
           m->pic * sum.velocity[1];
    } else {
      vx = pvx[p] + dt * sum.acceleration[0];
      vy = pvy[p] + dt * sum.acceleration[1];
    }
    double moved_x = px[p] + dt * sum.velocity[0]; /* m */
    double moved_y = py[p] + dt * sum.velocity[1];
    next_vx[p] = vx;
    next_vy[p] = vy;
    next_x[p] = moved_x;
    next_y[p] = moved_y;
    double scaled_x = (moved_x - m->origin[0]) * m->inv_cell;
    double scaled_y = (moved_y - m->origin[1]) * m->inv_cell;
    inside &= (scaled_x >= GM_GHOST_LAYERS) & (scaled_x < m->cells[0]) &
              (scaled_y >= GM_GHOST_LAYERS) & (scaled_y < m->cells[1]);
    if (!found)
      continue;
    /* m_i v_i += S_ip m_p v_p^{t+dt}: scatter_product's momentum, the
     * same products in the same order. */
    *columns = x0 + reach[0] + 1 > *columns ? x0 + reach[0] + 1 : *columns;
    *rows = y0 + reach[1] + 1 > *rows ? y0 + reach[1] + 1 : *rows;
    double mass = point_mass[p];
    double momentum_x = mass * vx, momentum_y = mass * vy; /* kg m/s */
    if (cpdi) {
      scatter_cpdi_momentum(tile, &kept, momentum_x, momentum_y);
      continue;
    }
    const double *weight_x = is_short ? axis[0].weight : product.weight[0];
    const double *weight_y = is_short ? axis[1].weight : product.weight[1];
    for (int64_t b = 0; b <= reach[1]; b++) {
      size_t row = (size_t)(x0 + EDGE * (y0 + b));
      for (int64_t a = 0; a <= reach[0]; a++) {
        double weight = weight_x[a] * weight_y[b];
        tile->node[row + (size_t)a][0] += weight * momentum_x;
        tile->node[row + (size_t)a][1] += weight * momentum_y;
      }
    }
  }
  return inside;
}

static void move_remap_blocks(void *context, size_t begin, size_t end,
                              int worker) {
  move_remap_wide_context *c = context;
  gm_domain *domain = c->domain;
  gm_worker_scratch *scratch = &domain->scratch[worker];
  momentum_tile tile;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = c->blocks[item];
    int64_t columns, rows;
    bool blend = c->move.pic != 0.0;
    bool inside;
    if (c->cpdi)
      inside = blend ? move_remap_block_kind(domain, c, block, &tile, &columns,
                                             &rows, scratch, true, true)
                     : move_remap_block_kind(domain, c, block, &tile, &columns,
                                             &rows, scratch, false, true);
    else
      inside = blend ? move_remap_block_kind(domain, c, block, &tile, &columns,
                                             &rows, scratch, true, false)
                     : move_remap_block_kind(domain, c, block, &tile, &columns,
                                             &rows, scratch, false, false);
    const uint32_t *links =
        domain->grid.neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
    flush_tile(c->sum, links, &tile, columns, rows);
    if (inside)
      continue;
    const gm_grid *grid = &domain->grid;
    for (uint32_t k = grid->point_start[block];
         k < grid->point_start[block + 1]; k++)
      gm_report_moved_point(domain, scratch, domain->points.order[k],
                            c->move.dt);
  }
}

/* Clears the spare sums of a range of blocks (before the sweep). */
static void clear_sums(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  move_remap_wide_context *c = context;
  gm_remap_sums_clear(c->sum, begin, end);
}

/* Copies the new momenta of a range of blocks to the grid (after it). */
static void copy_sums(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  move_remap_wide_context *c = context;
  gm_remap_sums_commit(&c->domain->grid, c->sum, begin, end);
}

void gm_move_remap_wide(gm_domain *domain, double dt) {
  gm_grid *grid = &domain->grid;
  gm_points *points = &domain->points;
  move_remap_wide_context c;
  memset(&c, 0, sizeof c);
  c.domain = domain;
  c.cpdi = domain->shape_grid.shape == GM_SHAPE_CPDI;
  if (c.cpdi) /* the scatter of this step kept them (gm_cpdi_cache_fits) */
    gm_cpdi_cache_arrays(domain, &c.cache);
  gm_linear_move_2d_init(domain, dt, &c.move);
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  gather_view *v = &c.view; /* what gather_wide.h reads, as g2p.c's view */
  for (int k = 0; k < 2; k++) {
    v->position[k] = from->position[k];
    v->grid_velocity[k] = grid->momentum[k]; /* velocity by now */
    v->grid_acceleration[k] = grid->force[k];
    v->domain_size[k] = points->domain_size[k];
  }
  v->grid_mass = grid->mass;
  v->shift = grid->shift; /* gather_product's node lookup (gm_block_node) */
  v->shape_grid = &domain->shape_grid;
  gm_support_tensor(domain, from, v->support_tensor);
  c.sum[0] = to->deformation[F_XX]; /* spare until DEFORM (move_remap.c) */
  c.sum[1] = to->deformation[F_XY];
  gm_parallel_for(&domain->pool, grid->block_count, clear_sums, &c);
  for (int colour = 0; colour < 4; colour++) { /* 2D: 4 colours */
    size_t first = grid->color_start[colour];
    size_t count = grid->color_start[colour + 1] - first;
    c.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, count, move_remap_blocks, &c);
  }
  gm_parallel_for(&domain->pool, grid->block_count, copy_sums, &c);
}
