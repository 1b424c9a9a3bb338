/*
 * rigid.c - rigid material points with a prescribed velocity (a retaining
 * wall, a load-cell plate, a moving tool; the impact problem of 000 sec
 * 4.4). Rigid points do not take part in the transfers of the deformable
 * material: instead, every grid node they touch (nonzero shape function)
 * takes their velocity, a no-slip contact enforced on nodes like the box
 * walls. The velocity change this imposes on a node, times its (deformable)
 * mass, is the impulse exchanged with the rigid body; its sum over a step,
 * divided by dt, is the reported force. The rigid points themselves move
 * with the prescribed velocity (their nodes all carry it, so the usual
 * G2P moves them exactly) and keep zero stress.
 */
#include "boundaries/boundaries.h"

#include <math.h>
#include <string.h>

gm_status gm_domain_add_rigid(gm_domain *domain, const gm_rigid_def *def,
                              int *material_id) {
  gm_rigid_def full;
  gm_status status =
      gm_api_take_def(domain, "gm_domain_add_rigid", GM_LAYOUT_RIGID_DEF, def,
                      &full, material_id, "material_id");
  if (status != GM_OK)
    return status;
  def = &full;
  if ((status = gm_refuse_in_3d(domain, "gm_domain_add_rigid")) != GM_OK)
    return status;
  /* Rigid points mark the nodes they touch, images beyond a periodic face
   * included, and their force sums nodal impulses: the seam's nodes would
   * count twice. */
  if (gm_periodic_x(domain))
    return gm_set_error(domain, GM_ERR_UNSUPPORTED,
                        "gm_domain_add_rigid: rigid materials are not "
                        "supported with periodic x faces (GM_WALL_PERIODIC) "
                        "in this version");
  for (int k = 0; k < domain->dim; k++)
    if (!isfinite(def->velocity[k]))
      return gm_set_error(domain, GM_ERR_NOT_FINITE,
                          "gm_rigid_def.velocity[%d] is not finite", k);
  gm_builtin_material spec;
  memset(&spec, 0, sizeof spec);
  spec.def_name = "gm_rigid_def";
  spec.name = def->name ? def->name : "rigid";
  spec.update = gm_stress_free_update; /* no stress, whatever the motion */
  /* Rigid points carry no waves; the stable dt is set by the deformable
   * material (and every point's own speed), so a token modulus. */
  spec.p_wave_modulus = 1e-300;
  spec.density = def->density;
  status = gm_add_builtin_material(domain, &spec, material_id);
  if (status != GM_OK)
    return status;
  gm_material *material = &domain->materials[*material_id];
  material->rigid = true;
  material->rigid_report = (gm_force_report){0};
  for (int k = 0; k < 2; k++)
    material->rigid_velocity[k] = k < domain->dim ? def->velocity[k] : 0.0;
  domain->rigid_count++;
  return GM_OK;
}

static gm_material *rigid_material(gm_domain *domain, int material_id,
                                   const char *what) {
  if (material_id < 0 || material_id >= domain->material_count ||
      !domain->materials[material_id].rigid) {
    gm_set_error(domain, GM_ERR_UNKNOWN_MATERIAL,
                 "%s: material %d is not a rigid material", what, material_id);
    return NULL;
  }
  return &domain->materials[material_id];
}

gm_status gm_domain_set_rigid_velocity(gm_domain *domain, int material_id,
                                       const double velocity[3]) {
  if (!domain)
    return GM_ERR_NULL;
  if (!velocity)
    return gm_set_error(domain, GM_ERR_NULL,
                        "gm_domain_set_rigid_velocity: velocity is NULL");
  if (domain->busy && !domain->in_hook)
    return gm_set_error(domain, GM_ERR_BUSY,
                        "gm_domain_set_rigid_velocity: called during a step");
  gm_material *material =
      rigid_material(domain, material_id, "gm_domain_set_rigid_velocity");
  if (!material)
    return GM_ERR_UNKNOWN_MATERIAL;
  for (int k = 0; k < domain->dim; k++)
    if (!isfinite(velocity[k]))
      return gm_set_error(domain, GM_ERR_NOT_FINITE,
                          "gm_domain_set_rigid_velocity: velocity[%d] is not "
                          "finite",
                          k);
  for (int k = 0; k < domain->dim; k++)
    material->rigid_velocity[k] = velocity[k];
  return GM_OK;
}

gm_status gm_domain_get_rigid_force(const gm_domain *domain, int material_id,
                                    double force[3]) {
  if (!domain)
    return GM_ERR_NULL;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  if (!force)
    return gm_set_error(mutable_domain, GM_ERR_NULL,
                        "gm_domain_get_rigid_force: force is NULL");
  const gm_material *material =
      rigid_material(mutable_domain, material_id, "gm_domain_get_rigid_force");
  if (!material)
    return GM_ERR_UNKNOWN_MATERIAL;
  force[0] = material->rigid_report.force[0];
  force[1] = material->rigid_report.force[1];
  force[2] = 0.0;
  return GM_OK;
}

gm_status gm_domain_get_rigid_load(const gm_domain *domain, int material_id,
                                   gm_rigid_load *load) {
  gm_status status = gm_api_check_result(domain, "gm_domain_get_rigid_load",
                                         GM_LAYOUT_RIGID_LOAD, load, "load");
  if (status != GM_OK)
    return status;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  const gm_material *material =
      rigid_material(mutable_domain, material_id, "gm_domain_get_rigid_load");
  if (!material)
    return GM_ERR_UNKNOWN_MATERIAL;
  const gm_force_report *report = &material->rigid_report;
  gm_rigid_load result = gm_rigid_load_default();
  for (int k = 0; k < 2; k++) {
    result.force[k] = report->force[k];
    result.impulse[k] = report->impulse[k];
    result.total_impulse[k] = report->total_impulse[k];
    result.smoothed_force[k] = report->smoothed_force[k];
  }
  result.duration = report->duration;
  result.total_duration = report->total_duration;
  result.smoothing_time = domain->force_smoothing_time;
  gm_api_give_result(GM_LAYOUT_RIGID_LOAD, load, &result);
  return GM_OK;
}

gm_status gm_rigid_reserve(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  size_t nodes = grid->block_capacity * GM_BLOCK_NODES;
  if (domain->rigid_count == 0 || nodes <= grid->rigid_capacity)
    return GM_OK;
  int32_t *marks = gm_calloc(nodes, sizeof(int32_t));
  double *impulse_x = gm_calloc(nodes, sizeof(double));
  double *impulse_y = gm_calloc(nodes, sizeof(double));
  if (!marks || !impulse_x || !impulse_y) {
    gm_free(marks);
    gm_free(impulse_x);
    gm_free(impulse_y);
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "rigid points: out of memory for %zu nodes", nodes);
  }
  gm_free(grid->rigid_material);
  gm_free(grid->rigid_impulse[0]);
  gm_free(grid->rigid_impulse[1]);
  grid->rigid_material = marks;
  grid->rigid_impulse[0] = impulse_x;
  grid->rigid_impulse[1] = impulse_y;
  grid->rigid_capacity = nodes;
  return GM_OK;
}

/* Marks the nodes of one rigid point (those with a nonzero weight in the
 * domain's shape functions, support.h). */
static void mark_point(gm_domain *domain, size_t p, int32_t mark) {
  gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  int dim = domain->dim;
  gm_point_domain point;
  gm_point_domain_at(domain, current, p, &point);
  gm_support support;
  if (!gm_support_compute(&domain->shape_grid, &point, &support))
    return; /* cannot happen: the binning placed the point by it */
  uint32_t block = points->point_block[p];
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int64_t base[2];
  gm_block_base(grid, grid->block_key[block], base);
  for (int e = 0; e < support.count; e++) {
    if (support.weight[e] == 0.0)
      continue; /* the point does not reach this node */
    int64_t x = support.lowest[0] - base[0] + support.offset[0][e];
    int64_t y =
        dim > 1 ? support.lowest[1] - base[1] + support.offset[1][e] : 0;
    grid->rigid_material[gm_block_node(links, grid->shift, x, y)] = mark;
  }
}

void gm_rigid_mark_nodes(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  size_t nodes = grid->block_count * GM_BLOCK_NODES;
  memset(grid->rigid_material, 0, nodes * sizeof(int32_t));
  memset(grid->rigid_impulse[0], 0, nodes * sizeof(double));
  memset(grid->rigid_impulse[1], 0, nodes * sizeof(double));
  const gm_points *points = &domain->points;
  /* Serial, in point order: where two rigid bodies share a node, the
   * later point wins, the same way for any worker count. */
  for (size_t p = 0; p < points->count; p++) {
    int32_t material = points->material[p];
    if (domain->materials[material].rigid)
      mark_point(domain, p, material + 1);
  }
}

void gm_rigid_constrain_node(gm_domain *domain, size_t node,
                             const double old_velocity[2], double dt,
                             bool full) {
  gm_grid *grid = &domain->grid;
  const gm_material *material =
      &domain->materials[grid->rigid_material[node] - 1];
  double mass = grid->mass[node]; /* deformable material only */
  for (int k = 0; k < domain->dim; k++) {
    double prescribed = material->rigid_velocity[k];
    if (full) {
      /* The material's velocity change is -(impulse on the rigid body). */
      grid->rigid_impulse[k][node] =
          mass * (grid->momentum[k][node] - prescribed);
      grid->force[k][node] = (prescribed - old_velocity[k]) / dt;
    }
    grid->momentum[k][node] = prescribed;
  }
}

void gm_rigid_add_impulse(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  size_t nodes = grid->block_count * GM_BLOCK_NODES;
  for (size_t node = 0; node < nodes; node++) {
    int32_t mark = grid->rigid_material[node];
    if (mark == 0)
      continue;
    gm_material *material = &domain->materials[mark - 1];
    for (int k = 0; k < domain->dim; k++)
      material->rigid_impulse[k] += grid->rigid_impulse[k][node];
  }
}

void gm_rigid_set_point_velocities(gm_domain *domain) {
  gm_points *points = &domain->points;
  gm_point_buffers *next = &points->buffer[points->cur ^ 1];
  for (size_t p = 0; p < points->count; p++) {
    const gm_material *material = &domain->materials[points->material[p]];
    if (!material->rigid)
      continue;
    for (int k = 0; k < domain->dim; k++)
      next->velocity[k][p] = material->rigid_velocity[k];
    for (int k = 0; k < gm_affine_stored(domain); k++)
      next->affine[k][p] = 0.0; /* APIC: a translation has none */
  }
}
