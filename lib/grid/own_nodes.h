/*
 * own_nodes.h - the nodes of a 2D block that only the block's own tile
 * reaches, which the linear scatters store instead of clearing and adding.
 *
 * The linear scatters (p2g.c, move_remap.c) sum a block's points into a
 * tile of its 8 x 8 nodes and a one-node halo (+x column, +y row, +x+y
 * corner), then add the tile to the grid, every block of the grid once per
 * scatter (each is in a colour list, and its tile is flushed even without
 * points). Row 0 and column 0 of a block also take the halos of its -x, -y
 * and -x-y neighbours; nodes (1..7) x (1..7) take this block's tile alone.
 * Those are stored: a tile's sum s starts at +0.0 and is never -0.0 in
 * rounding to nearest, toward zero or upward (a sum is -0 there only when
 * both terms are), and in rounding downward +0 + -0 is -0; so 0.0 + s, the
 * sum a cleared node would hold, is s bit for bit in every mode. Only
 * row 0 and column 0, 15 of the 64 nodes, are cleared before a scatter:
 * the granular cloud's node layers, mostly empty nodes, spent about 150
 * instructions per point-step clearing whole blocks
 * (bench/results/2026-11-30-cloud22.md).
 */
#ifndef GM_OWN_NODES_H
#define GM_OWN_NODES_H

#include "grid/grid.h"

#include <stdbool.h>
#include <stddef.h>

/* Zeroes row 0 and column 0 of the blocks [begin, end) of one node field. */
static inline void gm_clear_shared_nodes_2d(double *field, size_t begin,
                                            size_t end) {
  for (size_t b = begin; b < end; b++) {
    double *node = field + b * GM_BLOCK_NODES;
    for (int x = 0; x < GM_BLOCK_EDGE_2D; x++)
      node[x] = 0.0;
    for (int y = 1; y < GM_BLOCK_EDGE_2D; y++)
      node[y * GM_BLOCK_EDGE_2D] = 0.0;
  }
}

/* A node's value after a tile's sum s is flushed to it: added to the
 * node's value, or stored where only this tile reaches it (0.0 + s is s:
 * above). */
static inline double gm_own_sum(bool store, double node, double s) {
  return store ? s : node + s;
}

#endif
