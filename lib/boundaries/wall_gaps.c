/*
 * wall_gaps.c - how far the material of each node is from each planar
 * wall and each box face. A node on or behind a wall carries points whose
 * domains may have left the wall; holding the node's velocity at zero toward
 * the wall would then stop that material from ever coming back, and every
 * vibration would press it harder against the wall (a ratchet). The gap of a
 * node to a wall is the smallest distance from the wall to the domain of a
 * point with weight on the node: the contact lets the node close that gap in a
 * step and stops only the rest (walls.c).
 *
 * For the planar walls each node also gets the smallest distance from the
 * wall to the centre of a point it carries (grid->wall_centre_gap): with
 * the shapes wider than a tent (GIMP, CPDI, B-splines) a point gathers its
 * velocity from nodes the wall's contact does not reach, and walls.c keeps
 * those nodes from carrying a point's centre past the wall; with linear
 * MPM so do the nodes between one cell and |n_x| + |n_y| cells in front
 * of an oblique wall (gm_wall_tent_reach), which walls.c bounds alike.
 *
 * The box faces that hold material (slip and fixed) get the same measure,
 * after the planar walls in the gap records (gm_gap_face_slot): a face
 * node held at zero while its material is still a fraction of a cell
 * above the face would hang that material in the air (grid_update.c).
 * They get the centre gap too, from the points whose centres are less
 * than a cell from the face: the face holds only its face and ghost
 * nodes, and a point on it gathered from the node a cell in front as
 * well (face_centres.c, gm_limit_face_centres).
 * The faces of the B-splines are mirrors (bspline_faces.c) and are not
 * measured.
 *
 * Minima do not depend on the order they are taken in, and the blocks are
 * visited colour by colour as in p2g.c, so the result is deterministic and
 * free of races.
 *
 * Records are stored only for the blocks the measure visits and the
 * blocks they link (gm_walls_map_gaps, below); every other node reads one
 * sentinel node's records, infinite like a record no point lowered: a
 * granular cloud's node layers far above the floor took 28 B per point in
 * 2D and 78 in 3D for records nothing wrote (docs/performance.md, "Gap
 * records per block").
 */
#include "boundaries/boundaries.h"

#include <math.h>

/* Does box face f (2 axis + side) hold material and get a gap? In 3D
 * too: wall_gaps_3d.c measures it, grid_update_3d.c releases by it. */
static bool face_measured(const gm_domain *domain, int face) {
  return face / 2 < domain->dim && domain->def.walls[face] != GM_WALL_OPEN &&
         domain->def.walls[face] != GM_WALL_PERIODIC &&
         !gm_shape_is_bspline(domain->def.shape);
}

int gm_gap_face_slot(const gm_domain *domain, int face) {
  if (!face_measured(domain, face))
    return -1;
  int slot = domain->wall_count;
  for (int f = 0; f < face; f++)
    slot += face_measured(domain, f);
  return slot;
}

void gm_gap_layout_of(const gm_domain *domain, gm_gap_layout *out) {
  out->planes = gm_gap_plane_count(domain);
  out->centres = gm_centre_gap_plane_count(domain);
  for (int face = 0; face < 6; face++)
    out->face_slot[face] = gm_gap_face_slot(domain, face);
}

int gm_gap_plane_count(const gm_domain *domain) {
  int count = domain->wall_count;
  for (int face = 0; face < 2 * domain->dim; face++)
    count += face_measured(domain, face);
  return count;
}

/* A plane whose gaps are measured: a point on it and its unit normal
 * into the material's side. */
int gm_centre_gap_plane_count(const gm_domain *domain) {
  /* Linear MPM: the planar walls only, used on the band of an oblique
   * plane (gm_wall_tent_reach; walls.c in 2D, walls_3d.c in 3D); its box
   * faces need none (a point on a face has no weight on the node a cell
   * in front). */
  return domain->def.shape == GM_SHAPE_LINEAR ? domain->wall_count
                                              : gm_gap_plane_count(domain);
}

typedef struct gap_plane {
  double point[2];  /* m */
  double normal[2]; /* unit */
  bool face;        /* a box face: only its face and ghost nodes use it */
} gap_plane;

static int list_planes(const gm_domain *domain, gap_plane *planes) {
  int count = 0;
  for (int w = 0; w < domain->wall_count; w++, count++) {
    for (int k = 0; k < 2; k++) {
      planes[count].point[k] = domain->walls[w].point[k];
      planes[count].normal[k] = domain->walls[w].normal[k];
    }
    planes[count].face = false;
  }
  double h = domain->def.cell_size;
  for (int face = 0; face < 2 * domain->dim; face++) {
    if (!face_measured(domain, face))
      continue;
    int axis = face / 2, side = face % 2;
    gap_plane *plane = &planes[count++];
    plane->point[0] = plane->point[1] = 0.0;
    plane->normal[0] = plane->normal[1] = 0.0;
    /* The face node: GM_GHOST_LAYERS above node 0 (support.h), or
     * cells[axis] further on the upper side. */
    int64_t node = GM_GHOST_LAYERS + (side ? domain->cells[axis] : 0);
    plane->point[axis] = domain->shape_grid.origin[axis] + (double)node * h;
    plane->normal[axis] = side ? -1.0 : 1.0;
    plane->face = true;
  }
  return count;
}

typedef struct gap_context {
  gm_domain *domain;
  const uint32_t *blocks; /* of the colour being measured */
  gap_plane planes[GM_MAX_WALLS + 4];
  int plane_count;
} gap_context;

/* Half extent (m) of point p's current domain along the unit normal. */
static double extent_along(const gm_domain *domain,
                           const gm_point_domain *point,
                           const double normal[2]) {
  double corners[4][2];
  gm_point_domain_corners(domain->shape_grid.shape, domain->dim, point,
                          corners);
  /* r1 = (c1 - c0) / 2, r2 = (c3 - c0) / 2 */
  double r1[2] = {0.5 * (corners[1][0] - corners[0][0]),
                  0.5 * (corners[1][1] - corners[0][1])};
  double r2[2] = {0.5 * (corners[3][0] - corners[0][0]),
                  0.5 * (corners[3][1] - corners[0][1])};
  if (domain->dim == 1)
    r2[0] = r2[1] = 0.0;
  return fabs(r1[0] * normal[0] + r1[1] * normal[1]) +
         fabs(r2[0] * normal[0] + r2[1] * normal[1]);
}

/* Lowers the gap records of one node to distance (per plane) and its
 * centre gaps to centre_distance (the first `centres` planes). */
static GM_ALWAYS_INLINE void lower_node_gaps(gm_grid *grid, size_t node,
                                             int planes, int centres,
                                             const double *distance,
                                             const double *centre_distance) {
  size_t records = gm_gap_node(grid, node); /* a block with a slot */
  double *gap = grid->wall_gap + records * (size_t)planes;
  for (int w = 0; w < planes; w++)
    gap[w] = distance[w] < gap[w] ? distance[w] : gap[w];
  if (centres == 0)
    return; /* linear, box faces only: no centre gaps (the array is
               NULL, and even NULL + 0 is undefined; fuzz/fuzz_api) */
  double *centre_gap = grid->wall_centre_gap + records * (size_t)centres;
  for (int w = 0; w < centres; w++)
    centre_gap[w] =
        centre_distance[w] < centre_gap[w] ? centre_distance[w] : centre_gap[w];
}

/* The nodes of a 2D CPDI point's support (support_cpdi.h, bitwise
 * gm_support_compute's cells and values), corner by corner: the entries
 * of gm_cpdi_support_expand in its order, those of weight share N_i(x_c)
 * zero skipped as there (a node two corners share is lowered twice, to
 * the same minimum). Without the general support's out-of-line calls and
 * its table. */
static void lower_cpdi_gaps(gm_domain *domain, const gm_point_domain *point,
                            const uint32_t *links, const int64_t base[2],
                            int planes, int centres, const double *distance,
                            const double *centre_distance) {
  gm_grid *grid = &domain->grid;
  gm_cpdi_support s;
  int64_t reach[2];
  if (!gm_cpdi_support_2d(&domain->shape_grid, point->position[0],
                          point->position[1], point->deformation[0],
                          point->deformation[1], point->deformation[2],
                          point->deformation[3], point->half_size[0],
                          point->half_size[1], &s, reach))
    return; /* cannot happen: the binning placed the point by it */
  for (int c = 0; c < 4; c++)
    for (int b = 0; b < 2; b++)
      for (int a = 0; a < 2; a++) {
        if (s.share * (s.axis[c][0][a] * s.axis[c][1][b]) == 0.0)
          continue;
        size_t node =
            gm_block_node(links, grid->shift, s.cell[c][0] + a - base[0],
                          s.cell[c][1] + b - base[1]);
        lower_node_gaps(grid, node, planes, centres, distance, centre_distance);
      }
}

/* Lowers the gaps of the nodes point p reaches to its domain's distance
 * from each plane its support may reach past. */
static void measure_point(gm_domain *domain, const gap_context *ctx,
                          uint32_t block, size_t p) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  gm_grid *grid = &domain->grid;
  int dim = domain->dim, planes = ctx->plane_count;
  gm_point_domain point;
  gm_point_domain_at(domain, current, p, &point);
  double h = domain->def.cell_size; /* m */
  /* A support reaches at most 9 nodes (8 cells) from the point. */
  double reach = 8.0 * h; /* m */
  double distance[GM_MAX_WALLS + 4];
  double centre_distance[GM_MAX_WALLS + 4]; /* m */
  bool near = false;
  for (int w = 0; w < planes; w++) {
    const gap_plane *plane = &ctx->planes[w];
    double centre = (point.position[0] - plane->point[0]) * plane->normal[0] +
                    (point.position[1] - plane->point[1]) * plane->normal[1];
    distance[w] = INFINITY;
    /* A box face: within a cell only. A point farther away would need a
     * node faster than a cell per step to be carried past the face. */
    centre_distance[w] = centre > (plane->face ? h : reach) ? INFINITY : centre;
    if (centre > reach)
      continue; /* no node of its support lies behind this plane */
    double gap = centre - extent_along(domain, &point, plane->normal);
    /* A box face acts on its face and ghost nodes only, which a linear,
     * GIMP or CPDI support reaches only from less than a cell away. */
    if (plane->face && gap >= h)
      continue;
    distance[w] = gap;
    near = true;
  }
  if (!near)
    return;
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int64_t base[2];
  gm_block_base(grid, grid->block_key[block], base);
  int centres = gm_centre_gap_plane_count(domain);
  if (dim == 2 && domain->shape_grid.shape == GM_SHAPE_CPDI) {
    lower_cpdi_gaps(domain, &point, links, base, planes, centres, distance,
                    centre_distance);
    return;
  }
  gm_support support;
  if (!gm_support_compute(&domain->shape_grid, &point, &support))
    return; /* cannot happen: the binning placed the point by it */
  for (int e = 0; e < support.count; e++) {
    if (support.weight[e] == 0.0)
      continue;
    int64_t x = support.lowest[0] - base[0] + support.offset[0][e];
    int64_t y =
        dim > 1 ? support.lowest[1] - base[1] + support.offset[1][e] : 0;
    size_t node = gm_block_node(links, grid->shift, x, y);
    lower_node_gaps(grid, node, planes, centres, distance, centre_distance);
  }
}

/* Could a point binned in this block lie within the reach of
 * measure_point (8 cells) of a plane? The binning keys a point by its cell
 * (linear) or by the lowest node of its support (bins.c), and a support
 * spans at most GM_SUPPORT_MAX_SPAN nodes, so every point centre of the
 * block lies in nodes base .. base + edge + GM_SUPPORT_MAX_SPAN on each
 * axis; one more cell on each side keeps the test conservative against
 * rounding. A block no plane may reach holds only points measure_point
 * would return from without writing a gap, so skipping it leaves every gap
 * bit-for-bit the same and spares the reads of its points (issue 15). */
static bool block_may_reach(const gm_domain *domain, const gap_context *ctx,
                            uint32_t block) {
  const gm_grid *grid = &domain->grid;
  const double *origin = domain->shape_grid.origin;
  double h = domain->def.cell_size; /* m */
  double reach = 8.0 * h;           /* m, as in measure_point */
  int64_t base[2];
  gm_block_base(grid, grid->block_key[block], base);
  int64_t edge = (int64_t)1 << grid->shift;
  double low[2], high[2]; /* m, box holding every point centre of the block */
  for (int k = 0; k < 2; k++) {
    low[k] = origin[k] + (double)(base[k] - 1) * h;
    high[k] =
        origin[k] + (double)(base[k] + edge + GM_SUPPORT_MAX_SPAN + 1) * h;
  }
  for (int w = 0; w < ctx->plane_count; w++) {
    const gap_plane *plane = &ctx->planes[w];
    if (domain->dim == 1 && plane->normal[1] != 0.0)
      return true;        /* no box along y in 1D: measure every point */
    double nearest = 0.0; /* m, least signed distance of the box's corners */
    for (int k = 0; k < domain->dim; k++) {
      double corner = plane->normal[k] >= 0.0 ? low[k] : high[k];
      nearest += (corner - plane->point[k]) * plane->normal[k];
    }
    if (nearest <= reach)
      return true;
  }
  return false;
}

static void measure_blocks(void *context, size_t begin, size_t end,
                           int worker) {
  (void)worker;
  gap_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = ctx->blocks[item];
    if (!block_may_reach(domain, ctx, block))
      continue;
    for (uint32_t k = grid->point_start[block];
         k < grid->point_start[block + 1]; k++) {
      size_t p = points->order[k];
      if (!domain->materials[points->material[p]].rigid)
        measure_point(domain, ctx, block, p);
    }
  }
}

void gm_walls_mark_linked(gm_grid *grid, size_t b) {
  const uint32_t *link = grid->neighbour + b * GM_BLOCK_NEIGHBOURS;
  for (int slot = 0; slot < GM_BLOCK_NEIGHBOURS; slot++)
    if (link[slot] != GM_NO_BLOCK) /* 2D: slots 4-7 never link */
      grid->gap_slot[link[slot]] = 0;
}

size_t gm_walls_map_gaps(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  bool every = gm_periodic_x(domain);
  for (size_t b = 0; b < grid->block_count; b++)
    grid->gap_slot[b] = every ? 0 : GM_NO_BLOCK;
  if (gm_gap_plane_count(domain) > 0 && !every) {
    if (domain->dim == 3) {
      gm_walls_mark_gaps_3d(domain);
    } else {
      gap_context ctx;
      ctx.domain = domain;
      ctx.blocks = NULL;
      ctx.plane_count = list_planes(domain, ctx.planes);
      /* measure_point writes the nodes of the point's support, in its
       * block and the +x, +y, +x+y neighbours (gm_block_node). */
      for (size_t b = 0; b < grid->block_count; b++)
        if (block_may_reach(domain, &ctx, (uint32_t)b))
          gm_walls_mark_linked(grid, b);
    }
  }
  uint32_t slots = 0;
  for (size_t b = 0; b < grid->block_count; b++)
    if (grid->gap_slot[b] != GM_NO_BLOCK)
      grid->gap_slot[b] = slots++;
  grid->gap_sentinel = (size_t)slots * GM_BLOCK_NODES;
  return grid->gap_sentinel + 1;
}

/* Sets the gap records of nodes [begin, end) * GM_BLOCK_NODES (blocks
 * with a slot, in slot order) to infinity: no point measured yet. */
static void clear_gaps(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_clear_gap_records(domain, begin * GM_BLOCK_NODES, end * GM_BLOCK_NODES);
}

void gm_clear_gap_records(gm_domain *domain, size_t begin, size_t end) {
  size_t planes = (size_t)gm_gap_plane_count(domain);
  double *gap = domain->grid.wall_gap;
  for (size_t k = begin * planes; k < end * planes; k++)
    gap[k] = INFINITY;
  size_t centres = (size_t)gm_centre_gap_plane_count(domain);
  double *centre_gap = domain->grid.wall_centre_gap;
  for (size_t k = begin * centres; k < end * centres; k++)
    centre_gap[k] = INFINITY;
}

void gm_walls_measure_gaps(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  if (grid->block_count == 0)
    return; /* no nodes; and the block lists may be NULL (NULL + 0 is
               undefined) */
  size_t sentinel = grid->gap_sentinel;
  gm_parallel_for(&domain->pool, sentinel / GM_BLOCK_NODES, clear_gaps, domain);
  gm_clear_gap_records(domain, sentinel, sentinel + 1);
  gap_context ctx;
  ctx.domain = domain;
  ctx.blocks = NULL;
  ctx.plane_count = list_planes(domain, ctx.planes);
  for (int colour = 0; colour < 4; colour++) {
    size_t first = grid->color_start[colour];
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, grid->color_start[colour + 1] - first,
                    measure_blocks, &ctx);
  }
}
