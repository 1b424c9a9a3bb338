/*
 * fill_box.c - gm_domain_fill_box: points on a regular lattice, n per cell
 * edge, each at the centre of its sub-cell (the usual MPM initial
 * discretisation, e.g. 4 points per cell in 2D for n = 2, 8 in 3D).
 */
#include "points/points.h"

#include <limits.h>
#include <math.h>

/* Sub-cell index range [first, last) whose centres lie in [lower, upper). */
static void lattice_range(double lower, double upper, double origin,
                          double spacing, int64_t *first, int64_t *last) {
  *first = (int64_t)ceil((lower - origin) / spacing - 0.5);
  *last = (int64_t)ceil((upper - origin) / spacing - 0.5);
  if (*last < *first)
    *last = *first;
}

static gm_status validate_fill(gm_domain *domain, const gm_fill_def *def) {
  if (def->points_per_cell_axis < 1 || def->points_per_cell_axis > 16)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_fill_def.points_per_cell_axis is %d, must be in "
                        "1..16",
                        def->points_per_cell_axis);
  if (def->material < 0 || def->material >= domain->material_count)
    return gm_set_error(domain, GM_ERR_UNKNOWN_MATERIAL,
                        "gm_fill_def.material %d is unknown (%d materials "
                        "registered)",
                        def->material, domain->material_count);
  if (def->density < 0.0 || !isfinite(def->density))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_fill_def.density is %g kg/m^3, must be finite "
                        "and >= 0 (0 = material density)",
                        def->density);
  for (int k = 0; k < domain->dim; k++) {
    if (!isfinite(def->lower[k]) || !isfinite(def->upper[k]) ||
        !(def->upper[k] > def->lower[k]))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_fill_def: lower[%d] = %g and upper[%d] = %g "
                          "must be finite with upper > lower",
                          k, def->lower[k], k, def->upper[k]);
    if (!isfinite(def->velocity[k]))
      return gm_set_error(domain, GM_ERR_NOT_FINITE,
                          "gm_fill_def.velocity[%d] is not finite", k);
    /* A box reaching a whole grid box beyond the grid would place points
     * outside it, which the add refuses anyway; refusing it here keeps
     * its lattice indices (sub-cells from the origin) in range of int64
     * (found by fuzz/fuzz_api: a corner at 1e252 m). */
    double origin = domain->def.origin[k], extent = domain->def.extent[k];
    if (def->lower[k] < origin - extent || def->upper[k] > origin + 2 * extent)
      return gm_set_error(domain, GM_ERR_OUT_OF_GRID,
                          "gm_fill_def: lower[%d] = %g and upper[%d] = %g m "
                          "reach far outside the grid box (%g to %g m)",
                          k, def->lower[k], k, def->upper[k], origin,
                          origin + extent);
  }
  return GM_OK;
}

/* The lattice of a fill: sub-cell index ranges per axis. */
typedef struct lattice {
  int64_t first[3], last[3];
  double spacing; /* m */
  size_t total;
} lattice;

/* Site n of the lattice (row-major, x fastest, then y, then z) as a
 * point. */
static void lattice_site(const gm_domain *domain, const lattice *grid, size_t n,
                         double *position, double *edges, double *volume) {
  int64_t width = grid->last[0] - grid->first[0];
  int64_t depth = grid->last[1] - grid->first[1]; /* sites along y */
  /* Below 3D the y range is the whole rest of n (z has one site). */
  int64_t row = (int64_t)n / width;
  int64_t site[3] = {grid->first[0] + (int64_t)n % width,
                     grid->first[1] + (domain->dim == 3 ? row % depth : row),
                     grid->first[2] + (domain->dim == 3 ? row / depth : 0)};
  double measure = 1.0; /* length, area, or ring volume */
  for (int k = 0; k < domain->dim; k++) {
    position[k] =
        domain->def.origin[k] + ((double)site[k] + 0.5) * grid->spacing;
    edges[k] = grid->spacing;
    measure *= grid->spacing;
  }
  if (domain->axisymmetric)
    measure *= 2.0 * GM_PI * position[0]; /* full ring */
  *volume = measure;
}

/* Points are added in slabs so the temporary arrays stay small. */
enum { FILL_SLAB = 4096 };

typedef struct fill_arrays {
  double position[FILL_SLAB * 3];
  double velocity[FILL_SLAB * 3];
  double edges[FILL_SLAB * 3];
  double volume[FILL_SLAB];
  double density[FILL_SLAB];
} fill_arrays;

/* Adds sites [begin, end) of the lattice as one gm_domain_add_points. */
static gm_status add_slab(gm_domain *domain, const gm_fill_def *def,
                          const lattice *grid, size_t begin, size_t end,
                          double density, fill_arrays *arrays,
                          int64_t *first_id) {
  int dim = domain->dim;
  for (size_t n = begin; n < end; n++) {
    size_t j = n - begin;
    lattice_site(domain, grid, n, arrays->position + j * dim,
                 arrays->edges + j * dim, &arrays->volume[j]);
    for (int k = 0; k < dim; k++)
      arrays->velocity[j * dim + k] = def->velocity[k];
    arrays->density[j] = density;
  }
  gm_points_def points = gm_points_def_default();
  points.count = end - begin;
  points.material = def->material;
  points.position = arrays->position;
  points.velocity = arrays->velocity;
  points.volume = arrays->volume;
  points.density = arrays->density;
  points.domain_size = arrays->edges;
  return gm_domain_add_points(domain, &points, first_id);
}

/* All-or-nothing: the corner sites decide whether every site is valid. */
static gm_status check_corners(gm_domain *domain, const lattice *grid) {
  double position[3], edges[3], volume;
  size_t corners[2] = {0, grid->total - 1};
  for (int c = 0; c < 2; c++) {
    lattice_site(domain, grid, corners[c], position, edges, &volume);
    int64_t key;
    if (!gm_block_key_of(domain, position, &key))
      return gm_set_error(domain, GM_ERR_OUT_OF_GRID,
                          "gm_domain_fill_box: the box reaches outside the "
                          "grid (lattice site at x = %g, y = %g, z = %g m)",
                          position[0], domain->dim > 1 ? position[1] : 0.0,
                          domain->dim > 2 ? position[2] : 0.0);
    if (domain->axisymmetric && !(position[0] > 0.0))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_fill_box: lattice site at radius %g "
                          "must be > 0 in axisymmetry",
                          position[0]);
  }
  return GM_OK;
}

gm_status gm_domain_fill_box(gm_domain *domain, const gm_fill_def *def,
                             int64_t *first_id, size_t *count) {
  gm_fill_def full;
  gm_status status = gm_api_take_def(
      domain, "gm_domain_fill_box", GM_LAYOUT_FILL_DEF, def, &full, NULL, NULL);
  if (status != GM_OK)
    return status;
  def = &full;
  status = validate_fill(domain, def);
  if (status != GM_OK)
    return status;
  double density = def->density > 0.0
                       ? def->density
                       : domain->materials[def->material].density; /* kg/m^3 */
  if ((status = gm_check_placement_density(
           domain, def->material, density,
           "gm_domain_fill_box: the fill (gm_fill_def.density, 0 = "
           "the material's)")) != GM_OK)
    return status;
  lattice grid = {{0, 0, 0}, {1, 1, 1}, 0.0, 1};
  grid.spacing = domain->def.cell_size / def->points_per_cell_axis;
  for (int k = 0; k < domain->dim; k++) {
    lattice_range(def->lower[k], def->upper[k], domain->def.origin[k],
                  grid.spacing, &grid.first[k], &grid.last[k]);
    size_t sites = (size_t)(grid.last[k] - grid.first[k]);
    if (sites > (size_t)INT_MAX ||
        grid.total > (size_t)INT_MAX / (sites ? sites : 1))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_fill_box: the box holds more than %d "
                          "lattice sites",
                          INT_MAX);
    grid.total *= sites;
  }
  if (grid.total == 0)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_fill_box: the box holds no lattice site "
                        "(smaller than cell_size / points_per_cell_axis?)");
  if ((status = check_corners(domain, &grid)) != GM_OK)
    return status;
  gm_points *points = &domain->points;
  fill_arrays *arrays = gm_alloc(sizeof *arrays);
  /* The id map too is sized for the whole fill at once: growing it slab
   * by slab left it 1.4x too large (1.6 bytes per point). */
  if (!arrays ||
      gm_points_reserve(domain, points->count + grid.total) != GM_OK ||
      !gm_points_reserve_ids(points, grid.total)) {
    gm_free(arrays);
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "gm_domain_fill_box: out of memory for %zu points",
                        grid.total);
  }
  size_t count_before = points->count;
  int64_t id_before = points->next_id;
  for (size_t begin = 0; begin < grid.total && status == GM_OK;
       begin += FILL_SLAB) {
    size_t end =
        begin + FILL_SLAB < grid.total ? begin + FILL_SLAB : grid.total;
    status = add_slab(domain, def, &grid, begin, end, density, arrays, NULL);
  }
  gm_free(arrays);
  if (status != GM_OK) { /* out of memory for the id map: stay atomic */
    gm_points_truncate(domain, count_before, id_before);
    return status;
  }
  if (first_id)
    *first_id = id_before;
  if (count)
    *count = grid.total;
  return GM_OK;
}
