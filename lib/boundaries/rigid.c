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
 *
 * With the B-splines a rigid point holds the nodes of its own cell (the
 * linear rule), not its whole support: a quadratic (cubic) B-spline
 * reaches 1.5 (2) cells, so a floor layer of rigid points lying on the
 * node row y = 0 would also hold the row y = h above it, raising the
 * floor and narrowing every opening in it by a cell (the slot silo's
 * rate, docs/convergence.md sec. 31). The cell rule holds exactly the
 * nodes inside a body whose faces lie on node lines, and never fewer
 * than one cell's nodes for a body thinner than a cell. The supports of
 * its outer points then reach free nodes, so G2P no longer moves them
 * exactly: B-spline rigid points are moved by the prescribed velocity
 * itself and keep F and V (gm_rigid_move_points, the step's last stage).
 *
 * In 3D the same rule holds with three components: the nodes a rigid
 * point reaches are those of its trilinear cell (linear MPM and the
 * B-splines) or of its GIMP box (support_3d.h) with a nonzero weight,
 * the grid update
 * (grid_update_3d.c) gives them the prescribed 3-vector, and the impulse
 * and force have a z component.
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
  for (int k = 0; k < 3; k++)
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
  for (int k = 0; k < 3; k++) /* z: 0 outside 3D */
    force[k] = material->rigid_report.force[k];
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
  for (int k = 0; k < 3; k++) { /* z: 0 outside 3D */
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
  int components = domain->dim == 3 ? 3 : 2; /* z: 3D only */
  int32_t *marks = gm_calloc(nodes, sizeof(int32_t));
  double *impulse[3] = {NULL, NULL, NULL}; /* N s */
  bool failed = !marks;
  for (int k = 0; k < components; k++) {
    impulse[k] = gm_calloc(nodes, sizeof(double));
    failed = failed || !impulse[k];
  }
  if (failed) {
    gm_free(marks);
    for (int k = 0; k < 3; k++)
      gm_free(impulse[k]);
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "rigid points: out of memory for %zu nodes", nodes);
  }
  gm_free(grid->rigid_material);
  grid->rigid_material = marks;
  for (int k = 0; k < 3; k++) {
    gm_free(grid->rigid_impulse[k]);
    grid->rigid_impulse[k] = impulse[k];
  }
  grid->rigid_capacity = nodes;
  return GM_OK;
}

/* The shape functions a rigid point marks its nodes with: the domain's,
 * except that a B-spline point marks its cell's (the header). */
static gm_shape_grid marking_shapes(const gm_domain *domain) {
  gm_shape_grid shapes = domain->shape_grid;
  if (gm_shape_is_bspline(shapes.shape))
    shapes.shape = GM_SHAPE_LINEAR;
  return shapes;
}

/* Marks the nodes of one rigid point (those with a nonzero weight in
 * marking_shapes, support.h). */
static void mark_point(gm_domain *domain, size_t p, int32_t mark) {
  gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  int dim = domain->dim;
  gm_point_domain point;
  gm_point_domain_at(domain, current, p, &point);
  gm_support support;
  gm_shape_grid shapes = marking_shapes(domain);
  if (!gm_support_compute(&shapes, &point, &support))
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

/* mark_point in 3D: the nodes of the point's support with a nonzero
 * weight, reached through the 8 neighbour links of its block as the 3D
 * scatter reaches them (p2g_3d.c): a linear or B-spline point's
 * trilinear cell (the header), a GIMP point's box (support_3d.h; its
 * block is that of the support's lowest node); CPDI: mark_cpdi_point_3d. */
/* mark_point_3d for CPDI: the nodes of the dense support
 * (support_cpdi_3d.h) with a nonzero weight. */
static void mark_cpdi_point_3d(gm_domain *domain, size_t p, int32_t mark) {
  gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  /* The domain map D (cpdi_reset.c). */
  const double *const *deformation = gm_support_slots_3d(domain, current);
  double x[3] = {current->position[0][p], current->position[1][p],
                 current->position[2][p]}; /* m */
  double half[3], f[9];                    /* m; D row-major */
  gm_box_half_edges_3d(GM_SHAPE_CPDI,
                       (const double *const *)points->domain_size, deformation,
                       p, half);
  gm_deformation_rows_3d(deformation, p, f);
  gm_cpdi_support_3d support;
  if (!gm_cpdi_support_compute_3d(&domain->shape_grid, x, f, half, &support))
    return; /* cannot happen: the binning placed the point by it */
  uint32_t block = points->point_block[p];
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int64_t base[3], local[3];
  gm_block_coordinates_3d(grid, grid->block_key[block], base);
  for (int axis = 0; axis < 3; axis++) {
    local[axis] = support.lowest[axis] - (base[axis] << GM_BLOCK_SHIFT_3D);
    if (local[axis] < 0 ||
        local[axis] + support.span[axis] > 2 * GM_BLOCK_EDGE_3D)
      return; /* cannot happen either (the scatter fails the step) */
  }
  size_t entry = 0;
  for (int c = 0; c < support.span[2]; c++)
    for (int b = 0; b < support.span[1]; b++)
      for (int a = 0; a < support.span[0]; a++, entry++)
        if (support.weight[entry] != 0.0) /* else not reached */
          grid->rigid_material[gm_block_node_3d(
              links, local[0] + a, local[1] + b, local[2] + c)] = mark;
}

static void mark_point_3d(gm_domain *domain, size_t p, int32_t mark) {
  gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  double x[3] = {current->position[0][p], current->position[1][p],
                 current->position[2][p]}; /* m */
  double half[3] = {0.0, 0.0, 0.0};        /* m, 0: the linear tent */
  gm_box_support_3d support;
  int64_t local[3];
  uint32_t block = points->point_block[p];
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  if (domain->shape_grid.shape == GM_SHAPE_LINEAR) {
    for (int axis = 0; axis < 3; axis++) {
      local[axis] =
          gm_shape_linear_axis(x[axis], domain->shape_grid.origin[axis],
                               domain->inv_cell, support.weight[axis],
                               support.gradient[axis]) &
          (GM_BLOCK_EDGE_3D - 1);
      support.span[axis] = 2;
    }
  } else if (gm_shape_is_bspline(domain->shape_grid.shape)) {
    /* The cell rule (header), from the block of the B-spline support's
     * lowest node, where the binning put the point: the cell's lowest
     * node is at or above that node and at most one node beyond it. */
    int64_t base[3];
    gm_block_coordinates_3d(grid, grid->block_key[block], base);
    for (int axis = 0; axis < 3; axis++) {
      local[axis] =
          gm_shape_linear_axis(x[axis], domain->shape_grid.origin[axis],
                               domain->inv_cell, support.weight[axis],
                               support.gradient[axis]) -
          (base[axis] << GM_BLOCK_SHIFT_3D);
      support.span[axis] = 2;
      if (local[axis] < 0 || local[axis] + 2 > 2 * GM_BLOCK_EDGE_3D)
        return; /* cannot happen (the comment above) */
    }
  } else {
    gm_box_half_edges_3d(domain->shape_grid.shape,
                         (const double *const *)points->domain_size,
                         gm_support_slots_3d(domain, current), p, half);
    if (!gm_box_support_compute_3d(&domain->shape_grid, x, half, &support))
      return; /* cannot happen: the binning placed the point by it */
    int64_t base[3];
    gm_block_coordinates_3d(grid, grid->block_key[block], base);
    for (int axis = 0; axis < 3; axis++) {
      local[axis] = support.lowest[axis] - (base[axis] << GM_BLOCK_SHIFT_3D);
      if (local[axis] < 0 ||
          local[axis] + support.span[axis] > 2 * GM_BLOCK_EDGE_3D)
        return; /* cannot happen either (the scatter fails the step) */
    }
  }
  for (int c = 0; c < support.span[2]; c++)
    for (int b = 0; b < support.span[1]; b++)
      for (int a = 0; a < support.span[0]; a++) {
        if (support.weight[0][a] * support.weight[1][b] *
                support.weight[2][c] ==
            0.0)
          continue; /* the point does not reach this node */
        size_t node =
            gm_block_node_3d(links, local[0] + a, local[1] + b, local[2] + c);
        grid->rigid_material[node] = mark;
      }
}

void gm_rigid_mark_nodes(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  size_t nodes = grid->block_count * GM_BLOCK_NODES;
  memset(grid->rigid_material, 0, nodes * sizeof(int32_t));
  for (int k = 0; k < (domain->dim == 3 ? 3 : 2); k++)
    memset(grid->rigid_impulse[k], 0, nodes * sizeof(double));
  const gm_points *points = &domain->points;
  /* Serial, in point order: where two rigid bodies share a node, the
   * later point wins, the same way for any worker count. */
  for (size_t p = 0; p < points->count; p++) {
    int32_t material = points->material[p];
    if (!domain->materials[material].rigid)
      continue;
    if (domain->dim == 3 && domain->def.shape == GM_SHAPE_CPDI)
      mark_cpdi_point_3d(domain, p, material + 1);
    else if (domain->dim == 3)
      mark_point_3d(domain, p, material + 1);
    else
      mark_point(domain, p, material + 1);
  }
}

void gm_rigid_constrain_node(gm_domain *domain, size_t node,
                             const double *old_velocity, double dt, bool full) {
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

/* The block key of rigid point p's moved position, as the binning keys a
 * B-spline point (bins.c: its support's lowest node); false if the
 * position left the grid box (the test of every moved point, g2p.c) or
 * its support the ghost layer. */
static bool moved_key(const gm_domain *domain, const gm_point_buffers *next,
                      size_t p, int64_t *key) {
  const gm_points *points = &domain->points;
  double moved[3] = {0.0, 0.0, 0.0}; /* m */
  for (int k = 0; k < domain->dim; k++)
    moved[k] = next->position[k][p];
  if (!gm_block_key_of(domain, moved, key))
    return false;
  int64_t lowest[3], highest[2];
  if (domain->dim == 3) {
    const double *const *position = (const double *const *)next->position;
    if (!gm_wide_lowest_3d(&domain->shape_grid, position,
                           (const double *const *)points->domain_size,
                           gm_support_slots_3d(domain, next), p, lowest))
      return false;
    *key =
        gm_block_key_of_node_3d(&domain->grid, lowest[0], lowest[1], lowest[2]);
    return true;
  }
  double y = domain->dim > 1 ? next->position[1][p] : 0.0; /* m */
  if (!gm_support_bspline_bounds(&domain->shape_grid, next->position[0][p], y,
                                 lowest, highest))
    return false;
  *key = gm_block_key_of_node(&domain->grid, lowest[0], lowest[1]);
  return true;
}

void gm_rigid_hold_remap_velocities(gm_domain *domain) {
  if (gm_shape_is_bspline(domain->shape_grid.shape))
    gm_rigid_set_point_velocities(domain);
}

bool gm_rigid_move_is_provisional(const gm_domain *domain, size_t p) {
  return gm_shape_is_bspline(domain->shape_grid.shape) &&
         domain->materials[domain->points.material[p]].rigid;
}

gm_status gm_rigid_move_points(gm_domain *domain, double dt) {
  if (!gm_shape_is_bspline(domain->shape_grid.shape))
    return GM_OK; /* their G2P moved them exactly (the header) */
  gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  gm_point_buffers *next = &points->buffer[points->cur ^ 1];
  const int64_t *binned = domain->grid.block_key; /* keys of this binning */
  for (size_t p = 0; p < points->count; p++) {
    const gm_material *material = &domain->materials[points->material[p]];
    if (!material->rigid)
      continue;
    for (int k = 0; k < domain->dim; k++)
      next->position[k][p] =
          current->position[k][p] + dt * material->rigid_velocity[k];
    for (int k = 0; k < GM_F_SLOTS; k++)
      if (next->deformation[k])
        next->deformation[k][p] = current->deformation[k][p];
    next->volume[p] = current->volume[p];
    int64_t key;
    if (!moved_key(domain, next, p, &key))
      return gm_set_error(
          domain, GM_ERR_OUT_OF_GRID,
          "step: rigid point id %lld would leave the grid box (x = %g, y = "
          "%g m at t = %g s); the step was not taken",
          (long long)points->id[p], next->position[0][p],
          domain->dim > 1 ? next->position[1][p] : 0.0, domain->time + dt);
    if (key != binned[points->point_block[p]])
      points->blocks_kept = false; /* the next binning rebuilds the grid */
    points->block_key[p] = key;
  }
  return GM_OK;
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
