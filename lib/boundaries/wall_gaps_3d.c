/*
 * wall_gaps_3d.c - the gap of each node's material to each planar wall in
 * 3D, as wall_gaps.c measures it in 2D: the smallest distance from the
 * wall to the domain of a point with weight on the node, so that material
 * that has left the wall may come back to it within a step (walls.c,
 * walls_3d.c). The domain is, as in 2D for linear MPM, the point's initial
 * box (edges GM_FIELD_DOMAIN_SIZE) moved with its centre: its half extent
 * along the normal n is (l_x |n_x| + l_y |n_y| + l_z |n_z|) / 2. The box
 * faces of 3D hold their nodes without a gap (grid_update_3d.c) and are
 * not measured.
 *
 * Minima do not depend on the order they are taken in, and the blocks are
 * visited colour by colour as in p2g_3d.c (8 colours), so the result is
 * deterministic and free of races.
 */
#include "boundaries/boundaries.h"

#include <math.h>

/* A gap matters at the nodes that act on a wall or join its friction
 * patches, less than GM_STRIP_REACH (2) cells in front of it; a linear
 * tent carries points less than a cell from its node, so only points
 * whose centre lies less than 3 cells in front of the plane lower such a
 * gap. 4 cells keeps a margin. */
#define GM_GAP_REACH_3D 4.0

typedef struct gap_3d_context {
  gm_domain *domain;
  const uint32_t *blocks; /* of the colour being measured */
} gap_3d_context;

/* Could a point binned in this block (its cell's lowest node in the
 * block) lie within the reach of a wall? */
static bool block_may_reach_3d(const gm_domain *domain, const int64_t base[3]) {
  const double *origin = domain->shape_grid.origin; /* m, node 0 */
  double h = domain->def.cell_size;                 /* m */
  double low[3], high[3]; /* m, a box holding every point centre */
  for (int k = 0; k < 3; k++) {
    low[k] = origin[k] + (double)(base[k] - 1) * h;
    high[k] = origin[k] + (double)(base[k] + GM_BLOCK_EDGE_3D + 1) * h;
  }
  for (int w = 0; w < domain->wall_count; w++) {
    const gm_wall *wall = &domain->walls[w];
    double nearest = 0.0; /* m, least signed distance of the box corners */
    for (int k = 0; k < 3; k++) {
      double corner = wall->normal[k] >= 0.0 ? low[k] : high[k];
      nearest += (corner - wall->point[k]) * wall->normal[k];
    }
    if (nearest <= GM_GAP_REACH_3D * h)
      return true;
  }
  return false;
}

static void measure_point_3d(gm_domain *domain, uint32_t block, size_t p) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  gm_grid *grid = &domain->grid;
  int walls = domain->wall_count;
  double h = domain->def.cell_size; /* m */
  double x[3] = {current->position[0][p], current->position[1][p],
                 current->position[2][p]}; /* m */
  double distance[GM_MAX_WALLS];           /* m */
  bool near = false;
  for (int w = 0; w < walls; w++) {
    const gm_wall *wall = &domain->walls[w];
    double centre = 0.0, half_extent = 0.0; /* m */
    for (int k = 0; k < 3; k++) {
      centre += (x[k] - wall->point[k]) * wall->normal[k];
      half_extent += 0.5 * points->domain_size[k][p] * fabs(wall->normal[k]);
    }
    distance[w] = INFINITY;
    if (centre > GM_GAP_REACH_3D * h)
      continue;
    distance[w] = centre - half_extent;
    near = true;
  }
  if (!near)
    return;
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  double weight[3][2], gradient[3][2];
  int64_t local[3];
  for (int k = 0; k < 3; k++)
    local[k] = gm_shape_linear_axis(x[k], domain->shape_grid.origin[k],
                                    domain->inv_cell, weight[k], gradient[k]) &
               mask;
  for (int c = 0; c < 8; c++) {
    int a = c & 1, b = (c >> 1) & 1, z = c >> 2;
    if (weight[0][a] * weight[1][b] * weight[2][z] == 0.0)
      continue; /* no weight on this node (2D skips these as well) */
    size_t node =
        gm_block_node_3d(links, local[0] + a, local[1] + b, local[2] + z);
    double *gap = grid->wall_gap + node * (size_t)walls;
    for (int w = 0; w < walls; w++)
      gap[w] = distance[w] < gap[w] ? distance[w] : gap[w];
  }
}

static void measure_blocks_3d(void *context, size_t begin, size_t end,
                              int worker) {
  (void)worker;
  gap_3d_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = ctx->blocks[item];
    int64_t base[3];
    gm_block_coordinates_3d(grid, grid->block_key[block], base);
    for (int k = 0; k < 3; k++)
      base[k] <<= GM_BLOCK_SHIFT_3D;
    if (!block_may_reach_3d(domain, base))
      continue;
    for (uint32_t k = grid->point_start[block];
         k < grid->point_start[block + 1]; k++) {
      size_t p = points->order[k];
      if (!domain->materials[points->material[p]].rigid) /* as in 2D */
        measure_point_3d(domain, block, p);
    }
  }
}

static void clear_gaps_3d(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  gm_domain *domain = context;
  size_t stride = GM_BLOCK_NODES * (size_t)domain->wall_count;
  double *gap = domain->grid.wall_gap;
  for (size_t k = begin * stride; k < end * stride; k++)
    gap[k] = INFINITY;
}

void gm_walls_measure_gaps_3d(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  if (grid->block_count == 0)
    return; /* no nodes; and the block lists may be NULL */
  gm_parallel_for(&domain->pool, grid->block_count, clear_gaps_3d, domain);
  gap_3d_context ctx = {domain, NULL};
  for (int colour = 0; colour < GM_BLOCK_COLOURS; colour++) {
    size_t first = grid->color_start[colour];
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, grid->color_start[colour + 1] - first,
                    measure_blocks_3d, &ctx);
  }
}
