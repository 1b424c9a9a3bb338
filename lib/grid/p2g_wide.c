/*
 * p2g_wide.c - particle-to-grid transfer for the shape functions whose
 * support is wider than one cell: uGIMP, cpGIMP and CPDI (support.h). The
 * sums are those of p2g.c (004 eqs 3.13-3.15, the hoop row N_i / x in
 * axisymmetry) with the weights and gradients of the point's support.
 *
 * Points are binned by the lowest node of their support, so every node a
 * point of a block reaches lies in that block or its +x, +y, +x+y
 * neighbours: a tile of twice the block edge per axis holds them, and the
 * 4-colour scatter of p2g.c stays race-free and deterministic.
 */
#include "grid/grid.h"

#include "grid/transfer.h"

#include <string.h>

/* Nodes of the tile: 16 x 16 in 2D, 128 in 1D (two blocks either way). */
#define WIDE_TILE_NODES (4 * GM_BLOCK_NODES)

/* One array per field, nodes along x side by side: CPDI's corner hands
 * the two nodes of a cell row the values (N_a0, N_a1) N_b of one pair
 * product, and each field of the two nodes takes them as one pair
 * (scatter_cpdi), where a record per node (mass, momentum, force side by
 * side, as p2g.c's tile) took each node's mass alone and each node's
 * value broadcast to a pair (bench/results/2026-11-29-cpdi19.md). */
typedef struct wide_tile {
  double mass[WIDE_TILE_NODES];        /* kg */
  double momentum[2][WIDE_TILE_NODES]; /* kg m/s */
  double force[2][WIDE_TILE_NODES];    /* N */
} wide_tile;

/* Adds the tile's first `rows` x `columns` nodes to the grid. */
static void flush_wide_tile(const scatter_view *v, const gm_p2g_pass *pass,
                            const uint32_t *links, const wide_tile *tile,
                            int64_t columns, int64_t rows, int64_t tile_edge) {
  int dim = v->grid->dim;
  for (int64_t y = 0; y < rows; y++) {
    for (int64_t x = 0; x < columns; x++) {
      int neighbour = (int)(x >> v->shift) + 2 * (int)(y >> v->shift);
      if (links[neighbour] == GM_NO_BLOCK)
        continue; /* past the grid's last node: never reached */
      size_t node = gm_block_node(links, v->shift, x, y);
      size_t t = (size_t)(x + tile_edge * y);
      if (pass->mass)
        v->grid_mass[node] += tile->mass[t];
      for (int k = 0; k < dim; k++) {
        if (pass->momentum)
          v->grid_momentum[k][node] += tile->momentum[k][t];
        if (pass->forces)
          v->grid_force[k][node] += tile->force[k][t];
      }
    }
  }
}

/* APIC (Jiang et al. 2015): C = B_p D_p^-1 with the inertia-like tensor
 * D_p = sum_i N_ip (x_i - x_p)(x_i - x_p)^T of the point's support
 * (offset: x_i - x_p per entry, m). Entries repeating a node (CPDI) sum
 * right. D_p is positive definite for every domain of non-zero size:
 * sum_i N_i(x) (x_i - x)^2 > 0 between nodes, and the domain's own
 * spread adds to it; should it not be (a degenerate domain), the affine
 * part is dropped (C = 0) rather than divided by zero. Because
 * sum_i N_ip (x_i - x_p) = 0 and sum_i N_ip D_p^-1 (x_i - x_p) x_i^T = I,
 * the affine momentum adds nothing to the total momentum and exactly the
 * point's affine angular momentum, whatever the shape. */
static void affine_velocity(const gm_support *support, int dim,
                            double offset[2][GM_SUPPORT_MAX_ENTRIES],
                            const double b[4], double c[4]) {
  double d_xx = 0.0, d_xy = 0.0, d_yy = 0.0; /* m^2 */
  for (int e = 0; e < support->count; e++) {
    double w = support->weight[e];
    d_xx += w * offset[0][e] * offset[0][e];
    d_xy += w * offset[0][e] * offset[1][e];
    d_yy += w * offset[1][e] * offset[1][e];
  }
  c[0] = c[1] = c[2] = c[3] = 0.0; /* 1/s */
  if (dim == 1) {
    if (d_xx > 0.0)
      c[0] = b[0] / d_xx;
    return;
  }
  double det = d_xx * d_yy - d_xy * d_xy; /* m^4 */
  if (!(det > 0.0))
    return;
  double i_xx = d_yy / det, i_xy = -d_xy / det, i_yy = d_xx / det;
  c[0] = b[0] * i_xx + b[1] * i_xy;
  c[1] = b[0] * i_xy + b[1] * i_yy;
  c[2] = b[2] * i_xx + b[3] * i_xy;
  c[3] = b[2] * i_xy + b[3] * i_yy;
}

/* What one point hands the nodes of its support: per node i, mass
 * N_i m, momentum N_i m v (FLIP) and force N_i m g + N_i f_ext - V sigma
 * grad N_i (004 eqs 3.13-3.15). */
typedef struct point_load {
  double mass;          /* kg */
  double momentum[2];   /* kg m/s */
  double body[2];       /* N, gravity, external and hoop forces */
  double txx, tyy, txy; /* N m, stress times volume */
} point_load;

static GM_ALWAYS_INLINE void
add_to_node(wide_tile *tile, size_t t, double weight, double grad_x,
            double grad_y, const point_load *load, const bool do_mass,
            const bool do_momentum, const bool do_forces) {
  if (do_mass)
    tile->mass[t] += weight * load->mass;
  if (do_momentum) {
    tile->momentum[0][t] += weight * load->momentum[0];
    tile->momentum[1][t] += weight * load->momentum[1];
  }
  if (do_forces) {
    tile->force[0][t] +=
        weight * load->body[0] - (load->txx * grad_x + load->txy * grad_y);
    tile->force[1][t] +=
        weight * load->body[1] - (load->txy * grad_x + load->tyy * grad_y);
  }
}

/* A tensor-product support, node by node from its axis factors (the
 * products of gm_product_support_expand, bitwise). x0, y0: the support's
 * lowest node in tile coordinates. */
static GM_ALWAYS_INLINE void
scatter_product(wide_tile *tile, int64_t tile_edge, int64_t x0, int64_t y0,
                const gm_product_support *support, const point_load *load,
                const bool do_mass, const bool do_momentum,
                const bool do_forces) {
  int span_x = support->span[0];
  for (int b = 0; b < support->span[1]; b++) {
    double weight_y = support->weight[1][b],
           gradient_y = support->gradient_y[b];
    size_t row = (size_t)(x0 + tile_edge * (y0 + b));
    for (int a = 0; a < span_x; a++)
      add_to_node(tile, row + (size_t)a, support->weight[0][a] * weight_y,
                  support->gradient_x[a] * weight_y,
                  support->weight_x_per_cell[a] * gradient_y, load, do_mass,
                  do_momentum, do_forces);
  }
}

/* A short uGIMP or cpGIMP support in 2D (support_short.h), node by node in
 * scatter_product's order (the same bits). */
static GM_ALWAYS_INLINE void
scatter_short_2d(wide_tile *tile, int64_t tile_edge, int64_t x0, int64_t y0,
                 const gm_short_axis axis[2], double inv_cell,
                 const point_load *load, const bool do_mass,
                 const bool do_momentum, const bool do_forces) {
  double gradient_x[3], weight_x_per_cell[3]; /* 1/m, gm_product_support's */
  for (int a = 0; a < 3; a++) {
    gradient_x[a] = inv_cell * axis[0].gradient[a];
    weight_x_per_cell[a] = inv_cell * axis[0].weight[a];
  }
  /* Loops of 3 with an exit past the reach (see gather_short_nodes). */
  for (int b = 0; b < 3; b++) {
    if (b > axis[1].reach)
      break;
    double weight_y = axis[1].weight[b], gradient_y = axis[1].gradient[b];
    size_t row = (size_t)(x0 + tile_edge * (y0 + b));
    for (int a = 0; a < 3; a++) {
      if (a > axis[0].reach)
        break;
      add_to_node(tile, row + (size_t)a, axis[0].weight[a] * weight_y,
                  gradient_x[a] * weight_y, weight_x_per_cell[a] * gradient_y,
                  load, do_mass, do_momentum, do_forces);
    }
  }
}

#if defined(__GNUC__)
/* field[0], field[1] += value * (part, part): two neighbouring nodes'
 * sums, each the same operation as alone. */
static GM_ALWAYS_INLINE void add_pair(double *field, gm_pair value,
                                      double part) {
  gm_pair sum;
  memcpy(&sum, field, sizeof sum);
  sum += value * (gm_pair){part, part};
  memcpy(field, &sum, sizeof sum);
}
#endif

/* One CPDI corner (scatter_cpdi): each node i of its cell takes the
 * bilinear value N_i(x_c) times the corner's part of the point's mass,
 * momentum and force, the force's being share * body - sigma V g_c.
 * t: the cell's lower left node in the tile; axis: its (1 - f, f) per
 * axis; g: g_c (1/m); rows: 2 in 2D, 1 in 1D. */
static GM_ALWAYS_INLINE void
scatter_cpdi_corner(wide_tile *tile, int64_t tile_edge, int rows, size_t t,
                    const double axis[2][2], const double g[2], double share,
                    double mass, const double momentum[2],
                    const point_load *load, const bool do_mass,
                    const bool do_momentum, const bool do_forces) {
  double g_x = g[0], g_y = g[1]; /* 1/m */
  double force[2] = {
      /* N */
      share * load->body[0] - (load->txx * g_x + load->txy * g_y),
      share * load->body[1] - (load->txy * g_x + load->tyy * g_y)};
  for (int b = 0; b < rows; b++) {
    size_t row = t + (size_t)(tile_edge * b); /* node (0, b) */
    double weight_y = axis[1][b];
#if defined(__GNUC__) /* the row's two nodes as one pair, N_a N_b per lane */
    gm_pair axis_x, value;
    memcpy(&axis_x, axis[0], sizeof axis_x);
    value = axis_x * (gm_pair){weight_y, weight_y};
    if (do_mass)
      add_pair(&tile->mass[row], value, mass);
    if (do_momentum) {
      add_pair(&tile->momentum[0][row], value, momentum[0]);
      add_pair(&tile->momentum[1][row], value, momentum[1]);
    }
    if (do_forces) {
      add_pair(&tile->force[0][row], value, force[0]);
      add_pair(&tile->force[1][row], value, force[1]);
    }
#else
    for (int a = 0; a < 2; a++) {
      double value = axis[0][a] * weight_y;
      if (do_mass)
        tile->mass[row + a] += value * mass;
      if (do_momentum) {
        tile->momentum[0][row + a] += value * momentum[0];
        tile->momentum[1][row + a] += value * momentum[1];
      }
      if (do_forces) {
        tile->force[0][row + a] += value * force[0];
        tile->force[1][row + a] += value * force[1];
      }
    }
#endif
  }
}

/* CPDI, corner by corner (support.c): corner c hands each node i of its
 * cell the bilinear value N_i(x_c) times the corner's part of the point's
 * mass, momentum and force (scatter_cpdi_corner): the entry sums of 004
 * eqs 3.13-3.15 with weight share N_i and gradient N_i g_c, factored per
 * corner (half the multiplications of the entries; equal to round-off).
 * base: the block's base node. */
static GM_ALWAYS_INLINE void
scatter_cpdi(wide_tile *tile, int64_t tile_edge, int dim, const int64_t base[2],
             const gm_cpdi_support *support, const point_load *load,
             const bool do_mass, const bool do_momentum, const bool do_forces) {
  double share = support->share;
  double mass = share * load->mass; /* kg */
  double momentum[2] = {share * load->momentum[0],
                        share * load->momentum[1]}; /* kg m/s */
  for (int c = 0; c < support->corner_count; c++) {
    int64_t x = support->cell[c][0] - base[0];
    int64_t y = dim > 1 ? support->cell[c][1] - base[1] : 0;
    scatter_cpdi_corner(tile, tile_edge, dim > 1 ? 2 : 1,
                        (size_t)(x + tile_edge * y), support->axis[c],
                        support->corner_gradient[c], share, mass, momentum,
                        load, do_mass, do_momentum, do_forces);
  }
}

/* The same from a 2D support in its kept form (cpdi_cache.h), g_c
 * (1/m) apart: each corner's cell is its tile node as it is. */
static GM_ALWAYS_INLINE void
scatter_cpdi_kept(wide_tile *tile, const gm_cpdi_kept *kept,
                  double gradient[4][2], const point_load *load,
                  const bool do_mass, const bool do_momentum,
                  const bool do_forces) {
  double share = 0.25;              /* gm_cpdi_support_2d's */
  double mass = share * load->mass; /* kg */
  double momentum[2] = {share * load->momentum[0],
                        share * load->momentum[1]}; /* kg m/s */
  for (int c = 0; c < 4; c++)
    scatter_cpdi_corner(tile, 2 * GM_BLOCK_EDGE_2D, 2, (size_t)kept->tile[c],
                        kept->axis[c], gradient[c], share, mass, momentum, load,
                        do_mass, do_momentum, do_forces);
}

/* The entry table with APIC's affine momentum (offsets per entry). */
static void scatter_entries_affine(wide_tile *tile, int64_t tile_edge,
                                   int64_t x0, int64_t y0, int dim,
                                   const gm_support *support,
                                   const point_load *load,
                                   const gm_p2g_pass *pass,
                                   const scatter_view *v, size_t p) {
  double c[4] = {0.0, 0.0, 0.0, 0.0};       /* 1/s, B_p D_p^-1 */
  double offset[2][GM_SUPPORT_MAX_ENTRIES]; /* m, x_i - x_p */
  double h = v->cell;                       /* m */
  for (int axis = 0; axis < 2; axis++) {
    /* m, x_i - x_p of the support's lowest node */
    double node = axis < dim
                      ? v->origin[axis] + (double)support->lowest[axis] * h -
                            v->position[axis][p]
                      : 0.0;
    for (int e = 0; e < support->count; e++)
      offset[axis][e] =
          axis < dim ? node + (double)support->offset[axis][e] * h : 0.0;
  }
  double b[4] = {v->affine[0][p], dim > 1 ? v->affine[1][p] : 0.0,
                 dim > 1 ? v->affine[2][p] : 0.0,
                 dim > 1 ? v->affine[3][p] : 0.0};
  affine_velocity(support, dim, offset, b, c);
  double m = load->mass;
  for (int e = 0; e < support->count; e++) {
    int64_t x = x0 + support->offset[0][e], y = y0 + support->offset[1][e];
    size_t t = (size_t)(x + tile_edge * y);
    double weight = support->weight[e];
    add_to_node(tile, t, weight, support->gradient[0][e],
                support->gradient[1][e], load, pass->mass, false, pass->forces);
    double wm = weight * m; /* kg; m_p N_ip (v_p + C (x_i - x_p)) */
    tile->momentum[0][t] += weight * load->momentum[0] +
                            wm * (c[0] * offset[0][e] + c[1] * offset[1][e]);
    tile->momentum[1][t] += weight * load->momentum[1] +
                            wm * (c[2] * offset[0][e] + c[3] * offset[1][e]);
  }
}

/* Point p's mass, momentum, body force and stress times volume. */
static GM_ALWAYS_INLINE void load_point(const scatter_view *v, size_t p,
                                        const int dim, point_load *load) {
  double m = v->mass[p];
  load->mass = m;
  load->momentum[0] = m * v->velocity[0][p];
  load->momentum[1] = dim > 1 ? m * v->velocity[1][p] : 0.0;
  load->body[0] = m * v->gravity[0];
  load->body[1] = dim > 1 ? m * v->gravity[1] : 0.0;
  for (int c = 0; c < dim; c++)
    if (v->external_force[c])
      load->body[c] += v->external_force[c][p];
  double volume = v->volume[p]; /* stress times volume: N m */
  load->txx = v->stress[0][p] * volume;
  load->tyy = dim > 1 ? v->stress[1][p] * volume : 0.0;
  load->txy = dim > 1 ? v->stress[3][p] * volume : 0.0;
  if (v->axisymmetric) /* hoop row of B (002 sec 3) */
    load->body[0] -= v->stress[2][p] * volume / v->position[0][p];
}

/* Clears the tile's rows up to `rows` (tile rows, y) the first time a point
 * reaches them: a block's points reach the block's rows and one or two
 * more (10 of the 16 rows with 8-node blocks and a short GIMP support), so
 * clearing the whole tile up front cleared 256 nodes where 160 are read
 * (flush_wide_tile reads only the rows and columns a point touched). */
static GM_ALWAYS_INLINE void clear_tile_rows(wide_tile *tile, int64_t *cleared,
                                             int64_t rows, int64_t tile_edge) {
  if (rows <= *cleared)
    return;
  size_t first = (size_t)(*cleared * tile_edge);
  size_t bytes = (size_t)((rows - *cleared) * tile_edge) * sizeof(double);
  memset(&tile->mass[first], 0, bytes);
  for (int k = 0; k < 2; k++) {
    memset(&tile->momentum[k][first], 0, bytes);
    memset(&tile->force[k][first], 0, bytes);
  }
  *cleared = rows;
}

/* One block; do_* are compile-time constants in each specialisation
 * below, so each pass kind gets its own loop (as p2g.c), and the APIC
 * momentum goes through the entry table. */
static GM_ALWAYS_INLINE void scatter_block_kind(
    const scatter_view *shared, const gm_p2g_pass *pass, uint32_t block,
    const gm_domain *domain, gm_worker_scratch *scratch, wide_tile *tile,
    const bool do_mass, const bool do_momentum, const bool do_forces) {
  /* A local copy: the tile's stores (doubles) may alias the view's
   * gravity and the loop's calls (the failure path) anything else, so the
   * arrays' addresses, the gravity and the flags of load_point were loaded
   * again at every point. Its address stays in this function. */
  const scatter_view view = *shared;
  const scatter_view *v = &view;
  int dim = v->grid->dim;
  int64_t tile_edge = dim == 1 ? WIDE_TILE_NODES : 2 << v->shift;
  bool cpdi = v->shape_grid->shape == GM_SHAPE_CPDI;
  bool affine = v->apic && do_momentum;
  int64_t base[2];
  gm_block_base(v->grid, v->grid->block_key[block], base);
  int64_t columns = 0, rows = 1; /* extent of the touched tile nodes */
  int64_t cleared = 0; /* tile rows cleared so far (clear_tile_rows) */
  /* uGIMP and cpGIMP in 2D try the short support first (support_short.h);
   * a longer domain, or one the checks refuse, takes the general one. */
  gm_shape shape = v->shape_grid->shape;
  bool try_short = dim == 2 && !affine &&
                   (shape == GM_SHAPE_UGIMP || shape == GM_SHAPE_CPGIMP);
  /* CPDI in 2D likewise takes its inline support (support_cpdi.h). */
  bool try_cpdi = dim == 2 && !affine && cpdi;
  double inv_cell = v->shape_grid->inv_cell; /* 1/m */
  /* A local copy: the tile's stores (doubles) would otherwise reload the
   * grid's origin and spacing at every point. */
  const gm_shape_grid shape_grid = *v->shape_grid;
  wide_support support;
  for (uint32_t k = v->point_start[block]; k < v->point_start[block + 1]; k++) {
    size_t p = v->order[k];
    if (v->skip_rigid && v->rigid[v->material[p]])
      continue; /* rigid points take no part (rigid.c) */
    gm_short_axis axis[2];
    double half[2]; /* m */
    if (try_short) {
      gm_rectangle_half_edges(shape, 2, v->domain_size, v->deformation, p,
                              half);
      if (gm_short_support_2d(&shape_grid, v->position[0][p], v->position[1][p],
                              half[0], half[1], axis)) {
        int64_t sx = axis[0].lowest - base[0], sy = axis[1].lowest - base[1];
        int64_t short_reach[2] = {axis[0].reach, axis[1].reach};
        if (gm_wide_support_fits(2, sx, sy, short_reach, tile_edge)) {
          columns = sx + short_reach[0] + 1 > columns ? sx + short_reach[0] + 1
                                                      : columns;
          rows =
              sy + short_reach[1] + 1 > rows ? sy + short_reach[1] + 1 : rows;
          clear_tile_rows(tile, &cleared, rows, tile_edge);
          point_load load;
          load_point(v, p, 2, &load);
          scatter_short_2d(tile, tile_edge, sx, sy, axis, inv_cell, &load,
                           do_mass, do_momentum, do_forces);
          continue;
        }
      }
    }
    /* The support's lowest node and its reach (nodes past it) per axis. */
    int64_t lowest[2], reach[2];
    if (try_cpdi) { /* the support in its kept form (cpdi_cache.h) */
      gm_cpdi_kept kept;
      double gradient[4][2]; /* 1/m, g_c */
      if (gm_cpdi_kept_support_2d(&shape_grid, v->position, v->deformation,
                                  v->domain_size, p, base, &kept, gradient)) {
        if (v->cpdi_cache.packed) /* for the sweep and the deformation */
          gm_cpdi_cache_store_kept(&v->cpdi_cache, p, &kept);
        int64_t cx = kept.lowest[0], cy = kept.lowest[1];
        columns =
            cx + kept.reach[0] + 1 > columns ? cx + kept.reach[0] + 1 : columns;
        rows = cy + kept.reach[1] + 1 > rows ? cy + kept.reach[1] + 1 : rows;
        clear_tile_rows(tile, &cleared, rows, tile_edge);
        point_load load;
        load_point(v, p, 2, &load);
        scatter_cpdi_kept(tile, &kept, gradient, &load, do_mass, do_momentum,
                          do_forces);
        continue;
      }
    }
    bool found =
        gm_wide_point_support(v->shape_grid, dim, v->position, v->deformation,
                              v->domain_size, p, &support, lowest, reach);
    int64_t x0 = lowest[0] - base[0];
    int64_t y0 = dim > 1 ? lowest[1] - base[1] : 0;
    if (!found || !gm_wide_support_fits(dim, x0, y0, reach, tile_edge)) {
      gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                      "step: the support of point id %lld cannot be "
                      "computed or does not fit the block it was binned in "
                      "(a degenerate domain, e.g. an edge far below a cell); "
                      "the step was not taken",
                      (long long)domain->points.id[p]);
      continue;
    }
    columns = x0 + reach[0] + 1 > columns ? x0 + reach[0] + 1 : columns;
    rows = y0 + reach[1] + 1 > rows ? y0 + reach[1] + 1 : rows;
    clear_tile_rows(tile, &cleared, rows, tile_edge);
    point_load load;
    load_point(v, p, dim, &load);
    if (affine) {
      gm_support entries;
      if (cpdi)
        gm_cpdi_support_expand(&support.cpdi, dim, &entries);
      else
        gm_product_support_expand(&support.product, &entries);
      scatter_entries_affine(tile, tile_edge, x0, y0, dim, &entries, &load,
                             pass, v, p);
    } else if (cpdi) {
      scatter_cpdi(tile, tile_edge, dim, base, &support.cpdi, &load, do_mass,
                   do_momentum, do_forces);
    } else {
      scatter_product(tile, tile_edge, x0, y0, &support.product, &load, do_mass,
                      do_momentum, do_forces);
    }
  }
  const uint32_t *links = v->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  flush_wide_tile(shared, pass, links, tile, columns, rows, tile_edge);
}

void gm_scatter_block_wide(const scatter_view *v, const gm_p2g_pass *pass,
                           uint32_t block, const gm_domain *domain,
                           gm_worker_scratch *scratch) {
  wide_tile tile; /* cleared row by row as points reach it */
  if (pass->mass && pass->momentum && pass->forces)
    scatter_block_kind(v, pass, block, domain, scratch, &tile, true, true,
                       true);
  else if (pass->mass && pass->momentum)
    scatter_block_kind(v, pass, block, domain, scratch, &tile, true, true,
                       false);
  else if (pass->momentum && pass->forces)
    scatter_block_kind(v, pass, block, domain, scratch, &tile, false, true,
                       true);
  else if (!pass->mass && pass->momentum && !pass->forces) /* REMAP */
    scatter_block_kind(v, pass, block, domain, scratch, &tile, false, true,
                       false);
  else
    scatter_block_kind(v, pass, block, domain, scratch, &tile, pass->mass,
                       pass->momentum, pass->forces);
}
