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
 *
 * In 3D (issue 16) a domain is a parallelepiped: centre and three
 * half-edge vectors (a box for the rectangular variants, F r1, F r2, F r3
 * for CPDI). Its overlap test is the same theorem with the 15 candidate
 * axes of two convex polyhedra: the 3 face normals of each and the 9
 * cross products of an edge of one with an edge of the other.
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
/* The same from the domain's corners (m, counter-clockwise from the lower
 * left, gm_point_domain_corners; in 1D corners 0 and 1) and its centre. */
void gm_interaction_domain_from_corners(int dim, const double centre[2],
                                        double corners[4][2], double measure,
                                        gm_interaction_domain *out);

/* Do the interiors of a and b intersect? dim 1: segments along x; dim 2:
 * parallelograms (rectangles included). */
bool gm_interaction_overlap(int dim, const gm_interaction_domain *a,
                            const gm_interaction_domain *b);

/* A 3D domain of interaction: corners centre +- r1 +- r2 +- r3. */
typedef struct gm_interaction_domain3 {
  double centre[3];       /* m */
  double half_edge[3][3]; /* m, r1, r2, r3 */
} gm_interaction_domain3;

/* Scales d about its centre so its volume is `volume` (m^3); `volume` <= 0
 * or a domain of zero volume is left as it is. */
void gm_interaction_scale3(gm_interaction_domain3 *d, double volume);

/* Do the interiors of a and b intersect? Exact up to round-off in the
 * projections; domains that only touch do not overlap, and a domain of
 * zero volume has no interior, so it overlaps nothing. */
bool gm_interaction_overlap3(const gm_interaction_domain3 *a,
                             const gm_interaction_domain3 *b);

#endif
