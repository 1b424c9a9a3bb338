/*
 * interaction.c - domains of interaction and their exact overlap test (see
 * interaction.h).
 */
#include "granular/granular.h"

#include <math.h>

void gm_interaction_domain_of(gm_shape shape, int dim,
                              const gm_point_domain *point, double measure,
                              gm_interaction_domain *out) {
  double corners[4][2];
  gm_point_domain_corners(shape, dim, point, corners);
  gm_interaction_domain_from_corners(dim, point->position, corners, measure,
                                     out);
}

void gm_interaction_domain_from_corners(int dim, const double centre[2],
                                        double corners[4][2], double measure,
                                        gm_interaction_domain *out) {
  for (int k = 0; k < 2; k++) {
    out->centre[k] = centre[k];
    /* r1 = (c1 - c0) / 2, r2 = (c3 - c0) / 2 (corners counter-clockwise) */
    out->half_edge[0][k] = 0.5 * (corners[1][k] - corners[0][k]);
    out->half_edge[1][k] =
        dim > 1 ? 0.5 * (corners[3][k] - corners[0][k]) : 0.0;
  }
  if (!(measure > 0.0))
    return;
  double current; /* m^2 (m in 1D) */
  if (dim == 1)
    current = 2.0 * fabs(out->half_edge[0][0]);
  else
    current = 4.0 * fabs(out->half_edge[0][0] * out->half_edge[1][1] -
                         out->half_edge[0][1] * out->half_edge[1][0]);
  if (!(current > 0.0))
    return;
  /* Concentric and proportional (000 Fig. 4a): every edge scales alike. */
  double scale = dim == 1 ? measure / current : sqrt(measure / current);
  for (int e = 0; e < 2; e++)
    for (int k = 0; k < 2; k++)
      out->half_edge[e][k] *= scale;
}

/* Half-width of domain d's projection on axis n (|r1.n| + |r2.n|). */
static double projected_radius(const gm_interaction_domain *d,
                               const double axis[2]) {
  return fabs(d->half_edge[0][0] * axis[0] + d->half_edge[0][1] * axis[1]) +
         fabs(d->half_edge[1][0] * axis[0] + d->half_edge[1][1] * axis[1]);
}

/* Does `axis` separate a and b (touching counts as separated)? */
static bool separates(const gm_interaction_domain *a,
                      const gm_interaction_domain *b, const double axis[2]) {
  double distance = fabs((b->centre[0] - a->centre[0]) * axis[0] +
                         (b->centre[1] - a->centre[1]) * axis[1]);
  return distance >= projected_radius(a, axis) + projected_radius(b, axis);
}

bool gm_interaction_overlap(int dim, const gm_interaction_domain *a,
                            const gm_interaction_domain *b) {
  if (dim == 1)
    return fabs(b->centre[0] - a->centre[0]) <
           fabs(a->half_edge[0][0]) + fabs(b->half_edge[0][0]);
  const gm_interaction_domain *both[2] = {a, b};
  int tested = 0;
  for (int d = 0; d < 2; d++) {
    for (int e = 0; e < 2; e++) {
      /* Normal of edge vector r_e (unnormalised: the test is scale-free). */
      const double *edge = both[d]->half_edge[e];
      double axis[2] = {-edge[1], edge[0]};
      if (axis[0] == 0.0 && axis[1] == 0.0)
        continue; /* degenerate edge: the other axes decide */
      if (separates(a, b, axis))
        return false;
      tested++;
    }
  }
  /* Two points have no interior to share (domain sizes are > 0 through the
   * API, so this only guards the function's contract). */
  return tested > 0;
}

/* ------------------------------------------------------------------ 3D */

static double dot3(const double u[3], const double v[3]) {
  return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

static void cross3(const double u[3], const double v[3], double out[3]) {
  out[0] = u[1] * v[2] - u[2] * v[1];
  out[1] = u[2] * v[0] - u[0] * v[2];
  out[2] = u[0] * v[1] - u[1] * v[0];
}

/* r1 . (r2 x r3): an eighth of the signed volume (m^3). */
static double half_edge_determinant(const gm_interaction_domain3 *d) {
  double normal[3];
  cross3(d->half_edge[1], d->half_edge[2], normal);
  return dot3(d->half_edge[0], normal);
}

void gm_interaction_scale3(gm_interaction_domain3 *d, double volume) {
  double current = 8.0 * fabs(half_edge_determinant(d)); /* m^3 */
  if (!(volume > 0.0) || !(current > 0.0))
    return;
  /* Concentric and proportional, as in 2D (000 Fig. 4a). */
  double scale = cbrt(volume / current);
  for (int e = 0; e < 3; e++)
    for (int k = 0; k < 3; k++)
      d->half_edge[e][k] *= scale;
}

/* Half-width of d's projection on axis n: |r1.n| + |r2.n| + |r3.n|. */
static double projected_radius3(const gm_interaction_domain3 *d,
                                const double axis[3]) {
  return fabs(dot3(d->half_edge[0], axis)) + fabs(dot3(d->half_edge[1], axis)) +
         fabs(dot3(d->half_edge[2], axis));
}

/* Does `axis` separate a and b (touching counts as separated)? An axis of
 * zero length separates nothing (its test would read 0 >= 0). */
static bool separates3(const gm_interaction_domain3 *a,
                       const gm_interaction_domain3 *b, const double axis[3]) {
  if (axis[0] == 0.0 && axis[1] == 0.0 && axis[2] == 0.0)
    return false;
  double offset[3] = {b->centre[0] - a->centre[0], b->centre[1] - a->centre[1],
                      b->centre[2] - a->centre[2]};
  return fabs(dot3(offset, axis)) >=
         projected_radius3(a, axis) + projected_radius3(b, axis);
}

bool gm_interaction_overlap3(const gm_interaction_domain3 *a,
                             const gm_interaction_domain3 *b) {
  if (half_edge_determinant(a) == 0.0 || half_edge_determinant(b) == 0.0)
    return false; /* no interior */
  const gm_interaction_domain3 *both[2] = {a, b};
  double axis[3];
  /* Face normals (unnormalised: the test is scale-free). */
  for (int d = 0; d < 2; d++)
    for (int e = 0; e < 3; e++) {
      cross3(both[d]->half_edge[(e + 1) % 3], both[d]->half_edge[(e + 2) % 3],
             axis);
      if (separates3(a, b, axis))
        return false;
    }
  /* Edge against edge; parallel edges give a zero axis, and then a face
   * normal of the pair already covers the direction. */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      cross3(a->half_edge[i], b->half_edge[j], axis);
      if (separates3(a, b, axis))
        return false;
    }
  return true;
}
