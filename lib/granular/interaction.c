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
  for (int k = 0; k < 2; k++) {
    out->centre[k] = point->position[k];
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
