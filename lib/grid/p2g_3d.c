/*
 * p2g_3d.c - particle-to-grid transfer in 3D: lumped nodal mass, momentum
 * and forces (004 eqs 3.13-3.15 with three axes), with linear shape
 * functions (trilinear, the 8 nodes of the point's cell), a GIMP box
 * (uGIMP, cpGIMP: up to 5 nodes per axis) or a B-spline (3 or 4 nodes per
 * axis; support_3d.h, the "wide" supports here). Either way the
 * weight of a node is a product of axis factors, formed node by node.
 * Blocks are 4 x 4 x 4 nodes (block_grid.h); they are scattered colour by
 * colour (8 colours, the parities of the block coordinates), each block by
 * one worker, so a node receives the points of one block at a time, in
 * block-key order and point order: the sums are bitwise identical for any
 * worker count. A block's points write straight into the grid through its
 * 8 neighbour links (slot ox + 2 oy + 4 oz): a linear point is binned by
 * its cell, a GIMP point by its support's lowest node (g2p_3d.c), so both
 * reach only the block and its upper neighbours. Rigid points take no
 * part (rigid.c: their nodes take the prescribed velocity instead).
 *
 * GM_TRANSFER_APIC (Jiang et al. 2015) adds the affine momentum: node i
 * gets m_p N_ip (v_p + C_p (x_i - x_p)) instead of m_p N_ip v_p, with
 * C_p = B_p D_p^-1 (apic_3d.h) for the GIMP boxes and the B-splines
 * (whose D_p is the constant h^2/4 I or h^2/3 I), whose D_p is bounded
 * below, and C_p itself, stored, for linear MPM (as in 2D: p2g.c says why
 * a stored B_p divided by the tent's D_p = diag(f (1 - f) h^2) blows up
 * near node planes). sum_i N_ip (x_i - x_p) = 0 keeps the total momentum
 * as FLIP's; sum_i N_ip (x_i - x_p) (x) (x_i - x_p) D_p^-1 = I hands the
 * grid the point's affine angular momentum m_p eps : (C_p D_p).
 */
#include "grid/grid.h"

#include "grid/apic_3d.h"

#include <math.h>

typedef struct p2g_3d_context {
  gm_domain *domain;
  const gm_p2g_pass *pass;
  const uint32_t *blocks; /* blocks of the colour being scattered */
  const double *velocity[3];
  const double *stress[6]; /* Pa, Voigt xx yy zz xy yz zx */
  const double *volume;    /* m^3, of the stress buffer */
  /* GM_TRANSFER_APIC: the affine matrix of the velocity buffer, row-major
   * (B_p, m^2/s, for GIMP; C_p, 1/s, for linear MPM); NULL otherwise. */
  const double *affine[9];
  bool skip_rigid;              /* the domain has rigid materials */
  bool rigid[GM_MAX_MATERIALS]; /* per material, when skip_rigid */
} p2g_3d_context;

/* Names the first point of a block whose host inputs (velocity, external
 * force) are not finite; x * 0 is 0 for finite x and NaN otherwise. */
static void check_inputs_3d(const p2g_3d_context *ctx,
                            gm_worker_scratch *scratch, uint32_t begin,
                            uint32_t end) {
  const gm_points *points = &ctx->domain->points;
  double screen = 0.0;
  for (uint32_t k = begin; k < end; k++) {
    size_t p = points->order[k];
    for (int c = 0; c < 3; c++) {
      screen += ctx->velocity[c][p] * 0.0;
      if (points->external_force[c])
        screen += points->external_force[c][p] * 0.0;
    }
    for (int c = 0; ctx->affine[0] && c < 9; c++)
      screen += ctx->affine[c][p] * 0.0;
  }
  if (screen == 0.0)
    return;
  for (uint32_t k = begin; k < end; k++) {
    size_t p = points->order[k];
    for (int c = 0; c < 3; c++) {
      double force =
          points->external_force[c] ? points->external_force[c][p] : 0.0;
      if (isfinite(ctx->velocity[c][p]) && isfinite(force))
        continue;
      gm_worker_error(
          scratch, GM_ERR_NOT_FINITE, p,
          "step: point id %lld has a non-finite %s (component "
          "%d); the step was not taken",
          (long long)points->id[p],
          isfinite(ctx->velocity[c][p]) ? "external force" : "velocity", c);
    }
    for (int c = 0; ctx->affine[0] && c < 9; c++)
      if (!isfinite(ctx->affine[c][p]))
        gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                        "step: point id %lld has a non-finite affine "
                        "matrix B_p (GM_FIELD_AFFINE component %d); the "
                        "step was not taken",
                        (long long)points->id[p], c);
  }
}

/* Point p's support as axis factors: per axis the local index of its
 * lowest node in the block whose lowest node is base, its span, weights
 * and gradients (1/m). Linear MPM: the point's cell, span 2 (wide is a
 * constant in each specialisation, so the linear loops keep their fixed
 * trip counts). False when a GIMP support cannot be computed or does not
 * lie in the block and its upper neighbours (its key disagrees with it). */
static GM_ALWAYS_INLINE bool
point_support_3d(const gm_domain *domain, const double *const position[3],
                 const double *const deformation[9], size_t p,
                 const int64_t base[3], const bool wide,
                 gm_box_support_3d *support, int64_t local[3]) {
  const double *origin = domain->shape_grid.origin; /* m, node 0 */
  double inv_cell = domain->inv_cell;               /* 1/m */
  if (!wide) {
    const int64_t mask = GM_BLOCK_EDGE_3D - 1;
    for (int axis = 0; axis < 3; axis++) {
      local[axis] =
          gm_shape_linear_axis(position[axis][p], origin[axis], inv_cell,
                               support->weight[axis], support->gradient[axis]) &
          mask;
      support->span[axis] = 2;
    }
    return true;
  }
  const gm_points *points = &domain->points;
  double x[3] = {position[0][p], position[1][p], position[2][p]}; /* m */
  double half[3];                                                 /* m */
  gm_box_half_edges_3d(domain->shape_grid.shape,
                       (const double *const *)points->domain_size, deformation,
                       p, half);
  if (!gm_box_support_compute_3d(&domain->shape_grid, x, half, support))
    return false;
  bool fits = true;
  for (int axis = 0; axis < 3; axis++) {
    local[axis] = support->lowest[axis] - base[axis];
    fits = fits && local[axis] >= 0 &&
           local[axis] + support->span[axis] <= 2 * GM_BLOCK_EDGE_3D;
  }
  return fits;
}

/* Point p's CPDI support (support_cpdi_3d.h) and the local index of its
 * lowest node in the block whose lowest node is base; false as
 * point_support_3d. */
static bool point_cpdi_support_3d(const gm_domain *domain,
                                  const double *const position[3],
                                  const double *const deformation[9], size_t p,
                                  const int64_t base[3],
                                  gm_cpdi_support_3d *support,
                                  int64_t local[3]) {
  const gm_points *points = &domain->points;
  double x[3] = {position[0][p], position[1][p], position[2][p]}; /* m */
  double half[3], f[9]; /* m; F row-major */
  gm_box_half_edges_3d(GM_SHAPE_CPDI,
                       (const double *const *)points->domain_size, deformation,
                       p, half);
  gm_deformation_rows_3d(deformation, p, f);
  if (!gm_cpdi_support_compute_3d(&domain->shape_grid, x, f, half, support))
    return false;
  bool fits = true;
  for (int axis = 0; axis < 3; axis++) {
    local[axis] = support->lowest[axis] - base[axis];
    fits = fits && local[axis] >= 0 &&
           local[axis] + support->span[axis] <= 2 * GM_BLOCK_EDGE_3D;
  }
  return fits;
}

/* Names a point whose GIMP or CPDI support cannot be scattered. */
static void report_support_3d(const gm_domain *domain,
                              gm_worker_scratch *scratch, size_t p) {
  gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                  "step: the support of point id %lld cannot be computed "
                  "or does not fit the block it was binned in; the step "
                  "was not taken",
                  (long long)domain->points.id[p]);
}

/* APIC's C_p (1/s) of point p and the offsets x_i - x_p (m) of its
 * support per axis: the stored C_p for linear MPM, B_p D_p^-1 for a box
 * or CPDI's dense support (dense, when cpdi; see the top of the file). */
static GM_ALWAYS_INLINE void
affine_of_point_3d(const p2g_3d_context *ctx, const double *const position[3],
                   size_t p, const gm_box_support_3d *support,
                   const gm_cpdi_support_3d *dense, const bool wide,
                   const bool cpdi, double offset[3][GM_SUPPORT_3D_MAX_SPAN],
                   double c[9]) {
  const gm_domain *domain = ctx->domain;
  double cell = domain->def.cell_size; /* m */
  if (!wide) {
    for (int axis = 0; axis < 3; axis++)
      gm_linear_offsets(support->weight[axis], cell, offset[axis]);
    for (int k = 0; k < 9; k++)
      c[k] = ctx->affine[k][p];
    return;
  }
  double b[9]; /* m^2/s */
  for (int k = 0; k < 9; k++)
    b[k] = ctx->affine[k][p];
  const int64_t *lowest = cpdi ? dense->lowest : support->lowest;
  const int *span = cpdi ? dense->span : support->span;
  for (int axis = 0; axis < 3; axis++)
    gm_apic_axis_offsets_3d(domain->shape_grid.origin[axis], cell, lowest[axis],
                            span[axis], position[axis][p], offset[axis]);
  if (cpdi)
    gm_apic_dense_velocity_3d(dense->weight, dense->span,
                              (const double(*)[GM_SUPPORT_3D_MAX_SPAN])offset,
                              b, c);
  else if (gm_shape_is_bspline(domain->shape_grid.shape))
    gm_apic_bspline_velocity_3d(domain->shape_grid.shape, cell, b, c);
  else
    gm_apic_box_velocity_3d(
        support, (const double(*)[GM_SUPPORT_3D_MAX_SPAN])offset, b, c);
}

/* do_mass, do_momentum, do_forces, wide, apic and cpdi are constants in
 * each specialisation below (scatter_block_3d), so each pass kind and
 * support gets its own loop; each field is summed alone, so leaving the
 * others out changes no bit. CPDI (wide) reads its dense weights and
 * gradients instead of the axis products. */
static GM_ALWAYS_INLINE void
scatter_block_3d_kind(const p2g_3d_context *ctx, gm_worker_scratch *scratch,
                      uint32_t block, const bool do_mass,
                      const bool do_momentum, const bool do_forces,
                      const bool wide, const bool apic, const bool cpdi) {
  const gm_domain *domain = ctx->domain;
  const gm_points *points = &domain->points;
  const gm_grid *grid = &domain->grid;
  const gm_point_buffers *current = &points->buffer[points->cur];
  const double *const *position = (const double *const *)current->position;
  /* What deforms the domains: CPDI's D, else F (gm_support_slots_3d). */
  const double *const *deformation = gm_support_slots_3d(domain, current);
  const double *gravity = domain->def.gravity; /* m/s^2 */
  const uint32_t *links = grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
  int64_t base[3] = {0, 0, 0}; /* the block's lowest node */
  if (wide || cpdi) {
    gm_block_coordinates_3d(grid, grid->block_key[block], base);
    for (int axis = 0; axis < 3; axis++)
      base[axis] <<= GM_BLOCK_SHIFT_3D;
  }
  for (uint32_t k = grid->point_start[block]; k < grid->point_start[block + 1];
       k++) {
    size_t p = points->order[k];
    if (ctx->skip_rigid && ctx->rigid[points->material[p]])
      continue;                /* rigid points take no part (rigid.c) */
    gm_box_support_3d support; /* weights and gradients (1/m) per axis */
    gm_cpdi_support_3d dense;  /* CPDI: per node */
    int64_t local[3];
    bool found = cpdi ? point_cpdi_support_3d(domain, position, deformation, p,
                                              base, &dense, local)
                      : point_support_3d(domain, position, deformation, p, base,
                                         wide, &support, local);
    if (!found) {
      report_support_3d(domain, scratch, p);
      continue;
    }
    double(*w)[GM_SUPPORT_3D_MAX_SPAN] = support.weight;
    double(*d)[GM_SUPPORT_3D_MAX_SPAN] = support.gradient;
    const int *spans = cpdi ? dense.span : support.span;
    int span_x = wide ? spans[0] : 2, span_y = wide ? spans[1] : 2,
        span_z = wide ? spans[2] : 2;
    double m = points->mass[p]; /* kg */
    double velocity[3] = {ctx->velocity[0][p], ctx->velocity[1][p],
                          ctx->velocity[2][p]};   /* m/s */
    double body[3] = {0.0, 0.0, 0.0};             /* N */
    double t[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; /* stress V, N m */
    if (do_forces) {
      for (int c = 0; c < 3; c++)
        body[c] =
            m * gravity[c] +
            (points->external_force[c] ? points->external_force[c][p] : 0.0);
      double V = ctx->volume[p];
      for (int c = 0; c < 6; c++)
        t[c] = ctx->stress[c][p] * V;
    }
    double offset[3][GM_SUPPORT_3D_MAX_SPAN]; /* m, x_i - x_p per axis */
    double affine[9];                         /* 1/s, C_p */
    if (do_momentum && apic)
      affine_of_point_3d(ctx, position, p, &support, &dense, wide, cpdi, offset,
                         affine);
    size_t entry = 0; /* CPDI: (c span_y + b) span_x + a */
    for (int c = 0; c < span_z; c++) {
      for (int b = 0; b < span_y; b++) {
        for (int a = 0; a < span_x; a++, entry++) {
          int64_t nx = local[0] + a, ny = local[1] + b, nz = local[2] + c;
          size_t node = gm_block_node_3d(links, nx, ny, nz);
          double weight =
              cpdi ? dense.weight[entry] : w[0][a] * w[1][b] * w[2][c];
          if (do_mass)
            grid->mass[node] += weight * m;
          if (do_momentum && !apic)
            for (int axis = 0; axis < 3; axis++)
              grid->momentum[axis][node] += weight * m * velocity[axis];
          if (do_momentum && apic) { /* m_p N (v_p + C_p (x_i - x_p)) */
            double o[3] = {offset[0][a], offset[1][b], offset[2][c]}; /* m */
            for (int axis = 0; axis < 3; axis++) {
              const double *row = affine + 3 * axis; /* 1/s */
              grid->momentum[axis][node] +=
                  weight * m *
                  (velocity[axis] +
                   (row[0] * o[0] + row[1] * o[1] + row[2] * o[2]));
            }
          }
          if (!do_forces)
            continue;
          double gx = cpdi ? dense.gradient[0][entry]
                           : d[0][a] * w[1][b] * w[2][c]; /* 1/m */
          double gy =
              cpdi ? dense.gradient[1][entry] : w[0][a] * d[1][b] * w[2][c];
          double gz =
              cpdi ? dense.gradient[2][entry] : w[0][a] * w[1][b] * d[2][c];
          /* f_i = N_i b - V sigma grad N_i (004 eq 3.15) */
          grid->force[0][node] +=
              weight * body[0] -
              (t[GM_XX] * gx + t[GM_XY] * gy + t[GM_ZX] * gz);
          grid->force[1][node] +=
              weight * body[1] -
              (t[GM_XY] * gx + t[GM_YY] * gy + t[GM_YZ] * gz);
          grid->force[2][node] +=
              weight * body[2] -
              (t[GM_ZX] * gx + t[GM_YZ] * gy + t[GM_ZZ] * gz);
        }
      }
    }
  }
}

/* The pass kinds of the three schemes (step.c), for one support and
 * transfer. */
static GM_ALWAYS_INLINE void
scatter_block_3d_shape(const p2g_3d_context *ctx, gm_worker_scratch *scratch,
                       uint32_t block, const bool wide, const bool apic,
                       const bool cpdi) {
  const gm_p2g_pass *pass = ctx->pass;
  if (pass->mass && pass->momentum && pass->forces)
    scatter_block_3d_kind(ctx, scratch, block, true, true, true, wide, apic,
                          cpdi);
  else if (pass->mass && pass->momentum)
    scatter_block_3d_kind(ctx, scratch, block, true, true, false, wide, apic,
                          cpdi);
  else if (pass->momentum && pass->forces)
    scatter_block_3d_kind(ctx, scratch, block, false, true, true, wide, apic,
                          cpdi);
  else if (pass->momentum)
    scatter_block_3d_kind(ctx, scratch, block, false, true, false, wide, apic,
                          cpdi);
  else /* no momentum: the transfer does not matter */
    scatter_block_3d_kind(ctx, scratch, block, pass->mass, false, pass->forces,
                          wide, false, cpdi);
}

static void scatter_block_3d(const p2g_3d_context *ctx,
                             gm_worker_scratch *scratch, uint32_t block) {
  bool wide = ctx->domain->shape_grid.shape != GM_SHAPE_LINEAR;
  bool apic = ctx->affine[0] != NULL;
  /* uGIMP, cpGIMP, the B-splines and CPDI are the wide shapes */
  if (ctx->domain->shape_grid.shape == GM_SHAPE_CPDI && !apic)
    scatter_block_3d_shape(ctx, scratch, block, true, false, true);
  else if (ctx->domain->shape_grid.shape == GM_SHAPE_CPDI)
    scatter_block_3d_shape(ctx, scratch, block, true, true, true);
  else if (!wide && !apic)
    scatter_block_3d_shape(ctx, scratch, block, false, false, false);
  else if (!wide)
    scatter_block_3d_shape(ctx, scratch, block, false, true, false);
  else if (!apic)
    scatter_block_3d_shape(ctx, scratch, block, true, false, false);
  else
    scatter_block_3d_shape(ctx, scratch, block, true, true, false);
}

static void scatter_blocks_3d(void *context, size_t begin, size_t end,
                              int worker) {
  const p2g_3d_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gm_grid *grid = &domain->grid;
  for (size_t item = begin; item < end; item++) {
    uint32_t block = ctx->blocks[item];
    if (ctx->pass->check_inputs)
      check_inputs_3d(ctx, &domain->scratch[worker], grid->point_start[block],
                      grid->point_start[block + 1]);
    scatter_block_3d(ctx, &domain->scratch[worker], block);
  }
}

static void clear_blocks_3d(void *context, size_t begin, size_t end,
                            int worker) {
  (void)worker;
  const p2g_3d_context *ctx = context;
  gm_grid *grid = &ctx->domain->grid;
  size_t first = begin * GM_BLOCK_NODES, last = end * GM_BLOCK_NODES;
  for (size_t node = first; node < last; node++) {
    if (ctx->pass->mass)
      grid->mass[node] = 0.0;
    for (int k = 0; k < 3; k++) {
      if (ctx->pass->momentum)
        grid->momentum[k][node] = 0.0;
      if (ctx->pass->forces)
        grid->force[k][node] = 0.0;
    }
  }
}

void gm_p2g_3d(gm_domain *domain, const gm_p2g_pass *pass) {
  gm_grid *grid = &domain->grid;
  gm_points *points = &domain->points;
  const gm_point_buffers *moving = &points->buffer[pass->velocity_buffer];
  const gm_point_buffers *stressed = &points->buffer[pass->stress_buffer];
  p2g_3d_context ctx;
  ctx.domain = domain;
  ctx.pass = pass;
  ctx.blocks = NULL;
  for (int k = 0; k < 3; k++)
    ctx.velocity[k] = moving->velocity[k];
  for (int k = 0; k < 6; k++)
    ctx.stress[k] = stressed->stress[k];
  ctx.volume = stressed->volume;
  /* B_p travels with the velocity it belongs to (MUSL's re-map reads the
   * velocities and affine matrices just gathered). */
  bool apic = domain->def.transfer == GM_TRANSFER_APIC;
  for (int k = 0; k < 9; k++)
    ctx.affine[k] = apic ? moving->affine[k] : NULL;
  ctx.skip_rigid = domain->rigid_count > 0;
  for (int m = 0; ctx.skip_rigid && m < domain->material_count; m++)
    ctx.rigid[m] = domain->materials[m].rigid;
  gm_parallel_for(&domain->pool, grid->block_count, clear_blocks_3d, &ctx);
  for (int colour = 0; colour < GM_BLOCK_COLOURS; colour++) {
    size_t first = grid->color_start[colour];
    size_t count = grid->color_start[colour + 1] - first;
    ctx.blocks = grid->color_block + first;
    gm_parallel_for(&domain->pool, count, scatter_blocks_3d, &ctx);
  }
}
