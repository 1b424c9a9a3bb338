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

void gm_scatter_block_wide(const scatter_view *v, const gm_p2g_pass *pass,
                           uint32_t block, const gm_domain *domain,
                           gm_worker_scratch *scratch) {
  int dim = v->grid->dim;
  int64_t tile_edge = dim == 1 ? WIDE_TILE_NODES : 2 << v->shift;
  wide_tile tile;
  memset(&tile, 0, sizeof tile);
  int64_t base[2];
  gm_block_base(v->grid, v->grid->block_key[block], base);
  int64_t columns = 0, rows = 1; /* extent of the touched tile nodes */
  gm_support support;
  for (uint32_t k = v->point_start[block]; k < v->point_start[block + 1]; k++) {
    size_t p = v->order[k];
    if (v->skip_rigid && v->rigid[v->material[p]])
      continue; /* rigid points take no part (rigid.c) */
    bool found = gm_wide_support(v->shape_grid, dim, v->position,
                                 v->deformation, v->domain_size, p, &support);
    double m = v->mass[p];
    double momentum[2] = {m * v->velocity[0][p],
                          dim > 1 ? m * v->velocity[1][p] : 0.0};
    double body[2] = {m * v->gravity[0], dim > 1 ? m * v->gravity[1] : 0.0};
    for (int c = 0; c < dim; c++)
      if (v->external_force[c])
        body[c] += v->external_force[c][p];
    double volume = v->volume[p]; /* stress times volume: N m */
    double txx = v->stress[0][p] * volume;
    double tyy = dim > 1 ? v->stress[1][p] * volume : 0.0;
    double txy = dim > 1 ? v->stress[3][p] * volume : 0.0;
    if (v->axisymmetric) /* hoop row of B (002 sec 3) */
      body[0] -= v->stress[2][p] * volume / v->position[0][p];
    int64_t x0 = support.lowest[0] - base[0];
    int64_t y0 = dim > 1 ? support.lowest[1] - base[1] : 0;
    if (!found || !gm_support_within(&support, dim, x0, y0, tile_edge)) {
      gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                      "step: the support of point id %lld cannot be "
                      "computed or does not fit the block it was binned in "
                      "(a degenerate domain, e.g. an edge far below a cell); "
                      "the step was not taken",
                      (long long)domain->points.id[p]);
      continue;
    }
    bool affine = v->apic && pass->momentum;
    double c[4] = {0.0, 0.0, 0.0, 0.0};       /* 1/s, B_p D_p^-1 */
    double offset[2][GM_SUPPORT_MAX_ENTRIES]; /* m, x_i - x_p */
    if (affine) {
      double h = v->cell; /* m */
      for (int axis = 0; axis < 2; axis++) {
        /* m, x_i - x_p of the support's lowest node */
        double node = axis < dim
                          ? v->origin[axis] + (double)support.lowest[axis] * h -
                                v->position[axis][p]
                          : 0.0;
        for (int e = 0; e < support.count; e++)
          offset[axis][e] =
              axis < dim ? node + (double)support.offset[axis][e] * h : 0.0;
      }
      double b[4] = {v->affine[0][p], dim > 1 ? v->affine[1][p] : 0.0,
                     dim > 1 ? v->affine[2][p] : 0.0,
                     dim > 1 ? v->affine[3][p] : 0.0};
      affine_velocity(&support, dim, offset, b, c);
    }
    for (int e = 0; e < support.count; e++) {
      int64_t x = x0 + support.offset[0][e], y = y0 + support.offset[1][e];
      columns = x + 1 > columns ? x + 1 : columns;
      rows = y + 1 > rows ? y + 1 : rows;
      size_t t = (size_t)(x + tile_edge * y);
      double weight = support.weight[e];
      double grad_x = support.gradient[0][e], grad_y = support.gradient[1][e];
      if (pass->mass)
        tile.mass[t] += weight * m;
      if (pass->momentum && !affine) {
        tile.momentum[0][t] += weight * momentum[0];
        tile.momentum[1][t] += weight * momentum[1];
      }
      if (affine) {             /* m_p N_ip (v_p + C (x_i - x_p)) */
        double wm = weight * m; /* kg */
        tile.momentum[0][t] += weight * momentum[0] +
                               wm * (c[0] * offset[0][e] + c[1] * offset[1][e]);
        tile.momentum[1][t] += weight * momentum[1] +
                               wm * (c[2] * offset[0][e] + c[3] * offset[1][e]);
      }
      if (pass->forces) {
        tile.force[0][t] += weight * body[0] - (txx * grad_x + txy * grad_y);
        tile.force[1][t] += weight * body[1] - (txy * grad_x + tyy * grad_y);
      }
    }
  }
  const uint32_t *links = v->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  flush_wide_tile(v, pass, links, &tile, columns, rows, tile_edge);
}
