/*
 * test_tensor3.h - symmetric 3x3 tensors in the library's Voigt order
 * (GM_XX, GM_YY, GM_ZZ, GM_XY, GM_YZ, GM_ZX; tensor components, not
 * engineering shears) for the tests of 3D material states: conversion to
 * a matrix, the Frobenius norm, rotation R v R^T and random unit axes.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef TEST_TENSOR3_H
#define TEST_TENSOR3_H

#include "granmpm.h"
#include "test_random.h"

#include <math.h>

static inline void voigt_to_matrix(const double v[6], double m[3][3]) {
  m[0][0] = v[GM_XX];
  m[1][1] = v[GM_YY];
  m[2][2] = v[GM_ZZ];
  m[0][1] = m[1][0] = v[GM_XY];
  m[1][2] = m[2][1] = v[GM_YZ];
  m[2][0] = m[0][2] = v[GM_ZX];
}

/* Frobenius norm of the tensor (shear rows count twice). */
static inline double voigt_norm(const double v[6]) {
  return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] +
              2.0 * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]));
}

static inline double voigt_difference_norm(const double a[6],
                                           const double b[6]) {
  double d[6];
  for (int c = 0; c < 6; c++)
    d[c] = a[c] - b[c];
  return voigt_norm(d);
}

/* R v R^T in Voigt order. */
static inline void voigt_rotate(double r[3][3], const double v[6],
                                double out[6]) {
  static const int row[6] = {0, 1, 2, 0, 1, 2}, col[6] = {0, 1, 2, 1, 2, 0};
  double m[3][3];
  voigt_to_matrix(v, m);
  for (int c = 0; c < 6; c++) {
    double sum = 0.0;
    for (int p = 0; p < 3; p++)
      for (int q = 0; q < 3; q++)
        sum += r[row[c]][p] * m[p][q] * r[col[c]][q];
    out[c] = sum;
  }
}

/* A random unit axis: a point of the unit ball (rejection), normalised. */
static inline void random_unit_axis(double axis[3]) {
  double length;
  do {
    for (int c = 0; c < 3; c++)
      axis[c] = lcg_between(-1.0, 1.0);
    length = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  } while (length > 1.0 || length < 0.1);
  for (int c = 0; c < 3; c++)
    axis[c] /= length;
}

#endif
