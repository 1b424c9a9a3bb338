/*
 * test_silo_filling.c - a silo filled by pouring, at rest, against
 * Janssen (docs/references.md): the scene of
 * examples/papers/wieckowski2004_silo_filling_janssen.c (Wieckowski 2004,
 * sec 5.1.2) at a third of its size. Half of a planar silo, B = 0.6 m, Coulomb
 * side wall and floor with phi_w = 20 deg; a source releases a 12 x 12 block of
 * points just above the free surface every 0.2 s (8 blocks); the filling model
 * of eq 24 with the paper's data; the granular family with rho_cr where eq 24's
 * pressure has fallen to p0/100; 2 % PIC; then 1.5 s of settling and wall loads
 * averaged over the last 0.2 s.
 *
 *   sigma_v(z) = rho g B / (mu_w K) (1 - exp(-mu_w K z / B)),
 *   wall load  = integral of K sigma_v over the fill height,
 *
 * rho the fill's own bulk density (its mass over B times its mean
 * height). Which K: a poured fill is not loaded along one path, so we
 * bracket it between the at-rest ratio of the elastic fill, K0 = nu / (1 -
 * nu) = 0.43 (the example explains why the fill stays elastic), and Jaky's
 * 1 - sin(phi) = 0.5 (docs/references.md), both fixed by the material data
 * before the run. The wall load grows with K and sigma_v falls with it.
 * Measured in the example: the effective K falls with the fill's depth,
 * from about 0.51 for this 1.2 m fill to 0.43 for the 3.6 m one (pouring
 * locks in lateral stress that matters less as the fill deepens).
 * Asserted:
 *  - the fill is at rest: kinetic energy below 1e-6 of M g H (with pure
 *    FLIP it keeps ~1e-2 of it in velocity noise the grid cannot see);
 *  - the side-wall load between Janssen's with K0 and with Jaky's K, with
 *    design.md's 10 % on either side;
 *  - the vertical stress of every cell row deeper than B/2 between
 *    Janssen's with Jaky's K and with K0, 10 % on either side (near the
 *    surface the wall friction has not yet spread across the section, as
 *    tests/physics/test_janssen.c explains);
 *  - floor reaction plus wall friction equal the weight within 2 % (the
 *    averaged loads of a fill at rest; the residual is the wall-force
 *    noise of the last 0.2 s).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;       /* m/s^2 */
static const double HALF_WIDTH = 0.6;     /* m, B */
static const double CELL = 0.05;          /* m */
static const double SPACING = 0.025;      /* m, 2 x 2 points per cell */
static const double WALL_ANGLE = 20.0;    /* deg */
static const double PERIOD = 0.2;         /* s between portions */
static const double SETTLE_TIME = 1.5;    /* s */
static const double AVERAGING_TIME = 0.2; /* s */

enum { PORTIONS = 8, BLOCK = 12, MAX_ROWS = 64 };

typedef struct silo {
  gm_domain *domain;
  int material, side_wall, floor;
  double critical_density;  /* kg/m^3 */
  double at_rest_k, jaky_k; /* -, Janssen's K: the bracket above */
} silo;

static void add_wall(silo *s, double x, double normal_x, double normal_y,
                     int *id) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = x;
  wall.normal[0] = normal_x;
  wall.normal[1] = normal_y;
  wall.friction_static = wall.friction_kinetic = tan(WALL_ANGLE * PI / 180);
  TEST_ASSERT_OK(s->domain, gm_domain_add_wall(s->domain, &wall, id));
}

static silo make_silo(void) {
  silo s;
  gm_domain_def def = gm_domain_def_default();
  def.family = GM_FAMILY_GRANULAR;
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = CELL;
  def.origin[1] = -2.0 * CELL;
  def.extent[0] = HALF_WIDTH + 2.0 * CELL;
  def.extent[1] = 2.0; /* m, the fill reaches ~1.3 m */
  def.gravity[1] = -GRAVITY;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  def.damping = 0.05;
  def.pic_fraction = 0.02;
  s.domain = test_create_domain(&def);
  add_wall(&s, HALF_WIDTH - 1e-9 * CELL, -1.0, 0.0, &s.side_wall);
  add_wall(&s, 0.0, 0.0, 1.0, &s.floor);
  gm_filling_def model = gm_filling_def_default();
  model.max_pressure = 1e6; /* Pa */
  TEST_ASSERT_OK(s.domain,
                 gm_domain_add_filling(s.domain, &model, &s.material));
  s.at_rest_k = model.poisson_ratio / (1.0 - model.poisson_ratio);
  s.jaky_k = 1.0 - sin(model.friction_angle);
  gm_granular_def granular = gm_granular_def_default();
  s.critical_density = granular.critical_density =
      model.density * (1.0 + model.void_ratio) /
      (1.0 + model.void_ratio + model.kappa * log(100.0));
  TEST_ASSERT_OK(s.domain,
                 gm_domain_set_granular(s.domain, s.material, &granular));
  return s;
}

/* Height (m) of the highest point plus half a spacing; 0 when empty. */
static double surface(const gm_domain *domain) {
  const double *y = NULL;
  size_t count = gm_domain_point_count(domain);
  if (count == 0)
    return 0.0;
  TEST_ASSERT_OK((gm_domain *)domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  double top = y[0];
  for (size_t i = 1; i < count; i++)
    top = fmax(top, y[i]);
  return top + 0.5 * SPACING;
}

static void release_portion(silo *s, double time) {
  double bottom = surface(s->domain) + 0.5 * SPACING; /* m */
  double position[2 * BLOCK * BLOCK];
  for (int i = 0; i < BLOCK * BLOCK; i++) {
    position[2 * i] = (i % BLOCK + 0.5) * SPACING;
    position[2 * i + 1] = bottom + (i / BLOCK + 0.5) * SPACING;
  }
  gm_source_def source = gm_source_def_default();
  source.material = s->material;
  source.count = BLOCK * BLOCK;
  source.position = position;
  source.point_size = SPACING;
  source.start_time = time;
  source.density = s->critical_density;
  int id = -1;
  TEST_ASSERT_OK(s->domain, gm_domain_add_source(s->domain, &source, &id));
}

/* Wall loads averaged over the last AVERAGING_TIME (N/m). */
typedef struct loads {
  double wall_normal, wall_tangential, floor_normal, seconds;
} loads;

static loads fill_and_settle(silo *s) {
  loads averaged = {0.0, 0.0, 0.0, 0.0};
  double end = PORTIONS * PERIOD + SETTLE_TIME, time = 0.0; /* s */
  int placed = 0;
  while (end - time > 1e-9) {
    if (placed < PORTIONS && time >= placed * PERIOD - 1e-9)
      release_portion(s, time), placed++;
    double next = placed < PORTIONS ? placed * PERIOD : end; /* s */
    double dt = 1e-4; /* s, before any point exists */
    if (gm_domain_point_count(s->domain) > 0)
      TEST_ASSERT_OK(s->domain, gm_domain_stable_dt(s->domain, &dt));
    dt = fmin(dt, next - time);
    TEST_ASSERT_OK(s->domain, gm_domain_step(s->domain, dt));
    TEST_ASSERT_OK(s->domain, gm_domain_get_time(s->domain, &time, NULL));
    if (time > end - AVERAGING_TIME) {
      gm_wall_force side = gm_wall_force_default(), floor = side;
      TEST_ASSERT_OK(s->domain,
                     gm_domain_get_wall_force(s->domain, s->side_wall, &side));
      TEST_ASSERT_OK(s->domain,
                     gm_domain_get_wall_force(s->domain, s->floor, &floor));
      averaged.wall_normal += dt * side.normal;
      averaged.wall_tangential += dt * fabs(side.tangential);
      averaged.floor_normal += dt * floor.normal;
      averaged.seconds += dt;
    }
  }
  averaged.wall_normal /= averaged.seconds;
  averaged.wall_tangential /= averaged.seconds;
  averaged.floor_normal /= averaged.seconds;
  return averaged;
}

/* Mean fill height (m; over cell-wide columns, highest point plus half a
 * spacing), mass (kg/m) and the vertical stress each cell row transmits,
 * -sum(V sigma_yy)/(h B) (Pa). */
static double measure(const gm_domain *domain, double *mass_out,
                      double row_stress[MAX_ROWS]) {
  const double *x = NULL, *y = NULL, *mass = NULL, *volume = NULL,
               *sigma_yy = NULL;
  gm_domain *d = (gm_domain *)domain;
  TEST_ASSERT_OK(d, gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  TEST_ASSERT_OK(d, gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  TEST_ASSERT_OK(d, gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass));
  TEST_ASSERT_OK(d, gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume));
  TEST_ASSERT_OK(
      d, gm_domain_view_field(domain, GM_FIELD_STRESS, GM_YY, &sigma_yy));
  enum { COLUMNS = 12 }; /* B / h */
  double column_top[COLUMNS] = {0}, height = 0.0;
  *mass_out = 0.0;
  for (size_t i = 0; i < gm_domain_point_count(domain); i++) {
    int column = (int)(x[i] / CELL), row = (int)floor(y[i] / CELL);
    ck_assert(column >= 0 && column < COLUMNS && row >= 0 && row < MAX_ROWS);
    column_top[column] = fmax(column_top[column], y[i] + 0.5 * SPACING);
    row_stress[row] -= volume[i] * sigma_yy[i] / (CELL * HALF_WIDTH);
    *mass_out += mass[i];
  }
  for (int c = 0; c < COLUMNS; c++)
    height += column_top[c] / COLUMNS;
  return height;
}

/* Janssen's vertical stress (Pa) at depth z (m) and the side-wall load
 * above it, the integral of K sigma_v (N/m), for stress ratio k and bulk
 * density rho (kg/m^3). */
static double janssen_vertical(double k, double rho, double z) {
  double decay = tan(WALL_ANGLE * PI / 180.0) * k / HALF_WIDTH; /* 1/m */
  return rho * GRAVITY / decay * (1.0 - exp(-decay * z));
}

static double janssen_wall_load(double k, double rho, double z) {
  double decay = tan(WALL_ANGLE * PI / 180.0) * k / HALF_WIDTH; /* 1/m */
  return k * rho * GRAVITY / decay * (z - (1.0 - exp(-decay * z)) / decay);
}

START_TEST(test_poured_fill_against_janssen) {
  silo s = make_silo();
  loads wall = fill_and_settle(&s);
  ck_assert_uint_eq(gm_domain_point_count(s.domain), PORTIONS * BLOCK * BLOCK);
  double mass = 0.0, row_stress[MAX_ROWS] = {0};
  double height = measure(s.domain, &mass, row_stress);
  double rho = mass / (HALF_WIDTH * height);
  double weight = mass * GRAVITY; /* N/m */

  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(s.domain, gm_domain_get_summary(s.domain, &summary));
  printf("fill %.3f m high, %.0f kg/m^3; kinetic energy %.3g J/m (%.2g of "
         "M g H)\n",
         height, rho, summary.kinetic_energy,
         summary.kinetic_energy / (weight * height));
  ck_assert_msg(summary.kinetic_energy < 1e-6 * weight * height,
                "not at rest: kinetic energy %g J/m", summary.kinetic_energy);

  double low = janssen_wall_load(s.at_rest_k, rho, height);
  double high = janssen_wall_load(s.jaky_k, rho, height);
  printf("side-wall load %.0f N/m; Janssen %.0f (K0) to %.0f (Jaky) N/m\n",
         wall.wall_normal, low, high);
  ck_assert_msg(wall.wall_normal >= 0.9 * low && wall.wall_normal <= 1.1 * high,
                "wall load %.0f N/m outside [0.9 x %.0f, 1.1 x %.0f]",
                wall.wall_normal, low, high);

  for (int row = 0; (row + 1) * CELL < height - 0.5 * HALF_WIDTH; row++) {
    double depth = height - (row + 0.5) * CELL; /* m */
    double lower = janssen_vertical(s.jaky_k, rho, depth);
    double upper = janssen_vertical(s.at_rest_k, rho, depth);
    printf(
        "  depth %.3f m: sigma_v %.0f Pa; Janssen %.0f (Jaky) to %.0f (K0)\n",
        depth, row_stress[row], lower, upper);
    ck_assert_msg(row_stress[row] >= 0.9 * lower &&
                      row_stress[row] <= 1.1 * upper,
                  "row %d: sigma_v %.0f Pa outside [0.9 x %.0f, 1.1 x %.0f]",
                  row, row_stress[row], lower, upper);
  }

  double carried = wall.floor_normal + wall.wall_tangential; /* N/m */
  printf("floor %.0f + wall friction %.0f = %.4f of the weight\n",
         wall.floor_normal, wall.wall_tangential, carried / weight);
  ck_assert_msg(fabs(carried / weight - 1.0) <= 0.02,
                "floor + wall friction carry %.4f of the weight",
                carried / weight);
  gm_domain_destroy(s.domain);
}
END_TEST

static Suite *silo_filling_suite(void) {
  Suite *suite = suite_create("silo_filling");
  TCase *tcase = tcase_create("janssen");
  tcase_set_timeout(tcase, 600); /* s, for sanitizer and valgrind builds */
  /* ~40 s plain: tests/README.md, "Slow cases" (test_janssen and
   * test_filling keep the load and the filling under the sanitizers). */
  tcase_set_tags(tcase, "slow");
  tcase_add_test(tcase, test_poured_fill_against_janssen);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(silo_filling_suite()) ? 1 : 0;
}
