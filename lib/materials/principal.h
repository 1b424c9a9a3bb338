/*
 * principal.h - spectral decomposition of a symmetric 3x3 tensor given in
 * Voigt order (GM_XX, GM_YY, GM_ZZ, GM_XY, GM_YZ, GM_ZX; tensor components,
 * so xy is the off-diagonal entry itself, not twice it). Used by the
 * principal-stress return mapping of the Mohr-Coulomb model. Private to the
 * library.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_MATERIALS_PRINCIPAL_H
#define GM_MATERIALS_PRINCIPAL_H

#include <math.h>

/* Eigenvalues sorted descending, value[0] >= value[1] >= value[2] (units of
 * the tensor); vector[k] is the unit eigenvector of value[k] (Cartesian
 * components x, y, z), so the three vectors form an orthonormal basis. */
typedef struct gm_principal {
  double value[3];
  double vector[3][3];
} gm_principal;

/* Decomposes the symmetric tensor `voigt` in closed form (principal.c): when
 * yz = zx = 0 exactly (plane strain, axisymmetry, 1D: the library passes
 * those rows as zeros) by gm_principal_in_plane and
 * gm_principal_decompose_planar, otherwise by the root of the
 * characteristic cubic farthest from the other two, its eigenvector from
 * cross products and the remaining pair as a Mohr circle in the plane
 * orthogonal to it. Accurate to round-off of the tensor norm, also for
 * repeated eigenvalues (tests/unit/test_principal.c). Returns 0, or -1 for
 * non-finite input. */
int gm_principal_decompose(const double voigt[6], gm_principal *out);

/* The same decomposition by cyclic Jacobi rotations (principal_jacobi.c):
 * the iterative reference the closed form is tested and measured against.
 * Returns 0, or -1 if the rotations did not annihilate the off-diagonal part
 * within the sweep limit (only possible for non-finite input). */
int gm_principal_decompose_jacobi(const double voigt[6], gm_principal *out);

/* A general tensor prepared for its decomposition: scaled by its largest
 * entry, split into mean and deviator, and the simple root of the
 * deviator's characteristic cubic (principal.c). */
typedef struct gm_principal_cubic {
  double scale;       /* max |A_ij| (units of the tensor), >= 0 */
  double mean;        /* tr(A) / (3 scale) */
  double deviator[6]; /* A / scale - mean I, Voigt order */
  double radius;      /* p = sqrt(D:D / 6), 0 for an isotropic tensor */
  double root;        /* y, the simple root of y^3 - 3 y - 2 h (h =
                         det(D) / (2 p^3)) in units of p: in [sqrt 3, 2]
                         when h >= 0 (the largest), in [-2, -sqrt 3]
                         otherwise (the smallest) */
} gm_principal_cubic;

/* The principal values alone, descending, of a finite tensor (the simple
 * root of the cubic, then the quadratic left for the other two; no
 * eigenvectors, no trigonometric calls), and in *cubic what
 * gm_principal_decompose_cubic needs to finish the decomposition without
 * starting over. The largest and smallest values are within *error (units
 * of the tensor, >= 0) of the exact ones: a double root of the cubic is
 * only known to O(sqrt(eps)) of the norm, so *error is 1e-6 of the largest
 * entry. For a yield test that needs only the extremes; a decision within
 * *error of the surface takes the accurate values. */
void gm_principal_estimate(const double voigt[6], gm_principal_cubic *cubic,
                           double values[3], double *error);

/* The closed-form decomposition of the tensor whose cubic this is (what
 * gm_principal_decompose does to a general tensor). */
void gm_principal_decompose_cubic(const gm_principal_cubic *cubic,
                                  gm_principal *out);

/* The xy block of a tensor with yz = zx = 0 (units of the tensor): its
 * eigenvalues are centre + radius and centre - radius (Mohr's circle),
 * and the third principal value is voigt[GM_ZZ] with direction z. */
typedef struct gm_principal_circle {
  double centre;          /* (xx + yy) / 2 */
  double half_difference; /* (xx - yy) / 2 */
  double radius;          /* sqrt(half_difference^2 + xy^2) >= 0 */
} gm_principal_circle;

static inline gm_principal_circle gm_principal_in_plane(const double voigt[6]) {
  gm_principal_circle circle;
  circle.centre = 0.5 * (voigt[0] + voigt[1]);
  circle.half_difference = 0.5 * (voigt[0] - voigt[1]);
  circle.radius = sqrt(circle.half_difference * circle.half_difference +
                       voigt[3] * voigt[3]);
  return circle;
}

/* Closed-form decomposition of a tensor with yz = zx = 0, given its circle
 * from gm_principal_in_plane: the in-plane eigenvectors come from the
 * circle without trigonometric calls, sorted with z like
 * gm_principal_decompose. */
void gm_principal_decompose_planar(const double voigt[6],
                                   const gm_principal_circle *circle,
                                   gm_principal *out);

/* Writes sum_k values[k] vector[k] (x) vector[k] into voigt: the tensor with
 * the principal directions of `basis` and the principal values `values`. */
void gm_principal_compose(const gm_principal *basis, const double values[3],
                          double voigt[6]);

#endif /* GM_MATERIALS_PRINCIPAL_H */
