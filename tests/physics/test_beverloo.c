/*
 * test_beverloo.c - plane-strain slot discharge against Beverloo's scaling
 * (issue 6; docs/references.md "Silo discharge"; 002 sec 5.1, eq 19):
 *
 *   W' = C rho_b sqrt(g) (D - k d)^(3/2)   (mass per unit slot length, s)
 *
 * A flat-bottomed planar silo (half of it: the axis is a slip face) of the
 * Drucker-Prager material of 002 sec 5 (E = 1 MPa, nu = 0.3, phi = 25 deg,
 * rho = 1500 kg/m^3) with Coulomb side walls (phi_w = 20 deg) and a rigid
 * no-slip floor (rigid points: a planar wall cannot have a hole) discharges
 * through a slot of width D at four widths; a sink just below the orifice
 * counts the discharged mass. We fit log W' against log(D - k d) by least
 * squares and assert the exponent is 1.5 +- 0.15.
 *
 * The grain size of a continuum. Drucker-Prager has no length scale, so
 * the only length that can shorten the orifice is the grid: the orifice
 * edge node is held by the floor and the flow fades over the cells next to
 * it (an "empty band" made by the mesh, like Beverloo's empty annulus of
 * about one grain). We take d = h, the cell size, and k = 2.7: the offset
 * that gives the exponent 3/2 on the finer 0.025 m grid, measured with
 * examples/papers/wieckowski1999_silo_discharge (flat, D = 0.2, 0.3, 0.4, 0.5
 * m: W' = 320, 727, 1252, 1900 kg/(m s); offset 0.068 m = 2.7 cells). This test
 * runs on a 0.05 m grid, so the k it uses was not fitted to the data it checks;
 * it passes for k between about 1.7 and 3.3 (measured exponent 1.62 at k = 2,
 * 1.46 at k = 2.6). With d = 0 the exponent is 1.94 on the fine grid and
 * 2.15 on this one, printed below: it falls towards 1.5 as D/h grows,
 * which costs more than a unit test can spend.
 *
 * The steady window: mass against time is fitted from the moment 10 % of
 * the fill has left (the start-up transient - the orifice opens on a
 * geostatic fill and the arch accelerates over a fall of a few D, about
 * 0.3 s - is over) to the moment 40 % has left (the fill then still stands
 * above 1.2 silo widths, the height above which Beverloo's rate does not
 * depend on the head; Mankoc et al. 2007 in docs/references.md). The test also
 * asserts that the window is steady: the rates of its two halves agree
 * within 20 % (the sampled rate scatters by about +-5 % from sample to
 * sample in these coarse runs; a flow that is still accelerating or already
 * emptying differs by more).
 *
 * Published C for flat-bottomed planar silos: 002 derives the slot form of
 * Beverloo et al. (1961) from its hydraulic-diameter formula (eq 19,
 * W = 45 rho A' sqrt(g D'_h) in g/min, cgs: C = 45/60 = 0.75 in SI),
 * W' = 0.75 sqrt(2) rho sqrt(g) (D - 0.7 d)^1.5, i.e. C = 1.06. The fitted C
 * is printed next to it; it is not asserted (the continuum's C depends on
 * the contraction of the jet, which the coarse grid resolves poorly).
 *
 * Runs in about 9 s (user time, -O2, one core).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;        /* m/s^2 */
static const double DENSITY = 1500.0;      /* kg/m^3, 002 sec 5 */
static const double FRICTION_ANGLE = 25.0; /* deg, 002 sec 5 */
static const double WALL_ANGLE = 20.0;     /* deg, phi_w of 002 */
static const double POISSON_RATIO = 0.3;   /* - */
static const double CELL = 0.05;           /* m, h */
static const double GRAIN_FACTOR = 2.7;    /* k, with d = h (see above) */
static const double SAMPLE = 0.01;         /* s between mass readings */
static const double WINDOW_START = 0.1;    /* fraction of the fill out */
static const double WINDOW_END = 0.4;      /* fraction of the fill out */
static const double MAX_TIME = 6.0;        /* s, a jammed flow stops here */
static const double PUBLISHED_C = 1.0607;  /* 0.75 sqrt(2), 002 eq 19 */
static const double WIDTHS[] = {0.3, 0.4, 0.5, 0.6}; /* m, D: 6-12 cells */

enum { WIDTH_COUNT = 4, MAX_SAMPLES = 1000 };

/* One silo: half-width B = 1.25 D + h (full width 2.5 D + 2h, Beverloo's
 * lower bound of 2.5 D), fill height 2 full widths. */
typedef struct slot_silo {
  double orifice;     /* m, D */
  double half_width;  /* m, B */
  double fill_height; /* m */
  double fill_mass;   /* kg/m, both halves */
} slot_silo;

static gm_domain *create_silo_domain(const slot_silo *silo) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = CELL;
  def.origin[1] = -3.0 * CELL; /* floor layer and sink */
  def.extent[0] = silo->half_width + 2.0 * CELL;
  def.extent[1] = silo->fill_height + 5.0 * CELL;
  def.gravity[1] = -GRAVITY;
  def.walls[GM_FACE_XMIN] = GM_WALL_SLIP; /* symmetry axis */
  def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  return test_create_domain(&def);
}

/* Side wall on the node line x = B (shifted 1e-9 cells inwards so that the
 * node line is behind it whatever the rounding of node coordinates). */
static void add_side_wall(gm_domain *domain, const slot_silo *silo) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = silo->half_width - 1e-9 * CELL;
  wall.normal[0] = -1.0;
  wall.normal[1] = 0.0;
  wall.friction_static = wall.friction_kinetic = tan(WALL_ANGLE * PI / 180);
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
}

/* Rigid floor one cell thick from the orifice edge D/2 outwards. */
static void add_floor(gm_domain *domain, const slot_silo *silo) {
  gm_rigid_def rigid = gm_rigid_def_default();
  rigid.density = DENSITY;
  int floor = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_rigid(domain, &rigid, &floor));
  const double lower[3] = {0.5 * silo->orifice, -CELL, 0.0};
  const double upper[3] = {silo->half_width + 2.0 * CELL, 0.0, 0.0};
  test_fill_box(domain, floor, lower, upper, 2, NULL);
}

/* 2 x 2 points per cell with the geostatic stress sigma_v = -rho g (H - y),
 * sigma_h = nu/(1 - nu) sigma_v; returns the half silo's mass (kg/m). */
static double fill_silo(gm_domain *domain, const slot_silo *silo) {
  gm_drucker_prager_def dp = gm_drucker_prager_def_default();
  dp.density = DENSITY;
  dp.poisson_ratio = POISSON_RATIO;
  dp.friction_angle = FRICTION_ANGLE * PI / 180.0;
  int material = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_drucker_prager(domain, &dp, &material));
  double spacing = 0.5 * CELL; /* m */
  size_t columns = (size_t)llround(silo->half_width / spacing);
  size_t rows = (size_t)llround(silo->fill_height / spacing);
  size_t count = columns * rows;
  double *position = malloc(2 * count * sizeof *position);
  double *volume = malloc(count * sizeof *volume);
  double *stress = calloc(6 * count, sizeof *stress);
  ck_assert(position && volume && stress);
  double k0 = POISSON_RATIO / (1.0 - POISSON_RATIO);
  for (size_t i = 0; i < count; i++) {
    double y = (i / columns + 0.5) * spacing; /* m */
    position[2 * i] = (i % columns + 0.5) * spacing;
    position[2 * i + 1] = y;
    volume[i] = spacing * spacing;
    stress[6 * i + GM_YY] = -DENSITY * GRAVITY * (silo->fill_height - y);
    stress[6 * i + GM_XX] = stress[6 * i + GM_ZZ] = k0 * stress[6 * i + GM_YY];
  }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.volume = volume;
  points.stress = stress;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  free(position);
  free(volume);
  free(stress);
  return DENSITY * spacing * spacing * (double)count;
}

/* Least-squares slope of y against x over [first, last). */
static double slope(const double *x, const double *y, size_t first,
                    size_t last) {
  double n = (double)(last - first), sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = first; i < last; i++) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/* Discharges one silo; returns the steady rate W' (kg/(m s), full slot)
 * and asserts that the window is steady. */
static double steady_rate(double orifice) {
  slot_silo silo = {.orifice = orifice};
  silo.half_width = CELL * ceil(1.25 * orifice / CELL + 1.0);
  silo.fill_height = 4.0 * silo.half_width;
  gm_domain *domain = create_silo_domain(&silo);
  add_side_wall(domain, &silo);
  add_floor(domain, &silo);
  silo.fill_mass = 2.0 * fill_silo(domain, &silo);
  gm_sink_def below = gm_sink_def_default();
  below.upper[0] = 0.5 * orifice; /* under the orifice, below the floor */
  below.lower[1] = -3.0 * CELL;
  below.upper[1] = 0.0;
  int sink = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_sink(domain, &below, &sink));

  static double time[MAX_SAMPLES], mass[MAX_SAMPLES]; /* s, kg/m */
  size_t taken = 0, first = 0, last = 0;
  while (taken < MAX_SAMPLES && taken * SAMPLE <= MAX_TIME) {
    if (taken > 0)
      TEST_ASSERT_OK(domain,
                     gm_domain_advance(domain, taken * SAMPLE, 0, NULL, NULL));
    gm_flow_totals out = gm_flow_totals_default();
    TEST_ASSERT_OK(domain, gm_domain_get_sink_totals(domain, sink, &out));
    time[taken] = taken * SAMPLE;
    mass[taken] = 2.0 * out.mass; /* both halves */
    if (mass[taken] < WINDOW_START * silo.fill_mass)
      first = taken + 1;
    taken++;
    last = taken;
    if (mass[taken - 1] >= WINDOW_END * silo.fill_mass)
      break;
  }
  gm_domain_destroy(domain);
  ck_assert_msg(mass[last - 1] >= WINDOW_END * silo.fill_mass,
                "D = %g m: only %.0f %% of the fill left in %g s", orifice,
                100 * mass[last - 1] / silo.fill_mass, MAX_TIME);
  ck_assert_msg(last > first + 10, "D = %g m: steady window of %zu samples",
                orifice, last - first);
  size_t middle = (first + last) / 2;
  double rate = slope(time, mass, first, last);        /* kg/(m s) */
  double early = slope(time, mass, first, middle + 1); /* kg/(m s) */
  double late = slope(time, mass, middle, last);       /* kg/(m s) */
  printf("D = %.2f m: W' = %7.1f kg/(m s) over %.2f-%.2f s "
         "(halves %.1f, %.1f)\n",
         orifice, rate, time[first], time[last - 1], early, late);
  ck_assert_msg(fabs(late - early) <= 0.2 * rate,
                "D = %g m: the window is not steady: %g then %g kg/(m s)",
                orifice, early, late);
  return rate;
}

/* Fits log W' = log A + n log(D - offset); returns n, *prefactor = A. */
static double fit_exponent(const double *rates, double offset,
                           double *prefactor) {
  double x[WIDTH_COUNT], y[WIDTH_COUNT];
  for (int i = 0; i < WIDTH_COUNT; i++) {
    x[i] = log(WIDTHS[i] - offset);
    y[i] = log(rates[i]);
  }
  double n = slope(x, y, 0, WIDTH_COUNT), mean_x = 0, mean_y = 0;
  for (int i = 0; i < WIDTH_COUNT; i++) {
    mean_x += x[i] / WIDTH_COUNT;
    mean_y += y[i] / WIDTH_COUNT;
  }
  *prefactor = exp(mean_y - n * mean_x);
  return n;
}

START_TEST(test_slot_exponent) {
  double rates[WIDTH_COUNT]; /* kg/(m s) */
  for (int i = 0; i < WIDTH_COUNT; i++)
    rates[i] = steady_rate(WIDTHS[i]);
  double scale = DENSITY * sqrt(GRAVITY); /* kg/(m^2.5 s) */
  double offset = GRAIN_FACTOR * CELL, prefactor = 0.0, bare = 0.0; /* m */
  double exponent = fit_exponent(rates, offset, &prefactor);
  double bare_exponent = fit_exponent(rates, 0.0, &bare);
  double fixed_c = 0.0; /* C with the exponent held at 3/2 */
  for (int i = 0; i < WIDTH_COUNT; i++)
    fixed_c += rates[i] / (scale * pow(WIDTHS[i] - offset, 1.5)) / WIDTH_COUNT;
  printf("k d = %.2f x %.3f m: exponent %.3f (assert 1.5 +- 0.15), "
         "C = %.3f (fitted), %.3f (exponent 3/2); published C = %.2f "
         "(002 eq 19, slot)\n",
         GRAIN_FACTOR, CELL, exponent, prefactor / scale, fixed_c, PUBLISHED_C);
  printf("d = 0: exponent %.3f, C = %.3f (not asserted)\n", bare_exponent,
         bare / scale);
  ck_assert_msg(fabs(exponent - 1.5) <= 0.15,
                "Beverloo slot exponent %g, expected 1.5 +- 0.15", exponent);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("beverloo");
  TCase *slot = tcase_create("slot");
  tcase_add_test(slot, test_slot_exponent);
  tcase_set_timeout(slot, 120);
  suite_add_tcase(suite, slot);
  return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
