/*
 * tile_values.h - the nodal values a 2D CPDI gather reads, copied once per
 * block into the block's 16 x 16 tile (the block and its +x, +y, +x+y
 * neighbours; tile node x + 16 y, x and y from the block's base node):
 * each node's velocity and acceleration with x and y side by side, and
 * its mass, row by row as the block's points first reach a row.
 *
 * Why: the gathers (gather_wide.h) read the four nodes of each corner's
 * cell, sixteen per point. From the grid's arrays a node took its index
 * from a table of the tile's grid nodes, then x and y from two arrays
 * (two loads and a shuffle per vector); from the tile a corner's nodes
 * lie at t, t + 1, t + 16, t + 17 of its cell's tile node t and a vector
 * is one load (bench/results/2026-11-29-cpdi20.md). The copies are the
 * grid's values, so every sum keeps its bits.
 *
 * A block's points reach its 8 rows and one or two more (10 of the 16
 * with 2 x 2 points per cell), so rows are copied as a point first needs
 * them (gm_tile_values_reach), 16 nodes each, not the whole tile up
 * front. A missing neighbour (GM_NO_BLOCK, past the grid's last node) is
 * never reached by a support that fits the tile (p2g_wide.c); its half of
 * a row is left unset and never read.
 */
#ifndef GM_TILE_VALUES_H
#define GM_TILE_VALUES_H

#include "grid/transfer.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Tile nodes per axis: two blocks. */
#define GM_TILE_EDGE_2D  (2 * GM_BLOCK_EDGE_2D)
#define GM_TILE_NODES_2D (GM_TILE_EDGE_2D * GM_TILE_EDGE_2D)

typedef struct gm_tile_values {
  double velocity[GM_TILE_NODES_2D][2];     /* m/s, (v_x, v_y) */
  double acceleration[GM_TILE_NODES_2D][2]; /* m/s^2, where the pass reads it */
  double mass[GM_TILE_NODES_2D];            /* kg, where the pass deforms */
  const uint32_t *links; /* the block's neighbour links (self, +x, +y, +x+y) */
  int rows;              /* tile rows copied so far, from 0 */
} gm_tile_values;

/* Starts the tile of the block whose neighbour links are links: no row
 * copied yet. */
static inline void gm_tile_values_start(const uint32_t *links,
                                        gm_tile_values *tile) {
  tile->links = links;
  tile->rows = 0;
}

/* Copies the tile's rows up to `rows` (exclusive) that are not copied
 * yet: the velocities, and the accelerations and masses where the pass
 * reads them (compile-time constants where inlined). */
static GM_ALWAYS_INLINE void
gm_tile_values_reach(const gather_view *v, gm_tile_values *tile, int rows,
                     const bool acceleration, const bool mass) {
  const int edge = GM_BLOCK_EDGE_2D;
  for (int y = tile->rows; y < rows; y++) {
    for (int half = 0; half < 2; half++) { /* the row's two blocks */
      uint32_t block = tile->links[2 * (y / edge) + half];
      if (block == GM_NO_BLOCK)
        continue; /* never read (see above) */
      size_t first =
          (size_t)block * GM_BLOCK_NODES + (size_t)(edge * (y % edge));
      int t = GM_TILE_EDGE_2D * y + edge * half;
      for (int x = 0; x < edge; x++) {
        size_t node = first + (size_t)x;
        tile->velocity[t + x][0] = v->grid_velocity[0][node];
        tile->velocity[t + x][1] = v->grid_velocity[1][node];
        if (acceleration) {
          tile->acceleration[t + x][0] = v->grid_acceleration[0][node];
          tile->acceleration[t + x][1] = v->grid_acceleration[1][node];
        }
        if (mass)
          tile->mass[t + x] = v->grid_mass[node];
      }
    }
  }
  if (rows > tile->rows)
    tile->rows = rows;
}

#endif
