/*
 * block_grid.h - the sparse background grid. Nodes are stored in blocks of 64
 * (4 x 4 x 4 in 3D, 8 x 8 in 2D, 64 in a row in 1D); only blocks near points
 * exist, so memory
 * and work follow the occupied cells, not the box. Blocks are rebuilt every
 * step from the points' block keys and sorted by key, which fixes the order
 * of every sum (results do not depend on worker count).
 */
#ifndef GM_BLOCK_GRID_H
#define GM_BLOCK_GRID_H

#include "granmpm.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GM_BLOCK_NODES    64
#define GM_BLOCK_SHIFT_2D 3 /* 8 x 8 nodes */
#define GM_BLOCK_EDGE_2D  8
#define GM_BLOCK_SHIFT_1D 6 /* 64 nodes */
#define GM_BLOCK_SHIFT_3D 2 /* 4 x 4 x 4 nodes */
#define GM_BLOCK_EDGE_3D  4
#define GM_NO_BLOCK       UINT32_MAX
/* Neighbour slots: self, +x, +y, +x+y, +z, +x+z, +y+z, +x+y+z, slot
 * ox + 2 oy + 4 oz (a cell's upper nodes may lie in the next block along
 * each axis). 1D and 2D use the first two and four, as before 3D. */
#define GM_BLOCK_NEIGHBOURS 8
/* Block colours: the parities of the block coordinates (4 in 2D, 8 in
 * 3D). */
#define GM_BLOCK_COLOURS 8
/* Points are binned in at most this many fixed chunks (not per worker;
 * bins.c, bin_chunks): the chunks are consecutive index ranges, so the
 * order of points inside a block is index order whatever the worker count
 * and the number of chunks. */
#define GM_BIN_CHUNKS 32

typedef struct gm_grid {
  int dim;
  int shift;                  /* log2 of nodes per block edge */
  int64_t blocks_per_axis[3]; /* blocks covering nodes 0..cells */
  size_t block_count;
  size_t block_capacity;
  /* The last build left out the upper neighbours no point's cell reached
   * (block_grid.c, sparse_neighbours): it depends on the cells, not only
   * on the keys, so the next binning builds it again (bins.c). */
  bool sparse;
  int64_t *block_key;    /* sorted; key = (bz * blocks_y + by) * blocks_x
                            + bx */
  uint32_t *neighbour;   /* block_capacity * GM_BLOCK_NEIGHBOURS */
  uint32_t *point_start; /* block_capacity + 1, ranges in order[] */
  uint32_t *color_block; /* block indices grouped by colour */
  size_t color_start[GM_BLOCK_COLOURS + 1]; /* colour c: color_block
                                               [start[c]..start[c+1]) */
  /* Per block and chunk of the binning, chunks * blocks of this binning
   * (bins.c); chunk_capacity counters allocated. */
  uint32_t *chunk_counts;
  size_t chunk_capacity;
  size_t chunks; /* of the binning in progress */
  /* Open-addressing hash: block key -> block index. */
  int64_t *hash_key;
  uint32_t *hash_value;
  size_t hash_capacity; /* power of two */
  size_t hash_used;
  /* Node fields, block_capacity * GM_BLOCK_NODES each. */
  double *mass;        /* kg */
  double *momentum[3]; /* kg m/s; velocity (m/s) after the grid update
                          (z: 3D only) */
  double *force[3];    /* N; acceleration (m/s^2) after the grid update */
  /* Wall forces per block (N): block_capacity * wall_stride * 2 values,
   * summed in block order after the update (deterministic). */
  double *wall_force;
  /* Rigid materials (only when the domain has one): per node, the rigid
   * material + 1 touching it (0 = none) and the node's impulse (N s) on
   * it this step (z: 3D only). Sized like the node fields. */
  int32_t *rigid_material;
  double *rigid_impulse[3];
  size_t rigid_capacity;      /* nodes allocated */
  size_t wall_force_capacity; /* doubles allocated */
  int wall_stride;
  /* Per node, in the last full grid update: the first wall that acted
   * (wall id + 1, 0 = none) and the node's force from the walls (N). */
  int32_t *contact_wall;
  double *contact_force[2];
  size_t contact_capacity; /* nodes allocated */
  /* Per node, in the last grid update, for the friction shared along the
   * wall (walls.c, gm_walls_share_friction): the one wall that acted
   * (wall id + 1; 0 = none, or several), the node's normal impulse from it
   * (kg m/s) and its tangential velocity before friction (m/s, along
   * (n_y, -n_x)). Sized like contact_wall. */
  int32_t *pool_wall;
  double *pool_normal;
  double *pool_tangent;
  double *pool_tangent_3d; /* 3D: the second tangential component (m/s,
                              along the wall's t2, walls_3d.c) */
  /* Per wall and tangential bin of one cell: the pooled normal impulse and
   * tangential momentum (kg m/s), wall_bins pairs per wall. */
  double *pool_sums;
  size_t pool_sums_capacity; /* doubles allocated */
  /* Per node and gap plane (gm_gap_node(grid, node) * gm_gap_plane_count
   * + plane: the planar walls, then the measured box faces): the smallest
   * distance (m) from the plane to the domain of a point the node carries;
   * the node may approach the wall by that much in a step (walls.c). */
  double *wall_gap;
  size_t wall_gap_capacity; /* doubles allocated */
  /* The gap records (wall_gap, wall_centre_gap) are stored only for the
   * blocks a measured point may write them in (wall_gaps.c,
   * gm_walls_map_gaps): per block (block_capacity), its slot among those
   * blocks or GM_NO_BLOCK; the records of node (slot * GM_BLOCK_NODES +
   * local) follow, then one sentinel node (index gap_sentinel) whose
   * records stay infinite and stand for every node of a block without a
   * slot: those are never lowered, so they read as before (infinite) and
   * the granular cloud's node layers, far from the floor, cost no gap
   * records (docs/performance.md, "Gap records per block"). */
  uint32_t *gap_slot;
  size_t gap_sentinel; /* nodes with gap records = index of the sentinel */
  /* Per node and gap plane, as wall_gap (the planar walls only with
   * linear shapes, gm_centre_gap_plane_count): the smallest distance (m) from
   * the wall or box face to the centre of a point the node carries
   * (wall_gaps.c; for a face, points less than a cell from it); nodes the
   * wall's tent or the face does not reach may carry a point by at most
   * that much toward it in a step (walls.c, grid_update.c). */
  double *wall_centre_gap;
  size_t wall_centre_gap_capacity; /* doubles allocated */
  /* GM_VOLUMETRIC_CELL_MEAN only (grid/volumetric_mean.c), scratch of one
   * deformation pass: per cell, stored at its lowest node, the sums of
   * V_p tr L_p (m^3/s) and V_p (m^3) over its points; per point, tr L_p
   * (1/s) and the node index of its cell (SIZE_MAX: not averaged). */
  double *cell_rate_volume;
  double *cell_volume;
  size_t cell_capacity; /* nodes allocated */
  double *point_rate;
  size_t *point_cell;
  size_t point_capacity; /* points allocated */
} gm_grid;

/* Colour of a block for the parallel scatter: blocks of one colour are two
 * apart along each axis, so their nodes (own block and +1 neighbours) never
 * overlap and they can be scattered concurrently. */
static inline int gm_block_colour(const gm_grid *grid, int64_t key) {
  int64_t blocks_x = grid->blocks_per_axis[0];
  int colour = (int)((key % blocks_x) & 1) | (int)(((key / blocks_x) & 1) << 1);
  /* 3D: the y parity of the row within its z plane, and the z parity
   * within the node layer (granular family, gm_grid_layer_stride), so a
   * block of layer L has the colour of the same block of layer 0 and a
   * component's sums are added in the same order on any layer. */
  if (grid->dim == 3)
    colour = (int)((key % blocks_x) & 1) |
             (int)((((key / blocks_x) % grid->blocks_per_axis[1]) & 1) << 1) |
             (int)((((key / (blocks_x * grid->blocks_per_axis[1])) %
                     grid->blocks_per_axis[2]) &
                    1)
                   << 2);
  return colour;
}

/* The four node indices (grid field arrays) of the cell at local (x, y)
 * of the block with these links, order (0,0) (1,0) (0,1) (1,1). */
static inline void gm_cell_nodes_2d(const uint32_t *links, int shift,
                                    int64_t local_x, int64_t local_y,
                                    size_t node[4]) {
  int64_t edge = (int64_t)1 << shift, mask = edge - 1;
  int64_t next_x = local_x + 1, next_y = local_y + 1;
  int over_x = (int)(next_x >> shift), over_y = (int)(next_y >> shift);
  next_x &= mask;
  next_y &= mask;
  node[0] =
      (size_t)links[0] * GM_BLOCK_NODES + (size_t)(local_x + edge * local_y);
  node[1] = (size_t)links[over_x] * GM_BLOCK_NODES +
            (size_t)(next_x + edge * local_y);
  node[2] = (size_t)links[2 * over_y] * GM_BLOCK_NODES +
            (size_t)(local_x + edge * next_y);
  node[3] = (size_t)links[over_x + 2 * over_y] * GM_BLOCK_NODES +
            (size_t)(next_x + edge * next_y);
}

/* The grid field index of the node at (nx, ny, nz) counted from the origin
 * node of the block with these links (3D; each coordinate 0..2 edges - 1,
 * so a node past the block's edge is found through neighbour slot
 * ox + 2 oy + 4 oz). */
static inline size_t gm_block_node_3d(const uint32_t *links, int64_t nx,
                                      int64_t ny, int64_t nz) {
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  int slot = (int)(nx >> GM_BLOCK_SHIFT_3D) +
             2 * (int)(ny >> GM_BLOCK_SHIFT_3D) +
             4 * (int)(nz >> GM_BLOCK_SHIFT_3D);
  return (size_t)links[slot] * GM_BLOCK_NODES +
         (size_t)((nx & mask) + GM_BLOCK_EDGE_3D * (ny & mask) +
                  GM_BLOCK_EDGE_3D * GM_BLOCK_EDGE_3D * (nz & mask));
}

/* Block key of a position inside the grid (x, y: m; y ignored in 1D).
 * Truncation is floor here: inside the grid the cell coordinates are >= 0.
 * The arithmetic matches gm_shape_linear_axis, so the block agrees with
 * the cell the shape functions use. */
static inline int64_t gm_block_key_inside(const gm_grid *grid, double x,
                                          double y, const double *origin,
                                          double inv_cell) {
  int64_t block_x = (int64_t)((x - origin[0]) * inv_cell) >> grid->shift;
  if (grid->dim == 1)
    return block_x;
  int64_t block_y = (int64_t)((y - origin[1]) * inv_cell) >> grid->shift;
  return block_y * grid->blocks_per_axis[0] + block_x;
}

/* Block key of a position inside a 3D grid (m); as gm_block_key_inside. */
static inline int64_t gm_block_key_inside_3d(const gm_grid *grid, double x,
                                             double y, double z,
                                             const double *origin,
                                             double inv_cell) {
  int64_t block_x = (int64_t)((x - origin[0]) * inv_cell) >> grid->shift;
  int64_t block_y = (int64_t)((y - origin[1]) * inv_cell) >> grid->shift;
  int64_t block_z = (int64_t)((z - origin[2]) * inv_cell) >> grid->shift;
  return (block_z * grid->blocks_per_axis[1] + block_y) *
             grid->blocks_per_axis[0] +
         block_x;
}

/* Key of the block holding node (node_x, node_y, node_z) of a 3D grid. */
static inline int64_t gm_block_key_of_node_3d(const gm_grid *grid,
                                              int64_t node_x, int64_t node_y,
                                              int64_t node_z) {
  return ((node_z >> grid->shift) * grid->blocks_per_axis[1] +
          (node_y >> grid->shift)) *
             grid->blocks_per_axis[0] +
         (node_x >> grid->shift);
}

/* Block coordinates (x, y, z) of a key of a 3D grid. */
static inline void gm_block_coordinates_3d(const gm_grid *grid, int64_t key,
                                           int64_t block[3]) {
  int64_t blocks_x = grid->blocks_per_axis[0];
  int64_t blocks_y = grid->blocks_per_axis[1];
  block[0] = key % blocks_x;
  block[1] = (key / blocks_x) % blocks_y;
  /* Modulo the blocks along z: a key of node layer L (granular family,
   * gm_grid_layer_stride) is L * stride + key of layer 0. */
  block[2] = (key / (blocks_x * blocks_y)) % grid->blocks_per_axis[2];
}

/* Key of the block holding node (node_x, node_y) (node_y ignored in 1D). */
static inline int64_t gm_block_key_of_node(const gm_grid *grid, int64_t node_x,
                                           int64_t node_y) {
  int64_t block_x = node_x >> grid->shift;
  if (grid->dim == 1)
    return block_x;
  return (node_y >> grid->shift) * grid->blocks_per_axis[0] + block_x;
}

/* Keys of one node layer. The granular family keeps components that share
 * nodes on separate layers: layer L holds keys L * stride + key, so its
 * blocks are distinct from every other layer's (parallel grids, 000 sec
 * 3.3) while the position of a node follows from key modulo stride. */
static inline int64_t gm_grid_layer_stride(const gm_grid *grid) {
  if (grid->dim == 3) /* every block of the 3D box */
    return grid->blocks_per_axis[0] * grid->blocks_per_axis[1] *
           grid->blocks_per_axis[2];
  return grid->blocks_per_axis[0] *
         (grid->dim == 1 ? 1 : grid->blocks_per_axis[1]);
}

/* Block coordinates (x, y) of a key, whatever its layer. */
static inline void gm_block_coordinates(const gm_grid *grid, int64_t key,
                                        int64_t block[2]) {
  int64_t blocks_x = grid->blocks_per_axis[0];
  block[0] = key % blocks_x;
  block[1] = grid->dim == 1 ? 0 : (key / blocks_x) % grid->blocks_per_axis[1];
}

/* Lowest node (x, y) of the block with this key. */
static inline void gm_block_base(const gm_grid *grid, int64_t key,
                                 int64_t base[2]) {
  gm_block_coordinates(grid, key, base);
  base[0] <<= grid->shift;
  base[1] <<= grid->shift;
}

/* Grid field index of the node (x, y) nodes from the lower corner of the
 * block with these links; x, y < 2 * edge (the block or its +x, +y, +x+y
 * neighbours). The neighbour must exist. */
static inline size_t gm_block_node(const uint32_t *links, int shift, int64_t x,
                                   int64_t y) {
  int64_t mask = ((int64_t)1 << shift) - 1;
  int neighbour = (int)(x >> shift) + 2 * (int)(y >> shift);
  return (size_t)links[neighbour] * GM_BLOCK_NODES +
         (size_t)((x & mask) + ((y & mask) << shift));
}

/* Index of node's gap records (in nodes: wall_gap + index * planes,
 * wall_centre_gap + index * centre planes); the sentinel's, infinite, for
 * a node of a block without gap records. */
static inline size_t gm_gap_node(const gm_grid *grid, size_t node) {
  uint32_t slot = grid->gap_slot[node / GM_BLOCK_NODES];
  return slot == GM_NO_BLOCK
             ? grid->gap_sentinel
             : (size_t)slot * GM_BLOCK_NODES + node % GM_BLOCK_NODES;
}

/* Block index of key this step, or GM_NO_BLOCK. */
uint32_t gm_grid_find(const gm_grid *grid, int64_t key);
/* Block key of a position (block_grid.c); false if outside the grid. */
bool gm_block_key_of(const gm_domain *domain, const double *position_xyz,
                     int64_t *key);
/* The block grid of the step from the points' block keys (block_grid.c). */
gm_status gm_grid_build(gm_domain *domain);

#endif
