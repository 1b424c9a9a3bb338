/*
 * fields.c - reading and editing point fields: copies in point-index order,
 * zero-copy views of stored components, and domain totals.
 */
#include "points/points.h"

#include <math.h>
#include <string.h>

static bool field_known(gm_field field) {
  return field >= GM_FIELD_POSITION && field <= GM_FIELD_AFFINE;
}

static size_t components_of(const gm_domain *domain, gm_field field) {
  switch (field) {
  case GM_FIELD_POSITION:
  case GM_FIELD_VELOCITY:
  case GM_FIELD_EXTERNAL_FORCE:
  case GM_FIELD_DOMAIN_SIZE:
    return (size_t)domain->dim;
  case GM_FIELD_STRESS:
    return 6;
  case GM_FIELD_DEFORMATION_GRADIENT:
    return 9;
  case GM_FIELD_DOMAIN_CORNERS: /* 2 ends in 1D, 4 corners x, y in 2D, 8
                                   corners x, y, z in 3D */
    return domain->dim == 1 ? 2 : domain->dim == 2 ? 8 : 24;
  case GM_FIELD_AFFINE: /* B_p, dim x dim */
    return (size_t)(domain->dim * domain->dim);
  default:
    return 1;
  }
}

gm_status gm_domain_field_components(const gm_domain *domain, gm_field field,
                                     size_t *components) {
  if (!domain)
    return GM_ERR_NULL;
  if (!components)
    return gm_set_error((gm_domain *)domain, GM_ERR_NULL,
                        "gm_domain_field_components: components is NULL");
  if (!field_known(field))
    return gm_set_error((gm_domain *)domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_field_components: field %d is not a "
                        "gm_field value",
                        (int)field);
  *components = components_of(domain, field);
  return GM_OK;
}

/* Stored array holding component k of field, or NULL if that component is
 * not stored (identically zero/one here) or the field is computed. The
 * returned array belongs to the committed buffer. */
static double *stored_component(const gm_domain *domain, gm_field field,
                                size_t k) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *buffer = &points->buffer[points->cur];
  /* Slots not stored in this geometry are NULL (yz, zx and the
   * off-plane F below 3D; F_zz outside axisymmetry and 3D). */
  static const int stress_slot[6] = {GM_XX, GM_YY, GM_ZZ, GM_XY, GM_YZ, GM_ZX};
  static const int deformation_slot[9] = {F_XX, F_XY, F_XZ, F_YX, F_YY,
                                          F_YZ, F_ZX, F_ZY, F_ZZ};
  switch (field) {
  case GM_FIELD_POSITION:
    return buffer->position[k];
  case GM_FIELD_VELOCITY:
    return buffer->velocity[k];
  case GM_FIELD_EXTERNAL_FORCE:
    return points->external_force[k]; /* NULL until first edited: zeros */
  case GM_FIELD_DOMAIN_SIZE:
    return points->domain_size[k];
  case GM_FIELD_MASS:
    return points->mass;
  case GM_FIELD_VOLUME:
    return buffer->volume;
  case GM_FIELD_INITIAL_VOLUME:
    return points->initial_volume;
  case GM_FIELD_STRESS:
    return buffer->stress[stress_slot[k]];
  case GM_FIELD_DEFORMATION_GRADIENT:
    return buffer->deformation[deformation_slot[k]];
  case GM_FIELD_AFFINE: /* NULL without APIC: zeros (dim x dim slots) */
    return buffer->affine[k];
  default:
    return NULL;
  }
}

/* Component k of the 8 corners of point i's domain in 3D: the
 * parallelepiped spanned from the point by F r1, F r2, F r3, with r_a the
 * initial half edges (GM_FIELD_DOMAIN_SIZE / 2) along the axes, so its
 * volume is det F times the initial box's, the point's volume V = det F V0
 * (g2p_3d.c) when V0 is the initial box (fill_box). Linear MPM has no
 * domain of its own: this is the material box the point started as,
 * carried by F (the CPDI domain of 000 Fig. 12 in 3D). With GM_SHAPE_CPDI
 * the domain map D takes F's place: exactly the domain its weights
 * average over (support_cpdi_3d.h), F's until it is reset
 * (cpdi_reset.c), of the same volume det D = det F always. uGIMP
 * and cpGIMP
 * give their own box instead (axis-aligned; cpGIMP's edges stretched by
 * |F_kk|), whose volume is not V. Corner c has signs
 * (s_x, s_y, s_z) in VTK_HEXAHEDRON's vertex order: the lower face
 * counter-clockwise from (-, -, -) seen from +z, then the upper face. */
static double corner_value_3d(const gm_domain *domain, size_t k, size_t i) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *buffer = &points->buffer[points->cur];
  static const double sign[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1},
                                    {-1, 1, -1},  {-1, -1, 1}, {1, -1, 1},
                                    {1, 1, 1},    {-1, 1, 1}};
  /* Row `axis` of F, row-major slots (core.h). */
  static const int row[3][3] = {
      {F_XX, F_XY, F_XZ}, {F_YX, F_YY, F_YZ}, {F_ZX, F_ZY, F_ZZ}};
  size_t corner = k / 3, axis = k % 3;
  double value = buffer->position[axis][i]; /* m */
  gm_shape shape = domain->shape_grid.shape;
  if (shape != GM_SHAPE_LINEAR && shape != GM_SHAPE_CPDI) {
    /* uGIMP, cpGIMP: the box the weights average over, along the axes
     * (support_3d.h), as the 2D rectangle of support.h. */
    double half[3]; /* m */
    gm_box_half_edges_3d(domain->shape_grid.shape,
                         (const double *const *)points->domain_size,
                         (const double *const *)buffer->deformation, i, half);
    return value + sign[corner][axis] * half[axis];
  }
  const double *const *map = gm_support_slots_3d(domain, buffer); /* D, F */
  for (int a = 0; a < 3; a++)
    value += map[row[axis][a]][i] * sign[corner][a] * 0.5 *
             points->domain_size[a][i];
  return value;
}

/* Component k of the current domain corners of point i (support.h). */
static double corner_value(const gm_domain *domain, size_t k, size_t i) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *buffer = &points->buffer[points->cur];
  int dim = domain->dim;
  if (dim == 3)
    return corner_value_3d(domain, k, i);
  gm_point_domain point;
  gm_point_domain_at(domain, buffer, i, &point);
  double corners[4][2];
  gm_point_domain_corners(domain->shape_grid.shape, dim, &point, corners);
  return dim == 1 ? corners[k][0] : corners[k / 2][k % 2];
}

/* Value of component k of field for point i (computed where not stored). */
static double field_value(const gm_domain *domain, gm_field field, size_t k,
                          size_t i) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *buffer = &points->buffer[points->cur];
  switch (field) {
  case GM_FIELD_DENSITY:
    return points->mass[i] / buffer->volume[i];
  case GM_FIELD_MATERIAL:
    return (double)points->material[i];
  case GM_FIELD_ID:
    return (double)points->id[i];
  case GM_FIELD_STATE: /* stored as bytes; zeros outside the granular family */
    return buffer->granular_state ? (double)buffer->granular_state[i] : 0.0;
  case GM_FIELD_COMPONENT: /* stored as int32 */
    return buffer->component ? (double)buffer->component[i] : 0.0;
  case GM_FIELD_DOMAIN_CORNERS:
    return corner_value(domain, k, i);
  case GM_FIELD_DEFORMATION_GRADIENT: {
    const double *stored = stored_component(domain, field, k);
    if (stored)
      return stored[i];
    /* Not stored: off-plane shears are 0, F_zz is 1 outside axisymmetry. */
    return k == 0 || k == 4 || k == 8 ? 1.0 : 0.0;
  }
  default: {
    const double *stored = stored_component(domain, field, k);
    return stored ? stored[i] : 0.0;
  }
  }
}

gm_status gm_domain_get_field(const gm_domain *domain, gm_field field,
                              double *out, size_t out_length) {
  if (!domain)
    return GM_ERR_NULL;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  if (!out)
    return gm_set_error(mutable_domain, GM_ERR_NULL,
                        "gm_domain_get_field: out is NULL");
  if (!field_known(field))
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_get_field: field %d is not a gm_field "
                        "value",
                        (int)field);
  size_t components = components_of(domain, field);
  size_t count = domain->points.count;
  if (out_length < count * components)
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_get_field: out_length %zu < %zu points x "
                        "%zu components",
                        out_length, count, components);
  for (size_t k = 0; k < components; k++) {
    const double *stored = stored_component(domain, field, k);
    for (size_t i = 0; i < count; i++)
      out[i * components + k] =
          stored ? stored[i] : field_value(domain, field, k, i);
  }
  return GM_OK;
}

gm_status gm_domain_get_ids(const gm_domain *domain, int64_t *out,
                            size_t out_length) {
  if (!domain)
    return GM_ERR_NULL;
  if (!out)
    return gm_set_error((gm_domain *)domain, GM_ERR_NULL,
                        "gm_domain_get_ids: out is NULL");
  if (out_length < domain->points.count)
    return gm_set_error((gm_domain *)domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_get_ids: out_length %zu < %zu points",
                        out_length, domain->points.count);
  if (domain->points.count)
    memcpy(out, domain->points.id, domain->points.count * sizeof(int64_t));
  return GM_OK;
}

static gm_status check_view(const gm_domain *domain, gm_field field,
                            size_t component, const char *caller) {
  gm_domain *mutable_domain = (gm_domain *)domain;
  if (!field_known(field))
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: field %d is not a gm_field value", caller,
                        (int)field);
  size_t components = components_of(domain, field);
  if (component >= components)
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: component %zu out of range (field has %zu)",
                        caller, component, components);
  if (!stored_component(domain, field, component))
    return gm_set_error(mutable_domain, GM_ERR_UNSUPPORTED,
                        "%s: field %d component %zu is not stored as "
                        "doubles here (computed, identically zero in this "
                        "geometry, or small integers); use "
                        "gm_domain_get_field",
                        caller, (int)field, component);
  return GM_OK;
}

gm_status gm_domain_view_field(const gm_domain *domain, gm_field field,
                               size_t component, const double **data) {
  if (!domain)
    return GM_ERR_NULL;
  if (!data)
    return gm_set_error((gm_domain *)domain, GM_ERR_NULL,
                        "gm_domain_view_field: data is NULL");
  /* External forces are allocated on first use; a view makes them exist
   * (logically const: they are zeros). */
  if (field == GM_FIELD_EXTERNAL_FORCE &&
      gm_points_need_external_force((gm_domain *)domain) != GM_OK)
    return GM_ERR_NO_MEMORY;
  gm_status status =
      check_view(domain, field, component, "gm_domain_view_field");
  if (status != GM_OK)
    return status;
  *data = stored_component(domain, field, component);
  return GM_OK;
}

/* The checks shared by the two writers: the field is writable here, and
 * the external forces exist (they are allocated on first use). */
static gm_status check_writable(gm_domain *domain, gm_field field,
                                const char *caller) {
  if (domain->busy && !domain->in_hook)
    return gm_set_error(domain, GM_ERR_BUSY, "%s: called during a step",
                        caller);
  if (field != GM_FIELD_VELOCITY && field != GM_FIELD_EXTERNAL_FORCE &&
      field != GM_FIELD_AFFINE)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: field %d is read-only (only "
                        "GM_FIELD_VELOCITY, GM_FIELD_EXTERNAL_FORCE and "
                        "GM_FIELD_AFFINE are writable)",
                        caller, (int)field);
  if (field == GM_FIELD_AFFINE && domain->def.transfer != GM_TRANSFER_APIC)
    return gm_set_error(domain, GM_ERR_UNSUPPORTED,
                        "%s: GM_FIELD_AFFINE is stored with "
                        "gm_domain_def.transfer GM_TRANSFER_APIC only",
                        caller);
  if (field == GM_FIELD_EXTERNAL_FORCE &&
      gm_points_need_external_force(domain) != GM_OK)
    return GM_ERR_NO_MEMORY;
  return GM_OK;
}

/* What a writer must tell the next step: the stable dt must see new speeds,
 * and edited inputs are screened for NaN/inf at the next step. */
static void mark_edited(gm_domain *domain, gm_field field) {
  if (field == GM_FIELD_VELOCITY)
    domain->velocity_edited = true;
  domain->inputs_edited = true;
}

gm_status gm_domain_edit_field(gm_domain *domain, gm_field field,
                               size_t component, double **data) {
  if (!domain)
    return GM_ERR_NULL;
  if (!data)
    return gm_set_error(domain, GM_ERR_NULL,
                        "gm_domain_edit_field: data is NULL");
  gm_status status = check_writable(domain, field, "gm_domain_edit_field");
  if (status == GM_OK)
    status = check_view(domain, field, component, "gm_domain_edit_field");
  if (status != GM_OK)
    return status;
  mark_edited(domain, field);
  *data = stored_component(domain, field, component);
  return GM_OK;
}

gm_status gm_domain_set_field(gm_domain *domain, gm_field field,
                              const double *values, size_t length) {
  const char *what = "gm_domain_set_field";
  if (!domain)
    return GM_ERR_NULL;
  if (!values)
    return gm_set_error(domain, GM_ERR_NULL, "%s: values is NULL", what);
  if (!field_known(field))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: field %d is not a gm_field value", what,
                        (int)field);
  gm_status status = check_writable(domain, field, what);
  if (status != GM_OK)
    return status;
  size_t components = components_of(domain, field);
  size_t count = domain->points.count;
  if (length != count * components)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: length %zu, must be %zu points x %zu "
                        "components",
                        what, length, count, components);
  for (size_t k = 0; k < components && status == GM_OK; k++)
    status = check_view(domain, field, k, what); /* every component stored */
  if (status != GM_OK)
    return status;
  /* Screen everything before writing anything: a refused call leaves the
   * field as it was. */
  for (size_t n = 0; n < length; n++)
    if (!isfinite(values[n]))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "%s: value %g for point id %lld component %zu is "
                          "not finite",
                          what, values[n],
                          (long long)domain->points.id[n / components],
                          n % components);
  for (size_t k = 0; k < components; k++) {
    double *stored = stored_component(domain, field, k);
    for (size_t i = 0; i < count; i++)
      stored[i] = values[i * components + k];
  }
  mark_edited(domain, field);
  return GM_OK;
}

gm_status gm_domain_view_ids(const gm_domain *domain, const int64_t **ids) {
  if (!domain)
    return GM_ERR_NULL;
  if (!ids)
    return gm_set_error((gm_domain *)domain, GM_ERR_NULL,
                        "gm_domain_view_ids: ids is NULL");
  *ids = domain->points.id;
  return GM_OK;
}

gm_status gm_domain_get_summary(const gm_domain *domain, gm_summary *summary) {
  gm_status status = gm_api_check_result(domain, "gm_domain_get_summary",
                                         GM_LAYOUT_SUMMARY, summary, "summary");
  if (status != GM_OK)
    return status;
  const gm_points *points = &domain->points;
  const gm_point_buffers *buffer = &points->buffer[points->cur];
  gm_summary totals = gm_summary_default();
  double first_moment[3] = {0.0, 0.0, 0.0}; /* kg m */
  /* Sum in id order so the totals do not depend on the point order. */
  for (int64_t id = 0; id < points->next_id; id++) {
    if (points->index_of_id[id] == GM_REMOVED_POINT)
      continue;
    size_t i = (size_t)points->index_of_id[id];
    double mass = points->mass[i];
    totals.mass += mass;
    for (int k = 0; k < domain->dim; k++) {
      double velocity = buffer->velocity[k][i];
      totals.momentum[k] += mass * velocity;
      totals.kinetic_energy += 0.5 * mass * velocity * velocity;
      first_moment[k] += mass * buffer->position[k][i];
    }
  }
  for (int k = 0; k < domain->dim; k++)
    totals.centre_of_mass[k] =
        totals.mass > 0.0 ? first_moment[k] / totals.mass : 0.0;
  gm_api_give_result(GM_LAYOUT_SUMMARY, summary, &totals);
  return GM_OK;
}
