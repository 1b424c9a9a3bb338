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

/* Eigenvalues sorted descending, value[0] >= value[1] >= value[2] (units of
 * the tensor); vector[k] is the unit eigenvector of value[k] (Cartesian
 * components x, y, z), so the three vectors form an orthonormal basis. */
typedef struct gm_principal {
  double value[3];
  double vector[3][3];
} gm_principal;

/* Decomposes the symmetric tensor `voigt` with cyclic Jacobi rotations
 * (accurate to round-off also for repeated eigenvalues). Returns 0, or -1
 * if the rotations did not annihilate the off-diagonal part within the
 * sweep limit (only possible for non-finite input). */
int gm_principal_decompose(const double voigt[6], gm_principal *out);

/* Writes sum_k values[k] vector[k] (x) vector[k] into voigt: the tensor with
 * the principal directions of `basis` and the principal values `values`. */
void gm_principal_compose(const gm_principal *basis, const double values[3],
                          double voigt[6]);

#endif /* GM_MATERIALS_PRINCIPAL_H */
