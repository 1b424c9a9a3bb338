/*
 * test_slope_density.c - moderate flow down a slope (000 sec 2.3, Table 1,
 * Figs 1-2): a Mohr-Coulomb block (psi = 0, so plastic flow keeps the
 * volume) flows down a 30 degree slope. The grains neither gain nor lose
 * packing in a moderate flow, so the average density should stay at the
 * critical density. Conventional MPM (plain) and stress-free MPM let it
 * fall well below rho_cr; Granular MPM's density control (eqs 13-15)
 * holds every point at rho_cr or above.
 *
 * Asserted for linear MPM and CPDI:
 *  - granular: every point's density stays >= rho_cr - TOL at every step
 *    (eqs 13-15 return F to the previous step's whenever a connected point
 *    falls below, and disconnected points keep theirs: by induction from
 *    rho0 > rho_cr no point can end a step below), hence the average stays
 *    >= rho_cr - 0.5 % (the design target) all the time;
 *  - plain and stress_free lose at least DROP_FACTOR times as much density
 *    (rho0 - average, both averages) as granular by the end;
 *  - the block really flowed: its front moved more than one cell.
 *
 * Duration: the paper runs 0.25 s. The six runs (2 variants x 3 families)
 * then take ~26 s at -O2 on one core (~3x that under ASan), over the
 * budget of a test program, so the test stops at 0.1 s, where the drop of
 * plain and stress-free MPM is already ~5-9 times granular's. Setting the
 * environment variable GM_SLOPE_PAPER_TIME runs the full 0.25 s with the
 * same assertions (measured ratios there: 12-32).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>

#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;    /* m/s^2 */
static const double SLOPE = 30.0;      /* degrees, Table 1 */
static const double CELL = 0.01;       /* m, Table 1 */
static const double TIME_STEP = 7e-6;  /* s, Table 1 */
static const double PAPER_TIME = 0.25; /* s, Table 1 t_total */
static const double TEST_TIME = 0.1;   /* s, see the top of this file */
static const double DENSITY = 2250.0;  /* kg/m^3, rho_initial */
static const double CRITICAL = 2235.0; /* kg/m^3, rho_critical */
static const double TOLERANCE = 1e-6;  /* kg/m^3, TOL of 000 sec 3.2 */
static const double YOUNGS = 1e9;      /* Pa, Table 1 */
static const double POISSON = 0.3;     /* Table 1 */
static const double FRICTION = 30.0;   /* degrees, phi */
static const double BLOCK_LOWER[2] = {0.02, 0.0};  /* m, on the floor */
static const double BLOCK_UPPER[2] = {0.12, 0.03}; /* m: 10 x 3 cells */
static const size_t POINT_COUNT = 120; /* 4 per cell (2 x 2), sec 2.3 */

/* Measured loss ratios at 0.1 s (plain or stress-free over granular,
 * both averages, both variants) lie between 4.9 (stress-free CPDI, plain
 * average of m/V) and 8.7 (plain linear, mass-weighted); at 0.25 s
 * between 11.7 and 32. Asserting half the smallest leaves room for
 * round-off and platform differences while still demanding a drop several
 * times granular's. */
static const double DROP_FACTOR = 2.5;

/* Averages of the points' density (kg/m^3). */
typedef struct density_averages {
  double mass_weighted; /* total mass / total volume */
  double mean;          /* plain mean of m / V */
  double lowest_point;  /* smallest m / V */
} density_averages;

/* What one run measured. */
typedef struct slope_record {
  density_averages final;   /* at the end */
  density_averages minimum; /* each the smallest over all steps */
  double front_travel;      /* m, downslope move of the foremost point */
} slope_record;

static gm_domain *create_slope(gm_shape shape, gm_family family) {
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = CELL;
  def.extent[0] = 0.4; /* m: 0.28 m of room downslope of the block */
  def.extent[1] = 0.1; /* m */
  /* The slope is the floor; gravity is rotated by the inclination. */
  double angle = SLOPE * PI / 180.0; /* rad */
  def.gravity[0] = GRAVITY * sin(angle);
  def.gravity[1] = -GRAVITY * cos(angle);
  for (int face = GM_FACE_XMIN; face <= GM_FACE_YMAX; face++)
    def.walls[face] = GM_WALL_FIXED; /* "fixed on all the sides" */
  def.shape = shape;
  def.family = family;
  gm_domain *domain = test_create_domain(&def);
  gm_mohr_coulomb_def soil = gm_mohr_coulomb_def_default();
  soil.youngs_modulus = YOUNGS;
  soil.poisson_ratio = POISSON;
  soil.density = DENSITY;
  soil.friction_angle = FRICTION * PI / 180.0; /* rad */
  soil.dilation_angle = 0.0;
  soil.bagnold_viscosity = 0.0; /* sec 2.3 has no rate term */
  int material = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_mohr_coulomb(domain, &soil, &material));
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL;
  granular.tolerance = TOLERANCE;
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &granular));
  const double lower[3] = {BLOCK_LOWER[0], BLOCK_LOWER[1], 0.0};
  const double upper[3] = {BLOCK_UPPER[0], BLOCK_UPPER[1], 0.0};
  size_t count = test_fill_box(domain, material, lower, upper, 2, NULL);
  ck_assert_uint_eq(count, POINT_COUNT);
  return domain;
}

static density_averages measure_density(const gm_domain *domain) {
  const double *mass = NULL, *volume = NULL; /* kg/m, m^2 */
  TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass));
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume));
  size_t count = gm_domain_point_count(domain);
  double total_mass = 0.0, total_volume = 0.0, sum = 0.0;
  density_averages out = {0.0, 0.0, INFINITY};
  for (size_t p = 0; p < count; p++) {
    double density = mass[p] / volume[p]; /* kg/m^3 */
    total_mass += mass[p];
    total_volume += volume[p];
    sum += density;
    out.lowest_point = fmin(out.lowest_point, density);
  }
  out.mass_weighted = total_mass / total_volume;
  out.mean = sum / (double)count;
  return out;
}

/* Largest x (m) of any point. */
static double front_position(const gm_domain *domain) {
  const double *x = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  double front = -INFINITY;
  for (size_t p = 0; p < gm_domain_point_count(domain); p++)
    front = fmax(front, x[p]);
  return front;
}

static slope_record run_slope(gm_shape shape, gm_family family,
                              double duration) {
  gm_domain *domain = create_slope(shape, family);
  double start_front = front_position(domain);
  slope_record record;
  record.minimum = measure_density(domain);
  long steps = lround(duration / TIME_STEP);
  for (long step = 0; step < steps; step++) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, TIME_STEP));
    density_averages now = measure_density(domain);
    record.minimum.mass_weighted =
        fmin(record.minimum.mass_weighted, now.mass_weighted);
    record.minimum.mean = fmin(record.minimum.mean, now.mean);
    record.minimum.lowest_point =
        fmin(record.minimum.lowest_point, now.lowest_point);
  }
  record.final = measure_density(domain);
  record.front_travel = front_position(domain) - start_front;
  gm_domain_destroy(domain);
  return record;
}

static double run_duration(void) {
  return getenv("GM_SLOPE_PAPER_TIME") ? PAPER_TIME : TEST_TIME;
}

static const gm_shape SHAPES[] = {GM_SHAPE_LINEAR, GM_SHAPE_CPDI};
enum { SHAPE_COUNT = sizeof SHAPES / sizeof SHAPES[0] };

static const char *family_name(gm_family family) {
  return family == GM_FAMILY_PLAIN         ? "plain"
         : family == GM_FAMILY_STRESS_FREE ? "stress_free"
                                           : "granular";
}

/* Granular holds the density: the per-point invariant of eqs 13-15 and
 * the design target on the averages. */
static void check_granular(const slope_record *run, const char *shape) {
  /* m / V is computed from the same doubles as the library's check, so
   * the invariant holds to the last bit; 1e-9 kg/m^3 only covers a
   * different rounding of the division (1e-12 relative). */
  ck_assert_msg(run->minimum.lowest_point >= CRITICAL - TOLERANCE - 1e-9,
                "%s granular: a point reached %.9f kg/m^3 < rho_cr - TOL",
                shape, run->minimum.lowest_point);
  double floor_density = CRITICAL * (1.0 - 0.005); /* kg/m^3 */
  ck_assert_msg(run->minimum.mass_weighted >= floor_density &&
                    run->minimum.mean >= floor_density,
                "%s granular: average fell to %.3f (mass-weighted), %.3f "
                "(mean) < rho_cr - 0.5 %% = %.3f kg/m^3",
                shape, run->minimum.mass_weighted, run->minimum.mean,
                floor_density);
}

/* The other family lost at least DROP_FACTOR times granular's density. */
static void check_drop(const slope_record *run, const slope_record *granular,
                       const char *shape, const char *family) {
  double loss[2] = {DENSITY - run->final.mass_weighted,
                    DENSITY - run->final.mean}; /* kg/m^3 */
  double granular_loss[2] = {DENSITY - granular->final.mass_weighted,
                             DENSITY - granular->final.mean};
  for (int k = 0; k < 2; k++)
    ck_assert_msg(loss[k] > DROP_FACTOR * granular_loss[k],
                  "%s %s: %s density drop %.3f kg/m^3 is not %.1f x "
                  "granular's %.3f",
                  shape, family, k ? "mean" : "mass-weighted", loss[k],
                  DROP_FACTOR, granular_loss[k]);
}

START_TEST(test_granular_keeps_critical_density) {
  gm_shape shape = SHAPES[_i];
  const char *name = test_shape_name(shape);
  double duration = run_duration();
  slope_record granular = run_slope(shape, GM_FAMILY_GRANULAR, duration);
  check_granular(&granular, name);
  const gm_family others[2] = {GM_FAMILY_PLAIN, GM_FAMILY_STRESS_FREE};
  for (int f = 0; f < 2; f++) {
    slope_record run = run_slope(shape, others[f], duration);
    check_drop(&run, &granular, name, family_name(others[f]));
    /* Not a block at rest: the flow carried the front over a cell. */
    ck_assert_msg(run.front_travel > CELL, "%s %s: front moved %.4f m", name,
                  family_name(others[f]), run.front_travel);
  }
  ck_assert_msg(granular.front_travel > CELL, "%s granular: front moved %.4f m",
                name, granular.front_travel);
}
END_TEST

static Suite *slope_suite(void) {
  Suite *suite = suite_create("slope_density");
  TCase *tcase = tcase_create("moderate_flow");
  /* ~5 s per variant at -O2; generous for ASan and the full 0.25 s. */
  tcase_set_timeout(tcase, 300);
  tcase_add_loop_test(tcase, test_granular_keeps_critical_density, 0,
                      SHAPE_COUNT);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(slope_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
