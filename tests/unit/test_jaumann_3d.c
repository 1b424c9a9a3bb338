/*
 * test_jaumann_3d.c - the objective stress increment of a general 3D
 * motion (lib/materials/jaumann.c): sigma + (W sigma - sigma W) dt and
 * D dt from a 9-component velocity gradient (002 sec 4.1, 004 eqs
 * 3.20-3.21). The domain does not run 3D yet, so this is tested where it
 * lives, with the materials' own update functions around it:
 *   - it is the Jaumann increment: against W sigma - sigma W formed with
 *     3x3 matrix products in the test, for random L and sigma;
 *   - on plane states (W_yz = W_zx = 0, yz = zx = 0) it is bit for bit the
 *     plane rotation the domain applies today (grid/stress_update.c,
 *     rewritten here);
 *   - objectivity: a rigid rotation at rate omega about an arbitrary axis
 *     (D = 0), integrated step by step with the elastic and the
 *     Mohr-Coulomb update, keeps the trace to round-off and the other
 *     invariants to the first-order error of forward Euler, and turns the
 *     stress into R sigma_0 R^T (Rodrigues' R) with an error that halves
 *     when dt halves.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include <check.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "materials/materials.h"
#include "test_random.h"
#include "test_tensor3.h"

/* The Jaumann increment formed with matrix products, as the definition. */
START_TEST(test_matches_matrix_products) {
  lcg_state = 11u;
  double worst = 0.0;
  for (int n = 0; n < 5000; n++) {
    double l[9], sigma[6], m[3][3], w[3][3], expected[3][3];
    for (int k = 0; k < 9; k++)
      l[k] = lcg_between(-50.0, 50.0); /* 1/s */
    for (int c = 0; c < 6; c++)
      sigma[c] = lcg_between(-1e5, 1e5); /* Pa */
    double dt = 1e-4;                    /* s */
    voigt_to_matrix(sigma, m);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        w[i][j] = 0.5 * (l[3 * i + j] - l[3 * j + i]);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double rate = 0.0;
        for (int k = 0; k < 3; k++)
          rate += w[i][k] * m[k][j] - m[i][k] * w[k][j];
        expected[i][j] = m[i][j] + rate * dt;
      }
    double rotated[6];
    memcpy(rotated, sigma, sizeof rotated);
    gm_jaumann_rotate(l, dt, rotated);
    double got[3][3];
    voigt_to_matrix(rotated, got);
    /* Two sums of a few products of sizes |W| dt |sigma| <= 5e-3 |sigma|,
     * added to sigma: a few eps of |sigma|. */
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double error = fabs(got[i][j] - expected[i][j]) / voigt_norm(sigma);
        worst = fmax(worst, error);
        ck_assert_msg(error <= 8.0 * DBL_EPSILON, "%d: (%d,%d) off by %g", n, i,
                      j, error);
      }
    double increment[6];
    gm_strain_increment(l, dt, increment);
    static const int row[6] = {0, 1, 2, 0, 1, 2}, col[6] = {0, 1, 2, 1, 2, 0};
    for (int c = 0; c < 6; c++) {
      double d = 0.5 * (l[3 * row[c] + col[c]] + l[3 * col[c] + row[c]]) * dt;
      ck_assert_double_eq(increment[c], d);
    }
  }
  printf("jaumann: worst against the matrix products %.2f eps |sigma|\n",
         worst / DBL_EPSILON);
}
END_TEST

/* On plane states the 3D increment is the domain's plane one, bit for bit
 * (the arithmetic of grid/stress_update.c's prepare_rows, copied here). */
START_TEST(test_plane_states_bitwise) {
  lcg_state = 12u;
  for (int n = 0; n < 20000; n++) {
    double l_xx = lcg_between(-9, 9), l_xy = lcg_between(-9, 9);
    double l_yx = lcg_between(-9, 9), l_yy = lcg_between(-9, 9);
    double l_zz = lcg_between(-9, 9), dt = lcg_between(0.0, 1e-3);
    double s_xx = lcg_between(-1e4, 1e4), s_yy = lcg_between(-1e4, 1e4);
    double s_zz = lcg_between(-1e4, 1e4), s_xy = lcg_between(-1e4, 1e4);
    double spin = 0.5 * (l_xy - l_yx) * dt; /* the plane code */
    double plane[6] = {s_xx + 2.0 * spin * s_xy,
                       s_yy - 2.0 * spin * s_xy,
                       s_zz,
                       s_xy + spin * (s_yy - s_xx),
                       0.0,
                       0.0};
    double plane_increment[4] = {l_xx * dt, l_yy * dt, l_zz * dt,
                                 0.5 * (l_xy + l_yx) * dt};
    double l[9] = {l_xx, l_xy, 0.0, l_yx, l_yy, 0.0, 0.0, 0.0, l_zz};
    double stress[6] = {s_xx, s_yy, s_zz, s_xy, 0.0, 0.0}, increment[6];
    gm_jaumann_rotate(l, dt, stress);
    gm_strain_increment(l, dt, increment);
    for (int c = 0; c < 6; c++)
      ck_assert_msg(stress[c] == plane[c], "%d: component %d %.17g vs %.17g", n,
                    c, stress[c], plane[c]);
    for (int c = 0; c < 4; c++)
      ck_assert(increment[c] == plane_increment[c]);
    ck_assert(increment[GM_YZ] == 0.0 && increment[GM_ZX] == 0.0);
  }
}
END_TEST

/* Invariants of a Voigt tensor: trace, J2 = s:s/2, det. */
static void invariants(const double v[6], double out[3]) {
  double m[3][3];
  voigt_to_matrix(v, m);
  double mean = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
  out[0] = 3.0 * mean;
  double s[6] = {v[0] - mean, v[1] - mean, v[2] - mean, v[3], v[4], v[5]};
  out[1] = 0.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] +
                  2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
  out[2] = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

typedef enum { WITH_ELASTIC, WITH_MOHR_COULOMB } rotation_material;

/* Turns sigma0 by `angle` (rad) about the unit axis at omega = 1 rad/s in
 * `steps` steps of Jaumann rotation + material update with D = 0; returns
 * the error against R sigma0 R^T relative to |sigma0| and checks the
 * invariants on the way. */
static double rigid_rotation(const double axis[3], const double sigma0[6],
                             double angle, int steps,
                             rotation_material material) {
  double omega = 1.0, dt = angle / (omega * steps);
  /* L = W = omega [axis]x: v = omega axis x r. */
  double l[9] = {0.0, -omega * axis[2], omega * axis[1],  omega * axis[2],
                 0.0, -omega * axis[0], -omega * axis[1], omega * axis[0],
                 0.0};
  double stress[6][1], strain[6][1] = {{0}}, density[1] = {2000.0};
  double plastic[1] = {0.0}, *state[1] = {plastic};
  int64_t id[1] = {0};
  gm_material_batch batch;
  memset(&batch, 0, sizeof batch);
  batch.struct_size = sizeof batch;
  batch.count = 1;
  batch.geometry = GM_GEOMETRY_3D;
  batch.dt = dt;
  for (int c = 0; c < 6; c++) {
    stress[c][0] = sigma0[c];
    batch.stress[c] = stress[c];
    batch.strain_increment[c] = strain[c];
  }
  batch.density = density;
  batch.state = state;
  batch.state_count = 1;
  batch.point_id = id;
  gm_elastic_def elastic = gm_elastic_def_default();
  gm_mohr_coulomb_def mohr_coulomb = gm_mohr_coulomb_def_default();
  mohr_coulomb.youngs_modulus = 1e7;
  mohr_coulomb.friction_angle = 0.5;
  double initial[3];
  invariants(sigma0, initial);
  double scale = voigt_norm(sigma0);
  for (int step = 0; step < steps; step++) {
    double current[6];
    for (int c = 0; c < 6; c++)
      current[c] = stress[c][0];
    gm_jaumann_rotate(l, dt, current);
    for (int c = 0; c < 6; c++)
      stress[c][0] = current[c];
    char message[128];
    int result =
        material == WITH_ELASTIC
            ? gm_elastic_update(&batch, &elastic, message, sizeof message)
            : gm_mohr_coulomb_update(&batch, &mohr_coulomb, message,
                                     sizeof message);
    ck_assert_int_eq(result, 0);
  }
  double final[6], now[3];
  for (int c = 0; c < 6; c++)
    final[c] = stress[c][0];
  invariants(final, now);
  /* The trace: tr(W s - s W) = 0 exactly, so only round-off of the sums,
   * steps x a few eps of |sigma|. For Mohr-Coulomb the returns (only of the
   * O((omega dt)^2) growth) keep the trace when psi = 0. */
  ck_assert_msg(fabs(now[0] - initial[0]) <= 4.0 * steps * DBL_EPSILON * scale,
                "trace moved by %g", fabs(now[0] - initial[0]));
  /* sigma:sigma grows by at most (1 + 4 (omega dt)^2) per step (the
   * increment is orthogonal to sigma and at most 2 omega dt |sigma|), so J2
   * and det (scaled by their size) drift by at most 6 steps (omega dt)^2 =
   * 6 angle omega dt. */
  double bound = 6.0 * angle * omega * dt;
  ck_assert_msg(fabs(now[1] - initial[1]) <= bound * scale * scale,
                "J2 drifted by %g of |sigma|^2", fabs(now[1] - initial[1]));
  ck_assert_msg(fabs(now[2] - initial[2]) <= bound * scale * scale * scale,
                "det drifted by %g of |sigma|^3", fabs(now[2] - initial[2]));
  /* Rodrigues: R = I + sin(a) K + (1 - cos(a)) K^2, K = [axis]x. */
  double k[3][3] = {{0.0, -axis[2], axis[1]},
                    {axis[2], 0.0, -axis[0]},
                    {-axis[1], axis[0], 0.0}};
  double r[3][3], m0[3][3], expected[3][3];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double k2 = 0.0;
      for (int q = 0; q < 3; q++)
        k2 += k[i][q] * k[q][j];
      r[i][j] = (i == j) + sin(angle) * k[i][j] + (1.0 - cos(angle)) * k2;
    }
  voigt_to_matrix(sigma0, m0);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double sum = 0.0;
      for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++)
          sum += r[i][p] * m0[p][q] * r[j][q];
      expected[i][j] = sum;
    }
  double expected_voigt[6] = {expected[0][0], expected[1][1], expected[2][2],
                              expected[0][1], expected[1][2], expected[2][0]};
  return voigt_difference_norm(final, expected_voigt) / scale;
}

START_TEST(test_rigid_rotation_elastic) {
  lcg_state = 13u;
  for (int n = 0; n < 8; n++) {
    double axis[3], sigma0[6];
    random_unit_axis(axis);
    for (int c = 0; c < 6; c++)
      sigma0[c] = lcg_between(-1e4, 1e4);
    double angle = 1.0; /* rad */
    double coarse = rigid_rotation(axis, sigma0, angle, 1000, WITH_ELASTIC);
    double fine = rigid_rotation(axis, sigma0, angle, 2000, WITH_ELASTIC);
    /* Forward Euler's global error: per step (omega dt)^2 / 2 |A^2 sigma|
     * with |A| <= 2 omega, so at most 2 angle omega dt = 2e-3 here; and
     * first order: halving dt halves it (ratio 2 within 10 %). */
    ck_assert_msg(coarse <= 2.0 * angle * angle / 1000,
                  "axis %d: error %g after 1 rad", n, coarse);
    ck_assert_msg(coarse / fine > 1.8 && coarse / fine < 2.2,
                  "axis %d: error %g then %g: not first order", n, coarse,
                  fine);
    if (n == 0)
      printf("jaumann rigid rotation (elastic): error %.3g at dt omega = "
             "1e-3, %.3g at 5e-4\n",
             coarse, fine);
  }
}
END_TEST

/* The same with Mohr-Coulomb on a stress on its yield surface (a returned
 * trial): the rotation only turns it, so it stays on the surface and
 * follows R sigma0 R^T. */
START_TEST(test_rigid_rotation_mohr_coulomb) {
  lcg_state = 14u;
  gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
  def.youngs_modulus = 1e7;
  def.friction_angle = 0.5;
  for (int n = 0; n < 4; n++) {
    double axis[3];
    random_unit_axis(axis);
    /* A compressive trial with a large random deviator, returned. */
    double stress[6][1], strain[6][1] = {{0}}, density[1] = {2000.0};
    double plastic[1] = {0.0}, *state[1] = {plastic};
    int64_t id[1] = {0};
    gm_material_batch batch;
    memset(&batch, 0, sizeof batch);
    batch.struct_size = sizeof batch;
    batch.count = 1;
    batch.dt = 1e-4;
    for (int c = 0; c < 6; c++) {
      stress[c][0] = (c < 3 ? -1e4 : 0.0) + lcg_between(-8e3, 8e3);
      batch.stress[c] = stress[c];
      batch.strain_increment[c] = strain[c];
    }
    batch.density = density;
    batch.state = state;
    batch.state_count = 1;
    batch.point_id = id;
    char message[128];
    ck_assert_int_eq(
        gm_mohr_coulomb_update(&batch, &def, message, sizeof message), 0);
    ck_assert_double_gt(plastic[0], 0.0); /* it was outside: on it now */
    double sigma0[6];
    for (int c = 0; c < 6; c++)
      sigma0[c] = stress[c][0];
    double coarse = rigid_rotation(axis, sigma0, 1.0, 1000, WITH_MOHR_COULOMB);
    double fine = rigid_rotation(axis, sigma0, 1.0, 2000, WITH_MOHR_COULOMB);
    ck_assert_msg(coarse <= 2e-3, "axis %d: error %g", n, coarse);
    ck_assert_msg(coarse / fine > 1.8 && coarse / fine < 2.2,
                  "axis %d: error %g then %g: not first order", n, coarse,
                  fine);
  }
}
END_TEST

int main(void) {
  Suite *suite = suite_create("jaumann_3d");
  TCase *tc = tcase_create("jaumann_3d");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, test_matches_matrix_products);
  tcase_add_test(tc, test_plane_states_bitwise);
  tcase_add_test(tc, test_rigid_rotation_elastic);
  tcase_add_test(tc, test_rigid_rotation_mohr_coulomb);
  suite_add_tcase(suite, tc);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
