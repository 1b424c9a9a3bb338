/*
 * principal.c - closed-form (non-iterative) spectral decomposition of a
 * symmetric 3x3 tensor A, accurate to round-off of its norm for every
 * spectrum, repeated eigenvalues included.
 *
 * Tensors with yz = zx = 0 (every 1D, plane-strain and axisymmetric state)
 * take the shortest form: z is principal and the xy block is a Mohr circle,
 * solved with one square root for the values and one for the direction.
 *
 * A general tensor is scaled by its largest entry and split into its mean
 * m = tr(A)/3 and deviator D = A - m I. With p = sqrt(D:D / 6) and
 * h = det(D) / (2 p^3), the eigenvalues of D are the roots of the
 * characteristic cubic x^3 - 3 p^2 x - 2 p^3 h = 0, which the
 * trigonometric (Viete) solution gives as
 *   x_k = 2 p cos(theta - 2 pi k / 3),  theta = acos(h) / 3, k = 0, 1, -1.
 * A root of the cubic computed from rounded coefficients moves by
 * O(eps / gap^2): fine for a simple root, but a double root moves by
 * O(sqrt(eps)) p, so only one root is taken from the cubic: the one
 * farthest from the other two (the largest when h >= 0, the smallest
 * otherwise), which is at least sqrt(3) p away from both. Its eigenvector
 * is the largest cross product of two rows of D - x I (the rows span the
 * plane orthogonal to it, D - x I having two eigenvalues of size >= sqrt(3)
 * p). The other pair is the eigen-problem of D restricted to that plane:
 * a 2x2 symmetric block in an orthonormal basis of the plane, solved as a
 * Mohr circle like the planar case, which is accurate however close the
 * two values are (at a zero radius every direction of the plane is
 * principal). Cost: one acos, one cos, one sin and five square roots,
 * against a variable number of Jacobi rotations (principal_jacobi.c, kept
 * as the reference the tests compare with).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "materials/principal.h"

#include <math.h>

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

/* The scaled deviator of a general tensor and the roots of its cubic. */
typedef struct principal_cubic {
  double scale;       /* max |A_ij| (units of the tensor), > 0 */
  double mean;        /* tr(A) / (3 scale) */
  double deviator[6]; /* A / scale - mean I, Voigt order */
  double radius;      /* p = sqrt(D:D / 6), 0 for an isotropic tensor */
  double cosine;      /* cos(theta), theta = acos(h) / 3 in [0, pi/3] */
  double sine;        /* sin(theta) */
} principal_cubic;

/* Fills the cubic of a finite tensor with a non-zero entry. */
static void principal_cubic_of(const double voigt[6], principal_cubic *cubic) {
  double scale = 0.0;
  for (int c = 0; c < 6; c++)
    scale = fmax(scale, fabs(voigt[c]));
  double inverse = 1.0 / scale;
  double a[6];
  for (int c = 0; c < 6; c++)
    a[c] = voigt[c] * inverse;
  double mean = (a[0] + a[1] + a[2]) * (1.0 / 3.0);
  double *d = cubic->deviator;
  d[0] = a[0] - mean;
  d[1] = a[1] - mean;
  d[2] = a[2] - mean;
  d[3] = a[3];
  d[4] = a[4];
  d[5] = a[5];
  cubic->scale = scale;
  cubic->mean = mean;
  double squares = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] +
                   2.0 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
  double radius = sqrt(squares * (1.0 / 6.0));
  cubic->radius = radius;
  cubic->cosine = 1.0;
  cubic->sine = 0.0;
  if (radius == 0.0)
    return;
  /* det D of [[d0, d3, d5], [d3, d1, d4], [d5, d4, d2]]. */
  double determinant = d[0] * (d[1] * d[2] - d[4] * d[4]) -
                       d[3] * (d[3] * d[2] - d[4] * d[5]) +
                       d[5] * (d[3] * d[4] - d[1] * d[5]);
  double half = 0.5 * determinant / (radius * radius * radius);
  /* |h| <= 1 exactly; round-off may step past it. */
  half = fmin(1.0, fmax(-1.0, half));
  double theta = acos(half) * (1.0 / 3.0);
  cubic->cosine = cos(theta);
  cubic->sine = sin(theta);
}

/* sqrt(3) */
#define PRINCIPAL_SQRT3 1.73205080756887729353

void gm_principal_estimate(const double voigt[6], double values[3],
                           double *error) {
  principal_cubic cubic;
  double scale = 0.0;
  for (int c = 0; c < 6; c++)
    scale = fmax(scale, fabs(voigt[c]));
  if (scale == 0.0) {
    values[0] = values[1] = values[2] = 0.0;
    *error = 0.0;
    return;
  }
  principal_cubic_of(voigt, &cubic);
  double p = cubic.radius, c = cubic.cosine, s = cubic.sine;
  double m = cubic.mean;
  values[0] = cubic.scale * (m + 2.0 * p * c);
  values[1] = cubic.scale * (m + p * (PRINCIPAL_SQRT3 * s - c));
  values[2] = cubic.scale * (m - p * (PRINCIPAL_SQRT3 * s + c));
  /* A double root of the cubic moves by ~ sqrt(eps) p = 1.5e-8 p: a bound
   * 60 times that, in units of the tensor. */
  *error = 1e-6 * cubic.scale;
}

static double dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/* D x for the deviator D in Voigt order. */
static void deviator_times(const double d[6], const double x[3],
                           double out[3]) {
  out[0] = d[0] * x[0] + d[3] * x[1] + d[5] * x[2];
  out[1] = d[3] * x[0] + d[1] * x[1] + d[4] * x[2];
  out[2] = d[5] * x[0] + d[4] * x[1] + d[2] * x[2];
}

/* Unit eigenvector of the simple root x of D: the rows of D - x I span
 * the plane orthogonal to it, so their largest cross product is along it
 * (its length is at least the product of the other two eigenvalues of
 * D - x I over sqrt(3), both >= sqrt(3) p in size). */
static void isolated_vector(const double d[6], double root, double out[3]) {
  double rows[3][3] = {{d[0] - root, d[3], d[5]},
                       {d[3], d[1] - root, d[4]},
                       {d[5], d[4], d[2] - root}};
  double candidates[3][3];
  cross(rows[0], rows[1], candidates[0]);
  cross(rows[0], rows[2], candidates[1]);
  cross(rows[1], rows[2], candidates[2]);
  int best = 0;
  double best_length = dot(candidates[0], candidates[0]);
  for (int k = 1; k < 3; k++) {
    double length = dot(candidates[k], candidates[k]);
    if (length > best_length) {
      best = k;
      best_length = length;
    }
  }
  double inverse = 1.0 / sqrt(best_length);
  for (int c = 0; c < 3; c++)
    out[c] = candidates[best][c] * inverse;
}

static void set_vector(gm_principal *out, int slot, double value,
                       const double vector[3]) {
  out->value[slot] = value;
  for (int c = 0; c < 3; c++)
    out->vector[slot][c] = vector[c];
}

/* The general tensor (some of yz, zx non-zero, all finite). */
static void decompose_general(const double voigt[6], gm_principal *out) {
  principal_cubic cubic;
  principal_cubic_of(voigt, &cubic);
  const double *d = cubic.deviator;
  double scale = cubic.scale, mean = cubic.mean, p = cubic.radius;
  if (p == 0.0) { /* isotropic: every direction is principal */
    static const double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 3; k++)
      set_vector(out, k, scale * mean, axes[k]);
    return;
  }
  /* The simple root: the largest when h >= 0 (theta <= pi/6), else the
   * smallest. cos(theta) >= sqrt(3)/2 exactly when theta <= pi/6. */
  bool largest = cubic.cosine >= 0.5 * PRINCIPAL_SQRT3;
  double root = largest ? 2.0 * p * cubic.cosine
                        : -p * (PRINCIPAL_SQRT3 * cubic.sine + cubic.cosine);
  double isolated[3];
  isolated_vector(d, root, isolated);
  /* An orthonormal basis (u, w) of the plane orthogonal to it: u from the
   * two components not smaller than the third, so its length is >= 1/2. */
  double u[3], w[3];
  if (fabs(isolated[0]) > fabs(isolated[1])) {
    double inverse =
        1.0 / sqrt(isolated[0] * isolated[0] + isolated[2] * isolated[2]);
    u[0] = -isolated[2] * inverse;
    u[1] = 0.0;
    u[2] = isolated[0] * inverse;
  } else {
    double inverse =
        1.0 / sqrt(isolated[1] * isolated[1] + isolated[2] * isolated[2]);
    u[0] = 0.0;
    u[1] = isolated[2] * inverse;
    u[2] = -isolated[1] * inverse;
  }
  cross(isolated, u, w);
  /* D restricted to the plane, [[uu, uw], [uw, ww]], as a Mohr circle. */
  double du[3], dw[3];
  deviator_times(d, u, du);
  deviator_times(d, w, dw);
  double uu = dot(u, du), uw = dot(u, dw), ww = dot(w, dw);
  double centre = 0.5 * (uu + ww), half = 0.5 * (uu - ww);
  double radius = sqrt(half * half + uw * uw);
  /* Direction of the larger value, without cancellation (as in
   * gm_principal_decompose_planar). */
  double cosine = 1.0, sine = 0.0;
  if (radius > 0.0) {
    double x = half >= 0.0 ? radius + half : uw;
    double y = half >= 0.0 ? uw : radius - half;
    double inverse = 1.0 / sqrt(x * x + y * y);
    cosine = x * inverse;
    sine = y * inverse;
  }
  double major[3], minor[3];
  for (int c = 0; c < 3; c++) {
    major[c] = cosine * u[c] + sine * w[c];
    minor[c] = cosine * w[c] - sine * u[c];
  }
  /* The simple root is at least sqrt(3) p from the pair: the order is
   * fixed by which one it is. */
  int first = largest ? 1 : 0; /* slot of the pair's larger value */
  set_vector(out, largest ? 0 : 2, scale * (mean + root), isolated);
  set_vector(out, first, scale * (mean + centre + radius), major);
  set_vector(out, first + 1, scale * (mean + centre - radius), minor);
}

int gm_principal_decompose(const double voigt[6], gm_principal *out) {
  for (int c = 0; c < 6; c++)
    if (!isfinite(voigt[c]))
      return -1;
  if (voigt[4] == 0.0 && voigt[5] == 0.0) {
    gm_principal_circle circle = gm_principal_in_plane(voigt);
    gm_principal_decompose_planar(voigt, &circle, out);
    return 0;
  }
  decompose_general(voigt, out);
  return 0;
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
