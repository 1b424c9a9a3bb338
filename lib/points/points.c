/*
 * points.c - SoA point storage: capacity, insertion with validation
 * (all-or-nothing), stable ids, the fill-a-box convenience.
 */
#include "points/points.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define GROW(field, elem)                                                      \
  do {                                                                         \
    void *array_ = (field);                                                    \
    if (!gm_grow(&array_, (elem), old_capacity, capacity))                     \
      return GM_ERR_NO_MEMORY;                                                 \
    (field) = array_;                                                          \
  } while (0)

/* F components stored in this geometry: xx xy yx yy, plus the hoop zz;
 * all nine in 3D. */
static int stored_deformation(const gm_domain *domain) {
  if (domain->dim == 3)
    return GM_F_SLOTS;
  return domain->axisymmetric ? GM_F_STORED : F_ZZ;
}

int gm_domain_map_stored(const gm_domain *domain) {
  return domain->dim == 3 ? GM_F_SLOTS : F_ZZ;
}

int gm_stress_stored(const gm_domain *domain) {
  return domain->dim == 3 ? GM_STRESS_SLOTS : GM_STRESS_STORED;
}

gm_status gm_buffers_reserve(const gm_domain *domain, gm_point_buffers *buffer,
                             size_t old_capacity, size_t capacity) {
  for (int k = 0; k < domain->dim; k++) {
    GROW(buffer->position[k], sizeof(double));
    GROW(buffer->velocity[k], sizeof(double));
  }
  for (int k = 0; k < gm_stress_stored(domain); k++)
    GROW(buffer->stress[k], sizeof(double));
  for (int k = 0; k < stored_deformation(domain); k++)
    GROW(buffer->deformation[k], sizeof(double));
  /* CPDI's domain map D (cpdi_reset.c): F's slots xx xy yx yy below 3D,
   * all nine in 3D. */
  if (domain->def.shape == GM_SHAPE_CPDI)
    for (int k = 0; k < gm_domain_map_stored(domain); k++)
      GROW(buffer->domain_map[k], sizeof(double));
  GROW(buffer->volume, sizeof(double));
  if (domain->points.state_stride)
    GROW(buffer->state, domain->points.state_stride * sizeof(double));
  if (domain->def.family == GM_FAMILY_GRANULAR) {
    GROW(buffer->granular_state, sizeof(uint8_t));
    GROW(buffer->component, sizeof(int32_t));
  }
  for (int k = 0; k < gm_affine_stored(domain); k++)
    GROW(buffer->affine[k], sizeof(double));
  return GM_OK;
}

/* Grows every per-point array to hold capacity points. */
gm_status gm_points_reserve(gm_domain *domain, size_t capacity) {
  gm_points *points = &domain->points;
  size_t old_capacity = points->capacity;
  if (capacity <= old_capacity)
    return GM_OK;
  for (int b = 0; b < 2; b++) {
    gm_status status =
        gm_buffers_reserve(domain, &points->buffer[b], old_capacity, capacity);
    if (status != GM_OK)
      return status;
  }
  GROW(points->mass, sizeof(double));
  GROW(points->initial_volume, sizeof(double));
  for (int k = 0; k < domain->dim; k++) {
    GROW(points->domain_size[k], sizeof(double));
    if (points->external_force[k])
      GROW(points->external_force[k], sizeof(double));
  }
  GROW(points->id, sizeof(int64_t));
  GROW(points->material, sizeof(int32_t));
  GROW(points->block_key, sizeof(int64_t));
  GROW(points->point_block, sizeof(uint32_t));
  GROW(points->order, sizeof(uint32_t));
  points->capacity = capacity;
  return GM_OK;
}

gm_status gm_points_need_external_force(gm_domain *domain) {
  gm_points *points = &domain->points;
  for (int k = 0; k < domain->dim; k++) {
    if (points->external_force[k])
      continue;
    points->external_force[k] =
        gm_calloc(points->capacity ? points->capacity : 1, sizeof(double));
    if (!points->external_force[k])
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "external force: out of memory");
  }
  return GM_OK;
}

gm_status gm_points_restride_state(gm_domain *domain, size_t stride) {
  gm_points *points = &domain->points;
  size_t old_stride = points->state_stride;
  /* Both pools are allocated before either is touched: a failure leaves
   * the committed state exactly as it was. */
  double *widened[2];
  for (int b = 0; b < 2; b++)
    widened[b] = gm_calloc(points->capacity ? points->capacity : 1,
                           stride * sizeof(double));
  if (!widened[0] || !widened[1]) {
    gm_free(widened[0]);
    gm_free(widened[1]);
    return gm_set_error(domain, GM_ERR_NO_MEMORY, "state pool: out of memory");
  }
  for (int b = 0; b < 2; b++) {
    for (size_t i = 0; i < points->count; i++)
      for (size_t k = 0; k < old_stride; k++)
        widened[b][i * stride + k] =
            points->buffer[b].state[i * old_stride + k];
    gm_free(points->buffer[b].state);
    points->buffer[b].state = widened[b];
  }
  points->state_stride = stride;
  /* The retry snapshot is re-made with the new stride when next needed. */
  gm_buffers_free(&domain->snapshot);
  domain->snapshot_capacity = 0;
  return GM_OK;
}

void gm_buffers_free(gm_point_buffers *buffer) {
  for (int k = 0; k < 3; k++) {
    gm_free(buffer->position[k]);
    gm_free(buffer->velocity[k]);
  }
  for (int k = 0; k < GM_STRESS_SLOTS; k++)
    gm_free(buffer->stress[k]);
  for (int k = 0; k < GM_F_SLOTS; k++)
    gm_free(buffer->deformation[k]);
  for (int k = 0; k < GM_F_SLOTS; k++)
    gm_free(buffer->domain_map[k]);
  gm_free(buffer->volume);
  gm_free(buffer->state);
  gm_free(buffer->granular_state);
  gm_free(buffer->component);
  for (int k = 0; k < GM_AFFINE_STORED; k++)
    gm_free(buffer->affine[k]);
  memset(buffer, 0, sizeof *buffer);
}

static void copy_array(double *to, const double *from, size_t count) {
  if (to && from)
    memcpy(to, from, count * sizeof(double));
}

void gm_buffers_copy(gm_point_buffers *to, const gm_point_buffers *from,
                     size_t count, size_t state_stride) {
  for (int k = 0; k < 3; k++) {
    copy_array(to->position[k], from->position[k], count);
    copy_array(to->velocity[k], from->velocity[k], count);
  }
  for (int k = 0; k < GM_STRESS_SLOTS; k++) /* the slots stored: not NULL */
    copy_array(to->stress[k], from->stress[k], count);
  for (int k = 0; k < GM_F_SLOTS; k++)
    copy_array(to->deformation[k], from->deformation[k], count);
  for (int k = 0; k < GM_F_SLOTS; k++)
    copy_array(to->domain_map[k], from->domain_map[k], count);
  copy_array(to->volume, from->volume, count);
  copy_array(to->state, from->state, count * state_stride);
  if (to->granular_state && from->granular_state) {
    memcpy(to->granular_state, from->granular_state, count * sizeof(uint8_t));
    memcpy(to->component, from->component, count * sizeof(int32_t));
  }
  for (int k = 0; k < GM_AFFINE_STORED; k++)
    copy_array(to->affine[k], from->affine[k], count);
}

void gm_points_free(gm_points *points) {
  for (int b = 0; b < 2; b++)
    gm_buffers_free(&points->buffer[b]);
  gm_free(points->mass);
  gm_free(points->initial_volume);
  for (int k = 0; k < 3; k++) {
    gm_free(points->domain_size[k]);
    gm_free(points->external_force[k]);
  }
  gm_free(points->id);
  gm_free(points->material);
  gm_free(points->index_of_id);
  gm_free(points->block_key);
  gm_free(points->point_block);
  gm_free(points->order);
  memset(points, 0, sizeof *points);
}

/* Volume per unit measure -> the measure the domain size is taken from:
 * length (1D), area (plane strain), meridional area V/(2 pi r) (axisym),
 * volume (3D: a cube). */
static double default_domain_edge(const gm_domain *domain, double volume,
                                  double radius) {
  if (domain->dim == 1)
    return volume;
  if (domain->dim == 3)
    return cbrt(volume);
  if (domain->axisymmetric)
    return sqrt(volume / (2.0 * GM_PI * radius));
  return sqrt(volume);
}

static bool all_finite(const double *values, size_t count) {
  for (size_t k = 0; k < count; k++)
    if (!isfinite(values[k]))
      return false;
  return true;
}

static const char *axis_name(int k) {
  return k == 0 ? "x" : k == 1 ? "y" : "z";
}

/* In the granular family a point of a granular material may not be
 * placed looser than rho_cr - TOL: V_cr = m / rho_cr "is the highest volume
 * a material point can have" (000 sec 3.3). Below it, density control
 * (eqs 13-15) returns F every step, so the point never compacts, and its
 * domain of interaction (its domain scaled to V_cr) is smaller than the
 * point itself, so a loose block falls apart into single points. A
 * density given by mass is m / V, which may round a few ulps below a
 * density placed at exactly rho_cr: that slack is allowed. */
gm_status gm_check_placement_density(gm_domain *domain, int material_id,
                                     double density, const char *what) {
  const gm_material *material = &domain->materials[material_id];
  if (domain->def.family != GM_FAMILY_GRANULAR || !material->granular)
    return GM_OK;
  double critical = material->critical_density; /* kg/m^3 */
  double lowest = critical - material->tolerance -
                  4.0 * DBL_EPSILON * critical; /* kg/m^3 */
  if (!(density < lowest))
    return GM_OK;
  return gm_set_error(
      domain, GM_ERR_INVALID_ARGUMENT,
      "%s has density %.12g kg/m^3, below the critical density %.12g kg/m^3 "
      "(- tolerance %g) of granular material %d: in the granular family "
      "V_cr = m/rho_cr is the largest volume a point may have (000 sec "
      "3.3); place points at rho >= rho_cr",
      what, density, critical, material->tolerance, material_id);
}

/* A 3D GIMP point's initial box (support_3d.h) must lie within the ghost
 * layer around the grid box and span at most GM_SUPPORT_3D_MAX_SPAN nodes
 * per axis. Its weights can always be computed (a box far thinner than a
 * cell weighs its nodes as the tent), so the bounds are all to check. */
static gm_status validate_box_3d(gm_domain *domain, const gm_points_def *def,
                                 size_t i, const double *position,
                                 double volume) {
  double half[3]; /* m */
  for (int k = 0; k < 3; k++)
    half[k] = 0.5 * (def->domain_size
                         ? def->domain_size[i * 3 + (size_t)k]
                         : default_domain_edge(domain, volume, position[0]));
  int64_t lowest[3];
  if (domain->shape_grid.shape == GM_SHAPE_CPDI) {
    /* F = I. The whole support, so that a domain too thin for its
     * corner gradients (which divide by its volume) is refused here. */
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    gm_cpdi_support_3d support;
    if (gm_cpdi_support_lowest_3d(&domain->shape_grid, position, identity, half,
                                  lowest)) {
      if (gm_cpdi_support_compute_3d(&domain->shape_grid, position, identity,
                                     half, &support))
        return GM_OK;
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_add_points: point %zu domain (edges %g "
                          "x %g x %g m) is too thin for the shape functions "
                          "to weigh its nodes",
                          i, 2.0 * half[0], 2.0 * half[1], 2.0 * half[2]);
    }
  } else if (gm_box_support_lowest_3d(&domain->shape_grid, position, half,
                                      lowest)) {
    return GM_OK;
  }
  return gm_set_error(domain, GM_ERR_OUT_OF_GRID,
                      "gm_domain_add_points: point %zu domain (edges %g x %g "
                      "x %g m at x = %g, y = %g, z = %g m) reaches past the "
                      "ghost cell layer around the grid box or spans more "
                      "than %d cells along an axis",
                      i, 2.0 * half[0], 2.0 * half[1], 2.0 * half[2],
                      position[0], position[1], position[2],
                      GM_SUPPORT_3D_MAX_SPAN - 1);
}

/* Checks point i of def; the message names the point and the field. */
static gm_status validate_point(gm_domain *domain, const gm_points_def *def,
                                size_t i, double density) {
  int dim = domain->dim;
  const double *position = def->position + i * (size_t)dim;
  for (int k = 0; k < dim; k++) {
    if (!isfinite(position[k]))
      return gm_set_error(domain, GM_ERR_NOT_FINITE,
                          "gm_domain_add_points: point %zu position %s is "
                          "not finite",
                          i, axis_name(k));
  }
  int64_t key;
  if (!gm_block_key_of(domain, position, &key))
    return gm_set_error(domain, GM_ERR_OUT_OF_GRID,
                        "gm_domain_add_points: point %zu position (%g, %g, "
                        "%g) is outside the grid box",
                        i, position[0], dim > 1 ? position[1] : 0.0,
                        dim > 2 ? position[2] : 0.0);
  if (domain->axisymmetric && !(position[0] > 0.0))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_points: point %zu radius %g must be "
                        "> 0 in axisymmetry",
                        i, position[0]);
  if (def->velocity && !all_finite(def->velocity + i * (size_t)dim, dim))
    return gm_set_error(domain, GM_ERR_NOT_FINITE,
                        "gm_domain_add_points: point %zu velocity is not "
                        "finite",
                        i);
  double volume = def->volume[i];
  if (!(volume > 0.0) || !isfinite(volume))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_points: point %zu volume is %g, must "
                        "be finite and > 0",
                        i, volume);
  if (def->mass) {
    if (!(def->mass[i] > 0.0) || !isfinite(def->mass[i]))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_add_points: point %zu mass is %g kg, "
                          "must be finite and > 0",
                          i, def->mass[i]);
  } else if (!(density > 0.0) || !isfinite(density)) {
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_points: point %zu density is %g "
                        "kg/m^3, must be finite and > 0",
                        i, density);
  }
  if (def->domain_size) {
    for (int k = 0; k < dim; k++) {
      double edge = def->domain_size[i * (size_t)dim + (size_t)k];
      if (!(edge > 0.0) || !isfinite(edge))
        return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                            "gm_domain_add_points: point %zu domain_size %s "
                            "is %g m, must be finite and > 0",
                            i, axis_name(k), edge);
    }
  }
  if (domain->shape_grid.shape != GM_SHAPE_LINEAR && dim == 3) {
    gm_status status = validate_box_3d(domain, def, i, position, volume);
    if (status != GM_OK)
      return status;
  } else if (domain->shape_grid.shape != GM_SHAPE_LINEAR) {
    gm_point_domain shape = {{position[0], dim > 1 ? position[1] : 0.0},
                             {1.0, 0.0, 0.0, 1.0},
                             {0.0, 0.0}};
    for (int k = 0; k < dim; k++)
      shape.half_size[k] =
          0.5 * (def->domain_size
                     ? def->domain_size[i * (size_t)dim + (size_t)k]
                     : default_domain_edge(domain, volume, position[0]));
    int64_t lowest[2], highest[2];
    if (!gm_support_bounds(&domain->shape_grid, &shape, lowest, highest))
      return gm_set_error(domain, GM_ERR_OUT_OF_GRID,
                          "gm_domain_add_points: point %zu domain (edges %g "
                          "x %g m at x = %g, y = %g m) reaches past the ghost "
                          "cell layer around the grid box or spans more than "
                          "8 cells",
                          i, 2.0 * shape.half_size[0], 2.0 * shape.half_size[1],
                          position[0], shape.position[1]);
    /* A domain far thinner than a cell (edge 1e-175 m, say) passes the
     * bounds but its weights cannot be computed (CPDI's corner gradients
     * divide by its area): refused here, not by a failing step. */
    gm_support support;
    if (!gm_support_compute(&domain->shape_grid, &shape, &support))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_add_points: point %zu domain (edges %g "
                          "x %g m) is too thin for the shape functions to "
                          "weigh its nodes",
                          i, 2.0 * shape.half_size[0],
                          2.0 * shape.half_size[1]);
  }
  double placed = def->mass ? def->mass[i] / volume : density; /* kg/m^3 */
  char what[64];
  snprintf(what, sizeof what, "gm_domain_add_points: point %zu", i);
  gm_status status =
      gm_check_placement_density(domain, def->material, placed, what);
  if (status != GM_OK)
    return status;
  if (def->stress) {
    const double *stress = def->stress + i * 6;
    if (!all_finite(stress, 6))
      return gm_set_error(domain, GM_ERR_NOT_FINITE,
                          "gm_domain_add_points: point %zu stress is not "
                          "finite",
                          i);
    if (dim < 3 && (stress[GM_YZ] != 0.0 || stress[GM_ZX] != 0.0))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_add_points: point %zu stress yz/zx must "
                          "be 0 in 1D and 2D geometries",
                          i);
  }
  return GM_OK;
}

static void store_point(gm_domain *domain, const gm_points_def *def, size_t i,
                        double density) {
  gm_points *points = &domain->points;
  gm_point_buffers *buffer = &points->buffer[points->cur];
  const gm_material *material = &domain->materials[def->material];
  int dim = domain->dim;
  size_t p = points->count + i;
  const double *position = def->position + i * (size_t)dim;
  for (int k = 0; k < dim; k++) {
    buffer->position[k][p] = position[k];
    buffer->velocity[k][p] =
        def->velocity ? def->velocity[i * (size_t)dim + k] : 0.0;
    if (points->external_force[k])
      points->external_force[k][p] = 0.0;
  }
  double volume = def->volume[i];
  buffer->volume[p] = volume;
  points->initial_volume[p] = volume;
  points->mass[p] = def->mass ? def->mass[i] : density * volume;
  for (int k = 0; k < dim; k++)
    points->domain_size[k][p] =
        def->domain_size ? def->domain_size[i * (size_t)dim + k]
                         : default_domain_edge(domain, volume, position[0]);
  /* The stored slots are the Voigt order (core.h): 4 of them below 3D. */
  for (int k = 0; k < gm_stress_stored(domain); k++)
    buffer->stress[k][p] = def->stress ? def->stress[i * 6 + k] : 0.0;
  for (int k = 0; k < GM_AFFINE_STORED; k++) /* APIC: no affine part yet */
    if (buffer->affine[k])
      buffer->affine[k][p] = 0.0;
  if (buffer->granular_state) { /* decided by the next step */
    buffer->granular_state[p] = GM_STATE_QUASI_STATIC;
    buffer->component[p] = 0;
  }
  buffer->deformation[F_XX][p] = 1.0;
  buffer->deformation[F_XY][p] = 0.0;
  buffer->deformation[F_YX][p] = 0.0;
  buffer->deformation[F_YY][p] = 1.0;
  if (buffer->deformation[F_ZZ])
    buffer->deformation[F_ZZ][p] = 1.0;
  for (int k = F_XZ; k <= F_ZY; k++) /* 3D: off-plane shears */
    if (buffer->deformation[k])
      buffer->deformation[k][p] = 0.0;
  for (int k = 0; k < GM_F_SLOTS; k++) /* CPDI: the initial domain, D = I */
    if (buffer->domain_map[k])
      buffer->domain_map[k][p] =
          k == F_XX || k == F_YY || k == F_ZZ ? 1.0 : 0.0;
  for (size_t k = 0; k < points->state_stride; k++)
    buffer->state[p * points->state_stride + k] =
        k < material->state_count ? material->initial_state[k] : 0.0;
  points->material[p] = def->material;
  points->id[p] = points->next_id + (int64_t)i;
  points->index_of_id[points->next_id + (int64_t)i] = (uint32_t)p;
}

bool gm_points_reserve_ids(gm_points *points, size_t extra) {
  size_t needed = (size_t)points->next_id + extra;
  if (needed <= points->id_capacity)
    return true;
  size_t capacity = points->id_capacity + points->id_capacity / 2;
  if (capacity < needed)
    capacity = needed;
  void *map = points->index_of_id;
  if (!gm_grow(&map, sizeof(uint32_t), points->id_capacity, capacity))
    return false;
  points->index_of_id = map;
  points->id_capacity = capacity;
  return true;
}

gm_status gm_domain_add_points(gm_domain *domain, const gm_points_def *def,
                               int64_t *first_id) {
  gm_points_def full;
  gm_status status =
      gm_api_take_def(domain, "gm_domain_add_points", GM_LAYOUT_POINTS_DEF, def,
                      &full, NULL, NULL);
  if (status != GM_OK)
    return status;
  return gm_points_append(domain, &full, first_id);
}

gm_status gm_points_append(gm_domain *domain, const gm_points_def *def,
                           int64_t *first_id) {
  domain->granular.boxes_valid = false; /* new points have none */
  if (def->count == 0)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_points: count is 0");
  if (!def->position || !def->volume)
    return gm_set_error(domain, GM_ERR_NULL, "gm_domain_add_points: %s is NULL",
                        def->position ? "volume" : "position");
  if (def->material < 0 || def->material >= domain->material_count)
    return gm_set_error(domain, GM_ERR_UNKNOWN_MATERIAL,
                        "gm_domain_add_points: material %d is unknown (%d "
                        "materials registered)",
                        def->material, domain->material_count);
  gm_points *points = &domain->points;
  if (def->count > (size_t)INT_MAX - 1 - points->count)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_points: count %zu would exceed %d "
                        "points",
                        def->count, INT_MAX - 1);
  double material_density = domain->materials[def->material].density;
  for (size_t i = 0; i < def->count; i++) {
    double density = def->density ? def->density[i] : material_density;
    gm_status status = validate_point(domain, def, i, density);
    if (status != GM_OK)
      return status;
  }
  size_t needed = points->count + def->count;
  if (needed > points->capacity) {
    size_t capacity = points->capacity + points->capacity / 2;
    if (capacity < needed)
      capacity = needed;
    if (gm_points_reserve(domain, capacity) != GM_OK)
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "gm_domain_add_points: out of memory for %zu points",
                          needed);
  }
  if (!gm_points_reserve_ids(points, def->count))
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "gm_domain_add_points: out of memory for the id map");
  for (size_t i = 0; i < def->count; i++)
    store_point(domain, def, i,
                def->density ? def->density[i] : material_density);
  if (first_id)
    *first_id = points->next_id;
  points->count = needed;
  points->next_id += (int64_t)def->count;
  points->keys_valid = false;
  gm_recompute_signal_speed(domain);
  return GM_OK;
}

size_t gm_domain_point_count(const gm_domain *domain) {
  return domain ? domain->points.count : 0;
}

gm_status gm_domain_point_index(const gm_domain *domain, int64_t id,
                                size_t *index) {
  if (!domain)
    return GM_ERR_NULL;
  if (!index)
    return gm_set_error((gm_domain *)domain, GM_ERR_NULL,
                        "gm_domain_point_index: index is NULL");
  if (id < 0 || id >= domain->points.next_id)
    return gm_set_error((gm_domain *)domain, GM_ERR_UNKNOWN_POINT,
                        "gm_domain_point_index: no point with id %lld",
                        (long long)id);
  if (domain->points.index_of_id[id] == GM_REMOVED_POINT)
    return gm_set_error((gm_domain *)domain, GM_ERR_UNKNOWN_POINT,
                        "gm_domain_point_index: point id %lld was removed "
                        "(it entered a sink)",
                        (long long)id);
  *index = (size_t)domain->points.index_of_id[id];
  return GM_OK;
}

void gm_point_domain_at(const gm_domain *domain, const gm_point_buffers *buffer,
                        size_t p, gm_point_domain *out) {
  const gm_points *points = &domain->points;
  int dim = domain->dim;
  const double *const position[2] = {buffer->position[0],
                                     buffer->position[dim > 1 ? 1 : 0]};
  const double *deformation[4];
  gm_support_tensor(domain, buffer, deformation);
  const double *const size[2] = {points->domain_size[0],
                                 points->domain_size[dim > 1 ? 1 : 0]};
  gm_load_point_domain(dim, position, deformation, size, p, out);
}
