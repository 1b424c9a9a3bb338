/*
 * grid_update.c - the nodal update: velocities from momenta, accelerations
 * from forces (lumped mass, 004 eqs 3.14-3.16), and the box-wall boundary
 * conditions. After a condition changes a nodal velocity, the acceleration
 * is recomputed as (v_new - v_old)/dt so particle (FLIP) velocities and
 * nodal velocities agree on walls. The momentum arrays are overwritten with
 * velocities and the force arrays with accelerations, in place. Planar
 * walls (walls.c) act after the box faces, on nodes near them. With the
 * B-splines the ghost nodes then take the reflected values of their mirror
 * nodes instead of the held zeros (bspline_faces.c).
 */
#include "internal.h"

#include <math.h>

#include <string.h>

typedef struct update_context {
  gm_domain *domain;
  double dt; /* s */
  int mode;
} update_context;

/* Which velocity components of node (ix, iy) a wall or the axis holds.
 * Ghost nodes beyond a face (support.h) take that face's condition. */
static void constrained_components(const gm_domain *domain, int64_t ix,
                                   int64_t iy, bool fixed[2]) {
  const gm_wall_type *walls = domain->def.walls;
  fixed[0] = fixed[1] = false;
  int64_t index[2] = {ix, iy};
  for (int axis = 0; axis < domain->dim; axis++) {
    int64_t upper = domain->cells[axis] + GM_GHOST_LAYERS; /* box face node */
    for (int side = 0; side < 2; side++) {
      if (side ? index[axis] < upper : index[axis] > GM_GHOST_LAYERS)
        continue;
      gm_wall_type wall = walls[2 * axis + side];
      if (wall == GM_WALL_FIXED)
        fixed[0] = fixed[1] = true;
      else if (wall == GM_WALL_SLIP)
        fixed[axis] = true;
    }
  }
  /* Radial velocity vanishes on the symmetry axis r = 0. */
  if (domain->axisymmetric && ix <= GM_GHOST_LAYERS &&
      domain->def.origin[0] == 0.0)
    fixed[0] = true;
}

/* The planar walls (walls.c) on one node with mass; the acceleration is
 * made consistent with the constrained velocity again. */
static void apply_walls(const update_context *ctx, size_t node, int64_t ix,
                        int64_t iy, const double old_velocity[2],
                        double *block_force) {
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  int dim = domain->dim;
  double h = domain->def.cell_size;
  const double *origin = domain->shape_grid.origin; /* node 0 */
  double position[2] = {origin[0] + (double)ix * h,
                        dim > 1 ? origin[1] + (double)iy * h : 0.0};
  double velocity[2] = {grid->momentum[0][node],
                        dim > 1 ? grid->momentum[1][node] : 0.0};
  bool full = ctx->mode == GM_GRID_FULL;
  double before[2] = {velocity[0], velocity[1]};
  int first_wall = -1;
  const double *gap = grid->wall_gap + node * (size_t)domain->wall_count;
  if (!gm_walls_contact(domain, position, velocity, gap, ctx->dt,
                        full ? block_force : NULL, grid->mass[node] / ctx->dt,
                        &first_wall))
    return;
  for (int k = 0; k < dim; k++) {
    grid->momentum[k][node] = velocity[k];
    if (full)
      grid->force[k][node] = (velocity[k] - old_velocity[k]) / ctx->dt;
  }
  if (full) { /* the node's record for the traction profile */
    grid->contact_wall[node] = first_wall + 1;
    for (int k = 0; k < 2; k++)
      grid->contact_force[k][node] =
          grid->mass[node] / ctx->dt * (velocity[k] - before[k]);
  }
}

static void update_blocks(void *context, size_t begin, size_t end, int worker) {
  (void)worker;
  update_context *ctx = context;
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  int dim = domain->dim, shift = grid->shift;
  int64_t edge = (int64_t)1 << shift;
  double dt = ctx->dt;
  double damping = domain->def.damping; /* Cundall's local damping */
  for (size_t b = begin; b < end; b++) {
    int64_t base[2];
    gm_block_base(grid, grid->block_key[b], base);
    int64_t base_x = base[0], base_y = base[1];
    /* Does the block hold a box-face or ghost node (support.h)? */
    int64_t face_x = domain->cells[0] + GM_GHOST_LAYERS;
    int64_t face_y = domain->cells[1] + GM_GHOST_LAYERS;
    bool block_on_wall =
        base_x <= GM_GHOST_LAYERS || base_x + edge - 1 >= face_x ||
        (dim > 1 && (base_y <= GM_GHOST_LAYERS || base_y + edge - 1 >= face_y));
    bool near_walls =
        domain->wall_count > 0 && gm_walls_near_block(domain, base_x, base_y);
    double *block_force = NULL;
    if (domain->wall_count > 0) { /* this block's share of the wall forces */
      block_force = grid->wall_force + b * (size_t)grid->wall_stride * 2;
      if (ctx->mode == GM_GRID_FULL) {
        for (int w = 0; w < 2 * domain->wall_count; w++)
          block_force[w] = 0.0;
        memset(grid->contact_wall + b * GM_BLOCK_NODES, 0,
               GM_BLOCK_NODES * sizeof(int32_t));
      }
    }
    for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
      size_t node = b * GM_BLOCK_NODES + local;
      double mass = grid->mass[node];
      double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0; /* empty: 0 */
      double old_velocity[2] = {0.0, 0.0};
      for (int k = 0; k < dim; k++) {
        double *motion = &grid->momentum[k][node];
        old_velocity[k] = *motion * inverse_mass;
        if (ctx->mode == GM_GRID_VELOCITY_ONLY) {
          *motion = old_velocity[k];
          continue;
        }
        double force = grid->force[k][node];         /* N */
        if (damping > 0.0 && old_velocity[k] != 0.0) /* against the motion */
          force -= damping * fabs(force) * (old_velocity[k] > 0.0 ? 1.0 : -1.0);
        double acceleration = force * inverse_mass;
        grid->force[k][node] = acceleration;
        *motion = old_velocity[k] + acceleration * dt;
      }
      bool rigid = domain->rigid_count > 0 && grid->rigid_material[node] != 0;
      if (!block_on_wall && !near_walls && !rigid)
        continue;
      int64_t ix = base_x + (int64_t)(local & (size_t)(edge - 1));
      int64_t iy = dim > 1 ? base_y + (int64_t)(local >> shift) : 0;
      if (block_on_wall) {
        bool fixed[2];
        constrained_components(domain, ix, iy, fixed);
        for (int k = 0; k < dim; k++) {
          if (!fixed[k])
            continue;
          grid->momentum[k][node] = 0.0;
          if (ctx->mode != GM_GRID_VELOCITY_ONLY)
            grid->force[k][node] = -old_velocity[k] / dt;
        }
      }
      if (near_walls && mass > 0.0)
        apply_walls(ctx, node, ix, iy, old_velocity, block_force);
      if (rigid) /* last: a rigid body overrides walls where they meet */
        gm_rigid_constrain_node(domain, node, old_velocity, dt,
                                ctx->mode == GM_GRID_FULL);
    }
  }
}

void gm_grid_update(gm_domain *domain, double dt, int mode) {
  update_context ctx = {domain, dt, mode};
  gm_parallel_for(&domain->pool, domain->grid.block_count, update_blocks, &ctx);
  gm_bspline_mirror_ghosts(domain, mode); /* ghosts reflect their mirrors */
}
