/*
 * test_principal.c - the closed-form spectral decomposition of a symmetric
 * 3x3 tensor (lib/materials/principal.c) against the iterative Jacobi one
 * (principal_jacobi.c) and against the definition, on general tensors (yz
 * or zx non-zero: the simple root of the cubic, cross products and the Mohr
 * circle of the remaining pair).
 *
 * What is checked, for every tensor A (Voigt, norm |A| = sqrt(A:A)):
 *   - each pair (value, vector) is an eigenpair: |A v - value v| <= tol |A|;
 *   - the vectors are orthonormal to tol and the values descend;
 *   - sum value_k v_k v_k rebuilds A to tol |A| (gm_principal_compose);
 *   - the values agree with Jacobi's to tol |A|.
 * Backward-stable algorithms reach a few eps (2.2e-16) here; tol = 64 eps
 * = 1.4e-14 leaves room for the longest chain of roundings (scaling, the
 * mean shift, the cross product, the restricted 2x2 block: a dozen
 * operations) and still catches an O(sqrt(eps)) = 1.5e-8 loss, the error a
 * cubic root has at a double root, which is what the construction avoids.
 * The measured worst cases are printed.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include <check.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "materials/principal.h"
#include "test_random.h"
#include "test_tensor3.h"

#include "granmpm.h"

static const double TOLERANCE = 64.0 * DBL_EPSILON; /* relative to |A| */

/* A uniformly random rotation matrix, from a random unit quaternion. */
static void random_rotation(double r[3][3]) {
  double q[4], length = 0.0;
  do {
    length = 0.0;
    for (int k = 0; k < 4; k++) {
      q[k] = lcg_between(-1.0, 1.0);
      length += q[k] * q[k];
    }
  } while (length > 1.0 || length < 1e-3);
  length = sqrt(length);
  double w = q[0] / length, x = q[1] / length, y = q[2] / length,
         z = q[3] / length;
  r[0][0] = 1 - 2 * (y * y + z * z);
  r[0][1] = 2 * (x * y - w * z);
  r[0][2] = 2 * (x * z + w * y);
  r[1][0] = 2 * (x * y + w * z);
  r[1][1] = 1 - 2 * (x * x + z * z);
  r[1][2] = 2 * (y * z - w * x);
  r[2][0] = 2 * (x * z - w * y);
  r[2][1] = 2 * (y * z + w * x);
  r[2][2] = 1 - 2 * (x * x + y * y);
}

/* R diag(values) R^T in Voigt order. */
static void rotate_diagonal(double r[3][3], const double values[3],
                            double voigt[6]) {
  static const int row[6] = {0, 1, 2, 0, 1, 2}, col[6] = {0, 1, 2, 1, 2, 0};
  for (int c = 0; c < 6; c++) {
    double sum = 0.0;
    for (int k = 0; k < 3; k++)
      sum += r[row[c]][k] * values[k] * r[col[c]][k];
    voigt[c] = sum;
  }
}

/* Worst errors over a family of tensors, in units of |A|. */
typedef struct worst_errors {
  double residual, orthonormality, rebuild, against_jacobi;
} worst_errors;

/* Checks the closed form on one general tensor; updates the worst errors. */
static void check_tensor(const double voigt[6], worst_errors *worst,
                         const char *family, int n) {
  ck_assert_msg(voigt[GM_YZ] != 0.0 || voigt[GM_ZX] != 0.0,
                "%s %d: not a general tensor", family, n);
  gm_principal closed, jacobi;
  ck_assert_int_eq(gm_principal_decompose(voigt, &closed), 0);
  ck_assert_int_eq(gm_principal_decompose_jacobi(voigt, &jacobi), 0);
  double norm = voigt_norm(voigt);
  double a[3][3] = {{voigt[0], voigt[3], voigt[5]},
                    {voigt[3], voigt[1], voigt[4]},
                    {voigt[5], voigt[4], voigt[2]}};
  for (int k = 0; k < 3; k++) {
    const double *v = closed.vector[k];
    double residual = 0.0;
    for (int i = 0; i < 3; i++) {
      double component = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2] -
                         closed.value[k] * v[i];
      residual += component * component;
    }
    residual = sqrt(residual) / norm;
    worst->residual = fmax(worst->residual, residual);
    ck_assert_msg(residual <= TOLERANCE, "%s %d: |A v%d - l v%d| = %g |A|",
                  family, n, k, k, residual);
    for (int j = 0; j <= k; j++) {
      double overlap = 0.0;
      for (int c = 0; c < 3; c++)
        overlap += closed.vector[k][c] * closed.vector[j][c];
      double error = fabs(overlap - (j == k ? 1.0 : 0.0));
      worst->orthonormality = fmax(worst->orthonormality, error);
      ck_assert_msg(error <= TOLERANCE, "%s %d: v%d . v%d off by %g", family, n,
                    k, j, error);
    }
    double versus = fabs(closed.value[k] - jacobi.value[k]) / norm;
    worst->against_jacobi = fmax(worst->against_jacobi, versus);
    ck_assert_msg(versus <= TOLERANCE,
                  "%s %d: value %d %.17g against Jacobi %.17g (%g |A|)", family,
                  n, k, closed.value[k], jacobi.value[k], versus);
  }
  ck_assert_msg(closed.value[0] >= closed.value[1] &&
                    closed.value[1] >= closed.value[2],
                "%s %d: values not descending", family, n);
  double rebuilt[6];
  gm_principal_compose(&closed, closed.value, rebuilt);
  for (int c = 0; c < 6; c++) {
    double error = fabs(rebuilt[c] - voigt[c]) / norm;
    worst->rebuild = fmax(worst->rebuild, error);
    ck_assert_msg(error <= TOLERANCE, "%s %d: component %d rebuilt off by %g",
                  family, n, c, error);
  }
}

static void report(const char *family, const worst_errors *worst) {
  printf("principal %-18s worst (eps |A|): residual %.1f, orthonormality "
         "%.1f, rebuild %.1f, against Jacobi %.1f\n",
         family, worst->residual / DBL_EPSILON,
         worst->orthonormality / DBL_EPSILON, worst->rebuild / DBL_EPSILON,
         worst->against_jacobi / DBL_EPSILON);
}

/* Random spectra of either sign and random magnitudes (1e-3 .. 1e9: the
 * algorithm scales by the largest entry) under random rotations. */
START_TEST(test_random_tensors) {
  lcg_state = 20261125u;
  worst_errors worst = {0};
  for (int n = 0; n < 20000; n++) {
    double magnitude = pow(10.0, lcg_between(-3.0, 9.0));
    double values[3], r[3][3], voigt[6];
    for (int k = 0; k < 3; k++)
      values[k] = magnitude * lcg_between(-1.0, 1.0);
    if (n % 4 == 0) /* a large mean: the deviator is a small part */
      for (int k = 0; k < 3; k++)
        values[k] += 1e3 * magnitude;
    random_rotation(r);
    rotate_diagonal(r, values, voigt);
    check_tensor(voigt, &worst, "random", n);
  }
  report("random", &worst);
}
END_TEST

/* Repeated eigenvalues: a double largest, a double smallest and all three
 * equal (the rotated tensor then differs from lambda I only by round-off,
 * so the deviator is pure noise), plus the exact pair at h = 0 (0 between
 * +-x). These are where a root of the characteristic cubic is ill
 * conditioned. */
START_TEST(test_repeated_values) {
  lcg_state = 777u;
  worst_errors worst = {0};
  for (int n = 0; n < 6000; n++) {
    double big = lcg_between(-1e6, 1e6), other = lcg_between(-1e6, 1e6);
    double values[3], r[3][3], voigt[6];
    switch (n % 4) {
    case 0: /* double pair on top or at the bottom, by the sign of other */
      values[0] = values[1] = big;
      values[2] = other;
      break;
    case 1: /* the single one in the middle of the spectrum: h = 0 */
      values[0] = big + fabs(other);
      values[1] = big;
      values[2] = big - fabs(other);
      break;
    case 2: /* isotropic */
      values[0] = values[1] = values[2] = big;
      break;
    default: /* a double zero (uniaxial stress) */
      values[0] = values[1] = 0.0;
      values[2] = big;
      break;
    }
    random_rotation(r);
    rotate_diagonal(r, values, voigt);
    if (voigt[GM_YZ] == 0.0 && voigt[GM_ZX] == 0.0)
      voigt[GM_YZ] = 1e-300; /* keep it on the general path */
    check_tensor(voigt, &worst, "repeated", n);
  }
  report("repeated", &worst);
}
END_TEST

/* Nearly repeated: a pair split by 10^-k of the norm, k = 2 .. 16, on top
 * and at the bottom of the spectrum; the split values must still come out
 * to round-off (their directions are then ill conditioned, but the
 * residual and the rebuild are not). */
START_TEST(test_nearly_repeated_values) {
  lcg_state = 4242u;
  worst_errors worst = {0};
  int n = 0;
  for (int k = 2; k <= 16; k++) {
    for (int repeat = 0; repeat < 400; repeat++, n++) {
      double split = pow(10.0, -k);
      double sign = repeat % 2 ? 1.0 : -1.0;
      double values[3] = {1.0, 1.0 + split, 1.0 + sign * 2.5};
      double r[3][3], voigt[6];
      random_rotation(r);
      rotate_diagonal(r, values, voigt);
      check_tensor(voigt, &worst, "nearly-repeated", n);
    }
  }
  report("nearly-repeated", &worst);
}
END_TEST

/* Tensors that are diagonal or nearly so but still general (a yz or zx
 * entry far below the others, down to the smallest subnormal), and exact
 * ones whose spectrum is known: shear in yz only has values +-t and 0. */
START_TEST(test_diagonal_and_exact_tensors) {
  lcg_state = 99u;
  worst_errors worst = {0};
  for (int n = 0; n < 3000; n++) {
    double voigt[6] = {lcg_between(-1.0, 1.0),
                       lcg_between(-1.0, 1.0),
                       lcg_between(-1.0, 1.0),
                       0.0,
                       0.0,
                       0.0};
    if (n % 3 == 0)
      voigt[1] = voigt[0]; /* a repeated diagonal pair */
    double tiny = pow(10.0, -lcg_between(0.0, 320.0));
    voigt[n % 2 ? GM_YZ : GM_ZX] = tiny > 0.0 ? tiny : 4.9e-324;
    if (n % 5 == 0)
      voigt[GM_XY] = 1e-12;
    check_tensor(voigt, &worst, "nearly-diagonal", n);
  }
  report("nearly-diagonal", &worst);
  /* Pure shear t in yz: values t, 0, -t along (0, 1, 1)/sqrt 2, x, (0, 1,
   * -1)/sqrt 2: the values exactly (the cubic's h is exactly 0). */
  double shear[6] = {0.0, 0.0, 0.0, 0.0, 3.0, 0.0};
  gm_principal closed;
  ck_assert_int_eq(gm_principal_decompose(shear, &closed), 0);
  ck_assert_double_le(fabs(closed.value[0] - 3.0), 4.0 * DBL_EPSILON * 3.0);
  ck_assert_double_le(fabs(closed.value[1]), 4.0 * DBL_EPSILON * 3.0);
  ck_assert_double_le(fabs(closed.value[2] + 3.0), 4.0 * DBL_EPSILON * 3.0);
  ck_assert_double_le(fabs(fabs(closed.vector[1][0]) - 1.0), TOLERANCE);
  /* Uniaxial 2 along x plus shear 1 in yz: values 2, 1, -1. */
  double mixed[6] = {2.0, 0.0, 0.0, 0.0, 1.0, 0.0};
  ck_assert_int_eq(gm_principal_decompose(mixed, &closed), 0);
  ck_assert_double_le(fabs(closed.value[0] - 2.0), 8.0 * DBL_EPSILON);
  ck_assert_double_le(fabs(closed.value[1] - 1.0), 8.0 * DBL_EPSILON);
  ck_assert_double_le(fabs(closed.value[2] + 1.0), 8.0 * DBL_EPSILON);
  check_tensor(shear, &worst, "exact", 0);
  check_tensor(mixed, &worst, "exact", 1);
}
END_TEST

/* gm_principal_estimate: its extremes lie within its stated error of the
 * accurate values, and gm_principal_decompose_cubic finishes the
 * decomposition bit for bit as gm_principal_decompose does, on the hardest
 * family (a double root, where the cubic alone loses half the digits) and on
 * random tensors. */
START_TEST(test_estimate_within_its_error) {
  lcg_state = 31337u;
  double worst = 0.0; /* |estimate - accurate| / error */
  for (int n = 0; n < 10000; n++) {
    double big = lcg_between(-1e6, 1e6), other = lcg_between(-1e6, 1e6);
    double values[3] = {big, n % 2 ? big : other, other}, r[3][3], voigt[6];
    random_rotation(r);
    rotate_diagonal(r, values, voigt);
    if (voigt[GM_YZ] == 0.0 && voigt[GM_ZX] == 0.0)
      continue;
    double estimate[3], error;
    gm_principal_cubic cubic;
    gm_principal_estimate(voigt, &cubic, estimate, &error);
    gm_principal finished;
    gm_principal_decompose_cubic(&cubic, &finished);
    gm_principal accurate;
    ck_assert_int_eq(gm_principal_decompose(voigt, &accurate), 0);
    ck_assert_double_le(error, 1e-6 * voigt_norm(voigt));
    /* Finishing from the cubic is the decomposition itself. */
    ck_assert_mem_eq(&finished, &accurate, sizeof finished);
    for (int k = 0; k < 3; k += 2) {
      double miss = fabs(estimate[k] - accurate.value[k]);
      worst = fmax(worst, miss / error);
      ck_assert_msg(miss <= error, "%d: extreme %d off by %g > %g", n, k, miss,
                    error);
    }
  }
  printf("principal estimate: worst miss %.2g of its stated error\n", worst);
}
END_TEST

/* Non-finite input is refused, not decomposed. */
START_TEST(test_not_finite) {
  double voigt[6] = {1.0, 2.0, 3.0, 0.5, 0.25, NAN};
  gm_principal out;
  ck_assert_int_eq(gm_principal_decompose(voigt, &out), -1);
  voigt[GM_ZX] = INFINITY;
  ck_assert_int_eq(gm_principal_decompose(voigt, &out), -1);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("principal");
  TCase *tc = tcase_create("closed form");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_random_tensors);
  tcase_add_test(tc, test_repeated_values);
  tcase_add_test(tc, test_nearly_repeated_values);
  tcase_add_test(tc, test_diagonal_and_exact_tensors);
  tcase_add_test(tc, test_estimate_within_its_error);
  tcase_add_test(tc, test_not_finite);
  suite_add_tcase(suite, tc);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
