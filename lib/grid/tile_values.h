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
 *
 * The copied rows are a range [low, high) grown both ways, not rows 0 up
 * to the highest reached: the deformation gather takes its points in
 * index order, in which a block's points come a cell row at a time
 * between reorderings (every 16 steps; after the fill, until the first,
 * a block's first point may lie in its top cell row), and it starts the
 * tile again at each change of block, so copying from row 0 copied rows
 * its points never read (79 -> 46 instructions per point-step of copies
 * at 99 856 points, bench/results/2026-11-30-cpdi21.md).
 *
 * Where the pass reads the masses, the tile also tells whether every node
 * it copied has a positive mass (all_mass): then no corner of a support
 * in the tile reads a massless node, and the gather's test of the four
 * masses per corner is left out (gather_wide.h).
 */
#ifndef GM_TILE_VALUES_H
#define GM_TILE_VALUES_H

#include "grid/transfer.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* Tile nodes per axis: two blocks. A block's row is copied two nodes at
 * a time (gm_tile_values_reach). */
_Static_assert(GM_BLOCK_EDGE_2D % 2 == 0, "a block row of pairs of nodes");
#define GM_TILE_EDGE_2D  (2 * GM_BLOCK_EDGE_2D)
#define GM_TILE_NODES_2D (GM_TILE_EDGE_2D * GM_TILE_EDGE_2D)

typedef struct gm_tile_values {
  double velocity[GM_TILE_NODES_2D][2];     /* m/s, (v_x, v_y) */
  double acceleration[GM_TILE_NODES_2D][2]; /* m/s^2, where the pass reads it */
  double mass[GM_TILE_NODES_2D];            /* kg, where the pass deforms */
  const uint32_t *links; /* the block's neighbour links (self, +x, +y, +x+y) */
  int low, high;         /* tile rows copied: [low, high), empty if equal */
  bool all_mass;         /* every copied node's mass > 0 (where copied) */
} gm_tile_values;

/* Starts the tile of the block whose neighbour links are links: no row
 * copied yet. */
static inline void gm_tile_values_start(const uint32_t *links,
                                        gm_tile_values *tile) {
  tile->links = links;
  tile->low = 0;
  tile->high = 0;
  tile->all_mass = true;
}

#if defined(__GNUC__)
/* Nodes node and node + 1 of a field's x and y arrays into (x, y) per
 * node at out[0], out[1]: the same values. */
static GM_ALWAYS_INLINE void
gm_tile_values_interleave(const double *const field[2], size_t node,
                          double out[2][2]) {
  gm_pair x, y;
  memcpy(&x, &field[0][node], sizeof x);
  memcpy(&y, &field[1][node], sizeof y);
  gm_pair first = {x[0], y[0]}, second = {x[1], y[1]};
  memcpy(out[0], &first, sizeof first);
  memcpy(out[1], &second, sizeof second);
}
#endif

/* Makes tile rows [first, end) copied (a support's rows, first < end):
 * the velocities, and the accelerations and masses where the pass reads
 * them (compile-time constants where inlined). The copied rows stay one
 * range: the rows between it and [first, end) are copied too. One copy
 * loop, inline (out of line, behind a call, it saved nothing:
 * bench/results/2026-11-30-cpdi21.md). */
static GM_ALWAYS_INLINE void
gm_tile_values_reach(const gather_view *v, gm_tile_values *tile, int first,
                     int end, const bool acceleration, const bool mass) {
  if (first >= tile->low && end <= tile->high)
    return; /* the common case: copied */
  const int edge = GM_BLOCK_EDGE_2D;
  int low = tile->low, high = tile->high; /* copied: [low, high) */
  if (low == high)
    low = high = first; /* none */
  int from = first < low ? first : low, to = end > high ? end : high;
  bool positive = true; /* every copied mass > 0 (where copied) */
#if defined(__GNUC__)
  gm_pair_mask positive_lanes = {-1, -1}; /* the same per lane */
#endif
  for (int y = from; y < to; y++) {
    if (y == low) /* skip the copied rows */
      y = high;
    if (y >= to)
      break;
    for (int half = 0; half < 2; half++) { /* the row's two blocks */
      uint32_t block = tile->links[2 * (y / edge) + half];
      if (block == GM_NO_BLOCK)
        continue; /* never read (see above) */
      size_t node0 =
          (size_t)block * GM_BLOCK_NODES + (size_t)(edge * (y % edge));
      int t = GM_TILE_EDGE_2D * y + edge * half;
#if defined(__GNUC__)
      /* two nodes at a time: their x and their y as pairs, interleaved
       * into (v_x, v_y) per node, and the masses' test as a lane mask */
      for (int x = 0; x < edge; x += 2) {
        size_t node = node0 + (size_t)x;
        gm_tile_values_interleave(v->grid_velocity, node,
                                  &tile->velocity[t + x]);
        if (acceleration)
          gm_tile_values_interleave(v->grid_acceleration, node,
                                    &tile->acceleration[t + x]);
        if (mass) {
          gm_pair m, zero = {0.0, 0.0};
          memcpy(&m, &v->grid_mass[node], sizeof m);
          memcpy(&tile->mass[t + x], &m, sizeof m);
          positive_lanes &= (gm_pair_mask)(m > zero);
        }
      }
#else
      for (int x = 0; x < edge; x++) {
        size_t node = node0 + (size_t)x;
        tile->velocity[t + x][0] = v->grid_velocity[0][node];
        tile->velocity[t + x][1] = v->grid_velocity[1][node];
        if (acceleration) {
          tile->acceleration[t + x][0] = v->grid_acceleration[0][node];
          tile->acceleration[t + x][1] = v->grid_acceleration[1][node];
        }
        if (mass)
          tile->mass[t + x] = v->grid_mass[node];
        positive &= !mass || v->grid_mass[node] > 0.0;
      }
#endif
    }
  }
#if defined(__GNUC__)
  positive = positive_lanes[0] != 0 && positive_lanes[1] != 0;
#endif
  tile->low = from;
  tile->high = to;
  tile->all_mass = tile->all_mass && positive;
}

#endif
