/*
 * walls.c - rigid planar walls with Coulomb friction, enforced on grid
 * nodes (004 sec 3.3.2 and algorithm 3.1; the nodal contact of 002 sec
 * 4.2 without its penalty regularisation).
 *
 * A node on or behind a wall plane that moves into it (v.n < 0) has its
 * normal velocity removed: that change dv_n = -v.n is the wall's normal
 * impulse per unit nodal mass. Friction can then remove up to mu dv_n of
 * the tangential velocity: if the tangential speed is at most mu_s dv_n
 * the node sticks, otherwise it slides and loses mu_k dv_n of it (Coulomb:
 * tangential impulse <= mu times normal impulse). Nodes moving away from
 * the wall are free, so material can leave it. After the nodal update
 * Coulomb's law is applied again to the sums of one-cell strips along the
 * wall (gm_walls_share_friction below). Nodes in front of the plane
 * that carry a point centre near it may approach it at most by that
 * centre's distance (the centre-gap rule, gm_walls_contact): all of them
 * with the shapes wider than a tent, and with linear shapes those less
 * than h (|n_x| + |n_y|) in front of an oblique plane (gm_wall_tent_reach),
 * the band rule of 3D (walls_3d.c). We work with the impulse
 * rather than 002's penalty-regularised tangential force because it needs
 * no penalty parameter and is exact for a node that sticks.
 */
#include "boundaries/boundaries.h"

#include <math.h>

/* Doubles per friction strip: normal impulse, tangential momentum, the
 * largest material gap of its pushed nodes, and the node whose traction
 * entry takes the friction of the rows a cell or more in front (+1; 0:
 * none). */
#define GM_STRIP_SUMS 4
#include <stdlib.h>
#include <string.h>

/* Every shape takes planar walls anywhere, of any normal (in 3D
 * walls_3d.c; the wide shapes' centre-gap rule of 2D since 2026-11-28,
 * the B-splines since 2026-11-29, their supports measured in
 * wall_gaps_3d.c), but for one place with the B-splines, in every
 * geometry: on or near the plane of a box face that holds material (slip,
 * fixed, symmetry; and the axis r = 0 in axisymmetry, whatever its
 * walls[] entry). Such a face is a mirror for them (grid/bspline_faces.c):
 * it folds the ghost nodes' mass and momentum into the nodes inside and,
 * after the update, gives the ghosts their mirror nodes' reflected
 * velocities, free along the face (slip, symmetry). A wall on that plane
 * would push and rub on the same face and ghost nodes, whose velocities
 * the mirror then overwrites, and its reported impulse would count what
 * the mirror undoes; the face already is that wall without friction. A
 * parallel wall less than a support radius (1.5 cells quadratic, 2 cubic;
 * shape_bspline.h) from the face's plane, on either side, would have
 * material at it whose support reaches the face's nodes: refused, naming
 * the face (use an open face with the wall on its plane for a frictional
 * B-spline face, which test_face_friction_3d.c's test_which_walls and
 * test_face_mirror_walls.c accept). In 1D and 2D it was accepted until
 * 2026-11-29 and the friction lost: a block at 0.6 m/s on mu = 0.2 on
 * the plane of a slip floor face kept its speed (Coulomb: 0.21 m/s after
 * 0.2 s), with the floor half a cell above the face it still moved at
 * 0.31-0.37 m/s, and on a fixed face the block stuck
 * (test_face_mirror_walls.c). A wall 2 cells or more inside, as the 3D
 * silo's side walls (examples/papers/wieckowski1999_silo_discharge.c),
 * never meets the mirror's nodes; an oblique wall crosses a face along a
 * line, where its material meets both as at any corner of two walls. */

/* Whether box face `face` is the axis r = 0 of an axisymmetric domain,
 * which the B-splines mirror whatever its walls[] entry. */
static bool is_symmetry_axis(const gm_domain *domain, int face) {
  return face == GM_FACE_XMIN && domain->axisymmetric &&
         domain->def.origin[0] == 0.0;
}

/* Whether the B-splines mirror box face `face` (as face_signs in
 * grid/bspline_faces.c): a face that holds material, or the axis. */
static bool bspline_mirrors_face(const gm_domain *domain, int face) {
  gm_wall_type type = domain->def.walls[face];
  return is_symmetry_axis(domain, face) ||
         (type != GM_WALL_OPEN && type != GM_WALL_PERIODIC); /* periodic:
                                    images of the other side, no mirror */
}

static gm_status check_bspline_mirrors(gm_domain *domain,
                                       const double normal[3],
                                       const double point[3]) {
  static const char *const names[6] = {"xmin", "xmax", "ymin",
                                       "ymax", "zmin", "zmax"};
  if (!gm_shape_is_bspline(domain->def.shape))
    return GM_OK;
  double h = domain->def.cell_size; /* m */
  double radius =                   /* cells */
      domain->def.shape == GM_SHAPE_BSPLINE2 ? 1.5 : 2.0;
  for (int face = 0; face < 2 * domain->dim; face++) {
    if (!bspline_mirrors_face(domain, face))
      continue;
    int axis = face / 2, side = face % 2;
    /* parallel: the normal along the face's axis (unit, so the others 0) */
    if (normal[(axis + 1) % 3] != 0.0 || normal[(axis + 2) % 3] != 0.0)
      continue;
    double plane = domain->def.origin[axis] +
                   (side ? (double)domain->cells[axis] * h : 0.0); /* m */
    double apart = fabs(point[axis] - plane) / h;                  /* cells */
    if (apart < radius)
      return gm_set_error(
          domain, GM_ERR_UNSUPPORTED,
          "gm_domain_add_wall: wall %d lies %.3g cells from the %s box face "
          "(gm_domain_def.walls[%d] = %d%s), parallel to it; with the "
          "B-spline shapes (gm_domain_def.shape %d) that face is a mirror, "
          "and a wall less than %.3g cells from it is not supported in "
          "this version (the mirror would undo its friction): %s, or keep the "
          "wall "
          "%.3g cells or more from it",
          domain->wall_count, apart, names[face], face,
          (int)domain->def.walls[face],
          is_symmetry_axis(domain, face) ? ", the symmetry axis r = 0" : "",
          (int)domain->def.shape, radius,
          is_symmetry_axis(domain, face)
              ? "start the grid at r > 0 (gm_domain_def.origin[0]) with "
                "the face GM_WALL_OPEN to put a wall on its plane"
              : "make the face GM_WALL_OPEN to put a wall on its plane",
          radius);
  }
  return GM_OK;
}

gm_status gm_domain_add_wall(gm_domain *domain, const gm_wall_def *def,
                             int *wall_id) {
  gm_wall_def full;
  gm_status status =
      gm_api_take_def(domain, "gm_domain_add_wall", GM_LAYOUT_WALL_DEF, def,
                      &full, wall_id, "wall_id");
  if (status != GM_OK)
    return status;
  def = &full;
  if (domain->wall_count >= GM_MAX_WALLS)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_wall: at most %d walls", GM_MAX_WALLS);
  /* A wall's contact and friction act on every node near it, the images
   * beyond a periodic face included, so its force would count the seam's
   * nodes twice (and its friction strips are not periodic). */
  if (gm_periodic_x(domain))
    return gm_set_error(domain, GM_ERR_UNSUPPORTED,
                        "gm_domain_add_wall: planar walls are not supported "
                        "with periodic x faces (GM_WALL_PERIODIC) in this "
                        "version; use the box's y faces");
  double length_squared = 0.0;
  for (int k = 0; k < 3; k++) {
    if (!isfinite(def->point[k]) || !isfinite(def->normal[k]))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_wall_def.point[%d] / normal[%d] must be finite",
                          k, k);
    /* The friction strips are measured along the plane from this point
     * in cells (int64): a point 1e306 m away (found by fuzz/fuzz_api)
     * overflowed them. A billion cells is far beyond any grid. */
    if (k < domain->dim && !(fabs(def->point[k] - domain->def.origin[k]) <=
                             1e9 * domain->def.cell_size))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_wall_def.point[%d] is %g m, more than 1e9 "
                          "cells from the grid origin",
                          k, def->point[k]);
    if (k >= domain->dim && def->normal[k] != 0.0)
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_wall_def.normal[%d] is %g but must be 0 in a "
                          "%dD geometry",
                          k, def->normal[k], domain->dim);
    length_squared += def->normal[k] * def->normal[k];
  }
  if (!(length_squared > 0.0))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_wall_def.normal is the zero vector");
  double mu_s = def->friction_static, mu_k = def->friction_kinetic;
  if (!(mu_s >= 0.0 && isfinite(mu_s)) || !(mu_k >= 0.0 && mu_k <= mu_s))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_wall_def: friction_static = %g and "
                        "friction_kinetic = %g must satisfy 0 <= kinetic <= "
                        "static",
                        mu_s, mu_k);
  double inverse_length = 1.0 / sqrt(length_squared);
  double unit[3]; /* the unit normal, as stored below */
  for (int k = 0; k < 3; k++)
    unit[k] = def->normal[k] * inverse_length;
  status = check_bspline_mirrors(domain, unit, def->point);
  if (status != GM_OK)
    return status;
  gm_wall *wall = &domain->walls[domain->wall_count];
  for (int k = 0; k < 3; k++) {
    /* Coordinates beyond the geometry's mean nothing (the nodes of a 1D
     * grid all lie at y = 0) and are not range-checked above: a 1D wall at
     * y = -1.6e29 m (found by fuzz/fuzz_api) overflowed the friction-strip
     * index, which measures along the plane. They are stored as 0. */
    wall->point[k] = k < domain->dim ? def->point[k] : 0.0;
    wall->normal[k] = unit[k];
  }
  wall->friction_static = mu_s;
  wall->friction_kinetic = mu_k;
  domain->wall_report[domain->wall_count] = (gm_force_report){0};
  *wall_id = domain->wall_count++;
  return GM_OK;
}

/* The part of vector along the unit normal, and the length of the rest. */
static void split_along(const double *vector, const double *normal,
                        double *along, double *across) {
  *along = vector[0] * normal[0] + vector[1] * normal[1];
  *across =
      hypot(vector[0] - *along * normal[0], vector[1] - *along * normal[1]);
}

/* The same in 3D. */
static void split_along_3d(const double vector[3], const double normal[3],
                           double *along, double *across) {
  *along =
      vector[0] * normal[0] + vector[1] * normal[1] + vector[2] * normal[2];
  *across = hypot(
      hypot(vector[0] - *along * normal[0], vector[1] - *along * normal[1]),
      vector[2] - *along * normal[2]);
}

gm_status gm_domain_get_wall_force(const gm_domain *domain, int wall_id,
                                   gm_wall_force *force) {
  /* The layout before the impulse fields were appended is accepted: only
   * that prefix is written (api_check.h). */
  gm_status status = gm_api_check_result(domain, "gm_domain_get_wall_force",
                                         GM_LAYOUT_WALL_FORCE, force, "force");
  if (status != GM_OK)
    return status;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  if (wall_id < 0 || wall_id >= domain->wall_count)
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_get_wall_force: wall %d is unknown (%d "
                        "walls)",
                        wall_id, domain->wall_count);
  const gm_wall *wall = &domain->walls[wall_id];
  const gm_force_report *report = &domain->wall_report[wall_id];
  gm_wall_force result = gm_wall_force_default();
  for (int k = 0; k < 3; k++) { /* z: 0 below 3D */
    result.force[k] = report->force[k];
    result.impulse[k] = report->impulse[k];
    result.total_impulse[k] = report->total_impulse[k];
    result.smoothed_force[k] = report->smoothed_force[k];
  }
  void (*split)(const double *, const double *, double *, double *) =
      domain->dim == 3 ? split_along_3d : split_along;
  split(result.force, wall->normal, &result.normal, &result.tangential);
  split(result.impulse, wall->normal, &result.normal_impulse,
        &result.tangential_impulse);
  split(result.smoothed_force, wall->normal, &result.smoothed_normal,
        &result.smoothed_tangential);
  result.duration = report->duration;
  result.total_duration = report->total_duration;
  result.smoothing_time = domain->force_smoothing_time;
  gm_api_give_result(GM_LAYOUT_WALL_FORCE, force, &result);
  return GM_OK;
}

bool gm_walls_near_block(const gm_domain *domain, int64_t base_x,
                         int64_t base_y) {
  double h = domain->def.cell_size;
  /* m: the nodes that share a wall or join its friction strips, and with
   * the wide shapes those that may carry a point centre near it (see
   * gm_walls_contact), as far as a support reaches (wall_gaps.c) */
  double reach = domain->def.shape == GM_SHAPE_LINEAR
                     ? GM_STRIP_REACH * h
                     : (double)(GM_SUPPORT_MAX_SPAN - 1) * h;
  int64_t edge = (int64_t)1 << domain->grid.shift;
  int corners = domain->dim > 1 ? 4 : 2;
  for (int w = 0; w < domain->wall_count; w++) {
    const gm_wall *wall = &domain->walls[w];
    for (int c = 0; c < corners; c++) {
      const double *origin = domain->shape_grid.origin; /* node 0 */
      double x = origin[0] + (double)(base_x + (c & 1) * edge) * h;
      double y = domain->dim > 1
                     ? origin[1] + (double)(base_y + (c >> 1) * edge) * h
                     : wall->point[1];
      double distance = (x - wall->point[0]) * wall->normal[0] +
                        (y - wall->point[1]) * wall->normal[1];
      if (distance < reach)
        return true;
    }
  }
  return false;
}

/* One wall against one node velocity; returns whether it acted. The node
 * may approach the wall at up to approach_speed (m/s, >= 0: the gap of its
 * material to the wall over dt), so material that has left the wall can
 * come back to it; only the excess is removed, with Coulomb friction on
 * that normal impulse (004 algorithm 3.1) when `friction` is set. */
static bool contact_one(const gm_wall *wall, double velocity[2],
                        double approach_speed, bool friction,
                        double *normal_change_out, double *tangent_out) {
  double normal_speed =
      velocity[0] * wall->normal[0] + velocity[1] * wall->normal[1];
  if (normal_speed >= -approach_speed)
    return false; /* leaving, or not reaching the wall in this step */
  double normal_change = -approach_speed - normal_speed; /* m/s, > 0 */
  double tangent[2] = {velocity[0] - normal_speed * wall->normal[0],
                       velocity[1] - normal_speed * wall->normal[1]};
  double tangential_speed = hypot(tangent[0], tangent[1]);
  *normal_change_out = normal_change;
  *tangent_out = tangent[0] * wall->normal[1] - tangent[1] * wall->normal[0];
  double keep = 0.0; /* fraction of the tangential velocity kept */
  if (!friction)
    keep = 1.0;
  else if (tangential_speed > wall->friction_static * normal_change)
    keep = 1.0 - wall->friction_kinetic * normal_change / tangential_speed;
  velocity[0] = keep * tangent[0] - approach_speed * wall->normal[0];
  velocity[1] = keep * tangent[1] - approach_speed * wall->normal[1];
  return true;
}

/* Cells (less GM_ON_ROW) in front of the plane within which a node's
 * linear tent, the square (2D) or cube (3D) of half edge h about it,
 * reaches behind the plane: |n_x| + |n_y| + |n_z| (n_z = 0 in 2D), 1 for
 * a normal along an axis, up to sqrt(2) in 2D and sqrt(3) in 3D for an
 * oblique one. The contact's sharing nodes are those within one cell
 * (GM_WALL_REACH); a node between one cell and this reach is a corner of
 * a cell that the plane cuts, so it carries points whose centres lie on
 * the plane, with weight, and moving toward the wall unchecked it carried
 * them through it: in 3D with the normal (0.25, 0.35, 1) such a node lies
 * up to 1.47 cells in front, and a block of linear points falling onto
 * that plane at 1 m/s had a centre 3.3e-5 m behind it within 2 ms; in 2D
 * with the normal (0.6, -1) 4.4e-5 m (FLIP) and 3.9e-5 m (APIC) at the
 * first 2 ms (tests/physics/test_wall_watertight.c; docs/3d.md, "Linear
 * MPM through oblique walls"). Such a node gets the wide shapes'
 * centre-gap bound: it may approach the wall by at most the distance of
 * the nearest point centre it carries, less the contact tolerance, in the
 * step (a point's motion is a convex combination of its nodes'). A node
 * d >= h (|n_x| + |n_y| + |n_z|) in front carries a point c from the
 * plane with weight at most prod_k min(1, c / (|n_k| h)) (the point lies
 * within c of the cell's far corner along n), so it would have to move
 * more than c toward the wall in the step to carry that point through:
 * those nodes stay free (a centre-gap bound on every linear node changed
 * a sliding block's normal force by 2.7 %, gm_walls_contact). */
double gm_wall_tent_reach(const gm_wall *wall) {
  return fabs(wall->normal[0]) + fabs(wall->normal[1]) + fabs(wall->normal[2]) -
         GM_ON_ROW;
}

bool gm_walls_contact(const gm_domain *domain, const double node_position[2],
                      double velocity[2], const double *gap,
                      const double *centre_gap, double dt, bool friction,
                      double *block_force, double mass_over_dt, int *first_wall,
                      gm_wall_pool_record *record) {
  bool acted = false;
  int acting = 0, sharing = 0, shared_wall = -1;
  double shared_tangent = 0.0; /* m/s */
  /* The nodes that share the wall are those whose tent function reaches
   * behind the plane: nodes behind it and nodes less than a cell in front
   * (the nodes a rigid wall body and the material would share in the
   * multi-material contact of Bardenhagen, Brackbill & Sulsky 2000; 004
   * algorithm 3.1 applies the contact at such nodes). Acting only on
   * nodes behind the plane, as version 0.1 did, is right for a wall on a
   * node row, but a wall between rows then reaches the material through
   * the row behind it alone, which carries a small share of the material's
   * mass: it can stop the material's normal motion but remove only that
   * share of its tangential momentum, and friction was lost (a block at
   * 12 deg on mu = 0.3 slid 3 %, 16 % and 76 % of the frictionless
   * distance with the plane 0.2, 0.5 and 0.8 cells above a row). Whether a
   * node in front acts at all is decided by its material's gap (below):
   * material a gap away from the wall may close it first. */
  double reach = GM_WALL_REACH * domain->def.cell_size; /* m */
  bool wide = domain->def.shape != GM_SHAPE_LINEAR;     /* support.h */
  for (int w = 0; w < domain->wall_count; w++) {
    const gm_wall *wall = &domain->walls[w];
    double distance = (node_position[0] - wall->point[0]) * wall->normal[0] +
                      (node_position[1] - wall->point[1]) * wall->normal[1];
    /* A node the wall's tent does not reach may still carry a point whose
     * centre is at the wall: the shapes wider than a tent (uGIMP, cpGIMP,
     * CPDI and the B-splines, support.h) give a point on the plane weight
     * on nodes up to 1 + l_p/h, 1.5 or 2 cells in front of it (the
     * quadratic B-spline 1/8, the uGIMP of 2 x 2 points per cell 1/16 of
     * the node's velocity). The contact above stops only the nodes that
     * share the wall, so a point gathering from those nodes and from one
     * in front moving toward the wall went through it: the column
     * collapse with APIC (uGIMP, 2 x 2, cell 0.015 m) left a point at
     * y = -1.2e-7 m, its node on the plane held at 0, the node behind at
     * +1.23 m/s and the free node in front at -1.24 m/s (APIC's affine
     * field of an isolated point), and the quadratic B-spline (4 x 4,
     * cell 0.0075 m) one at -1.0e-6 m. Such a node may therefore approach
     * the wall by at most the distance of the nearest point centre it
     * carries, less the contact tolerance, in the step: the same gap rule
     * with the point's centre, not its domain, as the material's edge
     * (the velocity a point moves with is a weighted mean of its nodes',
     * so no point centre reaches the wall when none of its nodes carries
     * it there). Where it binds, the wall's impulse and Coulomb friction
     * are those of the contact above. Linear MPM does not need it for a
     * wall along a grid axis (a point at c from the plane has weight c/h
     * on such a node, so it could cross only with a node faster than a
     * cell per step) and gets it only in the band of an oblique plane
     * (gm_wall_tent_reach): on every node it bound only at nearly empty nodes
     * with the spurious velocities of USL's cell crossing (tens to thousands of
     * m/s), and changed the mean normal force of a sliding block in
     * tests/physics/test_friction.c by 2.7 %. */
    bool shares = distance < reach; /* this node shares the wall */
    /* the rows 1-2 cells in front (a cell in front of a wall on a node
     * row, or the second row of the bottom points' cells of a wall
     * between rows): friction strip only, if their material touches the
     * wall (gm_walls_share_friction). Linear shapes only: with the wide
     * ones that row may already act by the centre-gap rule below, and a
     * first version that let it join their strips too (and gave strips
     * without a pushed node no friction) put granular CPDI's run-out in
     * the a = 6 column collapse -13.7 % off the law, uGIMP's -1.7 %
     * (tests/physics/test_column_collapse.c allows 5 % more); not
     * measured further. */
    bool strip_only =
        !wide && !shares && distance < GM_STRIP_REACH * domain->def.cell_size;
    /* A node in front that carries a point centre near the wall: with the
     * wide shapes every such node (above); with linear ones those whose
     * tent still reaches behind an oblique plane (gm_wall_tent_reach). */
    bool by_centre =
        !shares && centre_gap && centre_gap[w] < INFINITY &&
        (wide || distance < gm_wall_tent_reach(wall) * domain->def.cell_size);
    if (!shares && !by_centre) {
      if (strip_only) {
        sharing++;
        shared_wall = w;
        shared_tangent =
            velocity[0] * wall->normal[1] - velocity[1] * wall->normal[0];
      }
      continue; /* and carries no point near it */
    }
    double before[2] = {velocity[0], velocity[1]};
    /* Gaps below GM_CONTACT_TOLERANCE cells count as contact: a resting
     * point's domain edge jitters by 1e-3..1e-2 cells with the elastic
     * vibration at the contact, and releasing the contact for those steps
     * loses friction (a block sliding at 30 deg on mu = 0.4 slid 3.7 %
     * too far with no tolerance, 0.8-1.0 % with 3e-3). A larger tolerance
     * lets the ratchet back in: material may stay that far from a wall,
     * pressed by it (the Janssen silo test fails from 5e-3 on). */
    double tolerance = GM_CONTACT_TOLERANCE * domain->def.cell_size; /* m */
    const double *material_gap = shares ? gap : centre_gap;
    double approach = material_gap && material_gap[w] > tolerance
                          ? (material_gap[w] - tolerance) / dt
                          : 0.0;                      /* m/s */
    double normal_change = 0.0, tangent_before = 0.0; /* m/s */
    if (!contact_one(wall, velocity, approach, friction, &normal_change,
                     &tangent_before)) {
      if ((shares && distance > GM_ON_ROW * domain->def.cell_size) ||
          strip_only) {
        /* in front of the plane: it may join its friction strip (below) */
        sharing++;
        shared_wall = w;
        shared_tangent =
            velocity[0] * wall->normal[1] - velocity[1] * wall->normal[0];
      }
      continue;
    }
    if (!acted && first_wall)
      *first_wall = w;
    if (record) {
      record->wall = w;
      record->normal_change = normal_change;
      record->tangent_before = tangent_before;
    }
    acting++;
    acted = true;
    if (block_force) { /* force on the material: m dv / dt */
      block_force[2 * w] += mass_over_dt * (velocity[0] - before[0]);
      block_force[2 * w + 1] += mass_over_dt * (velocity[1] - before[1]);
    }
  }
  /* A node in front of one wall that shares it and is not pushed by it in
   * this step is recorded for that wall's friction strip with no normal
   * impulse of its own (gm_walls_share_friction decides whether it
   * joins): its tangential momentum is part of the strip's. */
  if (record && acting == 0 && sharing == 1) {
    record->wall = shared_wall;
    record->normal_change = 0.0;
    record->tangent_before = shared_tangent;
  } else if (record && acting != 1)
    record->wall = -1; /* none, or a corner: per-node Coulomb stands */
  return acted;
}

/* Per-node contact records for the traction profile. */
static gm_status reserve_contacts(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  size_t nodes = grid->block_capacity * GM_BLOCK_NODES;
  if (nodes <= grid->contact_capacity)
    return GM_OK;
  int32_t *wall = gm_calloc(nodes, sizeof(int32_t));
  double *force_x = gm_calloc(nodes, sizeof(double));
  double *force_y = gm_calloc(nodes, sizeof(double));
  if (!wall || !force_x || !force_y) {
    gm_free(wall);
    gm_free(force_x);
    gm_free(force_y);
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "walls: out of memory for the traction profile");
  }
  gm_free(grid->contact_wall);
  gm_free(grid->contact_force[0]);
  gm_free(grid->contact_force[1]);
  grid->contact_wall = wall;
  grid->contact_force[0] = force_x;
  grid->contact_force[1] = force_y;
  grid->contact_capacity = nodes;
  return GM_OK;
}

/* The one-cell strips along wall w over which friction is pooled: strip
 * of a node at tangential coordinate s (m, from the wall's point along
 * (n_y, -n_x)) is round(s / h) - *lowest, of *count strips covering every
 * node of the grid box (ghost layers included). */
static void strip_range(const gm_domain *domain, int w, int64_t *lowest,
                        int64_t *count) {
  const gm_wall *wall = &domain->walls[w];
  double h = domain->def.cell_size;
  const double *origin = domain->shape_grid.origin; /* node 0 */
  double low = INFINITY, high = -INFINITY;
  for (int c = 0; c < 4; c++) {
    double ix = (c & 1) ? (double)(domain->cells[0] + 2 * GM_GHOST_LAYERS) : 0;
    double iy = (c >> 1) && domain->dim > 1
                    ? (double)(domain->cells[1] + 2 * GM_GHOST_LAYERS)
                    : 0.0;
    double x = origin[0] + ix * h - wall->point[0];
    double y = origin[1] + iy * h - wall->point[1];
    double s = (x * wall->normal[1] - y * wall->normal[0]) / h; /* cells */
    low = fmin(low, s);
    high = fmax(high, s);
  }
  *lowest = (int64_t)floor(low) - 1;
  *count = (int64_t)ceil(high) + 2 - *lowest;
}

static int64_t strip_of(const gm_domain *domain, int w, double x, double y,
                        int64_t lowest, int64_t count) {
  const gm_wall *wall = &domain->walls[w];
  double s = ((x - wall->point[0]) * wall->normal[1] -
              (y - wall->point[1]) * wall->normal[0]) /
             domain->def.cell_size; /* cells */
  int64_t strip = (int64_t)floor(s + 0.5) - lowest;
  return strip < 0 ? 0 : strip >= count ? count - 1 : strip;
}

static gm_status reserve_pool(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  size_t nodes = grid->block_capacity * GM_BLOCK_NODES;
  bool solid = domain->dim == 3; /* a second tangential component */
  if (nodes > grid->contact_capacity || !grid->pool_wall ||
      (solid && !grid->pool_tangent_3d)) {
    int32_t *wall = gm_calloc(nodes, sizeof(int32_t));
    double *normal = gm_calloc(nodes, sizeof(double));
    double *tangent = gm_calloc(nodes, sizeof(double));
    double *tangent_3d = solid ? gm_calloc(nodes, sizeof(double)) : NULL;
    if (!wall || !normal || !tangent || (solid && !tangent_3d)) {
      gm_free(wall);
      gm_free(normal);
      gm_free(tangent);
      gm_free(tangent_3d);
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "walls: out of memory for the shared friction");
    }
    gm_free(grid->pool_wall);
    gm_free(grid->pool_normal);
    gm_free(grid->pool_tangent);
    gm_free(grid->pool_tangent_3d);
    grid->pool_wall = wall;
    grid->pool_normal = normal;
    grid->pool_tangent = tangent;
    grid->pool_tangent_3d = tangent_3d;
  }
  size_t sums = 0;
  for (int w = 0; w < domain->wall_count; w++) {
    if (solid) { /* patches of the plane (walls_3d.c) */
      sums += gm_walls_patch_doubles_3d(domain, w);
      continue;
    }
    int64_t lowest, count;
    strip_range(domain, w, &lowest, &count);
    sums += GM_STRIP_SUMS * (size_t)count;
  }
  if (sums > grid->pool_sums_capacity) {
    double *grown = gm_alloc(sums * sizeof(double));
    if (!grown)
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "walls: out of memory for the shared friction");
    gm_free(grid->pool_sums);
    grid->pool_sums = grown;
    grid->pool_sums_capacity = sums;
  }
  return GM_OK;
}

gm_status gm_walls_reserve(gm_domain *domain) {
  gm_grid *grid = &domain->grid;
  if (domain->wall_count > 0) {
    gm_status status = reserve_pool(domain); /* before contact_capacity */
    if (status == GM_OK)
      status = reserve_contacts(domain);
    if (status != GM_OK)
      return status;
  }
  /* The records of the blocks a measured point may reach, not of every
   * block (gm_walls_map_gaps): the granular cloud's node layers far above
   * the floor took 28 bytes per point in 2D, 78 in 3D (docs/performance.md,
   * "Gap records per block"). That set moves with the material, so it is
   * grown with headroom (an eighth and 4 blocks, as the grid's blocks). */
  size_t nodes = gm_walls_map_gaps(domain);
  size_t room = nodes + (nodes / 8 + 4 * GM_BLOCK_NODES);
  size_t gaps = nodes * (size_t)gm_gap_plane_count(domain); /* doubles */
  if (gaps > grid->wall_gap_capacity) {
    gaps = room * (size_t)gm_gap_plane_count(domain);
    double *grown = gm_alloc(gaps * sizeof(double));
    if (!grown)
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "walls: out of memory for the contact gaps");
    gm_free(grid->wall_gap);
    grid->wall_gap = grown;
    grid->wall_gap_capacity = gaps;
  }
  size_t centre_gaps =
      nodes * (size_t)gm_centre_gap_plane_count(domain); /* doubles */
  if (centre_gaps > grid->wall_centre_gap_capacity) {
    centre_gaps = room * (size_t)gm_centre_gap_plane_count(domain);
    double *grown = gm_alloc(centre_gaps * sizeof(double));
    if (!grown)
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "walls: out of memory for the contact gaps");
    gm_free(grid->wall_centre_gap);
    grid->wall_centre_gap = grown;
    grid->wall_centre_gap_capacity = centre_gaps;
  }
  size_t needed = grid->block_capacity * (size_t)domain->wall_count *
                  (domain->dim == 3 ? 3 : 2); /* doubles */
  if (domain->wall_count == 0 || (needed <= grid->wall_force_capacity &&
                                  grid->wall_stride == domain->wall_count))
    return GM_OK;
  double *partial = gm_calloc(needed, sizeof(double));
  if (!partial)
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "walls: out of memory for the force report");
  gm_free(grid->wall_force);
  grid->wall_force = partial;
  grid->wall_force_capacity = needed;
  grid->wall_stride = domain->wall_count;
  return GM_OK;
}

/* ------------------------------------------------ friction per strip
 *
 * Coulomb's law per node (contact_one) loses friction where a wall lies
 * between node rows: the row behind the plane carries a small share of
 * the bottom points' mass yet takes much of the normal impulse, and a
 * light node sticks (its tangential momentum is below mu times its normal
 * impulse) while the heavier ones slide, so the contact as a whole gives
 * less than mu N. Measured (block at 40 deg on mu = 0.5, floor 0.625
 * cells above a row, MUSL): the row behind took 56 % of the normal
 * impulse with 1/8 of the bottom points' mass, stuck in 10 % of its
 * contacts and gave 0.466 of its normal impulse as friction; the block
 * slid 12.5 % too far (USL 13.9 %, USF 10.1 %; tilted plane 0.3 cells off
 * a row 5-8 %). Here Coulomb's law is applied to the sums of a strip
 * one cell wide along the wall (the nodes across the plane at one place,
 * behind and in front, with one acting wall): the strip sticks when its
 * tangential momentum T is at most mu_s times its normal impulse N, else
 * each node keeps 1 - mu_k N / |T| of its tangential velocity (the strip
 * loses mu_k N). Measured: 13.9 / 12.5 / 10.1 % (USL / MUSL / USF) too
 * far become 6.5 / 6.2 / 5.1 %, and the tilted plane 2.3 / 4.3 / 3.2 %.
 * Pooling over a whole contact patch (adjacent strips in contact) gave
 * 0.7-2.8 % but failed tests/physics/test_janssen.c (wall pressure 0.84 of
 * Janssen's): a silo wall is one patch, partly stuck and partly sliding,
 * and one Coulomb state for all of it is wrong for a deforming material;
 * strips two and three cells wide gave 7.6 % and 3.9 % (MUSL). This is
 * our rule (Coulomb's law on the resultant over a strip), not a
 * paper's.
 *
 * A strip also holds the nodes in front of the plane (less than a cell:
 * they share the wall) that the wall did not push in this step, with no
 * normal impulse of their own, as long as their material is no farther
 * from the wall than that of the nodes it pushed (pass 0 below). With
 * only the pushed nodes the strips still lost friction where the plane
 * lies 0.55-0.75 cells above a node row: the bottom points then sit just
 * below the row in front, give the row behind 5-20 % of their mass, and
 * their stress pushes that light row into the wall while the heavy row in
 * front moves away from it or not at all; the strip was then the light
 * node alone, its normal impulse (the weight of the column above) far
 * above mu times its own tangential momentum, so it stuck while the block
 * slid. Measured, MUSL, block at 30 deg on mu = 0.4 (40 deg on 0.5),
 * floor 0.6 / 0.625 / 0.7 cells above a row: +9.9 / +17.6 / +119 % (+1.9
 * / +6.2 / +43 % at 40 deg) too far, the wall's friction 0.15 of its
 * normal impulse at 0.7 cells; with the nodes in front +0.7 / +1.0 /
 * +1.9 % (+0.6 / +0.5 / -0.2 %), friction 0.397 of it. Across 25-50 deg,
 * eleven floor offsets and five tilted offsets in USL, MUSL and USF the
 * worst slide went from +17.6 % to +2.15 %.
 *
 * That +2.15 % was the floor on a node row (USL, 30 deg): nothing lies
 * less than a cell in front of it, so a strip was the node on the plane
 * alone, which carries the column's normal load but a tenth of its
 * tangential momentum (2 x 2 points per cell, 5 cells high), and it stuck
 * in some steps while the block slid (the wall's friction 0.396 of its
 * normal impulse). The row a whole cell in front (GM_STRIP_REACH) now
 * joins the strips under the same rule as the nodes less than a cell in
 * front, but for the strips only: the wall never pushes it (its tent does
 * not reach behind the plane). Measured (30 deg on 0.4, tests/physics/
 * test_friction.c, USL / MUSL / USF): +2.39 / +1.03 / +1.79 % became
 * +0.30 / +0.39 / +0.25 %, the friction 0.3995 of the normal impulse; the
 * Janssen silo's wall pressure (tests/physics/test_janssen.c) 0.996-1.077
 * of the formula's (0.998-1.092 before). How that row joins matters for
 * the silo, whose wall strips mostly stick: letting the wall push it too
 * (a reach of a cell plus 1e-6) made it a second wall a cell inside the
 * fill (wall pressure 1.10 of the formula's at 0.75 m depth, the vertical
 * stress of the bottom row 1 Pa); letting it count in T but not stop with
 * a sticking strip gave 1.118 at 2 m.
 *
 * The same loss, on a wall between rows: with the plane more than 0.75
 * cells above a node row (2 x 2 points per cell), the bottom points,
 * 0.25 cells above the plane, lie just above the row in front of it. The
 * row behind then carries no material and the row 0.05-0.25 cells in
 * front takes the whole normal load with 0.95-0.75 of the bottom points'
 * weight and 0.45-0.25 of the next ones' (a seventh of the column's mass
 * per cell), while the rest of the bottom points' mass lies on the row
 * 1.05-1.25 cells in front, outside the strips as long as they reached a
 * cell. That light strip stuck whenever the contact chattered: the block
 * vibrates on the wall (its centre rises up to 0.02 cells), the contact
 * of a strip opens and closes, and each closing brings a normal impulse
 * N with mu_s N above the strip's T. Measured (USL, 30 deg on mu = 0.4,
 * floor 0.8 cells above a row): the node of the middle strip was in
 * contact in 1313 of 3492 steps, the
 * wall's friction was 0.3959 of its normal impulse, and the block slid
 * 2.12 % too far (0.85 cells: 2.26 %; 1.04 and 1.34 % at half the stable
 * dt, the chatter being smaller). The strips therefore reach up to two
 * cells in front (GM_STRIP_REACH), and the gap rule (below) keeps out
 * every row whose material does not touch the wall: only the second node
 * of the bottom points' cells joins, at any offset. Measured over 20
 * offsets (0, 0.05, ..., 0.95 cells) at 25, 30 and 40 deg in USL, MUSL
 * and USF: the worst slide went from +2.26 % to +1.38 % (MUSL, 30 deg,
 * 0.7 cells, a case this change does not touch), 0.8 / 0.85 cells in USL
 * to +0.61 / +0.62 %. The bound is Bardenhagen, Brackbill & Sulsky's
 * (2000, CMAME 187: 529-541) Coulomb limit on the tangential momentum
 * exchange at the contact, |f_t| <= mu |f_n|, applied to a strip's nodes
 * together rather than to one node. */

void gm_walls_share_friction(gm_domain *domain, double dt, int mode) {
  gm_grid *grid = &domain->grid;
  if (domain->wall_count == 0)
    return;
  double h = domain->def.cell_size;
  const double *origin = domain->shape_grid.origin; /* node 0 */
  int64_t edge = (int64_t)1 << grid->shift;
  int64_t lowest[GM_MAX_WALLS], count[GM_MAX_WALLS];
  size_t first[GM_MAX_WALLS]; /* the wall's strips in pool_sums */
  size_t total = 0;
  for (int w = 0; w < domain->wall_count; w++) {
    strip_range(domain, w, &lowest[w], &count[w]);
    first[w] = total;
    total += GM_STRIP_SUMS * (size_t)count[w];
  }
  memset(grid->pool_sums, 0, total * sizeof(double));
  int planes = gm_gap_plane_count(domain);
  double tolerance = GM_CONTACT_TOLERANCE * h; /* m */
  /* In block order (deterministic): pass 0 the largest material gap of
   * the nodes the wall pushed in each strip, pass 1 the sums per strip,
   * pass 2 Coulomb's law on them. */
  for (int pass = 0; pass < 3; pass++) {
    for (size_t b = 0; b < grid->block_count; b++) {
      int64_t base[2];
      bool block_known = false;
      for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
        size_t node = b * GM_BLOCK_NODES + local;
        int w = grid->pool_wall[node] - 1;
        if (w < 0)
          continue;
        if (!block_known) {
          gm_block_base(grid, grid->block_key[b], base);
          block_known = true;
        }
        int64_t ix = base[0] + (int64_t)(local & (size_t)(edge - 1));
        int64_t iy =
            domain->dim > 1 ? base[1] + (int64_t)(local >> grid->shift) : 0;
        double x = origin[0] + (double)ix * h;
        double y = domain->dim > 1 ? origin[1] + (double)iy * h : 0.0;
        double *sum = grid->pool_sums + first[w] +
                      GM_STRIP_SUMS * (size_t)strip_of(domain, w, x, y,
                                                       lowest[w], count[w]);
        double mass = grid->mass[node]; /* kg */
        double gap = grid->wall_gap[gm_gap_node(grid, node) * (size_t)planes +
                                    (size_t)w]; /* m */
        bool pushed = grid->pool_normal[node] > 0.0;
        if (pass == 0) {
          if (pushed && gap > sum[2])
            sum[2] = gap;
          if (pushed && sum[3] == 0.0)
            sum[3] = (double)node + 1.0; /* the first in block order */
          continue;
        }
        /* A node the wall did not push joins its strip if its material is
         * no farther from the wall than that of the pushed ones. */
        if (!pushed && gap > fmax(sum[2], tolerance))
          continue;
        if (pass == 1) {
          sum[0] += mass * grid->pool_normal[node];
          sum[1] += mass * grid->pool_tangent[node];
          continue;
        }
        /* Pass 2: Coulomb on the strip's sums (stick when its tangential
         * momentum is at most mu_s times its normal impulse, otherwise
         * every node keeps the same fraction of its tangential velocity,
         * the strip losing mu_k times its normal impulse). */
        const gm_wall *wall = &domain->walls[w];
        double normal_impulse = sum[0], momentum = fabs(sum[1]);
        double keep = 0.0;
        if (momentum > wall->friction_static * normal_impulse)
          keep = 1.0 - wall->friction_kinetic * normal_impulse / momentum;
        double tangent[2] = {wall->normal[1], -wall->normal[0]};
        double now = grid->momentum[0][node] * tangent[0] +
                     (domain->dim > 1 ? grid->momentum[1][node] : 0.0) *
                         tangent[1];                           /* m/s */
        double change = keep * grid->pool_tangent[node] - now; /* m/s */
        if (change == 0.0)
          continue;
        /* The traction entry that takes this node's friction: its own,
         * but for the row a cell in front of a wall on a node row that of
         * the strip's first pushed node (the node on the plane, at the
         * same place along the wall), so that the profile does not list
         * that place twice. */
        double distance = (x - wall->point[0]) * wall->normal[0] +
                          (y - wall->point[1]) * wall->normal[1]; /* m */
        size_t entry = !pushed && distance >= GM_WALL_REACH * h && sum[3] > 0.0
                           ? (size_t)sum[3] - 1
                           : node;
        if (mode == GM_GRID_FULL && grid->contact_wall[entry] == 0) {
          /* a node the wall did not push: friction alone (traction
           * profile) */
          grid->contact_wall[entry] = w + 1;
          grid->contact_force[0][entry] = grid->contact_force[1][entry] = 0.0;
        }
        for (int k = 0; k < domain->dim; k++) {
          grid->momentum[k][node] += change * tangent[k];
          if (mode == GM_GRID_FULL) {
            double force = mass / dt * change * tangent[k]; /* N */
            grid->force[k][node] += change * tangent[k] / dt;
            grid->wall_force[(b * (size_t)grid->wall_stride + (size_t)w) * 2 +
                             (size_t)k] += force;
            grid->contact_force[k][entry] += force;
          }
        }
      }
    }
  }
}

void gm_walls_add_impulse(gm_domain *domain, double dt) {
  gm_grid *grid = &domain->grid;
  size_t components = domain->dim == 3 ? 3 : 2; /* per block and wall */
  for (int w = 0; w < domain->wall_count; w++) {
    double sum[3] = {0.0, 0.0, 0.0};
    for (size_t b = 0; b < grid->block_count; b++)
      for (size_t k = 0; k < components; k++)
        sum[k] += grid->wall_force[(b * (size_t)grid->wall_stride + (size_t)w) *
                                       components +
                                   k];
    for (size_t k = 0; k < components; k++)
      domain->wall_impulse[w][k] += sum[k] * dt;
  }
}

/* ------------------------------------------------------ traction profile */

static int compare_positions(const void *a, const void *b) {
  double left = ((const gm_wall_traction *)a)->position;
  double right = ((const gm_wall_traction *)b)->position;
  return (left > right) - (left < right);
}

gm_status gm_domain_get_wall_tractions(const gm_domain *domain, int wall_id,
                                       gm_wall_traction *tractions,
                                       size_t capacity, size_t *count) {
  if (!domain)
    return GM_ERR_NULL;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  const char *what = "gm_domain_get_wall_tractions";
  if (!count || (!tractions && capacity > 0))
    return gm_set_error(mutable_domain, GM_ERR_NULL, "%s: %s is NULL", what,
                        count ? "tractions" : "count");
  if (wall_id < 0 || wall_id >= domain->wall_count)
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: wall %d is unknown (%d walls)", what, wall_id,
                        domain->wall_count);
  /* A profile along a line has no 3D counterpart yet (a traction map over
   * the plane would be one); the profile is provisional (gm_walls(3)). */
  if (domain->dim == 3)
    return gm_set_error(mutable_domain, GM_ERR_UNSUPPORTED,
                        "%s: not available for a 3D domain in this version "
                        "(use gm_domain_get_wall_force)",
                        what);
  *count = 0;
  if (domain->points.count == 0)
    return GM_OK;
  if (!domain->wall_profile_valid)
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: no profile since the last failed step", what);
  const gm_grid *grid = &domain->grid;
  const gm_wall *wall = &domain->walls[wall_id];
  double tangent[2] = {wall->normal[1], -wall->normal[0]};
  double h = domain->def.cell_size;
  int64_t edge = (int64_t)1 << grid->shift;
  size_t found = 0;
  for (size_t b = 0; b < grid->block_count; b++) {
    int64_t base[2];
    gm_block_base(grid, grid->block_key[b], base);
    int64_t base_x = base[0], base_y = base[1];
    for (size_t local = 0; local < GM_BLOCK_NODES; local++) {
      size_t node = b * GM_BLOCK_NODES + local;
      if (grid->contact_wall[node] != wall_id + 1)
        continue;
      if (found < capacity) {
        int64_t ix = base_x + (int64_t)(local & (size_t)(edge - 1));
        int64_t iy =
            domain->dim > 1 ? base_y + (int64_t)(local >> grid->shift) : 0;
        const double *origin = domain->shape_grid.origin; /* node 0 */
        double x = origin[0] + (double)ix * h - wall->point[0];
        double y =
            domain->dim > 1 ? origin[1] + (double)iy * h - wall->point[1] : 0.0;
        double fx = grid->contact_force[0][node];
        double fy = grid->contact_force[1][node];
        gm_wall_traction *entry = &tractions[found];
        entry->position = x * tangent[0] + y * tangent[1];
        entry->normal = (fx * wall->normal[0] + fy * wall->normal[1]) / h;
        entry->tangential = (fx * tangent[0] + fy * tangent[1]) / h;
      }
      found++;
    }
  }
  *count = found;
  if (found > capacity)
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: %zu contact nodes, capacity %zu", what, found,
                        capacity);
  qsort(tractions, found, sizeof *tractions, compare_positions);
  return GM_OK;
}
