/*
 * bspline_faces.c - the box-face conditions for the B-spline shape
 * functions, by the method of images.
 *
 * The B-splines do not interpolate: a node's velocity is not the field's
 * value there. Holding the face node and the ghost node beyond it at zero,
 * as for linear MPM and GIMP (grid_update.c), leaves the quadratic field
 * near the face N_2 v_2 alone: 1/8 of the next node's value on the face,
 * zero only half a cell behind it. Points could then cross a slip floor,
 * and a fixed end acts as if a third of a cell further out (the fixed-free
 * bar's period came out 1.4 % long, test_bar.c).
 *
 * A wall face is a mirror instead. Each point has an image reflected in
 * the face, whose velocity is reflected too: the components the face
 * holds (the normal one on a slip face and on the symmetry axis, both on
 * a fixed face) change sign, the others keep it. Node j then receives from
 * the images what the real points give its mirror node 2f - j (f: the face
 * node), so, with one ghost layer, adding the ghost node's mass, momentum
 * and force to its mirror (two nodes inside, signs as above) makes the
 * grid carry the real points and their images (fold_ghosts, after the
 * scatter). After the update the ghost node takes its mirror's velocity
 * and acceleration, signs as above (mirror_ghosts): the field is odd
 * about the face in the held components and vanishes on it exactly, and
 * is even in the free tangential one. The face node's own image is itself:
 * its held components are zero already (grid_update.c).
 *
 * Each pass handles one axis over all blocks in parallel: it writes only
 * the mirror nodes (fold) or the ghost nodes (mirror) of that axis, each
 * from a single node, so it is race-free and deterministic. x goes before
 * y, which makes a corner's images right: its ghost folds into the
 * x-mirror, which as a y-ghost folds on into the diagonal node.
 *
 * 3D is the same with a z pass after y (an edge or corner ghost folds on
 * axis by axis into the node inside; in the mirror passes the last pass
 * that writes a ghost reads a mirror the earlier passes have finished),
 * with one difference: each face gets its own pass. With 2 cells along
 * an axis both ghosts of that axis fold into the same node, and the 4 x 4
 * x 4 blocks (block_grid.h) put the two ghosts in different blocks, which
 * one parallel pass could run at once; lower face first, then upper,
 * keeps the sums in one order for every worker count.
 */
#include "grid/grid.h"

/* Signs of the reflected velocity components beyond face (axis, side):
 * -1 for a component the face holds, +1 for a free one; false for an open
 * face (no image). */
static bool face_signs(const gm_domain *domain, int axis, int side,
                       double sign[3]) {
  gm_wall_type wall = domain->def.walls[2 * axis + side];
  bool symmetry_axis = axis == 0 && side == 0 && domain->axisymmetric &&
                       domain->def.origin[0] == 0.0; /* v_r = 0 at r = 0 */
  if ((wall == GM_WALL_OPEN || wall == GM_WALL_PERIODIC) && !symmetry_axis)
    return false; /* periodic faces: images of the other side (periodic.c) */
  for (int k = 0; k < 3; k++) /* z: 3D only */
    sign[k] = wall == GM_WALL_FIXED ||
                      (k == axis && (wall == GM_WALL_SLIP ||
                                     wall == GM_WALL_SYMMETRY || symmetry_axis))
                  ? -1.0
                  : 1.0;
  return true;
}

typedef struct image_context {
  gm_domain *domain;
  int axis;                   /* the faces of this axis */
  int side;                   /* 3D: the face of that axis, 0 lower */
  const gm_p2g_pass *scatter; /* fold: what was scattered; NULL: mirror */
  bool accelerations;         /* mirror: the force arrays hold them */
} image_context;

/* Node index of (x, y) in the blocks of the layer of `layer_keys`, or
 * SIZE_MAX if its block does not exist this step. */
static size_t node_at(const gm_grid *grid, int64_t layer_keys, int64_t x,
                      int64_t y) {
  uint32_t block =
      gm_grid_find(grid, layer_keys + gm_block_key_of_node(grid, x, y));
  if (block == GM_NO_BLOCK)
    return SIZE_MAX;
  int64_t mask = ((int64_t)1 << grid->shift) - 1;
  int64_t local = (x & mask) + (grid->dim > 1 ? (y & mask) << grid->shift : 0);
  return (size_t)block * GM_BLOCK_NODES + (size_t)local;
}

static void image_blocks(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  const image_context *ctx = context;
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  int axis = ctx->axis, dim = domain->dim;
  int64_t edge = (int64_t)1 << grid->shift;
  /* Ghost nodes of this axis: below the lower face, above the upper. */
  int64_t ghost[2] = {GM_GHOST_LAYERS - 1,
                      domain->cells[axis] + GM_GHOST_LAYERS + 1};
  double sign[2][3];
  bool active[2];
  for (int side = 0; side < 2; side++)
    active[side] = face_signs(domain, axis, side, sign[side]);
  int64_t stride = gm_grid_layer_stride(grid);
  for (size_t b = begin; b < end; b++) {
    int64_t key = grid->block_key[b], base[2];
    gm_block_base(grid, key, base);
    int64_t layer_keys = key - key % stride; /* layer * stride */
    for (int side = 0; side < 2; side++) {
      int64_t row = ghost[side] - base[axis]; /* local index along axis */
      if (!active[side] || row < 0 || row >= edge)
        continue;
      int64_t mirror = side ? ghost[side] - 2 : ghost[side] + 2;
      for (int64_t t = 0; t < (dim > 1 ? edge : 1); t++) {
        int64_t at[2] = {base[0] + (axis == 0 ? row : t),
                         dim > 1 ? base[1] + (axis == 0 ? t : row) : 0};
        size_t node = node_at(grid, layer_keys, at[0], at[1]);
        if (grid->mass[node] == 0.0)
          continue; /* no point reaches it (nor, then, its mirror's image) */
        at[axis] = mirror;
        size_t image = node_at(grid, layer_keys, at[0], at[1]);
        if (image == SIZE_MAX)
          continue; /* cannot happen: a point reaching the ghost reaches it */
        const gm_p2g_pass *scatter = ctx->scatter;
        for (int k = 0; k < dim; k++) {
          double s = sign[side][k];
          if (scatter) { /* fold the ghost's sums into its mirror */
            if (scatter->momentum)
              grid->momentum[k][image] += s * grid->momentum[k][node];
            if (scatter->forces)
              grid->force[k][image] += s * grid->force[k][node];
          } else { /* the ghost takes its mirror's reflected values */
            grid->momentum[k][node] = s * grid->momentum[k][image];
            if (ctx->accelerations)
              grid->force[k][node] = s * grid->force[k][image];
          }
        }
        if (scatter && scatter->mass)
          grid->mass[image] += grid->mass[node];
      }
    }
  }
}

/* Field index of node (x, y, z) of a 3D grid in the blocks of the layer
 * of `layer_keys` (granular node layers, as node_at), or SIZE_MAX if its
 * block does not exist this step. */
static size_t node_at_3d(const gm_grid *grid, int64_t layer_keys,
                         const int64_t at[3]) {
  uint32_t block = gm_grid_find(
      grid, layer_keys + gm_block_key_of_node_3d(grid, at[0], at[1], at[2]));
  if (block == GM_NO_BLOCK)
    return SIZE_MAX;
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  int64_t local = (at[0] & mask) + GM_BLOCK_EDGE_3D * (at[1] & mask) +
                  GM_BLOCK_EDGE_3D * GM_BLOCK_EDGE_3D * (at[2] & mask);
  return (size_t)block * GM_BLOCK_NODES + (size_t)local;
}

/* The 3D blocks [begin, end): the ghost nodes of face (axis, side) in
 * them, as image_blocks does for one axis in 2D. */
static void image_blocks_3d(void *context, size_t begin, size_t end,
                            int worker) {
  (void)worker;
  const image_context *ctx = context;
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  int axis = ctx->axis, side = ctx->side;
  const int64_t edge = GM_BLOCK_EDGE_3D;
  int64_t ghost =
      side ? domain->cells[axis] + GM_GHOST_LAYERS + 1 : GM_GHOST_LAYERS - 1;
  int64_t mirror = side ? ghost - 2 : ghost + 2;
  double sign[3];
  if (!face_signs(domain, axis, side, sign))
    return;
  /* The two axes along the face. */
  int first = axis == 0 ? 1 : 0, second = axis == 2 ? 1 : 2;
  const gm_p2g_pass *scatter = ctx->scatter;
  int64_t stride = gm_grid_layer_stride(grid);
  for (size_t b = begin; b < end; b++) {
    int64_t base[3];
    int64_t layer_keys = grid->block_key[b] - grid->block_key[b] % stride;
    gm_block_coordinates_3d(grid, grid->block_key[b], base);
    for (int k = 0; k < 3; k++)
      base[k] <<= GM_BLOCK_SHIFT_3D;
    if (ghost < base[axis] || ghost >= base[axis] + edge)
      continue;
    for (int64_t u = 0; u < edge; u++) {
      for (int64_t t = 0; t < edge; t++) {
        int64_t at[3];
        at[axis] = ghost;
        at[first] = base[first] + t;
        at[second] = base[second] + u;
        size_t node = node_at_3d(grid, layer_keys, at);
        if (grid->mass[node] == 0.0)
          continue; /* no point reaches it (nor, then, its mirror's image) */
        at[axis] = mirror;
        size_t image = node_at_3d(grid, layer_keys, at);
        if (image == SIZE_MAX)
          continue; /* cannot happen: a point reaching the ghost reaches it */
        for (int k = 0; k < 3; k++) {
          double s = sign[k];
          if (scatter) { /* fold the ghost's sums into its mirror */
            if (scatter->momentum)
              grid->momentum[k][image] += s * grid->momentum[k][node];
            if (scatter->forces)
              grid->force[k][image] += s * grid->force[k][node];
          } else { /* the ghost takes its mirror's reflected values */
            grid->momentum[k][node] = s * grid->momentum[k][image];
            if (ctx->accelerations)
              grid->force[k][node] = s * grid->force[k][image];
          }
        }
        if (scatter && scatter->mass)
          grid->mass[image] += grid->mass[node];
      }
    }
  }
}

static void run_axes(gm_domain *domain, const gm_p2g_pass *scatter,
                     bool accelerations) {
  if (!gm_shape_is_bspline(domain->shape_grid.shape))
    return;
  for (int axis = 0; axis < domain->dim; axis++) {
    if (domain->dim == 3) { /* one pass per face (see the top) */
      for (int side = 0; side < 2; side++) {
        image_context ctx = {domain, axis, side, scatter, accelerations};
        gm_parallel_for(&domain->pool, domain->grid.block_count,
                        image_blocks_3d, &ctx);
      }
      continue;
    }
    image_context ctx = {domain, axis, 0, scatter, accelerations};
    gm_parallel_for(&domain->pool, domain->grid.block_count, image_blocks,
                    &ctx);
  }
}

void gm_bspline_fold_ghosts(gm_domain *domain, const gm_p2g_pass *pass) {
  run_axes(domain, pass, false);
}

void gm_bspline_mirror_ghosts(gm_domain *domain, int mode) {
  run_axes(domain, NULL, mode == GM_GRID_FULL);
}
