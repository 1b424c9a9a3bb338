/*
 * tile_nodes.h - the grid node of every node of a 2D block's 16 x 16 tile
 * (the block and its +x, +y, +x+y neighbours; tile node x + 16 y, x and y
 * from the block's base node), the index gm_block_node gives, set once
 * per block.
 *
 * Why: the 2D CPDI gathers (gather_wide.h) find the four nodes of each
 * corner's cell. Inside the block they lie at fixed offsets, but a cell
 * crossing the block's edge (a corner of about 4 in 9 points at 2 x 2
 * points per cell) took the links apart per corner, about 25
 * instructions; from the table every corner's nodes are four loads, with
 * no test of where the cell lies (bench/results/2026-11-29-cpdi19.md).
 * A table costs about 300 instructions per block, a few per point.
 */
#ifndef GM_TILE_NODES_H
#define GM_TILE_NODES_H

#include "core/domain.h"

#include <stddef.h>
#include <stdint.h>

/* Tile nodes per axis: two blocks. */
#define GM_TILE_EDGE_2D (2 * GM_BLOCK_EDGE_2D)

typedef struct gm_tile_nodes {
  size_t node[GM_TILE_EDGE_2D * GM_TILE_EDGE_2D]; /* grid node index */
} gm_tile_nodes;

/* The table of the block whose neighbour links are links (self, +x, +y,
 * +x+y). A missing neighbour (GM_NO_BLOCK, past the grid's last node) is
 * never reached by a support that fits the tile (p2g_wide.c); its entries
 * hold gm_block_node's index all the same and are never read. */
static inline void gm_tile_nodes_init(const uint32_t *links,
                                      gm_tile_nodes *out) {
  const int edge = GM_BLOCK_EDGE_2D;
  for (int q = 0; q < 4; q++) {
    size_t first = (size_t)links[q] * GM_BLOCK_NODES;
    size_t *corner = out->node + (q & 1) * edge + (q >> 1) * edge * 2 * edge;
    for (int y = 0; y < edge; y++)
      for (int x = 0; x < edge; x++)
        corner[x + 2 * edge * y] = first + (size_t)(x + edge * y);
  }
}

#endif
