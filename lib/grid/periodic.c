/*
 * periodic.c - periodic x faces (GM_WALL_PERIODIC): the grid of a layer
 * that repeats every box length L = cells[0] cells along x.
 *
 * Node x = 1 lies on the xmin face and node x = cells[0] + 1 on the xmax
 * face (support.h counts nodes from the ghost layer): in a periodic box
 * they are one node. Nodes x = 1 .. cells[0] own the columns; every other
 * node along x (the ghost column 0 below xmin, and the face and ghost
 * columns cells[0] + 1, cells[0] + 2 above xmax) is the image of the owner
 * a box length away (owner = image -+ cells[0]). The points scatter onto
 * whichever copy their support reaches, as without periodicity; then
 *   - fold (after every scatter): each image's mass, momentum and force
 *     are added to its owner, so the owner carries the points on both
 *     sides of the seam;
 *   - the grid update solves the owners (the images' own results are
 *     discarded);
 *   - copy (after every grid update): each image takes its owner's mass,
 *     velocity and acceleration, so a point near the seam gathers the same
 *     field through either copy.
 * The point positions are wrapped into [x0, x0 + L) when they move
 * (g2p.c), and the block grid holds every block of a row that has one
 * (block_grid.c), so an image's owner always exists.
 *
 * Each owner receives from at most one image (the box has at least 3
 * cells: gm_domain_create; with 2, node 2 would own images 0 and 4) and an
 * image is never an owner, so a pass over the blocks in parallel writes every
 * node from one place: no races, and the sums do not depend on the worker
 * count. Nothing is allocated.
 *
 * In 3D the same, node by node of the 4 x 4 x 4 blocks: the image
 * (x, y, z) and its owner (x -+ cells[0], y, z) lie in the same row of
 * blocks along x, which the block grid holds whole (block_grid.c).
 */
#include "grid/grid.h"

#include <math.h>

typedef struct periodic_context {
  gm_domain *domain;
  const gm_p2g_pass *scatter; /* fold: what was scattered */
  int mode;                   /* copy: GM_GRID_FULL copies accelerations */
  int task;                   /* which of the three passes */
} periodic_context;

enum { TASK_FOLD = 0, TASK_COPY = 1, TASK_GAPS = 2 };

/* Field index of node (x, y) in the layer-0 blocks, or SIZE_MAX if its
 * block does not exist this step. */
static size_t node_at(const gm_grid *grid, int64_t x, int64_t y) {
  uint32_t block = gm_grid_find(grid, gm_block_key_of_node(grid, x, y));
  if (block == GM_NO_BLOCK)
    return SIZE_MAX;
  int64_t mask = ((int64_t)1 << grid->shift) - 1;
  int64_t local = (x & mask) + (grid->dim > 1 ? (y & mask) << grid->shift : 0);
  return (size_t)block * GM_BLOCK_NODES + (size_t)local;
}

/* Field index of node (x, y, z) of a 3D grid, or SIZE_MAX if its block
 * does not exist this step. */
static size_t node_at_3d(const gm_grid *grid, int64_t x, int64_t y, int64_t z) {
  uint32_t block = gm_grid_find(grid, gm_block_key_of_node_3d(grid, x, y, z));
  if (block == GM_NO_BLOCK)
    return SIZE_MAX;
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  int64_t local = (x & mask) + GM_BLOCK_EDGE_3D * (y & mask) +
                  GM_BLOCK_EDGE_3D * GM_BLOCK_EDGE_3D * (z & mask);
  return (size_t)block * GM_BLOCK_NODES + (size_t)local;
}

/* One image node and its owner: the task's transfer between them (the
 * same for every dimension). */
static void image_node(const periodic_context *ctx, size_t image, size_t owner,
                       int planes) {
  gm_grid *grid = &ctx->domain->grid;
  int dim = ctx->domain->dim;
  if (ctx->task == TASK_FOLD) {
    const gm_p2g_pass *scatter = ctx->scatter;
    if (scatter->mass)
      grid->mass[owner] += grid->mass[image];
    for (int k = 0; k < dim; k++) {
      if (scatter->momentum)
        grid->momentum[k][owner] += grid->momentum[k][image];
      if (scatter->forces)
        grid->force[k][owner] += grid->force[k][image];
    }
  } else if (ctx->task == TASK_COPY) {
    grid->mass[image] = grid->mass[owner];
    for (int k = 0; k < dim; k++) {
      grid->momentum[k][image] = grid->momentum[k][owner];
      if (ctx->mode == GM_GRID_FULL)
        grid->force[k][image] = grid->force[k][owner];
    }
  } else {
    /* Every block has gap records with periodic x faces
     * (gm_walls_map_gaps). */
    double *owner_gap =
        grid->wall_gap + gm_gap_node(grid, owner) * (size_t)planes;
    const double *image_gap =
        grid->wall_gap + gm_gap_node(grid, image) * (size_t)planes;
    for (int w = 0; w < planes; w++)
      owner_gap[w] = image_gap[w] < owner_gap[w] ? image_gap[w] : owner_gap[w];
  }
}

/* The 3D blocks [begin, end): every image node of theirs. */
static void image_columns_3d(void *context, size_t begin, size_t end,
                             int worker) {
  (void)worker;
  const periodic_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gm_grid *grid = &domain->grid;
  const int64_t edge = GM_BLOCK_EDGE_3D;
  int64_t cells = domain->cells[0];
  int64_t first_owner = GM_GHOST_LAYERS, last_owner = cells; /* x indices */
  int planes = ctx->task == TASK_GAPS ? gm_gap_plane_count(domain) : 0;
  for (size_t b = begin; b < end; b++) {
    int64_t base[3];
    gm_block_coordinates_3d(grid, grid->block_key[b], base);
    for (int axis = 0; axis < 3; axis++)
      base[axis] <<= GM_BLOCK_SHIFT_3D;
    for (int64_t lx = 0; lx < edge; lx++) {
      int64_t x = base[0] + lx;
      if (x >= first_owner && x <= last_owner)
        continue; /* an owner */
      if (x > domain->shape_grid.last_node[0])
        break; /* beyond the grid: no node */
      int64_t owner_x = x < first_owner ? x + cells : x - cells;
      for (int64_t lz = 0; lz < edge; lz++) {
        for (int64_t ly = 0; ly < edge; ly++) {
          size_t image =
              b * GM_BLOCK_NODES + (size_t)(lx + edge * ly + edge * edge * lz);
          if (ctx->task != TASK_COPY && grid->mass[image] == 0.0)
            continue; /* no point reaches it: nothing to fold */
          size_t owner = node_at_3d(grid, owner_x, base[1] + ly, base[2] + lz);
          if (owner == SIZE_MAX)
            continue; /* cannot happen: whole rows of blocks exist */
          image_node(ctx, image, owner, planes);
        }
      }
    }
  }
}

static void image_columns(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  const periodic_context *ctx = context;
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  int dim = domain->dim;
  int64_t edge = (int64_t)1 << grid->shift;
  int64_t cells = domain->cells[0];
  int64_t first_owner = GM_GHOST_LAYERS, last_owner = cells; /* x indices */
  int planes = ctx->task == TASK_GAPS ? gm_gap_plane_count(domain) : 0;
  for (size_t b = begin; b < end; b++) {
    int64_t base[2];
    gm_block_base(grid, grid->block_key[b], base);
    for (int64_t lx = 0; lx < (dim > 1 ? edge : (int64_t)GM_BLOCK_NODES);
         lx++) {
      int64_t x = base[0] + lx;
      if (x >= first_owner && x <= last_owner)
        continue; /* an owner */
      if (x > domain->shape_grid.last_node[0])
        break; /* beyond the grid: no node */
      int64_t owner_x = x < first_owner ? x + cells : x - cells;
      for (int64_t t = 0; t < (dim > 1 ? edge : 1); t++) {
        int64_t y = dim > 1 ? base[1] + t : 0;
        size_t image = (size_t)b * GM_BLOCK_NODES +
                       (size_t)(dim > 1 ? lx + (t << grid->shift) : lx);
        if (ctx->task != TASK_COPY && grid->mass[image] == 0.0)
          continue; /* no point reaches it: nothing to fold */
        size_t owner = node_at(grid, owner_x, y);
        if (owner == SIZE_MAX)
          continue; /* cannot happen: whole rows of blocks exist */
        image_node(ctx, image, owner, planes);
      }
    }
  }
}

static void run(gm_domain *domain, const gm_p2g_pass *scatter, int mode,
                int task) {
  if (!gm_periodic_x(domain) || domain->grid.block_count == 0)
    return;
  periodic_context ctx = {domain, scatter, mode, task};
  gm_parallel_for(&domain->pool, domain->grid.block_count,
                  domain->dim == 3 ? image_columns_3d : image_columns, &ctx);
}

void gm_periodic_fold_images(gm_domain *domain, const gm_p2g_pass *pass) {
  run(domain, pass, 0, TASK_FOLD);
}

void gm_periodic_copy_images(gm_domain *domain, int mode) {
  run(domain, NULL, mode, TASK_COPY);
}

void gm_periodic_fold_gaps(gm_domain *domain) {
  if (gm_gap_plane_count(domain) > 0)
    run(domain, NULL, 0, TASK_GAPS);
}

/* Scaled: node units from node 0, as gm_block_key_of measures. A point
 * that rounds onto the wrong side of the seam is put on the seam x0
 * itself, where both sides meet. */
double gm_periodic_wrap_x(const gm_domain *domain, double x) {
  double origin = domain->shape_grid.origin[0]; /* m, node 0 */
  double inv_cell = domain->inv_cell;           /* 1/m */
  /* scaled coordinate of the xmax face */
  double upper = (double)(domain->cells[0] + GM_GHOST_LAYERS);
  double box_lower = domain->def.origin[0];                         /* m */
  double period = (double)domain->cells[0] * domain->def.cell_size; /* m */
  double scaled = (x - origin) * inv_cell;
  if ((scaled >= GM_GHOST_LAYERS && scaled < upper) || !isfinite(x))
    return x;
  x -= period * floor((x - box_lower) / period);
  scaled = (x - origin) * inv_cell;
  if (scaled >= GM_GHOST_LAYERS && scaled < upper)
    return x;
  x = box_lower;
  while ((x - origin) * inv_cell < GM_GHOST_LAYERS)
    x = nextafter(x, INFINITY); /* a few ulps at most */
  return x;
}
