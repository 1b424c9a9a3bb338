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
 * h = det(D) / (2 p^3) in [-1, 1], the eigenvalues of D are p y for the
 * roots y of the characteristic cubic y^3 - 3 y - 2 h = 0, which the
 * trigonometric (Viete) solution writes y_k = 2 cos(theta - 2 pi k / 3),
 * theta = acos(h) / 3. A root of the cubic computed from rounded
 * coefficients moves by O(eps / gap^2): fine for a simple root, but a
 * double root moves by O(sqrt(eps)), so only one root is taken from the
 * cubic: the one farthest from the other two (the largest, in [sqrt 3, 2],
 * when h >= 0; the smallest otherwise), which is at least sqrt(3) p away
 * from both. It is computed without trigonometric calls (a quadratic
 * guess in |h| polished by two Halley steps: three library calls of acos,
 * cos and sin cost more than the rest of the decomposition). Its
 * eigenvector is the largest cross product of two rows of D - p y I (the
 * rows span the plane orthogonal to it, D - p y I having two eigenvalues
 * of size >= sqrt(3) p). The other pair is the eigen-problem of D
 * restricted to that plane: a 2x2 symmetric block in an orthonormal basis
 * of the plane, solved as a Mohr circle like the planar case, which is
 * accurate however close the two values are (at a zero radius every
 * direction of the plane is principal). Cost: five square roots and a
 * handful of divisions, against a variable number of Jacobi rotations
 * (principal_jacobi.c, kept as the reference the tests compare with).
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

/* The largest root of y^3 - 3 y - 2 t for t in [0, 1], in [sqrt 3, 2]
 * (2 cos(acos(t) / 3)) without trigonometric calls: a quadratic through
 * t = 0, 1/2, 1 (within 1.03e-3 of it on [0, 1]), then two Halley steps,
 * each cubing the error (the root is simple, P' = 3 y^2 - 3 >= 6 there):
 * 5.5e-10 after the first, under an ulp after the second (checked on a
 * grid of 1e5 values of t against 2 cos(acos(t) / 3)). */
static double largest_root(double t) {
  double y = 1.7320508075688772 + t * (0.3213883853 - 0.0534391928 * t);
  for (int step = 0; step < 2; step++) {
    double value = y * y * y - 3.0 * y - 2.0 * t; /* P(y) */
    double slope = 3.0 * y * y - 3.0;             /* P'(y) */
    double curvature = 6.0 * y;                   /* P''(y) */
    y -= 2.0 * value * slope / (2.0 * slope * slope - value * curvature);
  }
  return y;
}

/* Fills the cubic of a finite tensor whose largest |entry| is scale. */
static void cubic_of(const double voigt[6], double scale,
                     gm_principal_cubic *cubic) {
  cubic->scale = scale;
  cubic->mean = cubic->radius = cubic->root = 0.0;
  if (scale == 0.0) { /* the zero tensor: isotropic */
    for (int c = 0; c < 6; c++)
      cubic->deviator[c] = 0.0;
    return;
  }
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
  cubic->mean = mean;
  double squares = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] +
                   2.0 * (d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
  double radius = sqrt(squares * (1.0 / 6.0));
  cubic->radius = radius;
  if (radius == 0.0)
    return;
  /* det D of [[d0, d3, d5], [d3, d1, d4], [d5, d4, d2]]. */
  double determinant = d[0] * (d[1] * d[2] - d[4] * d[4]) -
                       d[3] * (d[3] * d[2] - d[4] * d[5]) +
                       d[5] * (d[3] * d[4] - d[1] * d[5]);
  /* h = det(D / p) / 2 is in [-1, 1] exactly; round-off may step past. */
  double half = 0.5 * determinant / (radius * radius * radius);
  half = half > 1.0 ? 1.0 : half < -1.0 ? -1.0 : half;
  /* The roots for -h are those for h negated: the smallest root for h < 0
   * is minus the largest for -h. */
  cubic->root = half >= 0.0 ? largest_root(half) : -largest_root(-half);
}

/* Largest |entry| (plain comparisons: the entries are finite, and fmax
 * is a library call where the compiler must keep its NaN rules). */
static double max_abs(const double voigt[6]) {
  double scale = 0.0;
  for (int c = 0; c < 6; c++) {
    double size = fabs(voigt[c]);
    scale = size > scale ? size : scale;
  }
  return scale;
}

void gm_principal_estimate(const double voigt[6], gm_principal_cubic *cubic,
                           double values[3], double *error) {
  double scale = max_abs(voigt);
  cubic_of(voigt, scale, cubic);
  double p = cubic->radius, y = cubic->root, m = cubic->mean;
  /* The other two roots solve y'^2 + y y' + y^2 - 3 = 0 (the cubic
   * divided by y' - y): (-y +- sqrt(12 - 3 y^2)) / 2. Near a double root
   * the square root cancels to ~sqrt(eps): the stated error covers it. */
  double discriminant = 12.0 - 3.0 * y * y;
  double split = discriminant > 0.0 ? 0.5 * sqrt(discriminant) : 0.0;
  double first = -0.5 * y + split, second = -0.5 * y - split;
  if (y > 0.0) {
    values[0] = scale * (m + p * y);
    values[1] = scale * (m + p * first);
    values[2] = scale * (m + p * second);
  } else {
    values[0] = scale * (m + p * first);
    values[1] = scale * (m + p * second);
    values[2] = scale * (m + p * y);
  }
  /* A double root of the cubic moves by ~ sqrt(eps) p = 1.5e-8 p: a bound
   * 60 times that, in units of the tensor. */
  *error = 1e-6 * scale;
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

void gm_principal_decompose_cubic(const gm_principal_cubic *cubic,
                                  gm_principal *out) {
  const double *d = cubic->deviator;
  double scale = cubic->scale, mean = cubic->mean, p = cubic->radius;
  if (p == 0.0) { /* isotropic: every direction is principal */
    static const double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 3; k++)
      set_vector(out, k, scale * mean, axes[k]);
    return;
  }
  /* The simple root: the largest when h >= 0, else the smallest. */
  bool largest = cubic->root > 0.0;
  double root = p * cubic->root;
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
  gm_principal_cubic cubic;
  cubic_of(voigt, max_abs(voigt), &cubic);
  gm_principal_decompose_cubic(&cubic, out);
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
