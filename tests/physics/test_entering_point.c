/*
 * test_entering_point.c - a stressed point that has just entered an empty
 * cell, in plain linear MPM (issue 12 item 3: the plain a = 2 column
 * collapse threw a point out of the box at t = 0.40 s; gm_domain_step(3),
 * "Stretched and isolated points").
 *
 * Mechanism: a point a distance e past a node line, in a cell no other
 * point reaches, gives the node beyond a mass N m_p, N = e / h, but a force
 * V_p sigma_p grad N that does not vanish with e. The updated nodal
 * velocity v_i + a_i dt (004 eq 3.17) there is of order dt sigma / (rho e),
 * and a strain rate taken from it gives the point a strain increment of
 * order (dt / h)^2 sigma / (rho e) = cfl^2 (sigma / M) (h / e) at the
 * stable step: unbounded as e -> 0. The library's USL takes its strain
 * rate from the velocities re-mapped from the updated point momenta
 * (Sulsky, Zhou & Schreyer 1995; step.c), where that node carries the
 * point's own velocity. Points of a flow enter cells all the time, at an
 * e spread evenly over one step's travel, so a long run meets small e
 * sooner or later; the collapse met one at t = 0.40 s.
 *
 * Scene: a block, 8 x 4 cells at 2 x 2 points per cell (plain family,
 * linear shapes, no gravity, no walls), placed so that its right column
 * and top row of points lie e = 1e-3 cells past a node line, with a uniform
 * stress of pressure p and shear tau, released from rest: its free edges
 * unload, and every edge point's outer nodes are light in the first step.
 * The points are half a cell apart, so every other column and row inside
 * the block lies 1e-3 cells past a node line too, and the block's
 * oscillation carries those points back and forth across it. Two
 * materials: the collapse's cohesionless Mohr-Coulomb (tau inside the
 * cone) and an elastic one with the same moduli. 600 stable steps (about
 * 36 wave transits of the block) in USL, MUSL and USF.
 *
 * Asserted:
 *  - every step succeeds and every point stays in the box;
 *  - no point moves faster than SPEED_FACTOR times the particle speed of a
 *    release wave, p / (rho c_p) (the velocity jump a pressure p gives a
 *    free face in 1D; the block's corners focus it);
 *  - the energy does not grow beyond what the scheme does to a block with
 *    no light node: kinetic plus elastic (complementary, linear elastic)
 *    energy at most `slack` above the elastic energy it started with
 *    (see ENERGY_SLACK).
 * The elastic case in USL fails on the code before commit a89915c (USL's
 * strain rate from v + a dt): step 2 fails with det F = -0.22 after 4
 * halvings of dt (with tau = 0: det F = -0.08). The Mohr-Coulomb case
 * passes there in USL: the huge extension that v + a dt gives the edge
 * points meets the tension cut-off (zero stress, F_xx stretched), which is
 * how plain MPM's stretched points arise, not how they are thrown; it is
 * kept as the collapse material's check of the same property. On that
 * code (bc373e1) USF, then the textbook one, fails too: energy 1.17
 * (Mohr-Coulomb) and 6.3 (elastic) times its start (fixed by USF's split
 * stress update, 9e3ded9). The elastic MUSL case fails on the code before
 * MUSL split its stress update the same way (step.c): energy 4.58 times
 * its start within the 600 steps (1.65 within the first 200), and a point
 * at 4.83 p/(rho c_p).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_util.h"

#include "granmpm/mohr_coulomb.h"

static const double PI = 3.14159265358979323846;
static const double CELL = 0.01;      /* m */
static const double YOUNGS = 5e5;     /* Pa, as examples/column_collapse */
static const double POISSON = 0.3;    /* - */
static const double DENSITY = 1800.0; /* kg/m^3 */
static const double FRICTION = 35.0;  /* degrees, phi */
static const double PRESSURE = 500.0; /* Pa, p: p / M = 7.4e-4 */
static const double SHEAR = 150.0;    /* Pa, tau_xy = 0.3 p < p tan(phi) */
static const double ENTERED = 1e-3;   /* cells, e / h */
enum { COLUMNS = 16, ROWS = 8, STEPS = 600 };
/* Largest point speed measured over the 600 steps: 2.88-3.42 p / (rho
 * c_p) (elastic MUSL the highest; the same block placed with no light
 * node, e = 0.25 cells: 3.0-3.38). 4.5 leaves 30 %. */
static const double SPEED_FACTOR = 4.5;
/* Energy slack, relative to the start, by material and scheme. Measured
 * largest energy over the start in the 600 steps: Mohr-Coulomb USL 1.000,
 * MUSL 1.019, USF 1.019 (the same block with no light node and no point
 * near a node line, e = 0.25 cells: 1.000, 1.018, 1.018); elastic USL
 * 1.110, MUSL 1.026, USF 1.026 (e = 0.25: 1.132, 1.027, 1.027). The
 * elastic block gains 11-13 % in USL whether or not a node is light (FLIP
 * release of a free elastic block, the stress updated last; not this
 * test's subject): 0.2 leaves it 6 %.
 * MUSL and USF update the stress in two halves (step.c) and stay within 3 %
 * of the start; 0.05 leaves them 2.4 % and fails MUSL with its stress
 * updated last (4.58 within these steps: the points on node lines pump
 * energy into the block's oscillation at each crossing, step.c; the light
 * nodes are not the cause). The Mohr-Coulomb block comes apart into
 * free-flying points, energy 0.81 of its start, from about step 100: 0.03
 * leaves 1 % above the measured 1.019. */
static const double ENERGY_SLACK[2][3] = {{0.03, 0.03, 0.03},
                                          {0.2, 0.05, 0.05}};

static gm_domain *make_block(gm_update_scheme scheme, int elastic) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.cell_size = CELL;
  def.extent[0] = 0.4;
  def.extent[1] = 0.3;
  gm_domain *domain = test_create_domain(&def);
  gm_mohr_coulomb_def material = gm_mohr_coulomb_def_default();
  material.youngs_modulus = YOUNGS;
  material.poisson_ratio = POISSON;
  material.density = DENSITY;
  material.friction_angle = FRICTION * PI / 180.0;
  material.dilation_angle = 0.0;
  material.bagnold_viscosity = 0.0;
  int id = -1;
  if (elastic)
    id = test_add_elastic(domain, YOUNGS, POISSON, DENSITY);
  else
    TEST_ASSERT_OK(domain, gm_domain_add_mohr_coulomb(domain, &material, &id));
  static double position[COLUMNS * ROWS * 2], volume[COLUMNS * ROWS];
  static double stress[COLUMNS * ROWS * 6];
  double spacing = 0.5 * CELL; /* m */
  /* The right column at 25 + e cells, the top row at 15 + e cells: the
   * other columns and rows lie at quarter cells + e. */
  double right = (25.0 + ENTERED) * CELL, top = (15.0 + ENTERED) * CELL;
  for (int j = 0; j < ROWS; j++)
    for (int i = 0; i < COLUMNS; i++) {
      int p = j * COLUMNS + i;
      position[2 * p] = right - (COLUMNS - 1 - i) * spacing;
      position[2 * p + 1] = top - (ROWS - 1 - j) * spacing;
      volume[p] = spacing * spacing;
      double *s = stress + 6 * p;
      s[GM_XX] = s[GM_YY] = s[GM_ZZ] = -PRESSURE; /* tension positive */
      s[GM_XY] = SHEAR;
      s[GM_YZ] = s[GM_ZX] = 0.0;
    }
  gm_points_def points = gm_points_def_default();
  points.count = COLUMNS * ROWS;
  points.material = id;
  points.position = position;
  points.volume = volume;
  points.stress = stress;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  return domain;
}

/* Kinetic + elastic energy (J per m); the elastic part is the
 * complementary energy V / (2E) (s_xx^2 + s_yy^2 + s_zz^2 - 2 nu (s_xx s_yy
 * + s_yy s_zz + s_zz s_xx) + 2 (1 + nu) s_xy^2). Also the largest point
 * speed (m/s) and whether every point lies inside the box. */
static double energy(const gm_domain *domain, double *fastest, int *inside) {
  size_t n = gm_domain_point_count(domain);
  const double *x = NULL, *y = NULL, *vx = NULL, *vy = NULL, *volume = NULL;
  const double *s[4] = {NULL, NULL, NULL, NULL};
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_VELOCITY, 0, &vx));
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_VELOCITY, 1, &vy));
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume));
  for (int c = 0; c < 4; c++)
    TEST_ASSERT_OK(domain,
                   gm_domain_view_field(domain, GM_FIELD_STRESS, c, &s[c]));
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  double total = summary.kinetic_energy;
  for (size_t p = 0; p < n; p++) {
    double xx = s[GM_XX][p], yy = s[GM_YY][p], zz = s[GM_ZZ][p];
    double xy = s[GM_XY][p];
    double normal = xx * xx + yy * yy + zz * zz -
                    2.0 * POISSON * (xx * yy + yy * zz + zz * xx);
    total +=
        volume[p] / (2.0 * YOUNGS) * (normal + 2.0 * (1.0 + POISSON) * xy * xy);
    *fastest = fmax(*fastest, hypot(vx[p], vy[p]));
    if (!(x[p] > 0.0 && x[p] < 0.4 && y[p] > 0.0 && y[p] < 0.3))
      *inside = 0;
  }
  return total;
}

START_TEST(test_stressed_point_entering_a_cell) {
  gm_update_scheme scheme = (gm_update_scheme)(_i % 3);
  int elastic = _i / 3;
  const char *name = elastic ? "elastic" : "Mohr-Coulomb";
  gm_domain *domain = make_block(scheme, elastic);
  double fastest = 0.0;
  int inside = 1;
  double start = energy(domain, &fastest, &inside);
  double most = start; /* J per m */
  for (int step = 0; step < STEPS; step++) {
    gm_status status = gm_domain_step(domain, 0.0);
    ck_assert_msg(status == GM_OK, "%s, %s: step %d failed: %s", name,
                  test_scheme_name(scheme), step, gm_domain_last_error(domain));
    most = fmax(most, energy(domain, &fastest, &inside));
    ck_assert_msg(inside, "%s, %s: a point left the box at step %d", name,
                  test_scheme_name(scheme), step);
  }
  double modulus =
      YOUNGS * (1.0 - POISSON) / ((1.0 + POISSON) * (1.0 - 2.0 * POISSON));
  double release = PRESSURE / sqrt(DENSITY * modulus); /* m/s, p/(rho c) */
  if (getenv("GM_VERBOSE"))
    fprintf(stderr,
            "%s, %s: energy at most %.6g of its start, fastest %.4g "
            "p/(rho c)\n",
            name, test_scheme_name(scheme), most / start, fastest / release);
  ck_assert_msg(most <= (1.0 + ENERGY_SLACK[elastic][_i % 3]) * start,
                "%s, %s: kinetic + elastic energy rose to %g J/m from %g J/m",
                name, test_scheme_name(scheme), most, start);
  ck_assert_msg(fastest < SPEED_FACTOR * release,
                "%s, %s: a point moved at %g m/s, %g times the release speed "
                "p / (rho c_p) = %g m/s",
                name, test_scheme_name(scheme), fastest, fastest / release,
                release);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("entering_point");
  TCase *tcase = tcase_create("plain linear");
  tcase_add_loop_test(tcase, test_stressed_point_entering_a_cell, 0, 2 * 3);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
