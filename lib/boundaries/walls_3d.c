/*
 * walls_3d.c - planar walls of any normal with Coulomb friction in 3D
 * (GM_GEOMETRY_3D; every shape, the B-splines but on or near the plane
 * of a box face they mirror, walls.c): the contact of walls.c on the
 * nodes of
 * the 3D grid, and its friction pooled over patches of the plane one cell
 * by one cell instead of one-cell strips along a line.
 *
 * The rule is the 2D one (walls.c, where its history and measurements
 * are): a node that shares the wall (on or behind the plane, or less than
 * a cell in front of it: its tent reaches behind the plane) and carries
 * mass loses the normal velocity by which it would approach the wall
 * faster than its material's gap allows (wall_gaps_3d.c); that change
 * dv_n is the wall's normal impulse per unit nodal mass (004 sec 3.3.2,
 * algorithm 3.1, in impulse form). Coulomb friction then bounds the
 * tangential impulse by mu times the normal one: per node first, then,
 * after the nodal update, on the sums of each patch (the nodes across
 * the plane at one place, behind and in front of it, and the rows up to
 * two cells in front whose material touches the wall: the 2D strips'
 * membership rule, unchanged). The tangential momentum of a patch is a
 * vector in the plane: the patch sticks when |T| <= mu_s N, otherwise
 * every node of it keeps the fraction 1 - mu_k N / |T| of its tangential
 * velocity, so the patch loses mu_k N against its sliding direction.
 * The wide shapes (uGIMP, cpGIMP, CPDI, the B-splines) get the
 * centre-gap rule of 2D
 * (walls.c, gm_walls_contact): their supports reach nodes in front of
 * those that share the wall, and a point gathering from a node that
 * shares it and from one farther out moving toward the wall could be
 * carried through the plane. Such a node may approach the wall by at most
 * the distance of the nearest point centre it carries, less the contact
 * tolerance, in the step (wall_gaps_3d.c measures it); where that binds
 * the node takes the wall's normal impulse and Coulomb friction as a node
 * that shares the wall does, and joins its patch. Their gaps are measured
 * over their GIMP, CPDI or B-spline supports (wall_gaps_3d.c; a quadratic
 * B-spline point on the plane has weight on nodes up to 1.5 cells in front
 * of it, a cubic one 2 cells). Linear MPM gets the
 * same bound on the nodes between one cell and |n_x| + |n_y| + |n_z|
 * cells in front of an oblique plane (gm_wall_tent_reach, walls.c), whose tents
 * still reach behind it; for a plane normal to an axis there are none, and its
 * contact is the 2D one.
 *
 * Patches: a node at x has plane coordinates s = (x - p).t1 and
 * u = (x - p).t2 (t1, t2 an orthonormal basis of the plane,
 * gm_wall_tangents_3d) and belongs to patch (round(s/h), round(u/h)).
 * For a wall on a node plane of the grid (normal along an axis) a patch
 * is one node column across the wall, as a 2D strip is; for an oblique
 * plane a patch holds the nodes whose projection falls in its square, as a
 * 2D strip of a tilted wall does.
 *
 * The pooling runs serially in block order, so the result does not
 * depend on the worker count.
 */
#include "boundaries/boundaries.h"

#include "shapes/shapes.h"

#include <math.h>
#include <string.h>

/* Doubles per patch: normal impulse (kg m/s), tangential momentum along
 * t1 and t2 (kg m/s), the largest material gap of its pushed nodes (m). */
#define GM_PATCH_SUMS 4

void gm_wall_tangents_3d(const gm_wall *wall, double t1[3], double t2[3]) {
  const double *n = wall->normal;
  /* t1: the grid axis least aligned with n, projected onto the plane (for
   * a normal along z, t1 = x and t2 = y: the patches are the grid's
   * columns). */
  int axis = 0;
  for (int k = 1; k < 3; k++)
    if (fabs(n[k]) < fabs(n[axis]))
      axis = k;
  double length = 0.0;
  for (int k = 0; k < 3; k++) {
    t1[k] = (k == axis ? 1.0 : 0.0) - n[axis] * n[k];
    length += t1[k] * t1[k];
  }
  length = sqrt(length); /* >= sqrt(2/3): n[axis]^2 <= 1/3 */
  for (int k = 0; k < 3; k++)
    t1[k] /= length;
  t2[0] = n[1] * t1[2] - n[2] * t1[1]; /* n x t1 */
  t2[1] = n[2] * t1[0] - n[0] * t1[2];
  t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

static double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Position (m) of node (ix, iy, iz) of the 3D grid. */
static void node_position(const gm_domain *domain, const int64_t index[3],
                          double position[3]) {
  double h = domain->def.cell_size;
  for (int k = 0; k < 3; k++)
    position[k] = domain->shape_grid.origin[k] + (double)index[k] * h;
}

/* The patches of wall w covering every node of the grid box (ghost
 * layers included): per plane axis the lowest index and the count. */
static void patch_range(const gm_domain *domain, int w, int64_t lowest[2],
                        int64_t count[2]) {
  const gm_wall *wall = &domain->walls[w];
  double t[2][3];
  gm_wall_tangents_3d(wall, t[0], t[1]);
  double h = domain->def.cell_size;
  double low[2] = {INFINITY, INFINITY}, high[2] = {-INFINITY, -INFINITY};
  for (int c = 0; c < 8; c++) {
    int64_t index[3];
    for (int k = 0; k < 3; k++)
      index[k] =
          (c >> k) & 1 ? domain->cells[k] + 2 * (int64_t)GM_GHOST_LAYERS : 0;
    double x[3];
    node_position(domain, index, x);
    for (int k = 0; k < 3; k++)
      x[k] -= wall->point[k];
    for (int a = 0; a < 2; a++) {
      double s = dot3(x, t[a]) / h; /* cells */
      low[a] = fmin(low[a], s);
      high[a] = fmax(high[a], s);
    }
  }
  for (int a = 0; a < 2; a++) {
    lowest[a] = (int64_t)floor(low[a]) - 1;
    count[a] = (int64_t)ceil(high[a]) + 2 - lowest[a];
  }
}

size_t gm_walls_patch_doubles_3d(const gm_domain *domain, int w) {
  int64_t lowest[2], count[2];
  patch_range(domain, w, lowest, count);
  return GM_PATCH_SUMS * (size_t)count[0] * (size_t)count[1];
}

static size_t patch_of(const gm_wall *wall, double t[2][3], const double x[3],
                       double h, const int64_t lowest[2],
                       const int64_t count[2]) {
  double relative[3] = {x[0] - wall->point[0], x[1] - wall->point[1],
                        x[2] - wall->point[2]};
  int64_t index[2];
  for (int a = 0; a < 2; a++) {
    int64_t i = (int64_t)floor(dot3(relative, t[a]) / h + 0.5) - lowest[a];
    index[a] = i < 0 ? 0 : i >= count[a] ? count[a] - 1 : i;
  }
  return (size_t)(index[0] * count[1] + index[1]);
}

bool gm_walls_near_block_3d(const gm_domain *domain, const int64_t base[3]) {
  double h = domain->def.cell_size;
  /* m, as gm_walls_near_block: the nodes that share a wall or join its
   * patches, and with the wide shapes those that may carry a point centre
   * near it, as far as a 3D support reaches (5 node planes) */
  double reach = domain->def.shape == GM_SHAPE_LINEAR
                     ? GM_STRIP_REACH * h
                     : (double)(GM_SUPPORT_3D_MAX_SPAN - 1) * h;
  for (int w = 0; w < domain->wall_count; w++) {
    const gm_wall *wall = &domain->walls[w];
    for (int c = 0; c < 8; c++) {
      int64_t index[3];
      for (int k = 0; k < 3; k++)
        index[k] = base[k] + ((c >> k) & 1) * GM_BLOCK_EDGE_3D;
      double x[3];
      node_position(domain, index, x);
      double distance = 0.0; /* m */
      for (int k = 0; k < 3; k++)
        distance += (x[k] - wall->point[k]) * wall->normal[k];
      if (distance < reach)
        return true;
    }
  }
  return false;
}

/* One wall against one node velocity (contact_one of walls.c in 3D):
 * the node may approach at approach_speed (m/s, >= 0); the excess is
 * removed, with per-node Coulomb friction when `friction` is set. Returns
 * whether it acted; *normal_change (m/s) and the tangential velocity
 * before friction along t1, t2 (m/s) are written then. */
static bool contact_one_3d(const gm_wall *wall, double t[2][3],
                           double velocity[3], double approach_speed,
                           bool friction, double *normal_change_out,
                           double tangent_out[2]) {
  const double *n = wall->normal;
  double normal_speed = dot3(velocity, n); /* m/s */
  if (normal_speed >= -approach_speed)
    return false;
  double normal_change = -approach_speed - normal_speed; /* m/s, > 0 */
  double tangent[3];
  for (int k = 0; k < 3; k++)
    tangent[k] = velocity[k] - normal_speed * n[k];
  double tangential_speed = sqrt(dot3(tangent, tangent));
  *normal_change_out = normal_change;
  tangent_out[0] = dot3(tangent, t[0]);
  tangent_out[1] = dot3(tangent, t[1]);
  double keep = 0.0; /* fraction of the tangential velocity kept */
  if (!friction)
    keep = 1.0;
  else if (tangential_speed > wall->friction_static * normal_change)
    keep = 1.0 - wall->friction_kinetic * normal_change / tangential_speed;
  for (int k = 0; k < 3; k++)
    velocity[k] = keep * tangent[k] - approach_speed * n[k];
  return true;
}

bool gm_walls_contact_3d(const gm_domain *domain, const double position[3],
                         double velocity[3], const double *gap,
                         const double *centre_gap, double dt, bool friction,
                         double *block_force, double mass_over_dt,
                         gm_wall_pool_record_3d *record) {
  bool acted = false;
  int acting = 0, sharing = 0, shared_wall = -1;
  double shared_tangent[2] = {0.0, 0.0}; /* m/s */
  double h = domain->def.cell_size;
  double tolerance = GM_CONTACT_TOLERANCE * h; /* m, as in walls.c */
  for (int w = 0; w < domain->wall_count; w++) {
    const gm_wall *wall = &domain->walls[w];
    double t[2][3];
    gm_wall_tangents_3d(wall, t[0], t[1]);
    double distance = 0.0; /* m, signed, into the material */
    for (int k = 0; k < 3; k++)
      distance += (position[k] - wall->point[k]) * wall->normal[k];
    bool shares = distance < GM_WALL_REACH * h;
    /* The rows 1-2 cells in front join the patches with linear shapes
     * only, as in 2D (walls.c, gm_walls_contact: there the wide shapes'
     * strips without them). Measured here with uGIMP on the floor face of
     * examples/column_collapse_3d (docs/3d.md, "Frictional box faces in
     * 3D"): with those rows the run-out fell 16 % (R0/6) and 9 % (R0/8)
     * short of the axisymmetric uGIMP run, without them +4.4 % and +3.6 %;
     * the sliding block of tests/physics/test_face_friction_3d.c stops
     * within 0.4 % of the closed form either way. The same with the
     * quadratic B-spline on that example's floor wall (2026-11-29, a = 1,
     * 2 x 2 x 2 points per cell; the axisymmetric run of the same column
     * 0.849 at R0/6, 0.897 at R0/8): 3D run-out 0.744 (-12.4 %) and
     * 0.814 (-9.3 %) with those rows, 0.898 (+5.7 %) and 0.933 (+4.0 %)
     * without; on the elastic block of tests/physics/test_walls_3d.c at
     * 30 deg on mu = 0.4 they would take the cubic B-spline's slide from
     * +2.9 % to +0.2 % of the closed form (docs/3d.md, "Planar walls with
     * the B-splines in 3D"), but a deforming flow is the case that
     * matters, so the B-splines stay without them. */
    bool strip_only = domain->def.shape == GM_SHAPE_LINEAR && !shares &&
                      distance < GM_STRIP_REACH * h;
    /* A node in front that carries a point centre near the wall
     * (centre_gap): its approach is bounded by that centre's distance, as
     * in 2D (walls.c). With the wide shapes every such node; with linear
     * ones those whose tent still reaches behind an oblique plane
     * (gm_wall_tent_reach, walls.c). */
    bool by_centre = !shares && centre_gap && centre_gap[w] < INFINITY &&
                     (domain->def.shape != GM_SHAPE_LINEAR ||
                      distance < gm_wall_tent_reach(wall) * h);
    const double *material_gap = shares ? gap : centre_gap;
    double approach = (shares || by_centre) && material_gap[w] > tolerance
                          ? (material_gap[w] - tolerance) / dt
                          : 0.0; /* m/s */
    double before[3] = {velocity[0], velocity[1], velocity[2]};
    double normal_change = 0.0, tangent_before[2] = {0.0, 0.0}; /* m/s */
    if (!(shares || by_centre) ||
        !contact_one_3d(wall, t, velocity, approach, friction, &normal_change,
                        tangent_before)) {
      /* in front of the plane: it may join its friction patch */
      if ((shares && distance > GM_ON_ROW * h) || strip_only) {
        sharing++;
        shared_wall = w;
        shared_tangent[0] = dot3(velocity, t[0]);
        shared_tangent[1] = dot3(velocity, t[1]);
      }
      continue;
    }
    if (record) {
      record->wall = w;
      record->normal_change = normal_change;
      record->tangent_before[0] = tangent_before[0];
      record->tangent_before[1] = tangent_before[1];
    }
    acting++;
    acted = true;
    if (block_force) /* force on the material: m dv / dt */
      for (int k = 0; k < 3; k++)
        block_force[3 * w + k] += mass_over_dt * (velocity[k] - before[k]);
  }
  if (record && acting == 0 && sharing == 1) {
    record->wall = shared_wall;
    record->normal_change = 0.0;
    record->tangent_before[0] = shared_tangent[0];
    record->tangent_before[1] = shared_tangent[1];
  } else if (record && acting != 1)
    record->wall = -1; /* none, or an edge of two walls: per-node Coulomb */
  return acted;
}

void gm_walls_share_friction_3d(gm_domain *domain, double dt, int mode) {
  gm_grid *grid = &domain->grid;
  if (domain->wall_count == 0)
    return;
  double h = domain->def.cell_size;
  int64_t lowest[GM_MAX_WALLS][2], count[GM_MAX_WALLS][2];
  double tangents[GM_MAX_WALLS][2][3];
  size_t first[GM_MAX_WALLS]; /* the wall's patches in pool_sums */
  size_t total = 0;
  for (int w = 0; w < domain->wall_count; w++) {
    patch_range(domain, w, lowest[w], count[w]);
    gm_wall_tangents_3d(&domain->walls[w], tangents[w][0], tangents[w][1]);
    first[w] = total;
    total += GM_PATCH_SUMS * (size_t)count[w][0] * (size_t)count[w][1];
  }
  memset(grid->pool_sums, 0, total * sizeof(double));
  int planes = gm_gap_plane_count(domain);
  double tolerance = GM_CONTACT_TOLERANCE * h; /* m */
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  /* In block order (deterministic): pass 0 the largest material gap of
   * the nodes the wall pushed in each patch, pass 1 the sums per patch,
   * pass 2 Coulomb's law on them (walls.c, gm_walls_share_friction). */
  for (int pass = 0; pass < 3; pass++) {
    for (size_t b = 0; b < grid->block_count; b++) {
      int64_t base[3];
      bool block_known = false;
      for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
        size_t node = b * GM_BLOCK_NODES + local;
        int w = grid->pool_wall[node] - 1;
        if (w < 0)
          continue;
        if (!block_known) {
          gm_block_coordinates_3d(grid, grid->block_key[b], base);
          for (int k = 0; k < 3; k++)
            base[k] <<= GM_BLOCK_SHIFT_3D;
          block_known = true;
        }
        int64_t index[3] = {base[0] + (int64_t)(local & (size_t)mask),
                            base[1] + (int64_t)((local >> 2) & (size_t)mask),
                            base[2] + (int64_t)(local >> 4)};
        double x[3];
        node_position(domain, index, x);
        const gm_wall *wall = &domain->walls[w];
        double(*t)[3] = tangents[w];
        double *sum =
            grid->pool_sums + first[w] +
            GM_PATCH_SUMS * patch_of(wall, t, x, h, lowest[w], count[w]);
        double mass = grid->mass[node]; /* kg */
        double gap = grid->wall_gap[gm_gap_node(grid, node) * (size_t)planes +
                                    (size_t)w]; /* m */
        bool pushed = grid->pool_normal[node] > 0.0;
        double tangent_before[2] = {grid->pool_tangent[node],
                                    grid->pool_tangent_3d[node]}; /* m/s */
        if (pass == 0) {
          if (pushed && gap > sum[3])
            sum[3] = gap;
          continue;
        }
        /* A node the wall did not push joins its patch if its material
         * is no farther from the wall than that of the pushed ones. */
        if (!pushed && gap > fmax(sum[3], tolerance))
          continue;
        if (pass == 1) {
          sum[0] += mass * grid->pool_normal[node];
          sum[1] += mass * tangent_before[0];
          sum[2] += mass * tangent_before[1];
          continue;
        }
        /* Pass 2: Coulomb on the patch's sums: stick when |T| <= mu_s N,
         * otherwise every node keeps the same fraction of its tangential
         * velocity and the patch loses mu_k N. */
        double normal_impulse = sum[0], momentum = hypot(sum[1], sum[2]);
        double keep = 0.0;
        if (momentum > wall->friction_static * normal_impulse)
          keep = 1.0 - wall->friction_kinetic * normal_impulse / momentum;
        double velocity[3] = {grid->momentum[0][node], grid->momentum[1][node],
                              grid->momentum[2][node]}; /* m/s */
        double change[2];                               /* m/s */
        for (int a = 0; a < 2; a++)
          change[a] = keep * tangent_before[a] - dot3(velocity, t[a]);
        if (change[0] == 0.0 && change[1] == 0.0)
          continue;
        for (int k = 0; k < 3; k++) {
          double dv = change[0] * t[0][k] + change[1] * t[1][k]; /* m/s */
          grid->momentum[k][node] += dv;
          if (mode == GM_GRID_FULL) {
            grid->force[k][node] += dv / dt;
            grid->wall_force[(b * (size_t)grid->wall_stride + (size_t)w) * 3 +
                             (size_t)k] += mass / dt * dv; /* N */
          }
        }
      }
    }
  }
}
