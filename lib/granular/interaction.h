/*
 * interaction.h - domains of interaction of the granular method (000 sec
 * 3.3, Table A2): a point's domain scaled about its centre to the critical
 * volume V_cr = m / rho_cr, the largest volume the point may have. Two
 * points interact (and share a grid) when their domains of interaction
 * overlap: strict overlap, so domains that only touch do not interact.
 *
 * A domain is stored as its centre and two half-edge vectors: a segment
 * (1D), an axis-aligned rectangle (linear MPM, uGIMP, cpGIMP) or a
 * parallelogram (CPDI). The overlap test is exact: the separating-axis
 * theorem, with the two edge normals of each parallelogram as the only
 * candidate axes (a convex polygon pair is disjoint iff some edge normal
 * separates them), instead of the paper's edge walk (Fig. A2), which
 * misses one domain nested inside the other.
 */
#ifndef GM_INTERACTION_H
#define GM_INTERACTION_H

#include "shapes/shapes.h"

#include <stdbool.h>

typedef struct gm_interaction_domain {
  double centre[2];       /* m */
  double half_edge[2][2]; /* m, r1 and r2: corners centre +- r1 +- r2 */
} gm_interaction_domain;

/* The domain of point `point` (variant `shape`) scaled about its centre so
 * its area (length in 1D) is `measure` (m^2, m in 1D); `measure` <= 0
 * keeps the domain as it is. */
void gm_interaction_domain_of(gm_shape shape, int dim,
                              const gm_point_domain *point, double measure,
                              gm_interaction_domain *out);

/* Do the interiors of a and b intersect? dim 1: segments along x; dim 2:
 * parallelograms (rectangles included). */
bool gm_interaction_overlap(int dim, const gm_interaction_domain *a,
                            const gm_interaction_domain *b);

#endif
