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
 *     are re-keyed into their layer's blocks (grid.h) and binned again.
 *     With one component, or none sharing nodes, nothing is re-binned.
 *
 * Most steps change few connections. The spanning forest of the last
 * search is kept: if all its edges still interact, the components can only
 * have merged, and every new edge between two of them has an end outside
 * the largest one, so only those points search (with full windows). A
 * broken edge, or points reordered, added or removed, means a full search.
 */
#include "internal.h"
#include "shape_gimp.h"

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
    work->support_low[k][p] = low[k];
    work->support_high[k][p] = high[k];
  }
  gm_interaction_domain *interaction = &work->interaction[p];
  gm_interaction_domain_of(domain->shape_grid.shape, domain->dim, point,
                           measure, interaction);
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
    double s = (point->position[k] - grid->origin[k]) * grid->inv_cell;
    int span = 2;
    int64_t low = grid->shape == GM_SHAPE_LINEAR
                      ? (int64_t)s /* s >= 0 inside the grid */
                      : gm_gimp_axis_bounds(s, half[k] * grid->inv_cell, &span);
    work->support_low[k][p] = low;
    work->support_high[k][p] = low + span - 1;
  }
  if (work->boxes_valid) /* constant: linear MPM and uGIMP */
    return;
  double scale = 1.0;
  double current = dim == 1 ? 2.0 * half[0] : 4.0 * half[0] * half[1];
  if (measure > 0.0 && current > 0.0) /* concentric and proportional */
    scale = dim == 1 ? measure / current : sqrt(measure / current);
  for (int k = 0; k < 2; k++)
    work->box_half[k][p] = half[k] * scale;
}

/* Support box and domain of interaction of every point (committed state). */
static void point_geometry(void *context, size_t begin, size_t end,
                           int worker) {
  (void)worker;
  gm_domain *domain = context;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  const gm_point_buffers *current = &points->buffer[points->cur];
  int dim = domain->dim;
  const double *const position[2] = {current->position[0],
                                     current->position[dim > 1 ? 1 : 0]};
  const double *const deformation[4] = {
      current->deformation[F_XX], current->deformation[F_XY],
      current->deformation[F_YX], current->deformation[F_YY]};
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
    if (parallelograms)
      general_geometry(domain, p, &point, measure);
    else
      rectangle_geometry(domain, p, &point, measure);
  }
}

void gm_granular_remap_forest(gm_domain *domain, uint32_t *scratch) {
  gm_granular_work *work = &domain->granular;
  if (!work->forest_valid)
    return;
  const gm_points *points = &domain->points;
  for (size_t k = 0; k < points->count; k++) /* old index -> new index */
    scratch[points->order[k]] = (uint32_t)k;
  for (size_t e = 0; e < work->forest_count; e++) {
    uint32_t p = scratch[work->forest[e] >> 32];
    uint32_t q = scratch[work->forest[e] & 0xffffffffu];
    work->forest[e] = (uint64_t)p << 32 | q;
  }
}

/* The widest support of the step, in nodes per axis. */
static void widest_support(const gm_domain *domain, int max_span[2]) {
  const gm_granular_work *work = &domain->granular;
  max_span[0] = max_span[1] = 1;
  for (size_t p = 0; p < domain->points.count; p++)
    for (int k = 0; k < domain->dim; k++) {
      int span = (int)(work->support_high[k][p] - work->support_low[k][p] + 1);
      max_span[k] = span > max_span[k] ? span : max_span[k];
    }
}

/* Re-joins the previous forest's edges; false if one no longer holds (the
 * sets are then partial: the caller starts again). */
static bool rejoin_forest(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  for (size_t e = 0; e < work->forest_count; e++) {
    uint32_t p = (uint32_t)(work->forest[e] >> 32);
    uint32_t q = (uint32_t)(work->forest[e] & 0xffffffffu);
    if (!gm_supports_share_node(work, domain->dim, p, q) ||
        !gm_pair_interacts(domain, p, q))
      return false;
    gm_union_find_join(work->parent, work->set_size, p, q);
  }
  return true;
}

/* Marks the points outside the largest set (lowest root index on ties). */
static void mark_outside_largest(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  size_t count = domain->points.count;
  uint32_t largest = gm_union_find_root(work->parent, 0);
  for (size_t p = 0; p < count; p++)
    if (work->parent[p] == p && work->set_size[p] > work->set_size[largest])
      largest = (uint32_t)p; /* roots hold their set's size */
  for (size_t p = 0; p < count; p++)
    work->visit[p] = gm_union_find_root(work->parent, (uint32_t)p) != largest;
}

/* Task 1 and the union-find: the sets of interacting points, and the
 * forest that produced them. */
static gm_status join_interacting(gm_domain *domain, const int max_span[2]) {
  gm_granular_work *work = &domain->granular;
  size_t count = domain->points.count;
  gm_union_find_init(work->parent, work->set_size, count);
  work->summary.forest_reused = 0;
  if (work->forest_valid && rejoin_forest(domain)) {
    mark_outside_largest(domain);
    work->summary.forest_reused = 1;
    return gm_pair_search(domain, max_span, GM_PASS_JOIN, work->visit);
  }
  gm_union_find_init(work->parent, work->set_size, count);
  work->forest_count = 0;
  return gm_pair_search(domain, max_span, GM_PASS_JOIN, NULL);
}

gm_status gm_granular_prepare(gm_domain *domain) {
  gm_status status = gm_granular_reserve(domain);
  if (status != GM_OK)
    return status;
  gm_points *points = &domain->points;
  gm_granular_work *work = &domain->granular;
  size_t count = points->count;
  double start = gm_monotonic_seconds();
  const gm_point_buffers *current = &points->buffer[points->cur];
  for (int k = 0; k < 2; k++) /* box centres are the points' positions */
    work->box_centre[k] = current->position[k < domain->dim ? k : 0];
  gm_parallel_for(&domain->pool, count, point_geometry, domain);
  gm_shape shape = domain->shape_grid.shape;
  work->boxes_valid = shape == GM_SHAPE_LINEAR || shape == GM_SHAPE_UGIMP;
  work->cells_sorted = false; /* sorted on the first search (pair_search.c) */
  int max_span[2];
  widest_support(domain, max_span);
  double geometry_done = gm_monotonic_seconds();
  /* The forest is rebuilt whole, or extended from the reused one. */
  status = join_interacting(domain, max_span);
  work->forest_valid = status == GM_OK;
  if (status != GM_OK)
    return status;
  double search_done = gm_monotonic_seconds();
  size_t components = gm_union_find_labels(
      work->parent, points->id, count, work->label, work->min_id, work->roots);
  memset(work->component_size, 0, components * sizeof(uint32_t));
  for (size_t p = 0; p < count; p++)
    work->component_size[work->label[p]]++;
  double labels_done = gm_monotonic_seconds();
  size_t layers = 1;
  memset(work->component_layer, 0, components * sizeof(int32_t));
  if (components > 1) {
    work->conflict_count = 0;
    /* Every conflict has an end outside the largest component. */
    if (work->summary.forest_reused)
      mark_outside_largest(domain);
    status = gm_pair_search(domain, max_span, GM_PASS_CONFLICTS,
                            work->summary.forest_reused ? work->visit : NULL);
    if (status == GM_OK)
      status = gm_assign_layers(domain, components, &layers);
    if (status != GM_OK)
      return status;
  }
  double *label_out = points->buffer[points->cur ^ 1].component;
  for (size_t p = 0; p < count; p++)
    label_out[p] = (double)work->label[p];
  if (layers > 1) {
    int64_t stride = gm_grid_layer_stride(&domain->grid);
    for (size_t p = 0; p < count; p++)
      points->block_key[p] +=
          (int64_t)work->component_layer[work->label[p]] * stride;
    points->keys_valid = true;
    status = gm_bin_points(domain);
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
