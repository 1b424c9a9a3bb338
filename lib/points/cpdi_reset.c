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

void gm_cpdi_reset_chunk(const gm_domain *domain, size_t first, size_t count) {
  if (domain->dim < 2) /* a segment cannot be distorted */
    return;
  const gm_points *points = &domain->points;
  double *const *map = points->buffer[points->cur ^ 1].domain_map;
  for (size_t p = first; p < first + count; p++) {
    double value[4] = {map[F_XX][p], map[F_XY][p], map[F_YX][p], map[F_YY][p]};
    if (gm_cpdi_domain_reset(value, GM_CPDI_MAX_DISTORTION))
      for (int k = 0; k < 4; k++)
        map[k][p] = value[k];
  }
}
