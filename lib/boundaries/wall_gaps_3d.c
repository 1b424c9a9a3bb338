/*
 * wall_gaps_3d.c - the gap of each node's material to each planar wall in
 * 3D, as wall_gaps.c measures it in 2D: the smallest distance from the
 * wall to the domain of a point with weight on the node, so that material
 * that has left the wall may come back to it within a step (walls.c,
 * walls_3d.c). The domain is, as in 2D, the point's box: for linear MPM
 * and uGIMP the initial one (edges GM_FIELD_DOMAIN_SIZE) moved with its
 * centre, for cpGIMP its edges stretched by |F_kk| (support_3d.h); its
 * half extent along the normal n is h_x |n_x| + h_y |n_y| + h_z |n_z|
 * (half edges h_k); CPDI's is the parallelepiped of edges F r_k, whose
 * half extent is sum_k |F r_k . n|. A B-spline point has no box of its
 * own; its domain is the initial box moved with its centre, as uGIMP's
 * and as the 2D B-splines' (wall_gaps.c: the same extent_along). The
 * nodes that get the gap are those the point has weight on: the 8 of its
 * tent with linear MPM, the nodes of its GIMP support (up to 3 per axis,
 * support_3d.h) with uGIMP and cpGIMP, those of its dense support with
 * CPDI (support_cpdi_3d.h), the 3 x 3 x 3 (quadratic) or 4 x 4 x 4
 * (cubic) nodes of its B-spline support (gm_box_support_compute_3d, the
 * factors p2g_3d.c and g2p_3d.c multiply; a cubic node at exactly 2
 * cells, of weight 0, is skipped as the transfers' zero weights are).
 *
 * The box faces that hold material (slip and fixed; not the B-splines'
 * mirrors) get the same measure after the walls, in the slots of
 * gm_gap_face_slot, as in 2D: a face node held at zero while its material
 * is still a fraction of a cell above the face would hang that material
 * there (grid_update_3d.c). A face acts on its face and ghost nodes only,
 * which a support reaches only from points less than a cell in front of it.
 *
 * Each node also gets, per planar wall, the smallest distance from the
 * wall to the centre of a point it carries (grid->wall_centre_gap), as in
 * 2D (wall_gaps.c): a wide support (uGIMP, cpGIMP, CPDI, the B-splines),
 * and a linear
 * tent where the plane is oblique, reaches nodes in front of the ones the
 * wall's contact acts on, and walls_3d.c keeps those from carrying a
 * point's centre past the wall. With the wide shapes the measured box
 * faces get it too, after the walls, from the points whose centres lie
 * less than a cell from the face (face_centres.c, gm_limit_face_centres:
 * the face holds only its face and ghost nodes, and a point on it gathers
 * from the node a cell in front as well), as in 2D. A wall on the plane
 * of an open box face gets the centre gaps as every wall does (from
 * 2026-11-28; before, it kept the rule of the frictional floors written
 * before walls anywhere, and a uGIMP, cpGIMP or CPDI centre on it was
 * carried out of the grid, failing the step: docs/3d.md).
 *
 * Minima do not depend on the order they are taken in, and the blocks are
 * visited colour by colour as in p2g_3d.c (8 colours), so the result is
 * deterministic and free of races.
 */
#include "boundaries/boundaries.h"

#include "shapes/shapes.h"

#include <math.h>

/* A gap matters at the nodes that act on a wall or join its friction
 * patches, less than GM_STRIP_REACH (2) cells in front of it; a linear
 * tent carries points less than a cell from its node, so only points
 * whose centre lies less than 3 cells in front of the plane lower such a
 * gap. 4 cells keeps a margin. A GIMP support reaches h + l/2 from the
 * centre (1.25 cells with 2 points per cell, 1.5 with one; cpGIMP's
 * stretched box farther): GM_GAP_REACH_WIDE_3D keeps the same margin for
 * boxes up to 3 cells long, the longest the 3D blocks take. A B-spline
 * reaches 1.5 (quadratic) or 2 cells (cubic) from its centre, so points
 * less than 4 cells in front lower the gaps that matter: inside the same
 * 6 cells. */
#define GM_GAP_REACH_3D      4.0
#define GM_GAP_REACH_WIDE_3D 6.0

/* A plane whose gaps are measured: a point on it and its unit normal into
 * the material's side. */
typedef struct gap_plane_3d {
  double point[3];  /* m */
  double normal[3]; /* unit */
  bool face;        /* a box face: only its face and ghost nodes use it */
} gap_plane_3d;

typedef struct gap_3d_context {
  gm_domain *domain;
  const uint32_t *blocks; /* of the colour being measured */
  gap_plane_3d planes[GM_MAX_WALLS + 6];
  int plane_count; /* gm_gap_plane_count: the walls, then the faces */
} gap_3d_context;

/* The walls, then the measured box faces, in gm_gap_face_slot's order. */
static int list_planes_3d(const gm_domain *domain, gap_plane_3d *planes) {
  int count = 0;
  for (int w = 0; w < domain->wall_count; w++, count++) {
    for (int k = 0; k < 3; k++) {
      planes[count].point[k] = domain->walls[w].point[k];
      planes[count].normal[k] = domain->walls[w].normal[k];
    }
    planes[count].face = false;
  }
  double h = domain->def.cell_size; /* m */
  for (int face = 0; face < 6; face++) {
    if (gm_gap_face_slot(domain, face) < 0)
      continue;
    int axis = face / 2, side = face % 2;
    gap_plane_3d *plane = &planes[count++];
    for (int k = 0; k < 3; k++)
      plane->point[k] = plane->normal[k] = 0.0;
    /* The face's node plane: GM_GHOST_LAYERS above node 0, or cells[axis]
     * further on the upper side. */
    int64_t node = GM_GHOST_LAYERS + (side ? domain->cells[axis] : 0);
    plane->point[axis] = domain->shape_grid.origin[axis] + (double)node * h;
    plane->normal[axis] = side ? -1.0 : 1.0;
    plane->face = true;
  }
  return count;
}

/* Could a point binned in this block (its cell's lowest node in the
 * block) lie within the reach of a wall? */
static bool block_may_reach_3d(const gm_domain *domain,
                               const gap_3d_context *ctx, const int64_t base[3],
                               double reach) {
  const double *origin = domain->shape_grid.origin; /* m, node 0 */
  double h = domain->def.cell_size;                 /* m */
  /* A GIMP point is binned by its support's lowest node, whose span may
   * be up to GM_SUPPORT_3D_MAX_SPAN nodes: its centre lies within that. */
  int64_t span = domain->def.shape == GM_SHAPE_LINEAR
                     ? 1
                     : GM_SUPPORT_3D_MAX_SPAN; /* nodes */
  double low[3], high[3]; /* m, a box holding every point centre */
  for (int k = 0; k < 3; k++) {
    low[k] = origin[k] + (double)(base[k] - 1) * h;
    high[k] = origin[k] + (double)(base[k] + GM_BLOCK_EDGE_3D + span) * h;
  }
  for (int w = 0; w < ctx->plane_count; w++) {
    const gap_plane_3d *plane = &ctx->planes[w];
    double nearest = 0.0; /* m, least signed distance of the box corners */
    for (int k = 0; k < 3; k++) {
      double corner = plane->normal[k] >= 0.0 ? low[k] : high[k];
      nearest += (corner - plane->point[k]) * plane->normal[k];
    }
    if (nearest <= reach)
      return true;
  }
  return false;
}

/* The nodes point p at x (m) has weight on, as a box support: the tent's
 * 2 per axis with linear MPM (the factors of the linear kernels, so the
 * linear gaps are those of before), the GIMP support with uGIMP and
 * cpGIMP, the B-spline's 3 or 4 per axis with the B-splines (half
 * unused). False if
 * the support leaves the grid (the transfers have failed the step then). */
static bool point_support_3d(const gm_domain *domain, const double x[3],
                             const double half[3], gm_box_support_3d *out) {
  if (domain->def.shape != GM_SHAPE_LINEAR)
    return gm_box_support_compute_3d(&domain->shape_grid, x, half, out);
  for (int k = 0; k < 3; k++) {
    double gradient[2];
    out->lowest[k] =
        gm_shape_linear_axis(x[k], domain->shape_grid.origin[k],
                             domain->inv_cell, out->weight[k], gradient);
    out->span[k] = 2;
  }
  return true;
}

/* The distances of one point (m): to its domain per gap plane, to its
 * centre per planar wall. */
typedef struct point_gaps_3d {
  double distance[GM_MAX_WALLS + 6];
  double centre[GM_MAX_WALLS + 6];
  int planes, centres;
} point_gaps_3d;

/* Lowers the gaps of node (local, in the block of links) to the point's. */
static void lower_node_gaps(gm_grid *grid, const uint32_t *links,
                            const int64_t local[3], const point_gaps_3d *pg) {
  size_t node =
      gm_gap_node(/* a block with a slot (gm_walls_map_gaps) */
                  grid, gm_block_node_3d(links, local[0], local[1], local[2]));
  double *gap = grid->wall_gap + node * (size_t)pg->planes;
  for (int w = 0; w < pg->planes; w++)
    gap[w] = pg->distance[w] < gap[w] ? pg->distance[w] : gap[w];
  if (pg->centres == 0)
    return; /* no walls: no centre gaps (the array may be NULL) */
  double *centre_gap = grid->wall_centre_gap + node * (size_t)pg->centres;
  for (int w = 0; w < pg->centres; w++)
    centre_gap[w] =
        pg->centre[w] < centre_gap[w] ? pg->centre[w] : centre_gap[w];
}

/* CPDI's nodes: the entries of its dense support (support_cpdi_3d.h) that
 * have weight. */
static void lower_cpdi_gaps(gm_domain *domain, uint32_t block,
                            const double x[3], const double f[9],
                            const double half[3], const point_gaps_3d *pg) {
  gm_grid *grid = &domain->grid;
  gm_cpdi_support_3d support;
  if (!gm_cpdi_support_compute_3d(&domain->shape_grid, x, f, half, &support))
    return; /* the transfers have failed the step then */
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int64_t base[3];
  gm_block_coordinates_3d(grid, grid->block_key[block], base);
  int entry = 0;
  for (int c = 0; c < support.span[2]; c++)
    for (int b = 0; b < support.span[1]; b++)
      for (int a = 0; a < support.span[0]; a++, entry++) {
        if (support.weight[entry] == 0.0)
          continue;
        int64_t local[3] = {
            support.lowest[0] - (base[0] << GM_BLOCK_SHIFT_3D) + a,
            support.lowest[1] - (base[1] << GM_BLOCK_SHIFT_3D) + b,
            support.lowest[2] - (base[2] << GM_BLOCK_SHIFT_3D) + c};
        lower_node_gaps(grid, links, local, pg);
      }
}

static void measure_point_3d(gm_domain *domain, const gap_3d_context *ctx,
                             uint32_t block, size_t p, double reach) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  gm_grid *grid = &domain->grid;
  point_gaps_3d pg;
  pg.planes = ctx->plane_count;
  pg.centres = gm_centre_gap_plane_count(domain); /* walls (, faces) */
  double h = domain->def.cell_size;               /* m */
  double x[3] = {current->position[0][p], current->position[1][p],
                 current->position[2][p]}; /* m */
  double half[3];                          /* m, the box's half edges */
  gm_box_half_edges_3d(domain->def.shape,
                       (const double *const *)points->domain_size,
                       gm_support_slots_3d(domain, current), p, half);
  /* CPDI: the parallelepiped of edges r_k = half_k (column k of the
   * domain map D), whose half extent along n is sum_k |r_k . n|
   * (support_cpdi_3d.h). */
  bool cpdi = domain->def.shape == GM_SHAPE_CPDI;
  double f[9] = {0.0}; /* D, row-major */
  if (cpdi)
    gm_deformation_rows_3d(gm_support_slots_3d(domain, current), p, f);
  bool near = false;
  for (int w = 0; w < pg.planes; w++) {
    const gap_plane_3d *plane = &ctx->planes[w];
    double centre = 0.0, half_extent = 0.0; /* m */
    const double *n = plane->normal;
    for (int k = 0; k < 3; k++) {
      centre += (x[k] - plane->point[k]) * n[k];
      half_extent += cpdi ? fabs(half[k] * (f[k] * n[0] + f[3 + k] * n[1] +
                                            f[6 + k] * n[2]))
                          : half[k] * fabs(n[k]);
    }
    pg.distance[w] = INFINITY;
    /* A planar wall, or with the wide shapes a box face: within a cell
     * only (2D: wall_gaps.c; a point farther away would need a node
     * faster than a cell per step to be carried past the face). */
    if (w < pg.centres)
      pg.centre[w] = centre > (plane->face ? h : reach) ? INFINITY : centre;
    if (centre > reach)
      continue;
    double gap = centre - half_extent; /* m */
    /* A box face acts on its face and ghost nodes only, which a support
     * reaches only from less than a cell away (wall_gaps.c). */
    if (plane->face && gap >= h)
      continue;
    pg.distance[w] = gap;
    near = true;
  }
  if (!near)
    return;
  if (cpdi) {
    lower_cpdi_gaps(domain, block, x, f, half, &pg);
    return;
  }
  gm_box_support_3d support;
  if (!point_support_3d(domain, x, half, &support))
    return;
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int64_t base[3], local[3];
  gm_block_coordinates_3d(grid, grid->block_key[block], base);
  for (int k = 0; k < 3; k++) /* the support's lowest node in the block */
    local[k] = support.lowest[k] - (base[k] << GM_BLOCK_SHIFT_3D);
  for (int c = 0; c < support.span[2]; c++)
    for (int b = 0; b < support.span[1]; b++)
      for (int a = 0; a < support.span[0]; a++) {
        if (support.weight[0][a] * support.weight[1][b] *
                support.weight[2][c] ==
            0.0)
          continue; /* no weight on this node (2D skips these as well) */
        int64_t node[3] = {local[0] + a, local[1] + b, local[2] + c};
        lower_node_gaps(grid, links, node, &pg);
      }
}

/* The reach of a point's gap (m): as in measure_point_3d. */
static double gap_reach_3d(const gm_domain *domain) {
  return (domain->def.shape == GM_SHAPE_LINEAR ? GM_GAP_REACH_3D
                                               : GM_GAP_REACH_WIDE_3D) *
         domain->def.cell_size;
}

void gm_walls_mark_gaps_3d(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  gap_3d_context ctx;
  ctx.domain = domain;
  ctx.blocks = NULL;
  ctx.plane_count = list_planes_3d(domain, ctx.planes);
  double reach = gap_reach_3d(domain); /* m */
  for (size_t b = 0; b < grid->block_count; b++) {
    int64_t base[3];
    gm_block_coordinates_3d(grid, grid->block_key[b], base);
    for (int k = 0; k < 3; k++)
      base[k] <<= GM_BLOCK_SHIFT_3D;
    /* measure_blocks_3d visits such a block; its points write the nodes
     * of their supports, in it and the blocks it links. */
    if (block_may_reach_3d(domain, &ctx, base, reach))
      gm_walls_mark_linked(grid, b);
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
    double reach = gap_reach_3d(domain); /* m */
    if (!block_may_reach_3d(domain, ctx, base, reach))
      continue;
    for (uint32_t k = grid->point_start[block];
         k < grid->point_start[block + 1]; k++) {
      size_t p = points->order[k];
      if (!domain->materials[points->material[p]].rigid) /* as in 2D */
        measure_point_3d(domain, ctx, block, p, reach);
    }
  }
}

/* Blocks [begin, end) of the gap slots: records to infinity. */
static void clear_gaps_3d(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  gm_clear_gap_records(context, begin * GM_BLOCK_NODES, end * GM_BLOCK_NODES);
}

void gm_walls_measure_gaps_3d(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  if (grid->block_count == 0)
    return; /* no nodes; and the block lists may be NULL */
  size_t sentinel = grid->gap_sentinel; /* gm_walls_map_gaps */
  gm_parallel_for(&domain->pool, sentinel / GM_BLOCK_NODES, clear_gaps_3d,
                  domain);
  gm_clear_gap_records(domain, sentinel, sentinel + 1);
  gap_3d_context ctx;
  ctx.domain = domain;
  ctx.blocks = NULL;
  ctx.plane_count = list_planes_3d(domain, ctx.planes);
  for (int colour = 0; colour < GM_BLOCK_COLOURS; colour++) {
    size_t first = grid->color_start[colour];
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, grid->color_start[colour + 1] - first,
                    measure_blocks_3d, &ctx);
  }
}
