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
#include "transfer.h"

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

void gm_scatter_block_wide(const scatter_view *v, const gm_p2g_pass *pass,
                           uint32_t block) {
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
    /* Cannot fail: the binning placed the point by this support. */
    gm_wide_support(v->shape_grid, dim, v->position, v->deformation,
                    v->domain_size, p, &support);
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
    for (int e = 0; e < support.count; e++) {
      int64_t x = x0 + support.offset[0][e], y = y0 + support.offset[1][e];
      columns = x + 1 > columns ? x + 1 : columns;
      rows = y + 1 > rows ? y + 1 : rows;
      size_t t = (size_t)(x + tile_edge * y);
      double weight = support.weight[e];
      double grad_x = support.gradient[0][e], grad_y = support.gradient[1][e];
      if (pass->mass)
        tile.mass[t] += weight * m;
      if (pass->momentum) {
        tile.momentum[0][t] += weight * momentum[0];
        tile.momentum[1][t] += weight * momentum[1];
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
