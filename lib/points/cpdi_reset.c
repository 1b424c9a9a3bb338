/*
 * cpdi_reset.c - keeping CPDI point domains usable under large shear.
 *
 * CPDI1 (Sadeghirad, Brannon & Burghardt 2011, IJNME 86:1435)
 * convects each point's domain with the deformation: the half edges are
 * r1 = F r1_0, r2 = F r2_0. Under sustained shear (a collapsing column, an
 * avalanche) the parallelogram becomes a long thin sliver: it reaches
 * across many cells, its corners sample the velocity far from the point,
 * and the gradient g_c = rot(x_{c+1} - x_{c-1}) / (2V) of a corner grows
 * as 1/V times the long diagonal. That is where granular CPDI used to
 * stop (an inverted point in the a = 3 column collapse, the singular-value
 * ratio of F at 193). The domain is only the interpolation domain of the
 * point: nothing in the balance laws says it must be F's image of the
 * initial square, only that it carries the point's volume. So the library
 * keeps the domain as its own per-point state, the domain map D
 * (r1 = D r1_0, r2 = D r2_0), which takes exactly the increments F takes
 * (g2p.c, density_control.c), and, once D is too distorted, replaces it
 * by the initial domain scaled to the same area:
 *   D <- sqrt(det D) I      when  sigma_max(D) / sigma_min(D) >
 * GM_CPDI_MAX_DISTORTION. This is the same idea as the CPDI domain limiting of
 * Homel, Brannon & Guilkey (2016, IJNME, doi:10.1002/nme.5151), which rescales
 * over-stretched domains to bound their reach; here the area is kept so that
 * the domain still covers the point's volume (det D = det F holds throughout,
 * up to rounding). F, stress, volume, mass and velocity are not touched: a
 * reset changes which nodes share the point's mass and momentum, not how
 * much there is (the CPDI weights are a partition of unity for any
 * parallelogram and their gradients sum to zero, support.c), so mass and
 * momentum are conserved exactly as for any other step.
 *
 * The ratio is read without a square root: with q = |D|_F^2 / (2 |det D|)
 * (Frobenius norm), the singular values s1 >= s2 satisfy s1 s2 = |det D|
 * and s1^2 + s2^2 = |D|_F^2, so q = (rho + 1/rho) / 2 for rho = s1 / s2,
 * and rho > T exactly when q > (T + 1/T) / 2.
 *
 * 3D (since 2026-11-29; before, a 3D domain followed F and a long shear
 * failed the step once its parallelepiped spanned more than the 5 node
 * planes a support may, GM_ERR_OUT_OF_GRID): the same with the nine
 * components of D (g2p_3d.c, density_control.c) and the reset
 *   D <- cbrt(det D) I      when  sigma_max(D) / sigma_min(D) > T,
 * which keeps det D, hence the volume. Two invariants no longer fix the
 * ratio rho = s1 / s3 of three singular values, so the test is exact in
 * two steps. First, root-free bounds: q = |D|_F^2 |cof D|_F^2 / det^2 D
 * = (s1^2 + s2^2 + s3^2)(1/s1^2 + 1/s2^2 + 1/s3^2) (|cof D|_F^2 = the sum
 * of the products s_i^2 s_j^2), which for a given rho lies between
 * q_min(rho) = (rho + 1 + 1/rho)^2 (at s2^2 = s1 s3) and q_max(rho) = 5 +
 * 2 rho^2 + 2 / rho^2 (at s2 = s1 or s3), both increasing in rho > 1. So
 * q <= q_min(T) (18.8 for T = 3) proves rho <= T: no reset, the common
 * case, with no root taken; q > q_max(T) (23.2) proves rho > T: a reset.
 * Between them, the largest and smallest eigenvalues of D^T D in closed
 * form (the trigonometric solution of the characteristic cubic, Smith
 * 1961, one acos and two cos) decide s1^2 > T^2 s3^2. A closed form
 * rather than a bound alone, so that 3D resets at the same ratio as 2D
 * (a test on q alone would let rho reach 3.54 before a reset, or reset
 * domains with rho down to 2.6). The arithmetic is per point and fixed,
 * so the results stay bitwise the same with any worker count.
 */
#include "points/points.h"

#include <math.h>

bool gm_cpdi_domain_reset(double map[4], double max_distortion) {
  double a = map[F_XX], b = map[F_XY], c = map[F_YX], d = map[F_YY];
  double determinant = a * d - b * c;
  double norm_squared = a * a + b * b + c * c + d * d;
  double limit = 0.5 * (max_distortion + 1.0 / max_distortion);
  /* A non-positive or non-finite D is left alone: F has the same
   * determinant, and the step fails on it (g2p.c). */
  if (!(determinant > 0.0 && isfinite(norm_squared)))
    return false;
  if (norm_squared <= 2.0 * limit * determinant)
    return false;
  double stretch = sqrt(determinant); /* keeps det D, hence the area */
  map[F_XX] = stretch;
  map[F_XY] = 0.0;
  map[F_YX] = 0.0;
  map[F_YY] = stretch;
  return true;
}

/* Squared singular values s1^2 >= s3^2 (the largest and smallest
 * eigenvalues) of the symmetric positive definite c = D^T D, row-major,
 * in closed form (the trigonometric solution of its characteristic
 * cubic: Smith 1961, CACM 4:168). */
static void extreme_squares(const double c[9], double *largest,
                            double *smallest) {
  double mean = (c[0] + c[4] + c[8]) / 3.0;
  double off = c[1] * c[1] + c[2] * c[2] + c[5] * c[5];
  double spread = (c[0] - mean) * (c[0] - mean) +
                  (c[4] - mean) * (c[4] - mean) +
                  (c[8] - mean) * (c[8] - mean) + 2.0 * off;
  double scale = sqrt(spread / 6.0);
  if (!(scale > 0.0)) { /* c = mean I */
    *largest = *smallest = mean;
    return;
  }
  double b[9]; /* (c - mean I) / scale, det b / 2 in [-1, 1] */
  for (int k = 0; k < 9; k++)
    b[k] = (c[k] - (k % 4 == 0 ? mean : 0.0)) / scale;
  double half_det = 0.5 * (b[0] * (b[4] * b[8] - b[5] * b[7]) -
                           b[1] * (b[3] * b[8] - b[5] * b[6]) +
                           b[2] * (b[3] * b[7] - b[4] * b[6]));
  half_det = half_det < -1.0 ? -1.0 : half_det > 1.0 ? 1.0 : half_det;
  double angle = acos(half_det) / 3.0;
  const double third_turn = 2.0943951023931954923; /* 2 pi / 3 */
  *largest = mean + 2.0 * scale * cos(angle);
  *smallest = mean + 2.0 * scale * cos(angle + third_turn);
}

bool gm_cpdi_domain_reset_3d(double map[9], double max_distortion) {
  const double *d = map; /* row-major */
  double determinant = d[0] * (d[4] * d[8] - d[5] * d[7]) -
                       d[1] * (d[3] * d[8] - d[5] * d[6]) +
                       d[2] * (d[3] * d[7] - d[4] * d[6]);
  double norm_squared = 0.0, cofactor_squared = 0.0; /* |D|_F^2, |cof D|_F^2 */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3,
          j2 = (j + 2) % 3;
      double cofactor =
          d[3 * i1 + j1] * d[3 * i2 + j2] - d[3 * i1 + j2] * d[3 * i2 + j1];
      norm_squared += d[3 * i + j] * d[3 * i + j];
      cofactor_squared += cofactor * cofactor;
    }
  /* A non-positive or non-finite D is left alone, as in 2D. */
  if (!(determinant > 0.0 && isfinite(norm_squared * cofactor_squared)))
    return false;
  double t = max_distortion;
  double q = norm_squared * cofactor_squared / (determinant * determinant);
  double below = (t + 1.0 + 1.0 / t) * (t + 1.0 + 1.0 / t); /* q_min(T) */
  double above = 5.0 + 2.0 * t * t + 2.0 / (t * t);         /* q_max(T) */
  bool distorted = q > above;
  if (q > below && !distorted) { /* the band: the singular values decide */
    double c[9];                 /* D^T D */
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        c[3 * i + j] = d[i] * d[j] + d[3 + i] * d[3 + j] + d[6 + i] * d[6 + j];
    double largest, smallest;
    extreme_squares(c, &largest, &smallest);
    distorted = largest > t * t * smallest;
  }
  if (!distorted)
    return false;
  double stretch = cbrt(determinant); /* keeps det D, hence the volume */
  for (int k = 0; k < 9; k++)
    map[k] = k % 4 == 0 ? stretch : 0.0;
  return true;
}

/* The 3D resets of the chunk: D read row-major from the nine slots. */
static void reset_chunk_3d(double *const *map, size_t first, size_t count) {
  static const int slot[9] = {F_XX, F_XY, F_XZ, F_YX, F_YY,
                              F_YZ, F_ZX, F_ZY, F_ZZ};
  for (size_t p = first; p < first + count; p++) {
    double value[9];
    for (int k = 0; k < 9; k++)
      value[k] = map[slot[k]][p];
    if (gm_cpdi_domain_reset_3d(value, GM_CPDI_MAX_DISTORTION))
      for (int k = 0; k < 9; k++)
        map[slot[k]][p] = value[k];
  }
}

void gm_cpdi_reset_chunk(const gm_domain *domain, size_t first, size_t count) {
  if (domain->dim < 2) /* a segment cannot be distorted */
    return;
  const gm_points *points = &domain->points;
  double *const *map = points->buffer[points->cur ^ 1].domain_map;
  if (domain->dim == 3) {
    reset_chunk_3d(map, first, count);
    return;
  }
  for (size_t p = first; p < first + count; p++) {
    double value[4] = {map[F_XX][p], map[F_XY][p], map[F_YX][p], map[F_YY][p]};
    if (gm_cpdi_domain_reset(value, GM_CPDI_MAX_DISTORTION))
      for (int k = 0; k < 4; k++)
        map[k][p] = value[k];
  }
}
