/*
 * principal_jacobi.c - cyclic Jacobi eigen-decomposition of a symmetric 3x3
 * tensor, the iterative reference for the closed form of principal.c. Each
 * rotation zeroes one off-diagonal entry; sweeps over the three pairs
 * converge quadratically, and the result keeps full accuracy for repeated
 * eigenvalues. The library's models use the closed form (principal.c),
 * which is as accurate and several times cheaper; this one stays to check
 * it against (tests/unit/test_principal.c) and to measure it.
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

int gm_principal_decompose_jacobi(const double voigt[6], gm_principal *out) {
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
