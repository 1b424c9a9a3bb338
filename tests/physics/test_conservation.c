/*
 * test_conservation.c - an elastic block with random initial velocities, no
 * gravity and no walls, far from the grid edges: the total mass is exactly
 * constant and the total linear momentum is constant to round-off, for every
 * update scheme, in 1D and in plane strain.
 *
 * Why momentum is conserved exactly in exact arithmetic: the change of
 * sum_p m_p v_p over a step is dt sum_p m_p sum_I N_Ip a_I
 * = dt sum_I m_I a_I = dt sum_I f_I (lumped mass m_I = sum_p N_Ip m_p), and
 * the internal forces f_I = -sum_p V_p sigma_p grad N_Ip sum to zero over I
 * because sum_I grad N_Ip = 0 (partition of unity). MUSL's re-mapping and
 * USF's ordering only move the stress update, not this identity.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "test_util.h"

enum { CONSERVATION_STEPS = 200 };

static const double BLOCK_CELL_SIZE = 0.125; /* m */
static const double BLOCK_YOUNGS = 1e6;      /* Pa */
static const double BLOCK_DENSITY = 1000.0;  /* kg/m^3 */
static const double MAX_SPEED = 0.05;        /* m/s, per velocity component */

/* A small 64-bit linear congruential generator (Knuth's MMIX constants):
 * reproducible on every platform, no dependence on rand(). */
static double lcg_uniform(uint64_t *state) {
  *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*state >> 11) * 0x1.0p-53; /* [0, 1) */
}

/* Gives every point velocity components uniform in [-MAX_SPEED, MAX_SPEED].
 * Index order at creation is deterministic, so the field is reproducible. */
static void set_random_velocity(gm_domain *domain, int dim, uint64_t seed) {
  size_t count = gm_domain_point_count(domain);
  uint64_t state = seed;
  for (int k = 0; k < dim; ++k) {
    double *velocity = NULL;
    TEST_ASSERT_OK(domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY,
                                                (size_t)k, &velocity));
    for (size_t i = 0; i < count; ++i)
      velocity[i] = MAX_SPEED * (2.0 * lcg_uniform(&state) - 1.0);
  }
}

/* sum_p m_p |v_p| (kg m/s): the scale of the momentum round-off. */
static double momentum_magnitude_sum(const gm_domain *domain, int dim) {
  size_t count = gm_domain_point_count(domain);
  const double *mass = NULL;
  TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass));
  double total = 0.0;
  for (size_t i = 0; i < count; ++i) {
    double speed_squared = 0.0;
    for (int k = 0; k < dim; ++k) {
      const double *velocity = NULL;
      TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_VELOCITY,
                                                  (size_t)k, &velocity));
      speed_squared += velocity[i] * velocity[i];
    }
    total += mass[i] * sqrt(speed_squared);
  }
  return total;
}

/* sum_p m_p v_p[k] (kg m/s) from the point fields, independent of the
 * library's summary. */
static double momentum_from_fields(const gm_domain *domain, int k) {
  size_t count = gm_domain_point_count(domain);
  const double *mass = NULL, *velocity = NULL;
  TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass));
  TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_VELOCITY,
                                              (size_t)k, &velocity));
  double total = 0.0;
  for (size_t i = 0; i < count; ++i)
    total += mass[i] * velocity[i];
  return total;
}

static gm_summary summary_of(const gm_domain *domain) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  return summary;
}

/* Loop index i: geometry (0: 1D, 1: plane strain) and scheme. */
START_TEST(test_mass_and_momentum) {
  gm_geometry geometry =
      _i / 3 == 0 ? GM_GEOMETRY_1D : GM_GEOMETRY_PLANE_STRAIN;
  gm_update_scheme scheme = (gm_update_scheme)(_i % 3);
  int dim = gm_geometry_dimension(geometry);

  /* A 4 m box, block of 8 x 8 cells in its middle: with |v| <= 0.07 m/s
   * over ~0.4 s the block moves a few cm, far from the open edges. */
  gm_domain_def def = gm_domain_def_default();
  def.geometry = geometry;
  def.cell_size = BLOCK_CELL_SIZE;
  def.scheme = scheme;
  for (int k = 0; k < 2; ++k)
    def.extent[k] = 4.0;
  gm_domain *domain = test_create_domain(&def);
  /* nu = 0 in 1D (uniaxial strain; any nu would do), 0.3 in 2D so shear and
   * normal stresses are coupled. */
  double poisson = dim == 1 ? 0.0 : 0.3;
  int material = test_add_elastic(domain, BLOCK_YOUNGS, poisson, BLOCK_DENSITY);
  const double lower[3] = {1.5, 1.5, 0.0}, upper[3] = {2.5, 2.5, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  set_random_velocity(domain, dim, 12345u + (uint64_t)_i);

  gm_summary initial = summary_of(domain);
  double magnitude_sum = momentum_magnitude_sum(domain, dim);
  ck_assert_double_gt(magnitude_sum, 0.0);

  for (int step = 1; step <= CONSERVATION_STEPS; ++step) {
    /* dt <= 0: the largest stable step, re-evaluated every step. */
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    gm_summary now = summary_of(domain);
    /* Point masses never change, and the summary sums in an
     * index-independent order: the total is bit-for-bit the same. */
    ck_assert_msg(now.mass == initial.mass,
                  "%s dim %d step %d: mass %.17g != %.17g",
                  test_scheme_name(scheme), dim, step, now.mass, initial.mass);
    /* Each step recomputes every v_p through ~10 roundings (p_I / m_I, the
     * sum over 2^dim nodes, v + dt a), each <= DBL_EPSILON (2.2e-16)
     * relative to |v_p| or to the impulse dt |a_I|, which is no larger than
     * |v| here. Those errors add to <~ 1e-14 sum m|v| per step, and they
     * accumulate at worst linearly; we allow 1e-13 per step. A real leak
     * (one node's force dropped, a wall where there is none) changes the
     * momentum by ~1e-3 of the sum per step. */
    double tolerance = 1e-13 * step * magnitude_sum;
    for (int k = 0; k < dim; ++k)
      ck_assert_msg(fabs(now.momentum[k] - initial.momentum[k]) <= tolerance,
                    "%s dim %d step %d: momentum[%d] %.17g, initially %.17g "
                    "(tolerance %.3g)",
                    test_scheme_name(scheme), dim, step, k, now.momentum[k],
                    initial.momentum[k], tolerance);
  }

  /* The summary agrees with sum m v taken from the fields (one summation's
   * round-off: count * eps relative to sum m|v|; 1e-12 is far above it). */
  gm_summary final_summary = summary_of(domain);
  for (int k = 0; k < dim; ++k)
    ck_assert_double_eq_tol(final_summary.momentum[k],
                            momentum_from_fields(domain, k),
                            1e-12 * magnitude_sum);

  gm_domain_destroy(domain);
}
END_TEST

/* cpGIMP, USL, a block pulled apart in x (v_x = 0.5/s (x - x_c)) in plane
 * strain at 2 x 2 points per cell (enough points for the fused pass's
 * spare node sums) and nearly no stiffness: F_xx grows past 2, so the
 * domains' half edges 0.25 F_xx cells pass half a cell and every point
 * takes the general support in the fused move and re-map
 * (move_remap_wide.c), whose node lookup read the block shift of an
 * unset view before 2026-11-28 (a crash or wrong nodes: this test ended
 * in a segmentation fault there at the first long support). The momentum
 * is conserved for the same reason as above (GIMP's weights are a
 * partition of unity too); loop index: 1 or 2 workers. */
START_TEST(test_stretched_cpgimp_usl) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_PLANE_STRAIN;
  def.cell_size = BLOCK_CELL_SIZE;
  def.scheme = GM_SCHEME_USL;
  def.shape = GM_SHAPE_CPGIMP;
  def.worker_count = _i + 1;
  def.extent[0] = 16.0; /* m: the block spans 4 m -> 11 m */
  def.extent[1] = 8.0;
  gm_domain *domain = test_create_domain(&def);
  /* E = 1 Pa: wave speed 0.03 m/s, the block flies apart nearly freely. */
  int material = test_add_elastic(domain, 1.0, 0.3, BLOCK_DENSITY);
  /* 32 x 32 cells, 4096 points: more than the block grid's nodes (the
   * fused pass's condition, gm_move_remap_wide_fits) */
  const double lower[3] = {6.0, 2.0, 0.0}, upper[3] = {10.0, 6.0, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  size_t count = gm_domain_point_count(domain);
  const double *position = NULL;
  double *velocity = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &position));
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity));
  for (size_t i = 0; i < count; ++i)
    velocity[i] = 0.5 * (position[i] - 8.0); /* m/s */
  gm_summary initial = summary_of(domain);
  double magnitude_sum = momentum_magnitude_sum(domain, 2);
  double time = 0.0; /* s */
  int steps = 0;
  while (time < 3.5 && steps < 1000) { /* F_xx near 2.75 by then */
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    time += dt;
    steps++;
    gm_summary now = summary_of(domain);
    /* The tolerance of the test above, per step. */
    double tolerance = 1e-13 * steps * magnitude_sum;
    for (int k = 0; k < 2; ++k)
      ck_assert_msg(fabs(now.momentum[k] - initial.momentum[k]) <= tolerance,
                    "cpGIMP USL step %d: momentum[%d] %.17g, initially %.17g "
                    "(tolerance %.3g)",
                    steps, k, now.momentum[k], initial.momentum[k], tolerance);
  }
  /* The supports were long: F_xx of the inner points past 2.2 (half
   * edge 0.55 cells; the edge points stretch less). */
  double *gradient = malloc(9 * count * sizeof *gradient);
  ck_assert_ptr_nonnull(gradient);
  TEST_ASSERT_OK(domain,
                 gm_domain_get_field(domain, GM_FIELD_DEFORMATION_GRADIENT,
                                     gradient, 9 * count));
  double largest = 0.0;
  for (size_t i = 0; i < count; ++i)
    largest = gradient[9 * i] > largest ? gradient[9 * i] : largest;
  ck_assert_msg(largest > 2.2, "largest F_xx %g after %d steps", largest,
                steps);
  free(gradient);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *conservation_suite(void) {
  Suite *suite = suite_create("conservation");
  TCase *tcase = tcase_create("elastic_block");
  tcase_set_timeout(tcase, 60);
  /* 0..2: 1D with USL, MUSL, USF; 3..5: plane strain with the same. */
  tcase_add_loop_test(tcase, test_mass_and_momentum, 0, 6);
  tcase_add_loop_test(tcase, test_stretched_cpgimp_usl, 0, 2);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(conservation_suite()) ? EXIT_FAILURE : 0;
}
