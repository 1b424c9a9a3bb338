/*
 * grid_update_3d.c - the nodal update in 3D: velocities from momenta,
 * accelerations from forces with lumped mass (004 eqs 3.14-3.16) and
 * Cundall's local damping, with the arithmetic of the 2D update
 * (grid_update.c), then the six box faces. The momentum arrays are
 * overwritten with velocities and the force arrays with accelerations, in
 * place.
 *
 * A node on or beyond a face (the face's node plane and the ghost layer
 * past it, support.h) takes that face's condition, by the rule of the 2D
 * faces (grid_update.c, constrain_faces): where its material touches the
 * face (gap at most GM_FACE_RELEASE cells, wall_gaps_3d.c; a node without
 * mass counts as touching) a fixed face holds all three velocity
 * components at zero, a slip face the normal one, an open face none;
 * farther away the node may approach the face by the gap less the contact
 * tolerance in this step and leave it freely, so material a fraction of a
 * cell above a face falls onto it instead of hanging there. A symmetry face
 * (GM_WALL_SYMMETRY) holds the normal component whatever the gap, and the
 * B-splines' faces are mirrors, not measured: they hold regardless, as
 * before. After a
 * condition changes a velocity the acceleration becomes (v_new - v_old)/dt,
 * so particle (FLIP) and nodal velocities agree on the faces. With the
 * wide shapes the nodes in front of a measured face carry a point centre
 * at most to it (boundaries/face_centres.c, the 2D faces' rule).
 *
 * Planar walls of any normal act after the faces, on the nodes near them
 * (walls_3d.c: the contact and Coulomb friction of walls.c, with the
 * friction pooled over patches of the plane after the nodal update, and
 * the wide shapes' centre-gap rule of the 2D walls).
 *
 * Rigid points act last, as in 2D (rigid.c): a node a rigid point reaches
 * takes the rigid material's prescribed velocity, all three components,
 * in every pass (a re-map included, so the re-mapped velocities move the
 * rigid points as prescribed), and in the full update its momentum change
 * against the prescribed velocity is the impulse on the rigid body. A
 * rigid body overrides faces and walls where they meet.
 */
#include "grid/grid.h"

#include <math.h>
#include <string.h>

typedef struct update_3d_context {
  gm_domain *domain;
  double dt; /* s */
  int mode;
  gm_gap_layout gaps; /* the gap records' layout, once per update */
} update_3d_context;

/* The planar walls (walls_3d.c) on one node with mass; the acceleration
 * is made consistent with the constrained velocity again. Friction acts
 * in the full update only, in every scheme, as in 2D (grid_update.c,
 * wall_friction: the only pass in which the wall exchanges momentum). */
static void apply_walls_3d(const update_3d_context *ctx, size_t node,
                           const int64_t index[3], const double old_velocity[3],
                           double *block_force) {
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  double h = domain->def.cell_size;
  double position[3], velocity[3]; /* m, m/s */
  for (int k = 0; k < 3; k++) {
    position[k] = domain->shape_grid.origin[k] + (double)index[k] * h;
    velocity[k] = grid->momentum[k][node];
  }
  bool full = ctx->mode == GM_GRID_FULL;
  size_t records = gm_gap_node(grid, node);
  const double *gap =
      grid->wall_gap + records * (size_t)gm_gap_plane_count(domain);
  int centres = gm_centre_gap_plane_count(domain); /* wide shapes: walls */
  const double *centre_gap =
      centres > 0 ? grid->wall_centre_gap + records * (size_t)centres : NULL;
  gm_wall_pool_record_3d record = {-1, 0.0, {0.0, 0.0}};
  bool acted = gm_walls_contact_3d(domain, position, velocity, gap, centre_gap,
                                   ctx->dt, full, full ? block_force : NULL,
                                   grid->mass[node] / ctx->dt, &record);
  if (record.wall >= 0) { /* its friction is shared over a patch */
    grid->pool_wall[node] = record.wall + 1;
    grid->pool_normal[node] = record.normal_change;
    grid->pool_tangent[node] = record.tangent_before[0];
    grid->pool_tangent_3d[node] = record.tangent_before[1];
  }
  if (!acted)
    return;
  for (int k = 0; k < 3; k++) {
    grid->momentum[k][node] = velocity[k];
    if (full)
      grid->force[k][node] = (velocity[k] - old_velocity[k]) / ctx->dt;
  }
}

/* The box faces on node (ix, iy, iz): which components they hold at zero
 * (held), and the velocity with its approach to a face limited (velocity,
 * changed in place); see the top of the file. */
static void constrain_faces_3d(const gm_domain *domain, size_t node,
                               const int64_t index[3], double dt,
                               double velocity[3], bool held[3]) {
  const gm_grid *grid = &domain->grid;
  int planes = gm_gap_plane_count(domain);
  double tolerance = GM_CONTACT_TOLERANCE * domain->def.cell_size; /* m */
  double release = GM_FACE_RELEASE * domain->def.cell_size;        /* m */
  held[0] = held[1] = held[2] = false;
  for (int axis = 0; axis < 3; axis++) {
    int64_t upper = domain->cells[axis] + GM_GHOST_LAYERS; /* face node */
    for (int side = 0; side < 2; side++) {
      if (side ? index[axis] < upper : index[axis] > GM_GHOST_LAYERS)
        continue;
      int face = 2 * axis + side;
      gm_wall_type wall = domain->def.walls[face];
      if (wall == GM_WALL_OPEN || wall == GM_WALL_PERIODIC)
        continue; /* periodic: the images take their owners' values */
      int slot = gm_gap_face_slot(domain, face);
      double gap =
          slot >= 0 && grid->mass[node] > 0.0
              ? grid->wall_gap[gm_gap_node(grid, node) * (size_t)planes +
                               (size_t)slot]
              : 0.0;                                    /* m */
      if (gap <= release || wall == GM_WALL_SYMMETRY) { /* touching */
        if (wall == GM_WALL_FIXED)
          held[0] = held[1] = held[2] = true;
        else
          held[axis] = true;
        continue;
      }
      double inward = side ? -1.0 : 1.0;        /* the face's normal */
      double approach = (gap - tolerance) / dt; /* m/s */
      if (inward * velocity[axis] < -approach)
        velocity[axis] = -inward * approach;
    }
  }
}

static void update_blocks_3d(void *context, size_t begin, size_t end,
                             int worker) {
  (void)worker;
  const update_3d_context *ctx = context;
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  double dt = ctx->dt;
  double damping = domain->def.damping; /* - */
  const int64_t edge = GM_BLOCK_EDGE_3D, mask = edge - 1;
  for (size_t b = begin; b < end; b++) {
    int64_t base[3];
    gm_block_coordinates_3d(grid, grid->block_key[b], base);
    bool on_face = false; /* does the block hold a face or ghost node? */
    for (int axis = 0; axis < 3; axis++) {
      base[axis] <<= GM_BLOCK_SHIFT_3D;
      on_face = on_face || base[axis] <= GM_GHOST_LAYERS ||
                base[axis] + edge - 1 >= domain->cells[axis] + GM_GHOST_LAYERS;
    }
    bool near_walls =
        domain->wall_count > 0 && gm_walls_near_block_3d(domain, base);
    bool near_faces = gm_block_near_faces(domain, base, GM_BLOCK_EDGE_3D,
                                          GM_SUPPORT_3D_MAX_SPAN);
    double *block_force = NULL;
    if (domain->wall_count > 0) { /* this block's share of the wall forces */
      block_force = grid->wall_force + b * (size_t)grid->wall_stride * 3;
      if (ctx->mode == GM_GRID_FULL)
        for (int w = 0; w < 3 * domain->wall_count; w++)
          block_force[w] = 0.0;
      memset(grid->pool_wall + b * GM_BLOCK_NODES, 0,
             GM_BLOCK_NODES * sizeof(int32_t));
    }
    for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
      size_t node = b * GM_BLOCK_NODES + local;
      double mass = grid->mass[node];                      /* kg */
      double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0; /* empty: 0 */
      double old_velocity[3];                              /* m/s */
      for (int k = 0; k < 3; k++) {
        double *motion = &grid->momentum[k][node];
        if (ctx->mode == GM_GRID_VELOCITY_ONLY)
          *motion = old_velocity[k] = *motion * inverse_mass;
        else
          old_velocity[k] = gm_node_accelerate(motion, &grid->force[k][node],
                                               inverse_mass, damping, dt);
      }
      bool rigid = domain->rigid_count > 0 && grid->rigid_material[node] != 0;
      if (!on_face && !near_walls && !near_faces && !rigid)
        continue;
      int64_t index[3] = {base[0] + (int64_t)(local & (size_t)mask),
                          base[1] + (int64_t)((local >> 2) & (size_t)mask),
                          base[2] + (int64_t)(local >> 4)};
      bool held[3];
      double velocity[3] = {grid->momentum[0][node], grid->momentum[1][node],
                            grid->momentum[2][node]}; /* m/s */
      constrain_faces_3d(domain, node, index, dt, velocity, held);
      if (near_faces && mass > 0.0)
        gm_limit_face_centres(
            domain, &ctx->gaps,
            grid->wall_centre_gap +
                node * (size_t)ctx->gaps.centres, /* wide: all planes */
            index, dt, velocity);
      for (int k = 0; k < 3; k++) {
        if (held[k]) {
          grid->momentum[k][node] = 0.0;
          if (ctx->mode != GM_GRID_VELOCITY_ONLY)
            grid->force[k][node] = -old_velocity[k] / dt;
        } else if (velocity[k] != grid->momentum[k][node]) { /* approach */
          grid->momentum[k][node] = velocity[k];
          if (ctx->mode != GM_GRID_VELOCITY_ONLY)
            grid->force[k][node] = (velocity[k] - old_velocity[k]) / dt;
        }
      }
      if (near_walls && mass > 0.0)
        apply_walls_3d(ctx, node, index, old_velocity, block_force);
      if (rigid) { /* last: a rigid body overrides faces and walls */
        gm_rigid_constrain_node(domain, node, old_velocity, dt,
                                ctx->mode == GM_GRID_FULL);
        if (domain->wall_count > 0)
          grid->pool_wall[node] = 0; /* no share in the patches' friction */
      }
    }
  }
}

void gm_grid_update_3d(gm_domain *domain, double dt, int mode) {
  update_3d_context ctx = {domain, dt, mode, {0, 0, {0}}};
  gm_gap_layout_of(domain, &ctx.gaps);
  gm_parallel_for(&domain->pool, domain->grid.block_count, update_blocks_3d,
                  &ctx);
  if (mode == GM_GRID_FULL && domain->wall_count > 0) /* serial */
    gm_walls_share_friction_3d(domain, dt, mode);
}
