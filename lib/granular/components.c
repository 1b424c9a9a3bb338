/*
 * components.c - parallel grids of the granular method (000 sec 3.3-3.4,
 * Tables A1-A3), run after the plain binning of each step:
 *
 *  1. each point's support (the node box it sends data to) and domain of
 *     interaction (interaction.h);
 *  2. the pre-task: candidate pairs are the points whose supports share a
 *     node, found in O(N) from cell buckets (pair_search.c);
 *  3. task 1: a candidate pair interacts if its domains of interaction
 *     overlap (both granular), if the granular point's domain of
 *     interaction overlaps the other point's own domain (one granular), or
 *     always (neither granular: plain MPM between them);
 *  4. task 2: connected components of the interaction graph by union-find,
 *     labelled in order of their smallest point id (deterministic);
 *  5. every component must behave as if alone on its grid. Components that
 *     share no node cannot affect each other on one grid, so only the
 *     components that do share a node are kept apart: a greedy colouring
 *     (in label order) gives each a node layer (layers.c), and the points
 *     are re-keyed into their layer's blocks (core/block_grid.h) and binned
 *     again by the step (step/step.c).
 *     With one component, or none sharing nodes, nothing is re-binned.
 *
 * Most steps change few connections. The spanning forest of the last
 * search is kept: its edges that still interact join sets that each lie
 * inside one component, and every edge between two sets has an end outside
 * the largest one, so only those points search (with full windows). More
 * than half the points outside it, or points reordered, added or removed,
 * mean a full search.
 * When the kept forest spans all points and every edge holds, there is one
 * component and the union-find is skipped: only the edges are checked, in
 * parallel (a connected flow, the common case).
 */
#include "granular/granular.h"

#include "granular/pair_rules.h"

#include <math.h>
#include <string.h>

/* Support box and domain of interaction of one point in the general way
 * (any variant; used for CPDI). */
static void general_geometry(gm_domain *domain, size_t p,
                             const gm_point_domain *point, double measure) {
  gm_granular_work *work = &domain->granular;
  int64_t low[2], high[2];
  /* Cannot fail: the binning checked the same support. */
  gm_support_bounds(&domain->shape_grid, point, low, high);
  for (int k = 0; k < 2; k++) {
    work->support_low[k][p] = (int32_t)low[k]; /* range: domain_granular.h */
    work->support_high[k][p] = (int32_t)high[k];
  }
  gm_interaction_domain *interaction = &work->interaction[p];
  gm_interaction_domain_of(domain->shape_grid.shape, domain->dim, point,
                           measure, interaction);
}

/* The same for CPDI in 2D: the corners once (support_cpdi.h, those of
 * gm_support_bounds and gm_point_domain_corners) for both. */
static void cpdi_geometry_2d(gm_domain *domain, size_t p,
                             const gm_point_domain *point, double measure) {
  gm_granular_work *work = &domain->granular;
  const double *d = point->deformation; /* the domain map D */
  double corners[4][2], cells[4][2];
  int64_t low[2] = {0, 0}, high[2] = {0, 0};
  /* Cannot fail: the binning checked the same support. */
  gm_cpdi_corners_2d(&domain->shape_grid, point->position[0],
                     point->position[1], d[0], d[1], d[2], d[3],
                     point->half_size[0], point->half_size[1], corners, cells,
                     low, high);
  for (int k = 0; k < 2; k++) {
    work->support_low[k][p] = (int32_t)low[k]; /* range: domain_granular.h */
    work->support_high[k][p] = (int32_t)high[k];
  }
  gm_interaction_domain_from_corners(2, point->position, corners, measure,
                                     &work->interaction[p]);
}

/* The support of point p along axis k at grid coordinate s (cells from the
 * origin) with box half edge `half` (m, GIMP only): the lowest node and,
 * where the span varies, the highest, as the 2D and 3D kernels take them
 * (the point's cell for linear MPM, the B-spline's lowest node,
 * gm_gimp_axis_bounds of the box). */
static void store_axis_support(gm_granular_work *work,
                               const gm_shape_grid *grid, size_t p, int k,
                               double s, double half) {
  int span = 2;
  int64_t low;
  if (grid->shape == GM_SHAPE_LINEAR) {
    low = (int64_t)s; /* s >= 0 inside the grid */
  } else if (grid->shape == GM_SHAPE_BSPLINE2) {
    low = gm_bspline2_lowest(s);
    span = 3;
  } else if (grid->shape == GM_SHAPE_BSPLINE3) {
    low = gm_bspline3_lowest(s);
    span = 4;
  } else {
    low = gm_gimp_axis_bounds(s, half * grid->inv_cell, &span);
  }
  work->support_low[k][p] = (int32_t)low; /* range: domain_granular.h */
  if (work->support_high[k]) /* else span - 1 is work->support_reach */
    work->support_high[k][p] = (int32_t)(low + span - 1);
}

/* The same for the rectangle variants, directly: the support as in
 * gm_support_bounds, the box half edges scaled to `measure`. */
static void rectangle_geometry(gm_domain *domain, size_t p,
                               const gm_point_domain *point, double measure) {
  gm_granular_work *work = &domain->granular;
  const gm_shape_grid *grid = &domain->shape_grid;
  int dim = domain->dim;
  double half[2] = {0.0, 0.0}; /* m, current half edges */
  for (int k = 0; k < dim; k++) {
    half[k] = point->half_size[k];
    if (grid->shape == GM_SHAPE_CPGIMP)
      half[k] *= fabs(point->deformation[3 * k]);
    store_axis_support(work, grid, p, k,
                       (point->position[k] - grid->origin[k]) * grid->inv_cell,
                       half[k]);
  }
  /* Constant: linear MPM, uGIMP and the B-splines (whose domain is the
   * initial rectangle, as uGIMP's). */
  if (work->boxes_valid)
    return;
  double scale = 1.0;
  double current = dim == 1 ? 2.0 * half[0] : 4.0 * half[0] * half[1];
  if (measure > 0.0 && current > 0.0) /* concentric and proportional */
    scale = dim == 1 ? measure / current : sqrt(measure / current);
  for (int k = 0; k < 2; k++)
    work->box_half[k][p] = half[k] * scale;
}

/* The same in 3D (linear MPM, uGIMP, cpGIMP, the B-splines; CPDI:
 * cpdi_geometry_3d): per axis the support of the 3D kernels (support_3d.c: the
 * point's cell, gm_gimp_axis_bounds of the box, the B-spline's lowest
 * node), and the box half edges scaled alike along the three axes so the
 * box's volume is `measure` (000 Fig. 4a, concentric and proportional). */
static void box_geometry_3d(gm_domain *domain, size_t p, const double x[3],
                            const double half[3], double measure) {
  gm_granular_work *work = &domain->granular;
  const gm_shape_grid *grid = &domain->shape_grid;
  for (int k = 0; k < 3; k++) {
    store_axis_support(work, grid, p, k,
                       (x[k] - grid->origin[k]) * grid->inv_cell, half[k]);
  }
  if (work->boxes_valid) /* constant but for cpGIMP, as in 2D */
    return;
  double scale = 1.0;
  double current = 8.0 * half[0] * half[1] * half[2]; /* m^3 */
  if (measure > 0.0 && current > 0.0)
    scale = cbrt(measure / current);
  for (int k = 0; k < 3; k++)
    work->box_half[k][p] = half[k] * scale;
}

/* The same for CPDI in 3D: the node box of the parallelepiped's corners
 * (support_cpdi_3d.h, as the kernels take it) and the parallelepiped
 * itself, centre x and half edges r_k = half_k (column k of F), scaled
 * about its centre to the volume `measure` (000 Fig. 4a: concentric and
 * proportional), tested against others by the 15 separating axes
 * (interaction.h). */
static void cpdi_geometry_3d(gm_domain *domain, size_t p, const double x[3],
                             const double half[3], double measure) {
  gm_granular_work *work = &domain->granular;
  const gm_point_buffers *current = &domain->points.buffer[domain->points.cur];
  double f[9]; /* the domain map D row-major (cpdi_reset.c) */
  gm_deformation_rows_3d(gm_support_slots_3d(domain, current), p, f);
  int64_t low[3] = {0, 0, 0}, high[3] = {0, 0, 0};
  /* Cannot fail: the binning checked the same support. */
  gm_cpdi_support_bounds_3d(&domain->shape_grid, x, f, half, low, high);
  gm_interaction_domain3 *d = &work->interaction3[p];
  for (int k = 0; k < 3; k++) {
    work->support_low[k][p] = (int32_t)low[k]; /* range: domain_granular.h */
    work->support_high[k][p] = (int32_t)high[k];
    d->centre[k] = x[k];
    for (int i = 0; i < 3; i++)
      d->half_edge[k][i] = f[3 * i + k] * half[k];
  }
  gm_interaction_scale3(d, measure);
}

/* Support box and domain of interaction of every point in 3D (committed
 * state): the domain is the point's box (the initial one, stretched by
 * |F_kk| for cpGIMP: gm_box_half_edges_3d) scaled to the volume
 * l_x l_y l_z V_cr / V0 (000 sec 3.3, Table A2, with the volume in place
 * of the area). */
static void point_geometry_3d(void *context, size_t begin, size_t end,
                              int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  const gm_point_buffers *current = &points->buffer[points->cur];
  const double *const *size = (const double *const *)points->domain_size;
  for (size_t p = begin; p < end; p++) {
    double x[3] = {current->position[0][p], current->position[1][p],
                   current->position[2][p]}; /* m */
    double half[3];                          /* m */
    gm_box_half_edges_3d(domain->shape_grid.shape, size,
                         gm_support_slots_3d(domain, current), p, half);
    const gm_material *material = &domain->materials[points->material[p]];
    double measure = 0.0; /* non-granular: its own domain */
    if (material->granular && !work->boxes_valid)
      measure = size[0][p] * size[1][p] * size[2][p] * points->mass[p] /
                points->initial_volume[p] / material->critical_density;
    work->granular[p] = material->granular;
    if (domain->shape_grid.shape == GM_SHAPE_CPDI)
      cpdi_geometry_3d(domain, p, x, half, measure);
    else
      box_geometry_3d(domain, p, x, half, measure);
  }
}

/* Support box and domain of interaction of every point (committed state). */
static void point_geometry(void *context, size_t begin, size_t end,
                           int worker) {
  (void)worker;
  gm_domain *domain = context;
  if (domain->dim == 3) {
    point_geometry_3d(context, begin, end, worker);
    return;
  }
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  const gm_point_buffers *current = &points->buffer[points->cur];
  int dim = domain->dim;
  const double *const position[2] = {current->position[0],
                                     current->position[dim > 1 ? 1 : 0]};
  const double *deformation[4];
  gm_support_tensor(domain, current, deformation);
  const double *const size[2] = {points->domain_size[0],
                                 points->domain_size[dim > 1 ? 1 : 0]};
  bool parallelograms = domain->shape_grid.shape == GM_SHAPE_CPDI;
  for (size_t p = begin; p < end; p++) {
    gm_point_domain point;
    gm_load_point_domain(dim, position, deformation, size, p, &point);
    const gm_material *material = &domain->materials[points->material[p]];
    double measure = 0.0; /* non-granular: its own domain */
    if (material->granular && !work->boxes_valid) {
      /* The initial domain's area (length in 1D) scaled to V_cr:
       * A0 V_cr / V0 = A0 (m / V0) / rho_cr (000 sec 3.3, Table A2). */
      double initial = size[0][p] * (dim > 1 ? size[1][p] : 1.0);
      measure = initial * points->mass[p] / points->initial_volume[p] /
                material->critical_density;
    }
    work->granular[p] = material->granular;
    if (parallelograms && dim == 2)
      cpdi_geometry_2d(domain, p, &point, measure);
    else if (parallelograms)
      general_geometry(domain, p, &point, measure);
    else
      rectangle_geometry(domain, p, &point, measure);
  }
}

/* The geometry of linear MPM once the interaction boxes are cached: only
 * the supports move, the cell of the point and the next node per axis.
 * The granular flags stay those of the step that cached the boxes: they
 * change only with the points' materials or a material's granular flag,
 * and whatever changes either (adding, removing or reordering points,
 * gm_domain_set_granular, loading a checkpoint) clears boxes_valid. */
static void linear_supports(void *context, size_t begin, size_t end,
                            int worker) {
  (void)worker;
  gm_domain *domain = context;
  const gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  const gm_shape_grid *grid = &domain->shape_grid;
  for (int k = 0; k < domain->dim; k++) {
    const double *position = points->buffer[points->cur].position[k];
    /* The highest: low + 1 (domain_granular.h). */
    int32_t *low = work->support_low[k];
    double origin = grid->origin[k], inv_cell = grid->inv_cell; /* m, 1/m */
    for (size_t p = begin; p < end; p++)
      low[p] = (int32_t)((position[p] - origin) * inv_cell); /* >= 0 */
  }
}

void gm_granular_remap_forest(gm_domain *domain, uint32_t *scratch) {
  gm_granular_work *work = &domain->granular;
  work->sets_count = 0; /* renamed points, and parent counts below */
  if (!work->forest_valid)
    return;
  const gm_points *points = &domain->points;
  size_t count = points->count;
  for (size_t k = 0; k < count; k++) /* old index -> new index */
    scratch[points->order[k]] = (uint32_t)k;
  for (size_t e = 0; e < work->forest_count; e++) {
    uint32_t p = scratch[work->forest[e] >> 32];
    uint32_t q = scratch[work->forest[e] & 0xffffffffu];
    work->forest[e] = (uint64_t)p << 32 | q;
  }
  /* The renamed edges, counting-sorted by their first end so that the
   * next steps' checks walk the point arrays in order (the reordering put
   * neighbours next to each other). Scratch of the granular phase is free
   * here: the union-find's parent array counts, the layers' CSR offsets
   * (8 bytes per point) hold the sorted edges; both are sized at the last
   * granular step, so points added since skip the sort (it only saves
   * time). */
  if (work->capacity < count)
    return;
  uint32_t *start = work->parent;
  uint64_t *sorted = (uint64_t *)(void *)work->adjacency_start; /* < count */
  memset(start, 0, count * sizeof(uint32_t));
  for (size_t e = 0; e < work->forest_count; e++)
    start[work->forest[e] >> 32]++;
  uint32_t offset = 0;
  for (size_t p = 0; p < count; p++) {
    uint32_t edges = start[p];
    start[p] = offset;
    offset += edges;
  }
  for (size_t e = 0; e < work->forest_count; e++)
    sorted[start[work->forest[e] >> 32]++] = work->forest[e];
  memcpy(work->forest, sorted, work->forest_count * sizeof(uint64_t));
}

/* The widest support of the step, in nodes per axis (2 for linear MPM,
 * whose support is always the cell's nodes). */
static void widest_support(const gm_domain *domain, int max_span[3]) {
  const gm_granular_work *work = &domain->granular;
  max_span[0] = max_span[1] = max_span[2] =
      domain->shape_grid.shape == GM_SHAPE_LINEAR ? 2 : 1;
  if (max_span[0] == 2)
    return;
  for (size_t p = 0; p < domain->points.count; p++)
    for (int k = 0; k < domain->dim; k++) {
      int span =
          (int)(gm_support_high(work, k, p) - work->support_low[k][p] + 1);
      max_span[k] = span > max_span[k] ? span : max_span[k];
    }
}

/* Forest edges per task of the parallel check below. */
#define FOREST_CHUNK 4096

/* Do p and q, the ends of a kept forest edge, still interact? */
static bool edge_holds(const gm_domain *domain, uint64_t edge) {
  uint32_t p = (uint32_t)(edge >> 32), q = (uint32_t)(edge & 0xffffffffu);
  return gm_supports_share_node(&domain->granular, domain->dim, p, q) &&
         gm_pair_interacts(domain, p, q);
}

/* Does every overlap of two interaction boxes imply a shared node
 * (work->overlap_shares_node)? Linear MPM, every point granular (so no
 * pair holds without overlapping), and every box half edge below 0.45
 * cell: overlapping boxes are less than 0.9 cell apart per axis, and the
 * cells (x - origin) / cell, each rounded a few ulps of the grid's
 * extent (at most 1e9 cells, domain.c), then differ by less than one:
 * their truncations, the points' cells, by at most one, the support's
 * reach. O(N), once per computation of the boxes. */
static bool overlap_shares_node(const gm_domain *domain) {
  const gm_granular_work *work = &domain->granular;
  if (domain->dim != 2 || domain->shape_grid.shape != GM_SHAPE_LINEAR)
    return false;
  double limit = 0.45 / domain->shape_grid.inv_cell; /* m */
  bool fits = true;
  for (size_t p = 0; p < domain->points.count; p++)
    fits &= (work->granular[p] != 0) & (work->box_half[0][p] < limit) &
            (work->box_half[1][p] < limit);
  return fits;
}

/* Do the edges [first, last) of the kept forest all hold? edge_holds for
 * the plane rectangle variants with a fixed support span (linear MPM, the
 * B-splines): the same two tests (pair_rules.h) with the arrays in locals
 * and every term evaluated, so that the loop has no branch per edge but
 * the loop's own (a connected body breaks no edge: an early exit would
 * save nothing). Both ends' indices are below the point count, so every
 * load is valid. */
static bool box_edges_hold_2d(const gm_granular_work *work, size_t first,
                              size_t last) {
  const int32_t *low_x = work->support_low[0], *low_y = work->support_low[1];
  const double *centre_x = work->box_centre[0]; /* m */
  const double *centre_y = work->box_centre[1]; /* m */
  const double *half_x = work->box_half[0], *half_y = work->box_half[1];
  const uint8_t *granular = work->granular;
  const uint64_t *forest = work->forest;
  int32_t reach = work->support_reach;
  bool hold = true;
  if (work->overlap_shares_node) { /* overlap alone decides: see above */
    for (size_t e = first; e < last; e++) {
      uint32_t p = (uint32_t)(forest[e] >> 32);
      uint32_t q = (uint32_t)(forest[e] & 0xffffffffu);
      hold &= (fabs(centre_x[q] - centre_x[p]) < half_x[p] + half_x[q]) &
              (fabs(centre_y[q] - centre_y[p]) < half_y[p] + half_y[q]);
    }
    return hold;
  }
  for (size_t e = first; e < last; e++) {
    uint32_t p = (uint32_t)(forest[e] >> 32);
    uint32_t q = (uint32_t)(forest[e] & 0xffffffffu);
    int32_t apart_x = low_x[p] - low_x[q], apart_y = low_y[p] - low_y[q];
    bool share = (apart_x <= reach) & (-apart_x <= reach) & (apart_y <= reach) &
                 (-apart_y <= reach);
    bool neither = !granular[p] & !granular[q];
    bool overlap = (fabs(centre_x[q] - centre_x[p]) < half_x[p] + half_x[q]) &
                   (fabs(centre_y[q] - centre_y[p]) < half_y[p] + half_y[q]);
    hold &= share & (neither | overlap);
  }
  return hold;
}

/* Flags (in work->visit, one per chunk of FOREST_CHUNK edges) the chunks
 * holding an edge that no longer holds. */
static void check_forest_chunks(void *context, size_t begin, size_t end,
                                int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_granular_work *work = &domain->granular;
  bool boxes = domain->dim == 2 && work->box_half[0] && !work->support_high[0];
  for (size_t c = begin; c < end; c++) {
    size_t first = c * FOREST_CHUNK, last = first + FOREST_CHUNK;
    last = last < work->forest_count ? last : work->forest_count;
    uint8_t broken = 0;
    if (boxes)
      broken = !box_edges_hold_2d(work, first, last);
    for (size_t e = first; e < last && !broken && !boxes; e++)
      broken = !edge_holds(domain, work->forest[e]);
    work->visit[c] = broken;
  }
}

/* Checks the kept forest's edges, in parallel (they are independent);
 * true if it is valid and every edge holds. The chunk flags stay in
 * work->visit for rejoin_forest. */
static bool check_forest(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  if (!work->forest_valid)
    return false;
  size_t chunks = (work->forest_count + FOREST_CHUNK - 1) / FOREST_CHUNK;
  gm_parallel_for(&domain->pool, chunks, check_forest_chunks, domain);
  bool all_hold = true;
  for (size_t c = 0; c < chunks; c++)
    all_hold = all_hold && !work->visit[c];
  return all_hold;
}

/* Re-joins the kept forest's edges that still hold (checked again only in
 * the chunks check_forest flagged) and drops the others: each set is then
 * connected by interacting pairs, a part of one component. */
static void rejoin_forest(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  size_t kept = 0;
  for (size_t e = 0; e < work->forest_count; e++) {
    if (work->visit[e / FOREST_CHUNK] && !edge_holds(domain, work->forest[e]))
      continue;
    uint32_t p = (uint32_t)(work->forest[e] >> 32);
    uint32_t q = (uint32_t)(work->forest[e] & 0xffffffffu);
    gm_union_find_join(work->parent, work->set_size, p, q);
    work->forest[kept++] = work->forest[e];
  }
  work->forest_count = kept;
}

/* Marks the points outside the largest set (lowest root index on ties);
 * returns how many there are. */
static size_t mark_outside_largest(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  size_t count = domain->points.count;
  uint32_t largest = gm_union_find_root(work->parent, 0);
  for (size_t p = 0; p < count; p++)
    if (work->parent[p] == p && work->set_size[p] > work->set_size[largest])
      largest = (uint32_t)p; /* roots hold their set's size */
  size_t outside = 0;
  for (size_t p = 0; p < count; p++) {
    work->visit[p] = gm_union_find_root(work->parent, (uint32_t)p) != largest;
    outside += work->visit[p];
  }
  return outside;
}

/* Task 1 and the union-find: the sets of interacting points, and the
 * forest that produced them. forest_holds: check_forest found every kept
 * edge holding. */
static gm_status join_interacting(gm_domain *domain, const int max_span[3],
                                  bool forest_holds) {
  gm_granular_work *work = &domain->granular;
  size_t count = domain->points.count;
  work->conflict_count = 0; /* the candidates of this search */
  work->summary.forest_reused = 0;
  gm_status status;
  if (work->forest_valid) {
    /* Every join of a search adds its edge to the forest, so the sets the
     * last search left are the forest's: where every edge holds, rejoining
     * them would give the same sets (with other roots, which decide only
     * between sets of equal size below, and the results do not depend on
     * which set is left out: pair_search.c). */
    if (!forest_holds || work->sets_count != count) {
      gm_union_find_init(work->parent, work->set_size, count);
      rejoin_forest(domain);
      work->labels_kept = false;
    }
    /* A point searching for the kept sets takes full windows, twice the
     * half windows of the full search: past half the points, start over. */
    if (mark_outside_largest(domain) <= count / 2) {
      work->summary.forest_reused = 1;
      size_t edges = work->forest_count; /* a join adds an edge */
      status = gm_pair_search(domain, max_span, GM_PASS_JOIN, work->visit);
      work->sets_count = status == GM_OK ? count : 0;
      work->labels_kept = work->labels_kept && work->forest_count == edges;
      return status;
    }
  }
  work->labels_kept = false;
  gm_union_find_init(work->parent, work->set_size, count);
  work->forest_count = 0;
  status = gm_pair_search(domain, max_span, GM_PASS_JOIN, NULL);
  work->sets_count = status == GM_OK ? count : 0;
  return status;
}

/* Turns the candidates of a subset search (point pairs sharing a node that
 * did not interact) into the pairs of different components, by label.
 * Every pair of components sharing a node is among them: the search met it
 * from one end (with full windows from every point outside the largest
 * kept set, a pair of two components has an end outside that set, and a
 * pair with both ends outside is met from the first in raster order:
 * pair_search.c), and it was not joined. */
static void keep_conflicts(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  size_t kept = 0;
  for (size_t i = 0; i < work->conflict_count; i++) {
    int32_t a = work->label[work->conflict[i] >> 32];
    int32_t b = work->label[work->conflict[i] & 0xffffffffu];
    if (a == b)
      continue;
    uint32_t low = (uint32_t)(a < b ? a : b), high = (uint32_t)(a < b ? b : a);
    work->conflict[kept++] = (uint64_t)low << 32 | high;
  }
  work->conflict_count = kept;
}

/* Labels by smallest id: through the id map when it is not much longer
 * than the point list (no sort), else by sorting the roots (after sinks
 * removed many points, the map is mostly holes). */
static size_t label_components(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  const gm_points *points = &domain->points;
  size_t count = points->count, id_count = (size_t)points->next_id;
  if (id_count <= 4 * count)
    return gm_union_find_labels_by_id(work->parent, points->index_of_id,
                                      id_count, GM_REMOVED_POINT, count,
                                      work->label, work->component_layer);
  return gm_union_find_labels(work->parent, points->id, count, work->label,
                              (uint32_t *)work->component_layer,
                              (uint32_t *)work->layer_stamp);
}

gm_status gm_granular_prepare(gm_domain *domain) {
  gm_status status = gm_granular_reserve(domain);
  if (status != GM_OK)
    return status;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  size_t count = points->count;
  /* The labels are written straight into the step's next buffer, where
   * they are committed with it (GM_FIELD_COMPONENT). */
  work->label = points->buffer[points->cur ^ 1].component;
  double start = gm_monotonic_seconds();
  const gm_point_buffers *current = &points->buffer[points->cur];
  for (int k = 0; k < 3; k++) /* box centres are the points' positions */
    work->box_centre[k] = current->position[k < domain->dim ? k : 0];
  gm_shape shape = domain->shape_grid.shape;
  bool boxes_cached = shape == GM_SHAPE_LINEAR && work->boxes_valid;
  /* Where an overlap decides a kept edge alone, the forest's check reads
   * no support: they are computed only if a search follows. */
  bool supports_deferred = boxes_cached && work->overlap_shares_node;
  if (!supports_deferred)
    gm_parallel_for(&domain->pool, count,
                    boxes_cached ? linear_supports : point_geometry, domain);
  if (!boxes_cached)
    work->overlap_shares_node = overlap_shares_node(domain);
  work->boxes_valid = shape == GM_SHAPE_LINEAR || shape == GM_SHAPE_UGIMP ||
                      gm_shape_is_bspline(shape);
  work->cells_sorted = false; /* sorted on the first search (pair_search.c) */
  int max_span[3];
  widest_support(domain, max_span);
  double geometry_done = gm_monotonic_seconds();
  size_t components = 1;
  double search_done = 0.0, labels_done = 0.0; /* s */
  /* A kept spanning tree of all points whose edges all hold: one
   * component, whatever other pairs interact, and neither union-find nor
   * a search is needed (a connected flow, the common case). */
  bool forest_holds = check_forest(domain);
  bool one_component = forest_holds && work->forest_count + 1 == count;
  if (one_component) {
    work->summary.forest_reused = 1;
  } else {
    if (supports_deferred) /* the search and rejoin_forest read them */
      gm_parallel_for(&domain->pool, count, linear_supports, domain);
    status = join_interacting(domain, max_span, forest_holds);
    work->forest_valid = status == GM_OK;
    if (status != GM_OK)
      return status;
    one_component =
        count > 0 &&
        work->set_size[gm_union_find_root(work->parent, 0)] == count;
  }
  search_done = gm_monotonic_seconds();
  if (one_component) {
    memset(work->label, 0, count * sizeof(int32_t));
    work->component_size[0] = (uint32_t)count;
  } else {
    /* Sets unchanged since they were labelled: the same labels (by
     * smallest id, of the same points). */
    const int32_t *kept = work->labels_kept
                              ? points->buffer[work->labels_buffer].component
                              : NULL;
    if (kept) { /* component_size was counted from them too */
      components = work->labels_components;
      if (kept != work->label)
        memcpy(work->label, kept, count * sizeof(int32_t));
    } else {
      components = label_components(domain);
      memset(work->component_size, 0, components * sizeof(uint32_t));
      for (size_t p = 0; p < count; p++)
        work->component_size[work->label[p]]++;
    }
  }
  work->labels_kept = true;
  work->labels_buffer = points->cur ^ 1;
  work->labels_components = components;
  labels_done = gm_monotonic_seconds();
  size_t layers = 1;
  memset(work->component_layer, 0, components * sizeof(int32_t));
  if (components > 1) {
    /* A subset search collected the candidates as it went; after a full
     * one (rare: the first step, or too many broken pairs) a second pass
     * finds the conflicts, which spares recording every non-interacting
     * pair of the early, fragmented union-find (~15 per point). */
    if (work->summary.forest_reused) {
      keep_conflicts(domain);
    } else {
      work->conflict_count = 0;
      status = gm_pair_search(domain, max_span, GM_PASS_CONFLICTS, NULL);
    }
    if (status == GM_OK)
      status = gm_assign_layers(domain, components, &layers);
    if (status != GM_OK)
      return status;
  }
  if (layers > 1) {
    int64_t stride = gm_grid_layer_stride(&domain->grid);
    for (size_t p = 0; p < count; p++)
      points->block_key[p] +=
          (int64_t)work->component_layer[work->label[p]] * stride;
    points->keys_valid = true; /* the step bins them again (step.c) */
  }
  double end = gm_monotonic_seconds();
  work->summary.component_count = components;
  work->summary.layer_count = layers;
  work->summary.geometry_seconds = geometry_done - start;
  work->summary.pair_search_seconds = search_done - geometry_done;
  work->summary.label_seconds = labels_done - search_done;
  work->summary.layer_seconds = end - labels_done;
  return status;
}
