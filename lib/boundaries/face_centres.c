/*
 * face_centres.c - the box faces' centre-gap rule, for every geometry. A
 * slip or fixed face holds only its face and ghost nodes, but a point of
 * a shape wider than a tent (uGIMP, cpGIMP, CPDI; the B-splines' faces are
 * mirrors, bspline_faces.c) on the face gathers from the node a cell in
 * front as well (uGIMP with 2 points per cell: 1/16 of its velocity per
 * axis). Moving toward the face, that node carried the point out of the
 * box: the uGIMP granular slot silo of
 * examples/papers/wieckowski1999_silo_discharge.c (cell 0.0125 m) lost a
 * point through its slip symmetry face at x = 0 (x = -7.6e-7 m at
 * t = 0.619 s, just after the orifice opened; tests/physics/test_face_gaps.c),
 * and in 3D a block of uGIMP points moving onto a slip face at 1 m/s failed
 * its first step with a point at x = -1.25e-5 m (docs/3d.md, "Linear MPM
 * through oblique walls, and the 3D box faces' centre gaps";
 * tests/physics/test_face_gaps_3d.c).
 *
 * This is the planar walls' centre-gap rule (walls.c, gm_walls_contact)
 * for the box faces, normal component only: such a node does not touch the
 * face, so a fixed face holds no tangential component of it. The centre
 * gaps are measured in wall_gaps.c (2D) and wall_gaps_3d.c (3D) from the
 * points whose centres are less than a cell from the face; the grid
 * updates (grid/grid_update.c, grid/grid_update_3d.c) call these two
 * functions.
 */
#include "boundaries/boundaries.h"

#include <math.h>

void gm_limit_face_centres(const gm_domain *domain, const gm_gap_layout *layout,
                           const double *centre_gap, const int64_t *index,
                           double dt, double *velocity) {
  double tolerance = GM_CONTACT_TOLERANCE * domain->def.cell_size; /* m */
  for (int axis = 0; axis < domain->dim; axis++) {
    int64_t upper = domain->cells[axis] + GM_GHOST_LAYERS; /* face node */
    for (int side = 0; side < 2; side++) {
      int slot = layout->face_slot[2 * axis + side];
      if (slot < 0 || !(centre_gap[slot] < INFINITY))
        continue;
      if (side ? index[axis] >= upper : index[axis] <= GM_GHOST_LAYERS)
        continue; /* the face's own nodes: the grid update's face rule */
      double inward = side ? -1.0 : 1.0; /* the face's normal */
      double approach = centre_gap[slot] > tolerance
                            ? (centre_gap[slot] - tolerance) / dt
                            : 0.0; /* m/s */
      if (inward * velocity[axis] < -approach)
        velocity[axis] = -inward * approach;
    }
  }
}

bool gm_block_near_faces(const gm_domain *domain, const int64_t *base,
                         int64_t edge, int64_t reach) {
  if (domain->def.shape == GM_SHAPE_LINEAR)
    return false;
  for (int axis = 0; axis < domain->dim; axis++) {
    int64_t upper = domain->cells[axis] + GM_GHOST_LAYERS; /* face node */
    if (gm_gap_face_slot(domain, 2 * axis) >= 0 &&
        base[axis] <= GM_GHOST_LAYERS + reach)
      return true;
    if (gm_gap_face_slot(domain, 2 * axis + 1) >= 0 &&
        base[axis] + edge - 1 >= upper - reach)
      return true;
  }
  return false;
}
