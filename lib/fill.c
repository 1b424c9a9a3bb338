/*
 * fill.c - gm_domain_fill_box: points on a regular lattice, n per cell
 * edge, each at the centre of its sub-cell (the usual MPM initial
 * discretisation, e.g. 4 points per cell in 2D for n = 2).
 */
#include "internal.h"

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
  if (def->struct_size < sizeof(gm_fill_def))
    return gm_set_error(domain, GM_ERR_STRUCT_SIZE,
                        "gm_fill_def.struct_size is %zu, expected %zu",
                        def->struct_size, sizeof(gm_fill_def));
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
  }
  return GM_OK;
}

gm_status gm_domain_fill_box(gm_domain *domain, const gm_fill_def *def,
                             int64_t *first_id, size_t *count) {
  if (!domain)
    return GM_ERR_NULL;
  if (!def)
    return gm_set_error(domain, GM_ERR_NULL, "gm_domain_fill_box: def is NULL");
  if (domain->busy)
    return gm_set_error(domain, GM_ERR_BUSY,
                        "gm_domain_fill_box: called during a step");
  gm_status status = validate_fill(domain, def);
  if (status != GM_OK)
    return status;
  int dim = domain->dim;
  double spacing = domain->def.cell_size / def->points_per_cell_axis; /* m */
  int64_t first[2] = {0, 0}, last[2] = {1, 1};
  size_t total = 1;
  for (int k = 0; k < dim; k++) {
    lattice_range(def->lower[k], def->upper[k], domain->def.origin[k], spacing,
                  &first[k], &last[k]);
    total *= (size_t)(last[k] - first[k]);
  }
  if (total == 0)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_fill_box: the box holds no lattice site "
                        "(smaller than cell_size / points_per_cell_axis?)");
  double *position = gm_alloc(total * (size_t)dim * sizeof(double));
  double *velocity = gm_alloc(total * (size_t)dim * sizeof(double));
  double *volume = gm_alloc(total * sizeof(double));
  double *edges = gm_alloc(total * (size_t)dim * sizeof(double));
  double *density = gm_alloc(total * sizeof(double));
  if (!position || !velocity || !volume || !edges || !density) {
    status = gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "gm_domain_fill_box: out of memory for %zu points",
                          total);
    goto done;
  }
  double fill_density = def->density > 0.0
                            ? def->density
                            : domain->materials[def->material].density;
  size_t n = 0;
  for (int64_t j = first[1]; j < last[1]; j++) {
    for (int64_t i = first[0]; i < last[0]; i++, n++) {
      int64_t site[2] = {i, j};
      double measure = 1.0; /* length, area, or ring volume */
      for (int k = 0; k < dim; k++) {
        position[n * dim + k] =
            domain->def.origin[k] + ((double)site[k] + 0.5) * spacing;
        velocity[n * dim + k] = def->velocity[k];
        edges[n * dim + k] = spacing;
        measure *= spacing;
      }
      if (domain->axisymmetric)
        measure *= 2.0 * GM_PI * position[n * dim]; /* full ring */
      volume[n] = measure;
      density[n] = fill_density;
    }
  }
  gm_points_def points = gm_points_def_default();
  points.count = total;
  points.material = def->material;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  points.density = density;
  points.domain_size = edges;
  status = gm_domain_add_points(domain, &points, first_id);
  if (status == GM_OK && count)
    *count = total;
done:
  gm_free(position);
  gm_free(velocity);
  gm_free(volume);
  gm_free(edges);
  gm_free(density);
  return status;
}
