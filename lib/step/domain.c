/*
 * domain.c - domain lifecycle: validation of the definition, creation,
 * destruction, the last error, time, hooks.
 */
#include "step/step.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* The message of a failed create goes to gm_last_create_error()
 * (core/status.c). */
#define CREATE_FAIL(status, ...)                                               \
  return gm_set_create_error((status), __VA_ARGS__)

static const char *face_name(int face) {
  static const char *names[6] = {"xmin", "xmax", "ymin",
                                 "ymax", "zmin", "zmax"};
  return names[face];
}

/* What GM_GEOMETRY_3D runs in this version (docs/3d.md): linear, uGIMP,
 * cpGIMP, the B-spline shapes and CPDI, every family (plain, stress_free,
 * granular: granular/components.c in 3D), FLIP/PIC/APIC with every shape
 * (APIC with CPDI since 2026-11-28), open, slip, fixed and periodic x box
 * faces; every scheme, gravity, damping, host forces; planar walls with
 * linear MPM, uGIMP, cpGIMP and CPDI (since 2026-11-28), rigid materials
 * with every shape. Refused by name, by the call that would add them:
 * planar walls with the B-splines (gm_domain_add_wall), and, as in 2D,
 * walls and rigid materials beside periodic x faces. Periodic y and z
 * faces are refused below for every geometry. */

static gm_status validate_def(const gm_domain_def *def) {
  int dim = gm_geometry_dimension(def->geometry);
  if (dim == 0)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.geometry %d is not a gm_geometry value",
                (int)def->geometry);
  if (!(def->cell_size > 0.0) || !isfinite(def->cell_size))
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.cell_size is %g m, must be finite and > 0",
                def->cell_size);
  for (int k = 0; k < dim; k++) {
    if (!isfinite(def->origin[k]))
      CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                  "gm_domain_def.origin[%d] is %g, must be finite", k,
                  def->origin[k]);
    if (!(def->extent[k] > 0.0) || !isfinite(def->extent[k]))
      CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                  "gm_domain_def.extent[%d] is %g m, must be finite and > 0", k,
                  def->extent[k]);
    double cells = ceil(def->extent[k] / def->cell_size - 1e-9);
    if (cells > 1e9)
      CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                  "gm_domain_def.extent[%d] / cell_size = %g cells, at most "
                  "1e9 per axis",
                  k, cells);
    if (!isfinite(def->gravity[k]))
      CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                  "gm_domain_def.gravity[%d] is %g, must be finite", k,
                  def->gravity[k]);
  }
  if (def->geometry == GM_GEOMETRY_AXISYMMETRIC && def->origin[0] < 0.0)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.origin[0] is %g but the radius must be >= 0 "
                "in GM_GEOMETRY_AXISYMMETRIC",
                def->origin[0]);
  if (def->scheme != GM_SCHEME_USL && def->scheme != GM_SCHEME_MUSL &&
      def->scheme != GM_SCHEME_USF)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.scheme %d is not a gm_update_scheme value",
                (int)def->scheme);
  for (int face = 0; face < 2 * dim; face++) {
    gm_wall_type wall = def->walls[face];
    if (wall != GM_WALL_OPEN && wall != GM_WALL_FIXED && wall != GM_WALL_SLIP &&
        wall != GM_WALL_PERIODIC && wall != GM_WALL_SYMMETRY)
      CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                  "gm_domain_def.walls[%d] (%s face) is %d, not a "
                  "gm_wall_type value",
                  face, face_name(face), (int)wall);
    if (wall == GM_WALL_PERIODIC && face >= GM_FACE_YMIN)
      CREATE_FAIL(GM_ERR_UNSUPPORTED,
                  "gm_domain_def.walls[%d] (%s face) is GM_WALL_PERIODIC; "
                  "only the x faces (xmin and xmax) may be periodic in "
                  "this version",
                  face, face_name(face));
  }
  bool periodic_min = def->walls[GM_FACE_XMIN] == GM_WALL_PERIODIC;
  bool periodic_max = def->walls[GM_FACE_XMAX] == GM_WALL_PERIODIC;
  if (periodic_min != periodic_max)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.walls: the xmin face is %s and the xmax face "
                "%s; the two x faces must be GM_WALL_PERIODIC together",
                periodic_min ? "periodic" : "not periodic",
                periodic_max ? "periodic" : "not");
  if (periodic_min && def->geometry == GM_GEOMETRY_AXISYMMETRIC)
    CREATE_FAIL(GM_ERR_UNSUPPORTED,
                "gm_domain_def.walls: periodic x faces (xmin, xmax) are "
                "radial faces in GM_GEOMETRY_AXISYMMETRIC, which cannot "
                "wrap around");
  if (periodic_min && dim > 0 &&
      ceil(def->extent[0] / def->cell_size - 1e-9) < 3.0)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.walls: periodic x faces (xmin, xmax) need at "
                "least 3 cells along x; extent[0] = %g m is %g cells",
                def->extent[0], ceil(def->extent[0] / def->cell_size - 1e-9));
  if (periodic_min && def->family == GM_FAMILY_GRANULAR)
    CREATE_FAIL(GM_ERR_UNSUPPORTED,
                "gm_domain_def.walls: periodic x faces (xmin, xmax) are not "
                "supported with GM_FAMILY_GRANULAR in this version (its "
                "pair search and parallel grids do not see across the "
                "seam); use GM_FAMILY_PLAIN or GM_FAMILY_STRESS_FREE");
  if (!(def->cfl > 0.0 && def->cfl <= 1.0))
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.cfl is %g, must be in (0, 1]", def->cfl);
  if (def->max_retries < 0 || def->max_retries > 20)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.max_retries is %d, must be in 0..20",
                def->max_retries);
  if (def->worker_count < 1 || def->worker_count > 256)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.worker_count is %d, must be in 1..256",
                def->worker_count);
  if (!(def->damping >= 0.0 && def->damping < 1.0))
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.damping is %g, must be in [0, 1)", def->damping);
  if (!(def->pic_fraction >= 0.0 && def->pic_fraction <= 1.0))
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.pic_fraction is %g, must be in [0, 1]",
                def->pic_fraction);
  if (def->shape != GM_SHAPE_LINEAR && def->shape != GM_SHAPE_UGIMP &&
      def->shape != GM_SHAPE_CPGIMP && def->shape != GM_SHAPE_CPDI &&
      def->shape != GM_SHAPE_BSPLINE2 && def->shape != GM_SHAPE_BSPLINE3)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.shape %d is not a gm_shape value",
                (int)def->shape);
  if (def->family != GM_FAMILY_PLAIN && def->family != GM_FAMILY_STRESS_FREE &&
      def->family != GM_FAMILY_GRANULAR)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.family %d is not a gm_family value",
                (int)def->family);
  if (def->transfer != GM_TRANSFER_FLIP && def->transfer != GM_TRANSFER_APIC)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.transfer %d is not a gm_transfer value",
                (int)def->transfer);
  /* APIC's point velocity is the PIC one, sum N_i v_i; its affine part
   * keeps what PIC loses, so a FLIP share has no meaning there. */
  if (def->transfer == GM_TRANSFER_APIC && def->pic_fraction != 0.0)
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.pic_fraction is %g but must be 0 with "
                "GM_TRANSFER_APIC (its point velocity is already the PIC "
                "one, sum N_i v_i)",
                def->pic_fraction);
  if ((def->enqueue_task == NULL) != (def->finish_task == NULL))
    CREATE_FAIL(GM_ERR_INVALID_ARGUMENT,
                "gm_domain_def.enqueue_task and finish_task must be set "
                "together");
  return GM_OK;
}

static gm_status allocate_scratch(gm_domain *domain) {
  domain->scratch =
      gm_calloc((size_t)domain->worker_count, sizeof(gm_worker_scratch));
  if (!domain->scratch)
    return GM_ERR_NO_MEMORY;
  for (int w = 0; w < domain->worker_count; w++) {
    gm_worker_scratch *scratch = &domain->scratch[w];
    scratch->state_storage =
        gm_calloc((size_t)GM_MAX_STATE * GM_BATCH_SIZE, sizeof(double));
    if (!scratch->state_storage)
      return GM_ERR_NO_MEMORY;
    for (int k = 0; k < GM_MAX_STATE; k++)
      scratch->state_columns[k] = scratch->state_storage + k * GM_BATCH_SIZE;
    for (uint32_t r = 0; r < GM_BATCH_SIZE; r++)
      scratch->identity_rows[r] = r;
    scratch->gather = gm_alloc(gm_chunk_gather_size());
    if (!scratch->gather)
      return GM_ERR_NO_MEMORY;
  }
  return GM_OK;
}

gm_status gm_domain_create(const gm_domain_def *def, gm_domain **out) {
  gm_set_create_error(GM_OK, "%s", ""); /* no message yet */
  if (!out)
    CREATE_FAIL(GM_ERR_NULL, "gm_domain_create: out is NULL");
  *out = NULL;
  if (!def)
    CREATE_FAIL(GM_ERR_NULL, "gm_domain_create: def is NULL");
  /* An earlier layout is completed with the defaults (api_check.h). */
  if (!gm_layout_known(GM_LAYOUT_DOMAIN_DEF, def->struct_size))
    return gm_layout_refuse(NULL, GM_LAYOUT_DOMAIN_DEF, def->struct_size);
  gm_domain_def full;
  gm_layout_complete(GM_LAYOUT_DOMAIN_DEF, def, &full);
  def = &full;
  gm_status status = validate_def(def);
  if (status != GM_OK)
    return status;
  gm_domain *domain = gm_calloc(1, sizeof *domain);
  if (!domain)
    CREATE_FAIL(GM_ERR_NO_MEMORY, "gm_domain_create: out of memory");
  domain->def = *def;
  domain->dim = gm_geometry_dimension(def->geometry);
  domain->axisymmetric = def->geometry == GM_GEOMETRY_AXISYMMETRIC;
  domain->inv_cell = 1.0 / def->cell_size;
  for (int k = 0; k < 3; k++)
    domain->cells[k] =
        k < domain->dim ? (int64_t)ceil(def->extent[k] / def->cell_size - 1e-9)
                        : 1;
  domain->worker_count = def->worker_count;
  domain->force_smoothing_time = GM_DEFAULT_FORCE_SMOOTHING_TIME;
  gm_grid *grid = &domain->grid;
  grid->dim = domain->dim;
  grid->shift = domain->dim == 1   ? GM_BLOCK_SHIFT_1D
                : domain->dim == 2 ? GM_BLOCK_SHIFT_2D
                                   : GM_BLOCK_SHIFT_3D;
  /* Node 0 is a ghost node one layer below the box (support.h). */
  gm_shape_grid *shape_grid = &domain->shape_grid;
  shape_grid->shape = def->shape;
  shape_grid->dim = domain->dim;
  shape_grid->inv_cell = domain->inv_cell;
  for (int k = 0; k < 3; k++) {
    bool used = k < domain->dim;
    shape_grid->origin[k] =
        used ? def->origin[k] - GM_GHOST_LAYERS * def->cell_size : 0.0;
    shape_grid->last_node[k] =
        used ? domain->cells[k] + 2 * GM_GHOST_LAYERS : 0;
  }
  for (int k = 0; k < 3; k++)
    grid->blocks_per_axis[k] =
        k < domain->dim ? (shape_grid->last_node[k] >> grid->shift) + 1 : 1;
  status = allocate_scratch(domain);
  if (status == GM_OK)
    status = gm_pool_start(&domain->pool, def->worker_count, def->enqueue_task,
                           def->finish_task, def->task_user);
  if (status != GM_OK) {
    gm_domain_destroy(domain);
    CREATE_FAIL(status, "gm_domain_create: could not allocate %d workers",
                def->worker_count);
  }
  domain->materials = NULL;
  *out = domain;
  return GM_OK;
}

static void free_grid(gm_grid *grid) {
  gm_free(grid->block_key);
  gm_free(grid->neighbour);
  gm_free(grid->point_start);
  gm_free(grid->color_block);
  gm_free(grid->gap_slot);
  gm_free(grid->chunk_counts);
  gm_free(grid->hash_key);
  gm_free(grid->hash_value);
  gm_free(grid->mass);
  gm_free(grid->wall_force);
  gm_free(grid->wall_gap);
  gm_free(grid->wall_centre_gap);
  gm_free(grid->contact_wall);
  gm_free(grid->contact_force[0]);
  gm_free(grid->contact_force[1]);
  gm_free(grid->pool_wall);
  gm_free(grid->pool_normal);
  gm_free(grid->pool_tangent);
  gm_free(grid->pool_tangent_3d);
  gm_free(grid->pool_sums);
  gm_free(grid->rigid_material);
  gm_free(grid->rigid_impulse[0]);
  gm_free(grid->rigid_impulse[1]);
  gm_free(grid->rigid_impulse[2]);
  gm_free(grid->cell_rate_volume);
  gm_free(grid->cell_volume);
  gm_free(grid->point_rate);
  gm_free(grid->point_cell);
  for (int k = 0; k < 3; k++) {
    gm_free(grid->momentum[k]);
    gm_free(grid->force[k]);
  }
}

void gm_domain_destroy(gm_domain *domain) {
  if (!domain || domain->busy) /* never free a domain under a running step */
    return;
  gm_pool_stop(&domain->pool);
  gm_sources_free(domain);
  gm_points_free(&domain->points);
  gm_buffers_free(&domain->snapshot);
  gm_granular_free(domain);
  free_grid(&domain->grid);
  if (domain->scratch) {
    for (int w = 0; w < domain->worker_count; w++) {
      gm_free(domain->scratch[w].state_storage);
      gm_free(domain->scratch[w].gather);
    }
  }
  gm_free(domain->scratch);
  gm_free(domain->materials);
  gm_free(domain);
}

const char *gm_domain_last_error(const gm_domain *domain) {
  if (!domain)
    return "domain is NULL";
  return domain->last_error;
}

gm_status gm_domain_set_step_hook(gm_domain *domain, gm_step_hook_fn *hook,
                                  void *user) {
  if (!domain)
    return GM_ERR_NULL;
  if (domain->busy)
    return gm_set_error(domain, GM_ERR_BUSY,
                        "gm_domain_set_step_hook: called during a step");
  domain->hook = hook;
  domain->hook_user = user;
  return GM_OK;
}

gm_status gm_domain_get_time(const gm_domain *domain, double *time,
                             uint64_t *step_count) {
  if (!domain)
    return GM_ERR_NULL;
  if (!time && !step_count)
    return gm_set_error((gm_domain *)domain, GM_ERR_NULL,
                        "gm_domain_get_time: time and step_count are both "
                        "NULL");
  if (time)
    *time = domain->time;
  if (step_count)
    *step_count = domain->step_count;
  return GM_OK;
}

gm_status gm_domain_set_volumetric(gm_domain *domain,
                                   gm_volumetric volumetric) {
  if (!domain)
    return GM_ERR_NULL;
  if (domain->busy) /* one setting for all the passes of a step */
    return gm_set_error(domain, GM_ERR_BUSY,
                        "gm_domain_set_volumetric: called during a step");
  if (volumetric != GM_VOLUMETRIC_POINT &&
      volumetric != GM_VOLUMETRIC_CELL_MEAN)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_set_volumetric: %d is not a gm_volumetric "
                        "value",
                        (int)volumetric);
  /* Locking needs more constraints than a cell's nodes can meet: none in
   * 1D (one strain component). */
  if (volumetric == GM_VOLUMETRIC_CELL_MEAN && domain->dim == 1)
    return gm_set_error(domain, GM_ERR_UNSUPPORTED,
                        "gm_domain_set_volumetric: GM_VOLUMETRIC_CELL_MEAN "
                        "is for plane strain, axisymmetry and "
                        "GM_GEOMETRY_3D; a 1D domain has no volumetric "
                        "locking to remove");
  domain->volumetric = volumetric;
  return GM_OK;
}
