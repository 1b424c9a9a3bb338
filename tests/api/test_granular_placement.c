/*
 * test_granular_placement.c - in the granular family, points of a granular
 * material may not be placed looser than rho_cr - TOL: V_cr = m / rho_cr
 * "is the highest volume a material point can have" (000 sec 3.3). Below
 * it, density control (eqs 13-15) returns F every step, so the point can
 * never compact, and its domain of interaction is smaller than the point.
 *
 *  1. gm_domain_add_points refuses such a point (density given, by mass,
 *     or the material's density) with GM_ERR_INVALID_ARGUMENT and a message
 *     naming the critical density and the point index, and adds nothing.
 *  2. It accepts points at exactly rho_cr, at rho_cr - TOL / 2 and at
 *     rho_cr - TOL, and at rho_cr through a rounded mass with TOL = 0.
 *  3. gm_domain_fill_box and gm_domain_add_source refuse likewise.
 *  4. gm_domain_set_granular refuses a rho_cr that an existing point (or a
 *     source) of the material would be below, and changes nothing then.
 *  5. The plain and stress_free families accept all of these (in
 *     stress_free loose points compact stress-free: Dunatunga-Kamrin).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

static const double CRITICAL = 1431.0; /* kg/m^3, rho_cr */
static const double TOLERANCE = 0.5;   /* kg/m^3, TOL: boundaries are clear */
static const double DENSE = 1600.0;    /* kg/m^3, the material's density */
static const double LOOSE = 1000.0;    /* kg/m^3, well below rho_cr - TOL */
static const double EDGE = 0.05;       /* m, point domain edge: half a cell */

enum { BATCH = 5, LOOSE_INDEX = 3 };

/* A 1 m x 1 m plane-strain box of 0.1 m cells in `family`, with one
 * elastic material of density `density`, made granular with rho_cr
 * `critical` and TOL `tolerance` (kg/m^3); *material receives its id. */
static gm_domain *granular_domain(gm_family family, double density,
                                  double critical, double tolerance,
                                  int *material) {
  gm_domain_def def = gm_domain_def_default();
  def.family = family;
  def.cell_size = 0.1;
  def.extent[0] = def.extent[1] = 1.0; /* m */
  gm_domain *domain = test_create_domain(&def);
  *material = test_add_elastic(domain, 1e6, 0.3, density);
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = critical;
  granular.tolerance = tolerance;
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, *material, &granular));
  return domain;
}

/* The same with rho_cr CRITICAL and TOL TOLERANCE. */
static gm_domain *placement_domain(gm_family family, double density,
                                   int *material) {
  return granular_domain(family, density, CRITICAL, TOLERANCE, material);
}

/* A row of BATCH points along y = 0.5 m, x = 0.15, 0.3, ... m. */
static void batch_positions(double position[2 * BATCH], double x0) {
  for (int p = 0; p < BATCH; p++) {
    position[2 * p] = x0 + 0.15 * p;
    position[2 * p + 1] = 0.5;
  }
}

/* Adds `count` points of `material` at `densities` (kg/m^3), given as the
 * density array, or as masses (m = rho V) if by_mass. */
static gm_status add_row(gm_domain *domain, int material, size_t count,
                         const double *densities, bool by_mass, double x0,
                         int64_t *first_id) {
  double position[2 * BATCH], volume[BATCH], mass[BATCH];
  ck_assert_uint_le(count, BATCH);
  batch_positions(position, x0);
  for (size_t p = 0; p < count; p++) {
    volume[p] = EDGE * EDGE; /* m^2 per m of thickness */
    mass[p] = densities ? densities[p] * volume[p] : 0.0;
  }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.volume = volume;
  if (densities && by_mass)
    points.mass = mass;
  else
    points.density = densities;
  return gm_domain_add_points(domain, &points, first_id);
}

static void assert_message_has(const gm_domain *domain, const char *text) {
  const char *message = gm_domain_last_error(domain);
  ck_assert_msg(strstr(message, text) != NULL,
                "the message '%s' does not contain '%s'", message, text);
}

/* Refused with GM_ERR_INVALID_ARGUMENT and a message naming the critical
 * density, `entry` (the entry point) and `detail`. */
static void assert_refused(const gm_domain *domain, gm_status status,
                           const char *entry, const char *detail) {
  ck_assert_msg(status == GM_ERR_INVALID_ARGUMENT, "%s: %s (%s)", entry,
                gm_strerror(status), gm_domain_last_error(domain));
  assert_message_has(domain, entry);
  assert_message_has(domain, "critical");
  assert_message_has(domain, detail);
}

/* ---------------------------------------------------- 1. add_points */

/* _i: 0 the density array, 1 masses, 2 the material's density. The batch
 * of BATCH points has its one loose point at index LOOSE_INDEX; two dense
 * points were added before, so all-or-nothing is checked on a non-empty
 * domain: nothing added, and the next id is still 2. */
START_TEST(test_add_points_refuses_loose) {
  bool by_mass = _i == 1, by_material = _i == 2;
  int material = -1, dense_material = -1;
  gm_domain *domain = placement_domain(GM_FAMILY_GRANULAR,
                                       by_material ? LOOSE : DENSE, &material);
  /* The dense points of the by_material case need a second material. */
  dense_material =
      by_material ? test_add_elastic(domain, 1e6, 0.3, DENSE) : material;
  const double dense[2] = {DENSE, DENSE}; /* kg/m^3 */
  TEST_ASSERT_OK(domain,
                 add_row(domain, dense_material, 2, dense, false, 0.1, NULL));
  double densities[BATCH]; /* kg/m^3 */
  for (int p = 0; p < BATCH; p++)
    densities[p] = p == LOOSE_INDEX ? LOOSE : DENSE;
  gm_status status =
      add_row(domain, material, BATCH, by_material ? NULL : densities, by_mass,
              0.15, NULL);
  /* By the material's density every point is loose: the first is named. */
  assert_refused(domain, status, "gm_domain_add_points",
                 by_material ? "point 0 " : "point 3 ");
  assert_message_has(domain, "1000 kg/m^3");
  assert_message_has(domain, "1431 kg/m^3");
  ck_assert_uint_eq(gm_domain_point_count(domain), 2);
  int64_t first = -1;
  TEST_ASSERT_OK(domain,
                 add_row(domain, dense_material, 1, dense, false, 0.2, &first));
  ck_assert_int_eq(first, 2); /* no id was used by the refused batch */
  gm_domain_destroy(domain);
}
END_TEST

/* Points of a material not marked granular are not concerned. */
START_TEST(test_add_points_ignores_other_materials) {
  int material = -1;
  gm_domain *domain = placement_domain(GM_FAMILY_GRANULAR, DENSE, &material);
  int plain = test_add_elastic(domain, 1e6, 0.3, LOOSE);
  TEST_ASSERT_OK(domain, add_row(domain, plain, BATCH, NULL, false, 0.2, NULL));
  ck_assert_uint_eq(gm_domain_point_count(domain), BATCH);
  gm_domain_destroy(domain);
}
END_TEST

/* ----------------------------------------------------- 2. boundaries */

/* rho_cr, rho_cr - TOL / 2 and rho_cr - TOL are accepted (density control
 * acts only below rho_cr - TOL, eqs 13-15); 2 TOL below is refused. */
START_TEST(test_add_points_accepts_down_to_tolerance) {
  int material = -1;
  gm_domain *domain = placement_domain(GM_FAMILY_GRANULAR, DENSE, &material);
  const double accepted[3] = {CRITICAL, CRITICAL - 0.5 * TOLERANCE,
                              CRITICAL - TOLERANCE}; /* kg/m^3 */
  for (int by_mass = 0; by_mass < 2; by_mass++)
    TEST_ASSERT_OK(domain, add_row(domain, material, 3, accepted, by_mass,
                                   0.1 + 0.05 * by_mass, NULL));
  ck_assert_uint_eq(gm_domain_point_count(domain), 6);
  const double below = CRITICAL - 2.0 * TOLERANCE; /* kg/m^3 */
  assert_refused(domain, add_row(domain, material, 1, &below, false, 0.2, NULL),
                 "gm_domain_add_points", "point 0 ");
  ck_assert_uint_eq(gm_domain_point_count(domain), 6);
  gm_domain_destroy(domain);
}
END_TEST

/* With TOL = 0, a point placed at rho_cr through its mass m = rho_cr V
 * (rounded) has m / V one ulp below rho_cr for some V: still accepted.
 * 200 volumes between 0.4 and 0.6 cells squared cover both roundings. */
START_TEST(test_rounded_mass_at_critical_is_accepted) {
  int material = -1;
  gm_domain *domain =
      granular_domain(GM_FAMILY_GRANULAR, DENSE, CRITICAL, 0.0, &material);
  enum { VOLUMES = 200 };
  int rounded_below = 0;
  for (int k = 0; k < VOLUMES; k++) {
    double edge = 0.04 + 0.02 * k / VOLUMES; /* m */
    double volume = edge * edge;             /* m^2 */
    double mass = CRITICAL * volume;         /* kg per m */
    rounded_below += mass / volume < CRITICAL;
    const double position[2] = {0.5, 0.5}; /* m */
    gm_points_def points = gm_points_def_default();
    points.count = 1;
    points.material = material;
    points.position = position;
    points.volume = &volume;
    points.mass = &mass;
    TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  }
  ck_assert_msg(rounded_below > 0, "no volume rounded m / V below rho_cr: "
                                   "the test does not test the rounding");
  gm_domain_destroy(domain);
}
END_TEST

/* --------------------------------------------- 3. fill_box, sources */

/* _i: 0 the fill's density, 1 the material's density (fill density 0). */
START_TEST(test_fill_box_refuses_loose) {
  int material = -1;
  gm_domain *domain =
      placement_domain(GM_FAMILY_GRANULAR, _i ? LOOSE : DENSE, &material);
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.density = _i ? 0.0 : LOOSE;
  fill.lower[0] = fill.lower[1] = 0.2; /* m */
  fill.upper[0] = fill.upper[1] = 0.6; /* m */
  fill.points_per_cell_axis = 2;
  int64_t first = -1;
  size_t count = 0;
  assert_refused(domain, gm_domain_fill_box(domain, &fill, &first, &count),
                 "gm_domain_fill_box", "1000 kg/m^3");
  ck_assert_uint_eq(gm_domain_point_count(domain), 0);
  fill.density = CRITICAL;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, &first, &count));
  ck_assert_int_eq(first, 0);
  ck_assert_uint_eq(count, 64); /* 4 x 4 cells, 2 x 2 points each */
  gm_domain_destroy(domain);
}
END_TEST

static gm_source_def source_at(int material, double density,
                               const double position[2]) {
  gm_source_def source = gm_source_def_default();
  source.material = material;
  source.count = 1;
  source.position = position;
  source.point_size = EDGE;
  source.density = density;
  return source;
}

/* _i: 0 the source's density, 1 the material's density (density 0). */
START_TEST(test_add_source_refuses_loose) {
  int material = -1;
  gm_domain *domain =
      placement_domain(GM_FAMILY_GRANULAR, _i ? LOOSE : DENSE, &material);
  const double position[2] = {0.5, 0.5}; /* m */
  gm_source_def source = source_at(material, _i ? 0.0 : LOOSE, position);
  int id = -1;
  assert_refused(domain, gm_domain_add_source(domain, &source, &id),
                 "gm_domain_add_source", "1000 kg/m^3");
  ck_assert_int_eq(id, -1);
  source.density = CRITICAL;
  TEST_ASSERT_OK(domain, gm_domain_add_source(domain, &source, &id));
  ck_assert_int_eq(id, 0); /* the refused source took no slot */
  TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-5));
  ck_assert_uint_eq(gm_domain_point_count(domain), 1); /* it injected */
  gm_domain_destroy(domain);
}
END_TEST

/* ------------------------------------------------- 4. set_granular */

/* Points at 1600, 1200, 1300, 1100 kg/m^3 under rho_cr 1000: raising
 * rho_cr to 1431 would leave ids 1, 2 and 3 below; id 1 is named. Raising
 * it to 1200 + TOL keeps them all in. */
START_TEST(test_set_granular_refuses_raising_above_points) {
  int material = -1;
  gm_domain *domain = granular_domain(GM_FAMILY_GRANULAR, DENSE, 1000.0,
                                      TOLERANCE, &material); /* kg/m^3 */
  gm_granular_def granular = gm_granular_def_default();
  granular.tolerance = TOLERANCE;
  const double densities[4] = {1600.0, 1200.0, 1300.0, 1100.0}; /* kg/m^3 */
  TEST_ASSERT_OK(domain,
                 add_row(domain, material, 4, densities, false, 0.1, NULL));
  granular.critical_density = CRITICAL;
  assert_refused(domain, gm_domain_set_granular(domain, material, &granular),
                 "gm_domain_set_granular", "point id 1 ");
  assert_message_has(domain, "1200 kg/m^3");
  /* Nothing changed: rho_cr is still 1000, so 1050 kg/m^3 is accepted. */
  const double between = 1050.0; /* kg/m^3 */
  TEST_ASSERT_OK(domain,
                 add_row(domain, material, 1, &between, false, 0.8, NULL));
  granular.critical_density = 1050.0 + TOLERANCE; /* the loosest point */
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &granular));
  gm_domain_destroy(domain);
}
END_TEST

/* A source of the material that would inject below the new rho_cr. */
START_TEST(test_set_granular_refuses_raising_above_source) {
  int material = -1;
  gm_domain *domain = placement_domain(GM_FAMILY_GRANULAR, DENSE, &material);
  const double position[2] = {0.5, 0.5}; /* m */
  gm_source_def source = source_at(material, 1500.0, position);
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_source(domain, &source, &id));
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = 1550.0; /* kg/m^3 */
  assert_refused(domain, gm_domain_set_granular(domain, material, &granular),
                 "gm_domain_set_granular", "source 0 ");
  gm_domain_destroy(domain);
}
END_TEST

/* -------------------------------------- 5. plain and stress_free */

/* _i: GM_FAMILY_PLAIN or GM_FAMILY_STRESS_FREE. Every placement refused
 * above is accepted, and the domain steps. */
START_TEST(test_other_families_accept_loose) {
  gm_family family = _i ? GM_FAMILY_STRESS_FREE : GM_FAMILY_PLAIN;
  int material = -1;
  gm_domain *domain = placement_domain(family, LOOSE, &material);
  TEST_ASSERT_OK(domain,
                 add_row(domain, material, BATCH, NULL, false, 0.1, NULL));
  const double loose[1] = {LOOSE}; /* kg/m^3 */
  TEST_ASSERT_OK(domain, add_row(domain, material, 1, loose, true, 0.2, NULL));
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.density = LOOSE;
  fill.lower[0] = 0.2, fill.lower[1] = 0.7; /* m */
  fill.upper[0] = 0.4, fill.upper[1] = 0.9; /* m */
  fill.points_per_cell_axis = 2;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  const double position[2] = {0.7, 0.2}; /* m */
  gm_source_def source = source_at(material, LOOSE, position);
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_source(domain, &source, &id));
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = 2.0 * CRITICAL; /* above every point */
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &granular));
  TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-5));
  ck_assert_uint_eq(gm_domain_point_count(domain), BATCH + 1 + 16 + 1);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *placement_suite(void) {
  Suite *suite = suite_create("granular_placement");
  TCase *points = tcase_create("points");
  tcase_add_loop_test(points, test_add_points_refuses_loose, 0, 3);
  tcase_add_test(points, test_add_points_ignores_other_materials);
  tcase_add_test(points, test_add_points_accepts_down_to_tolerance);
  tcase_add_test(points, test_rounded_mass_at_critical_is_accepted);
  suite_add_tcase(suite, points);
  TCase *other = tcase_create("fill_and_sources");
  tcase_add_loop_test(other, test_fill_box_refuses_loose, 0, 2);
  tcase_add_loop_test(other, test_add_source_refuses_loose, 0, 2);
  suite_add_tcase(suite, other);
  TCase *granular = tcase_create("set_granular");
  tcase_add_test(granular, test_set_granular_refuses_raising_above_points);
  tcase_add_test(granular, test_set_granular_refuses_raising_above_source);
  suite_add_tcase(suite, granular);
  TCase *families = tcase_create("families");
  tcase_add_loop_test(families, test_other_families_accept_loose, 0, 2);
  suite_add_tcase(suite, families);
  return suite;
}

int main(void) {
  return test_run_suite(placement_suite()) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
