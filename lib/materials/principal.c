/*
 * principal.c - cyclic Jacobi eigen-decomposition of a symmetric 3x3 tensor.
 * Each rotation zeroes one off-diagonal entry; sweeps over the three pairs
 * converge quadratically. Jacobi is chosen over the closed-form cubic because
 * it keeps full relative accuracy when two eigenvalues coincide, which is
 * exactly where the Mohr-Coulomb edge returns put the stress. Tensors with
 * yz = zx = 0 (every 1D, plane-strain and axisymmetric state) take a closed
 * form instead: z is principal and the xy block is a Mohr circle, solved
 * with one square root for the values and one for the direction.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "materials/principal.h"

#include <math.h>

/* Far more than needed: 3x3 Jacobi converges to round-off in < 10 sweeps. */
enum { PRINCIPAL_MAX_SWEEPS = 50 };

/* Applies the rotation in the (p, q) plane that zeroes a[p][q], and
 * accumulates it into the eigenvector columns of v. */
static void jacobi_rotate(double a[3][3], double v[3][3], int p, int q) {
  double apq = a[p][q];
  /* theta = cot(2 angle); t = tan(angle), the smaller root for stability. */
  double theta = (a[q][q] - a[p][p]) / (2.0 * apq);
  double t = 1.0 / (fabs(theta) + sqrt(theta * theta + 1.0));
  if (theta < 0.0)
    t = -t;
  double c = 1.0 / sqrt(t * t + 1.0);
  double s = t * c;
  a[p][p] -= t * apq;
  a[q][q] += t * apq;
  a[p][q] = a[q][p] = 0.0;
  int r = 3 - p - q; /* the third index */
  double arp = a[r][p], arq = a[r][q];
  a[r][p] = a[p][r] = c * arp - s * arq;
  a[r][q] = a[q][r] = s * arp + c * arq;
  for (int k = 0; k < 3; k++) {
    double vkp = v[k][p], vkq = v[k][q];
    v[k][p] = c * vkp - s * vkq;
    v[k][q] = s * vkp + c * vkq;
  }
}

/* True when a[p][q] no longer changes the diagonal entries in double
 * precision: it is then set to zero instead of rotated. */
static int negligible(double apq, double app, double aqq) {
  double scaled = 100.0 * fabs(apq);
  return fabs(app) + scaled == fabs(app) && fabs(aqq) + scaled == fabs(aqq);
}

static void sort_descending(double value[3], double v[3][3],
                            gm_principal *out) {
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 2; i++)
    for (int j = i + 1; j < 3; j++)
      if (value[order[j]] > value[order[i]]) {
        int swap = order[i];
        order[i] = order[j];
        order[j] = swap;
      }
  for (int k = 0; k < 3; k++) {
    out->value[k] = value[order[k]];
    for (int c = 0; c < 3; c++)
      out->vector[k][c] = v[c][order[k]];
  }
}

/* The eigenvector of centre + radius of [[xx, xy], [xy, yy]] solves
 * (d - r) x + xy y = 0 and xy x - (d + r) y = 0 (d the half difference, r
 * the radius), so it is along (r + d, xy) or along (xy, r - d). Taking the
 * first when d >= 0 and the second otherwise keeps r + |d| >= r in it: no
 * cancellation, so the direction has full relative accuracy even when the
 * circle is tiny against its centre (nearly repeated values). At r = 0
 * (repeated in-plane values) every direction is principal: x and y. */
void gm_principal_decompose_planar(const double voigt[6],
                                   const gm_principal_circle *circle,
                                   gm_principal *out) {
  double d = circle->half_difference, r = circle->radius, xy = voigt[3];
  double cosine = 1.0, sine = 0.0; /* of the major in-plane direction */
  if (r > 0.0) {
    double x = d >= 0.0 ? r + d : xy, y = d >= 0.0 ? xy : r - d;
    double inverse_length = 1.0 / sqrt(x * x + y * y);
    cosine = x * inverse_length;
    sine = y * inverse_length;
  }
  double major = circle->centre + r, minor = circle->centre - r;
  double zz = voigt[2];
  /* Slots of the in-plane pair and of z in the descending order; ties keep
   * the order major, minor, z (as the Jacobi path's sort does). */
  int major_slot = 0, minor_slot = 1, z_slot = 2;
  if (zz > major) {
    z_slot = 0;
    major_slot = 1;
    minor_slot = 2;
  } else if (zz > minor) {
    z_slot = 1;
    minor_slot = 2;
  }
  out->value[major_slot] = major;
  out->vector[major_slot][0] = cosine;
  out->vector[major_slot][1] = sine;
  out->vector[major_slot][2] = 0.0;
  out->value[minor_slot] = minor;
  out->vector[minor_slot][0] = -sine;
  out->vector[minor_slot][1] = cosine;
  out->vector[minor_slot][2] = 0.0;
  out->value[z_slot] = zz;
  out->vector[z_slot][0] = 0.0;
  out->vector[z_slot][1] = 0.0;
  out->vector[z_slot][2] = 1.0;
}

int gm_principal_decompose(const double voigt[6], gm_principal *out) {
  if (voigt[4] == 0.0 && voigt[5] == 0.0) {
    if (!(isfinite(voigt[0]) && isfinite(voigt[1]) && isfinite(voigt[2]) &&
          isfinite(voigt[3])))
      return -1;
    gm_principal_circle circle = gm_principal_in_plane(voigt);
    gm_principal_decompose_planar(voigt, &circle, out);
    return 0;
  }
  double a[3][3] = {{voigt[0], voigt[3], voigt[5]},
                    {voigt[3], voigt[1], voigt[4]},
                    {voigt[5], voigt[4], voigt[2]}};
  double v[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  static const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  int converged = 0;
  for (int sweep = 0; sweep < PRINCIPAL_MAX_SWEEPS && !converged; sweep++) {
    converged = 1;
    for (int k = 0; k < 3; k++) {
      int p = pairs[k][0], q = pairs[k][1];
      if (a[p][q] == 0.0)
        continue;
      converged = 0;
      if (negligible(a[p][q], a[p][p], a[q][q]))
        a[p][q] = a[q][p] = 0.0;
      else
        jacobi_rotate(a, v, p, q);
    }
  }
  double value[3] = {a[0][0], a[1][1], a[2][2]};
  sort_descending(value, v, out);
  return converged ? 0 : -1;
}

void gm_principal_compose(const gm_principal *basis, const double values[3],
                          double voigt[6]) {
  /* Index pairs of the Voigt components GM_XX .. GM_ZX. */
  static const int row[6] = {0, 1, 2, 0, 1, 2};
  static const int col[6] = {0, 1, 2, 1, 2, 0};
  for (int c = 0; c < 6; c++) {
    double sum = 0.0;
    for (int k = 0; k < 3; k++)
      sum += values[k] * basis->vector[k][row[c]] * basis->vector[k][col[c]];
    voigt[c] = sum;
  }
}
