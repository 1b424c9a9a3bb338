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
#include "grid/grid.h"

#include <math.h>

#include <string.h>

typedef struct update_context {
  gm_domain *domain;
  double dt; /* s */
  int mode;
  bool wall_friction; /* planar walls apply Coulomb friction (see below) */
  gm_gap_layout gaps; /* the gap records' layout, once per update */
  bool face_acts[4];  /* 2D: face 2 axis + side may hold or limit its nodes */
} update_context;

/* Whether the planar walls' Coulomb friction acts in this grid update:
 * in the full update only, in every scheme. Coulomb's law bounds the
 * tangential impulse a contact exchanges by mu times the normal impulse
 * it exchanges in the same step (Bardenhagen, Brackbill & Sulsky 2000,
 * CMAME 187: 529-541, nodal friction on the momentum change; 004 algorithm
 * 3.1). The full update is the only pass in which the wall exchanges
 * momentum with the material (and the only one its impulse report
 * counts). A re-map (GM_GRID_VELOCITY_ONLY: the momenta re-mapped from the
 * updated points in USL and MUSL, USF's velocities before the stress
 * update) rebuilds nodal velocities from point velocities that already
 * carry the step's friction; the walls keep those velocities out of the
 * plane, but that correction is kinematic, no impulse, and friction on it
 * would be friction without a normal impulse of its own: taken a second
 * time, from MUSL's displacement (its re-mapped velocities move the
 * points, 002 sec 4.4 step 9) or from USL's and USF's strain rate.
 * Nairn, Hammerquist & Smith (2020, CMAME 362: 112859) likewise correct
 * for contact more than once per step (after the extrapolation to the
 * grid and after the momentum update); keeping the corrections of
 * velocities that exchange no momentum to the normal direction is this
 * library's rule.
 *
 * Measured before this rule was one (the re-maps of USL and USF applied
 * friction, MUSL's did not): with friction in MUSL's re-map a block at 40
 * deg on mu = 0.5, floor 0.7 cells above a row, slid 2.2 % short (it hops
 * on the wall and every landing gave the re-mapped velocities a normal
 * approach); without friction in USL's re-map a block at 30 deg on mu =
 * 0.4, floor 0.875 cells above a row, slid 2.7 % too far, which was the
 * friction lost in the strips (walls.c, gm_walls_share_friction) and is
 * gone since the second row of the bottom points' cells joins them
 * (+0.62 % now). Over the offsets of tests/physics/test_wall_offsets.c
 * and 20 floor offsets at 25, 30 and 40 deg the worst USL and USF slides
 * with this rule are +1.28 % and +0.99 %. With 1 x 1 and 3 x 3 points
 * per cell (30 deg, floor offsets 0-0.9 cells) the worst is +1.93 % (USL,
 * 1 x 1, 0.6 cells; +0.35 % at half the stable dt, so the contact's
 * chatter) and +1.64 % (USL, 3 x 3, 0.8 cells); friction in every re-map
 * gave +0.63 % and +1.34 % there but +1.89 % in MUSL with 2 x 2: it damps
 * the chatter rather than adding friction, and is not used. */
static bool wall_friction(int mode) {
  return mode == GM_GRID_FULL;
}

/* The box faces and the symmetry axis on node (ix, iy): which velocity
 * components they hold at zero (held), and the velocity with its approach
 * to a face limited (velocity, changed in place). Ghost nodes beyond a
 * face (support.h) take that face's condition.
 *
 * A face holds a component only where the node's material touches it
 * (wall_gaps.c measures the gap from the face to the domains of the
 * node's points). Farther away, the node may approach the face by the gap
 * in this step and only the excess of its normal velocity is removed, so
 * material a fraction of a cell above a face falls onto it; held at zero
 * regardless, a face node carrying the bottom points of a block 0.3-0.7
 * cells above a floor hung the block there (no point ever reached a
 * quarter of the free-fall impact speed). This is the contact detection
 * of multi-material MPM, contact only where the material has reached the
 * other body (Bardenhagen, Guilkey, Roessig, Brackbill, Witzel & Foster
 * 2001, "An improved contact algorithm for the material point method",
 * CMES 2: 509-522), with the face a rigid body and the gap measured
 * between the face and the points' domains, as walls.c does.
 *
 * A face holds its nodes, both ways, as version 0.1 held them, while the
 * gap is at most GM_FACE_RELEASE; beyond that the node may approach by
 * the gap less GM_CONTACT_TOLERANCE (the planar walls' contact
 * tolerance) and leave freely. The release gap is larger than the planar
 * walls' tolerance because the gap of material pressed against a face
 * creeps open as its points are compressed, their domains shrinking
 * toward their centres: with the walls' 3e-3 cells the fill of
 * tests/physics/test_silo_filling.c came off its symmetry face and was pushed
 * back (a ratchet, each compression closing a new gap), and the jitter let
 * Cundall's damping carry 3.9 % of the fill's weight (2.8 % with a release
 * at 0.05 cells that let closing nodes in). The price is that material
 * stops up to 0.01 cells short of a face it falls onto (measured 0.008
 * cells: a block falling 0.3 cells reaches 98.4 % of the impact speed).
 *
 * A symmetry face (GM_WALL_SYMMETRY) holds its nodes' normal velocity
 * whatever the gap: beyond it lies the mirror image of the material, which
 * never opens a gap. The faces of the B-splines are mirrors
 * (bspline_faces.c) and hold as before. */
static void constrain_faces(const gm_domain *domain,
                            const gm_gap_layout *layout, size_t node,
                            int64_t ix, int64_t iy, double dt,
                            double velocity[2], bool held[2]) {
  const gm_wall_type *walls = domain->def.walls;
  const gm_grid *grid = &domain->grid;
  held[0] = held[1] = false;
  int64_t index[2] = {ix, iy};
  int planes = layout->planes;
  double tolerance = GM_CONTACT_TOLERANCE * domain->def.cell_size; /* m */
  double release = GM_FACE_RELEASE * domain->def.cell_size;        /* m */
  for (int axis = 0; axis < domain->dim; axis++) {
    int64_t upper = domain->cells[axis] + GM_GHOST_LAYERS; /* box face node */
    for (int side = 0; side < 2; side++) {
      if (side ? index[axis] < upper : index[axis] > GM_GHOST_LAYERS)
        continue;
      int face = 2 * axis + side;
      gm_wall_type wall = walls[face];
      if (wall == GM_WALL_OPEN || wall == GM_WALL_PERIODIC)
        continue; /* periodic: the images take their owners' values */
      int slot = layout->face_slot[face];
      double gap =
          slot >= 0 && grid->mass[node] > 0.0
              ? grid->wall_gap[gm_gap_node(grid, node) * (size_t)planes +
                               (size_t)slot]
              : 0.0;                                    /* m */
      if (gap <= release || wall == GM_WALL_SYMMETRY) { /* touching */
        if (wall == GM_WALL_FIXED)
          held[0] = held[1] = true;
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
  /* Radial velocity vanishes on the symmetry axis r = 0. */
  if (domain->axisymmetric && ix <= GM_GHOST_LAYERS &&
      domain->def.origin[0] == 0.0)
    held[0] = true;
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
  size_t records = gm_gap_node(grid, node);
  const double *gap = grid->wall_gap + records * (size_t)ctx->gaps.planes;
  const double *centre_gap =
      grid->wall_centre_gap + records * (size_t)ctx->gaps.centres;
  gm_wall_pool_record record = {-1, 0.0, 0.0};
  bool acted =
      gm_walls_contact(domain, position, velocity, gap, centre_gap, ctx->dt,
                       ctx->wall_friction, full ? block_force : NULL,
                       grid->mass[node] / ctx->dt, &first_wall, &record);
  if (record.wall >= 0) { /* its friction is shared along the wall */
    grid->pool_wall[node] = record.wall + 1;
    grid->pool_normal[node] = record.normal_change;
    grid->pool_tangent[node] = record.tangent_before;
  }
  if (!acted)
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

#if defined(__GNUC__)
static inline gm_pair load_pair(const double *values) {
  gm_pair pair;
  memcpy(&pair, values, sizeof pair);
  return pair;
}

static inline void store_pair(double *values, gm_pair pair) {
  memcpy(values, &pair, sizeof pair);
}

/* update_free_block_2d's loops without damping, two nodes per pass
 * (gm_pair): 1 / mass where mass > 0 and 0 elsewhere, an empty node
 * dividing a stand-in 1 whose quotient is masked off, then
 * gm_node_accelerate's products with the force left as it is (no damping).
 * Each lane does the scalar loop's operations on one node, so the bits are
 * the scalar loop's; the scalar loop's test before the division (the
 * compiler may not divide speculatively) kept it from vectorising: the
 * granular cloud's node layers, mostly empty nodes, took about 56
 * instructions per node in the two updates of a step. */
static inline void
update_undamped_pair(const double *restrict mass, double *restrict momentum_x,
                     double *restrict momentum_y, double *restrict force_x,
                     double *restrict force_y, double dt, bool velocity_only) {
  const gm_pair zero = {0.0, 0.0}, one = {1.0, 1.0};
  gm_pair node_mass = load_pair(mass); /* kg */
  gm_pair_mask filled = (gm_pair_mask)(node_mass > zero);
  gm_pair divisor = (gm_pair)(((gm_pair_mask)node_mass & filled) |
                              ((gm_pair_mask)one & ~filled)); /* kg */
  gm_pair inverse = (gm_pair)((gm_pair_mask)(one / divisor) & filled);
  gm_pair velocity_x = load_pair(momentum_x) * inverse; /* m/s */
  gm_pair velocity_y = load_pair(momentum_y) * inverse;
  if (velocity_only) {
    store_pair(momentum_x, velocity_x);
    store_pair(momentum_y, velocity_y);
    return;
  }
  gm_pair acceleration_x = load_pair(force_x) * inverse; /* m/s^2 */
  gm_pair acceleration_y = load_pair(force_y) * inverse;
  store_pair(force_x, acceleration_x);
  store_pair(force_y, acceleration_y);
  store_pair(momentum_x, velocity_x + acceleration_x * dt);
  store_pair(momentum_y, velocity_y + acceleration_y * dt);
}

static void
update_undamped_pairs(const double *restrict mass, double *restrict momentum_x,
                      double *restrict momentum_y, double *restrict force_x,
                      double *restrict force_y, double dt, bool velocity_only) {
  for (size_t local = 0; local < GM_BLOCK_NODES; local += 2)
    update_undamped_pair(mass + local, momentum_x + local, momentum_y + local,
                         force_x + local, force_y + local, dt, velocity_only);
}
#endif

/* The nodes of a 2D block that no box face, planar wall or rigid body
 * touches: the loop of update_blocks without the per-node tests of the
 * mode, the dimension and the boundaries (the same expressions, so the
 * same bits). Most blocks of a scene are such blocks; the granular cloud's
 * node layers hold three times the plain cloud's nodes, most of them
 * empty (docs/performance.md, "The granular cloud"). */
static void update_free_block_2d(gm_grid *grid, size_t b, double dt,
                                 double damping, bool velocity_only) {
  size_t first = b * GM_BLOCK_NODES;
  const double *restrict mass = grid->mass + first;
  double *restrict momentum_x = grid->momentum[0] + first;
  double *restrict momentum_y = grid->momentum[1] + first;
  double *restrict force_x = grid->force[0] + first;
  double *restrict force_y = grid->force[1] + first;
#if defined(__GNUC__)
  if (velocity_only || !(damping > 0.0)) {
    update_undamped_pairs(mass, momentum_x, momentum_y, force_x, force_y, dt,
                          velocity_only);
    return;
  }
#endif
  if (velocity_only) {
    for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
      double inverse_mass = mass[local] > 0.0 ? 1.0 / mass[local] : 0.0;
      momentum_x[local] = momentum_x[local] * inverse_mass;
      momentum_y[local] = momentum_y[local] * inverse_mass;
    }
    return;
  }
  for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
    double inverse_mass = mass[local] > 0.0 ? 1.0 / mass[local] : 0.0;
    double *momentum[2] = {&momentum_x[local], &momentum_y[local]};
    double *force_of[2] = {&force_x[local], &force_y[local]};
    for (int k = 0; k < 2; k++)
      gm_node_accelerate(momentum[k], force_of[k], inverse_mass, damping, dt);
  }
}

/* A node's velocity after the faces' conditions (held components zero,
 * the others limited in velocity), its acceleration made consistent with
 * it again: (v_new - v_old) / dt. */
static inline void settle_node(gm_grid *grid, size_t node, int dim,
                               const double velocity[2], const bool held[2],
                               const double old_velocity[2], double dt,
                               bool velocity_only) {
  for (int k = 0; k < dim; k++) {
    if (held[k]) {
      grid->momentum[k][node] = 0.0;
      if (!velocity_only)
        grid->force[k][node] = -old_velocity[k] / dt;
    } else if (velocity[k] != grid->momentum[k][node]) { /* approach */
      grid->momentum[k][node] = velocity[k];
      if (!velocity_only)
        grid->force[k][node] = (velocity[k] - old_velocity[k]) / dt;
    }
  }
}

#if defined(__GNUC__)
/* Whether constrain_faces can change the nodes of 2D column ix (of row
 * iy): they are on or beyond a face that is neither open nor periodic,
 * or on the symmetry axis (face_acts, gm_grid_update). Elsewhere it
 * leaves the velocity as it is and holds nothing. */
static inline bool column_acts(const update_context *ctx, int64_t ix,
                               int64_t face_x) {
  return (ix <= GM_GHOST_LAYERS && ctx->face_acts[0]) ||
         (ix >= face_x && ctx->face_acts[1]);
}

static inline bool row_acts(const update_context *ctx, int64_t iy,
                            int64_t face_y) {
  return (iy <= GM_GHOST_LAYERS && ctx->face_acts[2]) ||
         (iy >= face_y && ctx->face_acts[3]);
}

/* A 2D block on the box's faces and nothing else (no planar wall, face
 * centre or rigid body near it), without damping or in a re-map: row by
 * row, two nodes at a time as in update_free_block_2d where no face acts
 * on them, the nodes of acting faces one by one with update_blocks'
 * expressions (so the same bits). An open or periodic face leaves its
 * nodes as the acceleration left them (constrain_faces skips it), so
 * its nodes are pairs too. A quarter of the granular cloud's node
 * layers' blocks are on a face, most of them on the open sides and top
 * of the bench's box; node by node they took about 95 instructions per
 * point-step (bench/results/2026-11-30-cloud23.md). */
static void update_face_block_2d(const update_context *ctx, size_t b,
                                 int64_t base_x, int64_t base_y) {
  gm_domain *domain = ctx->domain;
  gm_grid *grid = &domain->grid;
  int64_t edge = (int64_t)1 << grid->shift;
  int64_t face_x = domain->cells[0] + GM_GHOST_LAYERS;
  int64_t face_y = domain->cells[1] + GM_GHOST_LAYERS;
  double dt = ctx->dt;
  double damping = domain->def.damping; /* not > 0, or a re-map */
  bool velocity_only = ctx->mode == GM_GRID_VELOCITY_ONLY;
  unsigned acting_columns = 0; /* bit c: column base_x + c */
  for (int64_t column = 0; column < edge; column++)
    if (column_acts(ctx, base_x + column, face_x))
      acting_columns |= 1u << column;
  for (int64_t row = 0; row < edge; row++) {
    int64_t iy = base_y + row;
    unsigned acting = row_acts(ctx, iy, face_y) ? ~0u : acting_columns;
    size_t first = b * GM_BLOCK_NODES + (size_t)(row * edge);
    for (int64_t column = 0; column < edge; column += 2) {
      int64_t ix = base_x + column;
      size_t node = first + (size_t)column;
      if (!((acting >> column) & 3u)) {
        update_undamped_pair(grid->mass + node, grid->momentum[0] + node,
                             grid->momentum[1] + node, grid->force[0] + node,
                             grid->force[1] + node, dt, velocity_only);
        continue;
      }
      for (int64_t n = 0; n < 2; n++) {
        double mass = grid->mass[node + (size_t)n];
        double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0; /* empty: 0 */
        double old_velocity[2];
        for (int k = 0; k < 2; k++) {
          double *motion = &grid->momentum[k][node + (size_t)n];
          if (velocity_only)
            *motion = old_velocity[k] = *motion * inverse_mass;
          else
            old_velocity[k] =
                gm_node_accelerate(motion, &grid->force[k][node + (size_t)n],
                                   inverse_mass, damping, dt);
        }
        if (!((acting >> (column + n)) & 1u))
          continue; /* off the faces, or on open or periodic ones only */
        bool held[2];
        double velocity[2] = {grid->momentum[0][node + (size_t)n],
                              grid->momentum[1][node + (size_t)n]};
        constrain_faces(domain, &ctx->gaps, node + (size_t)n, ix + n, iy, dt,
                        velocity, held);
        settle_node(grid, node + (size_t)n, 2, velocity, held, old_velocity, dt,
                    velocity_only);
      }
    }
  }
}
#endif

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
    bool near_faces =
        gm_block_near_faces(domain, base, edge, GM_SUPPORT_MAX_SPAN);
    double *block_force = NULL;
    if (domain->wall_count > 0) { /* this block's share of the wall forces */
      block_force = grid->wall_force + b * (size_t)grid->wall_stride * 2;
      if (ctx->mode == GM_GRID_FULL) {
        for (int w = 0; w < 2 * domain->wall_count; w++)
          block_force[w] = 0.0;
        memset(grid->contact_wall + b * GM_BLOCK_NODES, 0,
               GM_BLOCK_NODES * sizeof(int32_t));
      }
      memset(grid->pool_wall + b * GM_BLOCK_NODES, 0,
             GM_BLOCK_NODES * sizeof(int32_t));
    }
    /* After the wall records are cleared: they stay cleared. */
    if (dim == 2 && !block_on_wall && !near_walls && !near_faces &&
        domain->rigid_count == 0) {
      update_free_block_2d(grid, b, dt, damping,
                           ctx->mode == GM_GRID_VELOCITY_ONLY);
      continue;
    }
#if defined(__GNUC__)
    if (dim == 2 && !near_walls && !near_faces && domain->rigid_count == 0 &&
        (ctx->mode == GM_GRID_VELOCITY_ONLY || !(damping > 0.0))) {
      update_face_block_2d(ctx, b, base_x, base_y);
      continue;
    }
#endif
    for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
      size_t node = b * GM_BLOCK_NODES + local;
      double mass = grid->mass[node];
      double inverse_mass = mass > 0.0 ? 1.0 / mass : 0.0; /* empty: 0 */
      double old_velocity[2] = {0.0, 0.0};
      for (int k = 0; k < dim; k++) {
        double *motion = &grid->momentum[k][node];
        if (ctx->mode == GM_GRID_VELOCITY_ONLY)
          *motion = old_velocity[k] = *motion * inverse_mass;
        else
          old_velocity[k] = gm_node_accelerate(motion, &grid->force[k][node],
                                               inverse_mass, damping, dt);
      }
      bool rigid = domain->rigid_count > 0 && grid->rigid_material[node] != 0;
      if (!block_on_wall && !near_walls && !near_faces && !rigid)
        continue;
      int64_t ix = base_x + (int64_t)(local & (size_t)(edge - 1));
      int64_t iy = dim > 1 ? base_y + (int64_t)(local >> shift) : 0;
      /* constrain_faces acts on face and ghost nodes only (and the
       * symmetry axis, a face node): the others of the block are left as
       * they are, without the call. */
      bool on_face = block_on_wall &&
                     (ix <= GM_GHOST_LAYERS || ix >= face_x ||
                      (dim > 1 && (iy <= GM_GHOST_LAYERS || iy >= face_y)));
      bool centres = near_faces && mass > 0.0;
      if (on_face || centres) {
        bool held[2] = {false, false};
        double velocity[2] = {grid->momentum[0][node],
                              dim > 1 ? grid->momentum[1][node] : 0.0};
        if (on_face)
          constrain_faces(domain, &ctx->gaps, node, ix, iy, dt, velocity, held);
        if (centres) {
          int64_t index[2] = {ix, iy};
          gm_limit_face_centres(
              domain, &ctx->gaps,
              grid->wall_centre_gap +
                  gm_gap_node(grid, node) *
                      (size_t)ctx->gaps.centres, /* wide: all planes */
              index, dt, velocity);
        }
        settle_node(grid, node, dim, velocity, held, old_velocity, dt,
                    ctx->mode == GM_GRID_VELOCITY_ONLY);
      }
      if (near_walls && mass > 0.0)
        apply_walls(ctx, node, ix, iy, old_velocity, block_force);
      if (rigid) { /* last: a rigid body overrides walls where they meet */
        gm_rigid_constrain_node(domain, node, old_velocity, dt,
                                ctx->mode == GM_GRID_FULL);
        if (domain->wall_count > 0)
          grid->pool_wall[node] = 0;
      }
    }
  }
}

void gm_grid_update(gm_domain *domain, double dt, int mode) {
  if (domain->dim == 3) { /* box faces only in 3D (grid_update_3d.c) */
    gm_grid_update_3d(domain, dt, mode);
    return;
  }
  update_context ctx = {.domain = domain,
                        .dt = dt,
                        .mode = mode,
                        .wall_friction = wall_friction(mode)};
  gm_gap_layout_of(domain, &ctx.gaps);
  for (int face = 0; face < 4; face++)
    ctx.face_acts[face] = domain->def.walls[face] != GM_WALL_OPEN &&
                          domain->def.walls[face] != GM_WALL_PERIODIC;
  if (domain->axisymmetric && domain->def.origin[0] == 0.0)
    ctx.face_acts[0] = true; /* the symmetry axis (constrain_faces) */
  gm_parallel_for(&domain->pool, domain->grid.block_count, update_blocks, &ctx);
}
