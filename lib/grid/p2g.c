/*
 * p2g.c - particle-to-grid transfer: lumped nodal mass, momentum and forces
 * (004 eqs 3.13-3.15; 002 eq 9 with the axisymmetric hoop row N_i/x of B).
 * Blocks are scattered colour by colour, each block by one worker, in a
 * fixed order: the sums are bitwise identical for any worker count.
 *
 * The kernels copy every array pointer into restrict-qualified locals
 * (struct scatter_view) so the compiler keeps them in registers instead of
 * reloading them after each store to the grid.
 */
#include "grid/grid.h"

#include "grid/own_nodes.h"
#include "grid/transfer.h"

#include <math.h>
#include <string.h>

typedef struct p2g_context {
  gm_domain *domain;
  const gm_p2g_pass *pass;
  scatter_view view;
  const uint32_t *blocks; /* blocks of the colour being scattered */
} p2g_context;

/* Names the first point of a block whose host inputs are not finite. A
 * cheap screen first: x * 0 is 0 for every finite x and NaN otherwise. */
static void check_inputs(gm_domain *domain, gm_worker_scratch *scratch,
                         const scatter_view *v, uint32_t begin, uint32_t end) {
  int dim = domain->dim;
  double screen = 0.0;
  for (uint32_t k = begin; k < end; k++) {
    size_t p = v->order[k];
    for (int c = 0; c < dim; c++) {
      screen += v->velocity[c][p] * 0.0;
      if (v->external_force[c])
        screen += v->external_force[c][p] * 0.0;
    }
    for (int c = 0; v->apic && c < dim * dim; c++)
      screen += v->affine[c][p] * 0.0;
  }
  if (screen == 0.0)
    return;
  for (uint32_t k = begin; k < end; k++) {
    size_t p = v->order[k];
    for (int c = 0; c < dim; c++) {
      double force = v->external_force[c] ? v->external_force[c][p] : 0.0;
      if (isfinite(v->velocity[c][p]) && isfinite(force))
        continue;
      gm_worker_error(
          scratch, GM_ERR_NOT_FINITE, p,
          "step: point id %lld has a non-finite %s (component "
          "%d); the step was not taken",
          (long long)domain->points.id[p],
          isfinite(v->velocity[c][p]) ? "external force" : "velocity", c);
    }
    for (int c = 0; v->apic && c < dim * dim; c++)
      if (!isfinite(v->affine[c][p]))
        gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                        "step: point id %lld has a non-finite affine "
                        "matrix B_p (GM_FIELD_AFFINE component %d); the "
                        "step was not taken",
                        (long long)domain->points.id[p], c);
  }
}

/* A block's points are first summed into a stack tile of the block's
 * nodes plus the one-node halo its cells reach (9 x 9 in 2D), where the
 * four nodes of a cell are at i, i+1, i+T, i+T+1: no neighbour lookups per
 * point. The tile is then added to the grid once per block. A tile node
 * holds its fields side by side (one base pointer for the whole tile: the
 * kernel has fewer live pointers than x86-64 has registers, where five
 * separate field arrays made it spill; and a point's updates of one node
 * share a cache line). Each field of each node is still summed alone, in
 * point order, so the sums are bitwise those of separate arrays. */
#define TILE       (GM_BLOCK_EDGE_2D + 1)
#define TILE_NODES (TILE * TILE)

enum {
  TILE_MASS,       /* kg */
  TILE_MOMENTUM_X, /* kg m/s */
  TILE_MOMENTUM_Y,
  TILE_FORCE_X, /* N */
  TILE_FORCE_Y,
  TILE_FIELDS
};

typedef struct scatter_tile {
  double node[TILE_NODES][TILE_FIELDS];
} scatter_tile;

/* Adds the rows [y0, y1) x columns [x0, x1) of the tile (tile
 * coordinates) to the block `block` of the grid, whose node (0, 0) is tile
 * node (base_x, base_y); with `store`, a region only this tile reaches,
 * stores them (own_nodes.h). */
static GM_ALWAYS_INLINE void
flush_region(const scatter_view *v, uint32_t block, const scatter_tile *tile,
             int x0, int x1, int y0, int y1, int base_x, int base_y,
             const bool do_mass, const bool do_momentum, const bool do_forces,
             const bool store) {
  double *restrict mass = v->grid_mass;
  double *restrict momentum_x = v->grid_momentum[0];
  double *restrict momentum_y = v->grid_momentum[1];
  double *restrict force_x = v->grid_force[0];
  double *restrict force_y = v->grid_force[1];
  size_t block_first = (size_t)block * GM_BLOCK_NODES;
  for (int ty = y0; ty < y1; ty++) {
    size_t row = block_first + GM_BLOCK_EDGE_2D * (size_t)(ty - base_y);
    for (int tx = x0; tx < x1; tx++) {
      size_t node = row + (size_t)(tx - base_x);
      const double *sums = tile->node[tx + TILE * ty];
      if (do_mass)
        mass[node] = gm_own_sum(store, mass[node], sums[TILE_MASS]);
      if (do_momentum) {
        momentum_x[node] =
            gm_own_sum(store, momentum_x[node], sums[TILE_MOMENTUM_X]);
        momentum_y[node] =
            gm_own_sum(store, momentum_y[node], sums[TILE_MOMENTUM_Y]);
      }
      if (do_forces) {
        force_x[node] = gm_own_sum(store, force_x[node], sums[TILE_FORCE_X]);
        force_y[node] = gm_own_sum(store, force_y[node], sums[TILE_FORCE_Y]);
      }
    }
  }
}

/* Adds the tile to the grid through the links: the block's own 8 x 8
 * nodes (row 0 and column 0 added to their cleared values, the others
 * stored: own_nodes.h), then the halo column (+x neighbour), row (+y) and
 * corner (+x+y), each a rectangle of one block (every node receives one
 * sum per field, as before: the order of the additions to a node does not
 * change). A neighbour past the grid's last node (GM_NO_BLOCK) is never
 * reached by points and is skipped. */
static void flush_tile(const scatter_view *v, const uint32_t *links,
                       const scatter_tile *tile, const bool do_mass,
                       const bool do_momentum, const bool do_forces) {
  const int E = GM_BLOCK_EDGE_2D;
  flush_region(v, links[0], tile, 0, E, 0, 1, 0, 0, do_mass, do_momentum,
               do_forces, false);
  flush_region(v, links[0], tile, 0, 1, 1, E, 0, 0, do_mass, do_momentum,
               do_forces, false);
  flush_region(v, links[0], tile, 1, E, 1, E, 0, 0, do_mass, do_momentum,
               do_forces, true);
  if (links[1] != GM_NO_BLOCK)
    flush_region(v, links[1], tile, E, TILE, 0, E, E, 0, do_mass, do_momentum,
                 do_forces, false);
  if (links[2] != GM_NO_BLOCK)
    flush_region(v, links[2], tile, 0, E, E, TILE, 0, E, do_mass, do_momentum,
                 do_forces, false);
  if (links[3] != GM_NO_BLOCK)
    flush_region(v, links[3], tile, E, TILE, E, TILE, E, E, do_mass,
                 do_momentum, do_forces, false);
}

/* do_* and apic are compile-time constants in each specialisation below,
 * so each pass kind gets its own tight loop.
 *
 * APIC with multilinear weights. Per axis a point at fraction f of its
 * cell has N = (1 - f, f) at offsets x_i - x_p = (-f h, (1 - f) h), so
 * D_p = diag(f (1 - f) h^2) and N_ip D_p^-1 (x_i - x_p) = grad N_ip
 * (-1/h, 1/h): the paper's affine momentum m_p N_ip B_p D_p^-1 (x_i - x_p)
 * (Jiang et al. 2015) hands a node m_p B_p / h however small the point's
 * weight on it. B_p was gathered where D_p was larger (the step before),
 * so a point that has just moved close to a node line puts finite
 * momentum on a node of vanishing mass, whose velocity then blows up
 * (measured: the rotating disc of test_apic.c inverts a point within 15
 * steps; flooring D_p at h^2/16 or h^2/64 keeps it stable but loses 5.5
 * or 1.3 % of the angular momentum over its 100 steps). Linear MPM
 * therefore keeps C_p = B_p D_p^-1 itself, gathered as C_p = sum v_i (x)
 * grad N_ip (the same matrix at the positions of the gather), and hands
 * node i m_p N_ip (v_p + C_p (x_i - x_p)): bounded, exact for affine
 * velocity fields at every step, and momentum-conserving
 * (sum_i N_ip (x_i - x_p) = 0). Angular momentum is then exact across the
 * transfers except for the change of D_p as points move (the moment
 * m_p C_p D_p is gathered with one D_p and scattered with the next): a
 * bounded error, 0.5 % for the disc, that does not accumulate. The wide
 * shapes (p2g_wide.c) have D_p bounded below and keep the exact form.
 * Keeping C_p makes each node's velocity a degree of freedom of its own,
 * unstable at nodes of tiny mass: the gather takes their acceleration into
 * C_p in part only (apic_linear.h). */
static GM_ALWAYS_INLINE void
scatter_block_2d_kind(const scatter_view *v, uint32_t block, scatter_tile *tile,
                      const bool do_mass, const bool do_momentum,
                      const bool do_forces, const bool apic) {
  const double *restrict px = v->position[0], *restrict py = v->position[1];
  const double *restrict vx = v->velocity[0], *restrict vy = v->velocity[1];
  const double *restrict point_mass = v->mass, *restrict volume = v->volume;
  const double *restrict sxx = v->stress[0], *restrict syy = v->stress[1];
  const double *restrict szz = v->stress[2], *restrict sxy = v->stress[3];
  const double *restrict fx_ext = v->external_force[0];
  const double *restrict fy_ext = v->external_force[1];
  /* APIC's C_p (1/s) in linear MPM: see above. */
  const double *restrict c_xx = v->affine[0], *restrict c_xy = v->affine[1];
  const double *restrict c_yx = v->affine[2], *restrict c_yy = v->affine[3];
  double(*restrict tn)[TILE_FIELDS] = tile->node;
  const uint32_t *restrict order = v->order;
  int64_t mask = GM_BLOCK_EDGE_2D - 1;
  double origin_x = v->origin[0], origin_y = v->origin[1];
  double inv_cell = v->inv_cell;
  double gravity_x = v->gravity[0], gravity_y = v->gravity[1];
  double cell = v->cell; /* m */
  bool axisymmetric = v->axisymmetric, has_external = fx_ext != NULL;
  for (int t = 0; t < TILE_NODES; t++)
    for (int f = 0; f < TILE_FIELDS; f++)
      tn[t][f] = 0.0;
  for (uint32_t k = v->point_start[block]; k < v->point_start[block + 1]; k++) {
    size_t p = order[k];
    if (v->skip_rigid && v->rigid[v->material[p]])
      continue; /* rigid points take no part (rigid.c) */
    double wx[2], dx[2], wy[2], dy[2];
    int64_t cx = gm_shape_linear_axis_inside(px[p], origin_x, inv_cell, wx, dx);
    int64_t cy = gm_shape_linear_axis_inside(py[p], origin_y, inv_cell, wy, dy);
    size_t t = (size_t)((cx & mask) + TILE * (cy & mask));
    double m = point_mass[p];
    for (int b = 0; b < 2; b++) {
      size_t row = t + (size_t)(TILE * b);
      if (do_mass) {
        tn[row][TILE_MASS] += wx[0] * wy[b] * m;
        tn[row + 1][TILE_MASS] += wx[1] * wy[b] * m;
      }
      if (do_momentum && !apic) {
        double mvx = m * vx[p] * wy[b], mvy = m * vy[p] * wy[b];
        tn[row][TILE_MOMENTUM_X] += wx[0] * mvx;
        tn[row + 1][TILE_MOMENTUM_X] += wx[1] * mvx;
        tn[row][TILE_MOMENTUM_Y] += wx[0] * mvy;
        tn[row + 1][TILE_MOMENTUM_Y] += wx[1] * mvy;
      }
      if (do_momentum && apic) { /* m_p N (v_p + C_p (x_i - x_p)) */
        double ox[2], oy[2];     /* m, x_i - x_p per axis */
        gm_linear_offsets(wx, cell, ox);
        gm_linear_offsets(wy, cell, oy);
        double node_vx = vx[p] + c_xy[p] * oy[b]; /* m/s, before x */
        double node_vy = vy[p] + c_yy[p] * oy[b];
        for (int a = 0; a < 2; a++) {
          double weight = wx[a] * wy[b] * m; /* kg */
          tn[row + a][TILE_MOMENTUM_X] += weight * (node_vx + c_xx[p] * ox[a]);
          tn[row + a][TILE_MOMENTUM_Y] += weight * (node_vy + c_yx[p] * ox[a]);
        }
      }
    }
    if (!do_forces)
      continue;
    double V = volume[p]; /* stress times volume: N m */
    double txx = sxx[p] * V, tyy = syy[p] * V, txy = sxy[p] * V;
    double body_x = m * gravity_x, body_y = m * gravity_y;
    if (has_external) {
      body_x += fx_ext[p];
      body_y += fy_ext[p];
    }
    /* Hoop row of B (002 sec 3): sigma_tt V N_i / x acts radially. */
    if (axisymmetric)
      body_x -= szz[p] * V / px[p];
    for (int b = 0; b < 2; b++) {
      size_t row = t + (size_t)(TILE * b);
      for (int a = 0; a < 2; a++) {
        double weight = wx[a] * wy[b];
        double grad_x = dx[a] * wy[b], grad_y = wx[a] * dy[b];
        tn[row + a][TILE_FORCE_X] +=
            weight * body_x - (txx * grad_x + txy * grad_y);
        tn[row + a][TILE_FORCE_Y] +=
            weight * body_y - (txy * grad_x + tyy * grad_y);
      }
    }
  }
  const uint32_t *links = v->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  flush_tile(v, links, tile, do_mass, do_momentum, do_forces);
}

static GM_ALWAYS_INLINE void
scatter_block_2d_pass(const scatter_view *v, const gm_p2g_pass *pass,
                      uint32_t block, scatter_tile *tile, const bool apic) {
  if (pass->mass && pass->momentum && pass->forces)
    scatter_block_2d_kind(v, block, tile, true, true, true, apic);
  else if (pass->mass && pass->momentum)
    scatter_block_2d_kind(v, block, tile, true, true, false, apic);
  else if (pass->momentum && pass->forces)
    scatter_block_2d_kind(v, block, tile, false, true, true, apic);
  else if (pass->momentum)
    scatter_block_2d_kind(v, block, tile, false, true, false, apic);
  else /* no momentum: the transfer choice does not matter */
    scatter_block_2d_kind(v, block, tile, pass->mass, false, pass->forces,
                          false);
}

static void scatter_block_2d(const scatter_view *v, const gm_p2g_pass *pass,
                             uint32_t block) {
  scatter_tile tile;
  if (v->apic)
    scatter_block_2d_pass(v, pass, block, &tile, true);
  else
    scatter_block_2d_pass(v, pass, block, &tile, false);
}

static void scatter_block_1d(const scatter_view *v, const gm_p2g_pass *pass,
                             uint32_t block) {
  const double *restrict px = v->position[0], *restrict vx = v->velocity[0];
  const double *restrict point_mass = v->mass, *restrict volume = v->volume;
  const double *restrict sxx = v->stress[0];
  const double *restrict fx_ext = v->external_force[0];
  double *restrict gm = v->grid_mass, *restrict gpx = v->grid_momentum[0];
  double *restrict gfx = v->grid_force[0];
  const uint32_t *links = v->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int64_t edge = (int64_t)1 << v->shift, mask = edge - 1;
  for (uint32_t k = v->point_start[block]; k < v->point_start[block + 1]; k++) {
    size_t p = v->order[k];
    if (v->skip_rigid && v->rigid[v->material[p]])
      continue; /* rigid points take no part (rigid.c) */
    double w[2], d[2];
    int64_t local =
        gm_shape_linear_axis(px[p], v->origin[0], v->inv_cell, w, d) & mask;
    int64_t next = local + 1;
    size_t node[2] = {(size_t)links[0] * GM_BLOCK_NODES + (size_t)local,
                      (size_t)links[next >> v->shift] * GM_BLOCK_NODES +
                          (size_t)(next & mask)};
    double m = point_mass[p];
    double body = m * v->gravity[0] + (fx_ext ? fx_ext[p] : 0.0);
    double txx = sxx[p] * volume[p];
    /* APIC: m_p N (v_p + C_p (x_i - x_p)), as in 2D. */
    double offset[2] = {0.0, 0.0}; /* m */
    if (v->apic)
      gm_linear_offsets(w, v->cell, offset);
    for (int n = 0; n < 2; n++) {
      if (pass->mass)
        gm[node[n]] += w[n] * m;
      if (pass->momentum && v->apic)
        gpx[node[n]] += w[n] * m * (vx[p] + v->affine[0][p] * offset[n]);
      else if (pass->momentum)
        gpx[node[n]] += w[n] * m * vx[p];
      if (pass->forces)
        gfx[node[n]] += w[n] * body - txx * d[n];
    }
  }
}

static void scatter_blocks(void *context, size_t begin, size_t end,
                           int worker) {
  p2g_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const scatter_view *view = &ctx->view;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = ctx->blocks[item];
    if (ctx->pass->check_inputs)
      check_inputs(domain, &domain->scratch[worker], view,
                   view->point_start[block], view->point_start[block + 1]);
    if (view->shape_grid->shape != GM_SHAPE_LINEAR)
      gm_scatter_block_wide(view, ctx->pass, block, domain,
                            &domain->scratch[worker]);
    else if (domain->dim == 1)
      scatter_block_1d(view, ctx->pass, block);
    else
      scatter_block_2d(view, ctx->pass, block);
  }
}

static void clear_blocks(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  p2g_context *ctx = context;
  gm_grid *grid = &ctx->domain->grid;
  int dim = grid->dim;
  size_t first = begin * GM_BLOCK_NODES;
  size_t bytes = (end - begin) * GM_BLOCK_NODES * sizeof(double);
  if (dim == 2 && ctx->view.shape_grid->shape == GM_SHAPE_LINEAR) {
    /* scatter_block_2d stores the rest (own_nodes.h). */
    if (ctx->pass->mass)
      gm_clear_shared_nodes_2d(grid->mass, begin, end);
    for (int k = 0; k < dim; k++) {
      if (ctx->pass->momentum)
        gm_clear_shared_nodes_2d(grid->momentum[k], begin, end);
      if (ctx->pass->forces)
        gm_clear_shared_nodes_2d(grid->force[k], begin, end);
    }
    return;
  }
  /* One field at a time over the worker's whole range of blocks (a
   * memset each, instead of a loop testing the pass per node). */
  if (ctx->pass->mass)
    memset(grid->mass + first, 0, bytes);
  for (int k = 0; k < dim; k++) {
    if (ctx->pass->momentum)
      memset(grid->momentum[k] + first, 0, bytes);
    if (ctx->pass->forces)
      memset(grid->force[k] + first, 0, bytes);
  }
}

static void make_view(gm_domain *domain, const gm_p2g_pass *pass,
                      scatter_view *view) {
  gm_points *points = &domain->points;
  gm_grid *grid = &domain->grid;
  const gm_point_buffers *current = &points->buffer[points->cur];
  const gm_point_buffers *moving = &points->buffer[pass->velocity_buffer];
  const gm_point_buffers *stressed = &points->buffer[pass->stress_buffer];
  for (int k = 0; k < 2; k++) {
    int c = k < domain->dim ? k : 0;
    view->position[k] = current->position[c];
    view->velocity[k] = moving->velocity[c];
    view->external_force[k] = points->external_force[c];
    view->grid_momentum[k] = grid->momentum[c];
    view->grid_force[k] = grid->force[c];
    view->origin[k] = domain->shape_grid.origin[c]; /* node 0 */
    view->domain_size[k] = points->domain_size[c];
    view->gravity[k] = domain->def.gravity[k];
  }
  view->mass = points->mass;
  view->volume = stressed->volume;
  for (int k = 0; k < 4; k++)
    view->stress[k] = stressed->stress[k];
  view->grid_mass = grid->mass;
  view->order = points->order;
  view->point_start = grid->point_start;
  view->neighbour = grid->neighbour;
  view->inv_cell = domain->inv_cell;
  view->shift = grid->shift;
  view->axisymmetric = domain->axisymmetric;
  view->skip_rigid = domain->rigid_count > 0;
  view->material = points->material;
  view->shape_grid = &domain->shape_grid;
  view->grid = grid;
  gm_support_tensor(domain, current, view->deformation);
  /* B_p travels with the velocity it belongs to (MUSL's remap reads the
   * velocities and affine matrices just gathered). 1D: only B_xx. */
  view->apic = domain->def.transfer == GM_TRANSFER_APIC;
  view->cell = domain->def.cell_size;
  for (int k = 0; k < 4; k++)
    view->affine[k] = view->apic
                          ? moving->affine[k < gm_affine_stored(domain) ? k : 0]
                          : NULL;
  for (int m = 0; m < domain->material_count; m++)
    view->rigid[m] = domain->materials[m].rigid;
  /* USL's scatter (the only full scatter of a step that takes the sweep)
   * keeps the CPDI supports' cells for the sweep and the deformation
   * gather (cpdi_cache.h). */
  memset(&view->cpdi_cache, 0, sizeof view->cpdi_cache);
  if (pass->mass && pass->momentum && pass->forces &&
      gm_cpdi_cache_fits(domain))
    gm_cpdi_cache_arrays(domain, &view->cpdi_cache);
}

void gm_p2g(gm_domain *domain, const gm_p2g_pass *pass) {
  if (domain->dim == 3) {
    gm_p2g_3d(domain, pass);
    return;
  }
  gm_grid *grid = &domain->grid;
  p2g_context ctx;
  ctx.domain = domain;
  ctx.pass = pass;
  make_view(domain, pass, &ctx.view);
  gm_parallel_for(&domain->pool, grid->block_count, clear_blocks, &ctx);
  for (int colour = 0; colour < 4; colour++) {
    size_t first = grid->color_start[colour];
    size_t count = grid->color_start[colour + 1] - first;
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, count, scatter_blocks, &ctx);
  }
}
