/*
 * test_collapse_refinement.c - the planar column collapse with the setting
 * docs/convergence.md section 20 found converged near Lube et al.'s (2005)
 * law at a = 1-3 (issue 13 item 4, "make check asserts these at the
 * coarsest grids that still show them"):
 *   Perzyna Drucker-Prager (gm_domain_add_perzyna), psi = 0, N = 1, the
 *   cone matched to Mohr-Coulomb phi = 37 deg in plane strain (m = 1.0424),
 *   fluidity gamma = 300 1/s, reference stress 1795 Pa, E = 0.5 MPa,
 *   nu = 0.3, rho = 1800 kg/m^3; quadratic B-splines, plain family, FLIP,
 *   USL; Coulomb floor wall mu_b = 0.45, frictionless back wall; a = 1.3,
 *   L0 = 0.15 m; 6 tau_c in 200 equal output intervals.
 * The scene is built by bench/convergence/collapse_scene.c, the one the
 * convergence probe energy_budget.c uses, and the run follows the probe's
 * output schedule, so the numbers here are the ones of section 20 (run-out
 * 1.548 on L0/10 and 1.585 on L0/20 with 2 x 2 points per cell; 1.551 and
 * 1.548 with 3 x 3 and 4 x 4 on L0/10; 1.608 on L0/40 and 1.602 on L0/80,
 * which are too long for make check).
 *
 * Asserted:
 *  - the first halving, L0/10 -> L0/20, moves the run-out by at most 3 %
 *    (issue 13's bound for the two finest grids; here the two coarsest,
 *    which move the most: +2.4 % measured, then +1.5 % and -0.3 %). The
 *    rate-free Mohr-Coulomb of the example moves +12.6 % on the same
 *    halving (section 17), so the check separates a converging setting
 *    from the one the issue was filed against;
 *  - 2 x 2, 3 x 3 and 4 x 4 points per cell on L0/10 agree within 5 %
 *    (issue 13's bound; measured 0.2 %);
 *  - each run-out within +-10 % of the law 1.2 a = 1.56 and the final
 *    height (the highest point top) within +-15 % of H_inf/L0 = a^0.4 = 1.11
 *    (issue 13's bounds; measured -0.8 % / +1.6 % and -6.5 %);
 *  - every run settled: the front moved less than 1 % of L0 over the last
 *    tau_c, so the run-out is the final one.
 * Not asserted here: a = 0.5 converges 25 % short of the law with this
 * material (section 20 part 3; part 5 shows no rate term of this family
 * fits a = 0.5 and 1.3 together), a = 3 takes 74 s on L0/20.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "collapse_scene.h"
#include "test_util.h"

static const double ASPECT = 1.3;              /* a = H0 / L0 */
static const double LENGTH = 0.15;             /* L0, m */
static const double FRICTION_DEG = 37.0;       /* the flowing friction */
static const double FLOOR_FRICTION = 0.45;     /* mu_b of the floor wall */
static const double FLUIDITY = 300.0;          /* gamma, 1/s */
static const double REFERENCE_STRESS = 1795.0; /* sigma_ref, Pa */
static const double YOUNGS_MODULUS = 5e5;      /* Pa */
static const double POISSON_RATIO = 0.3;       /* - */
static const double RUN_TAU = 6.0;             /* run length, tau_c */
enum { ROW_COUNT = 200 };                      /* the probe's output rows */
static const double HALVING_BOUND = 0.03;      /* issue 13 item 4 */
static const double PPC_BOUND = 0.05;          /* issue 13 item 4 */
static const double LAW_BOUND = 0.10;          /* issue 13 item 4 */
static const double HEIGHT_BOUND = 0.15;       /* issue 13 item 4 */
static const double SETTLED_FRACTION = 0.01;   /* of L0, over the last tau_c */

/* What one run gave. */
typedef struct collapse_outcome {
  double runout;      /* (L_inf - L0) / L0 */
  double height;      /* H_inf / L0, the highest point top */
  double late_motion; /* of the front over the last tau_c, m */
} collapse_outcome;

static collapse_scene scene_at(double cell, int ppc) {
  collapse_scene scene = {.cell = cell,
                          .ppc = ppc,
                          .shape = GM_SHAPE_BSPLINE2,
                          .family = GM_FAMILY_PLAIN,
                          .workers = 1,
                          .cfl = 0.0,
                          .aspect = ASPECT,
                          .length = LENGTH,
                          .floor = "wall",
                          .floor_mu = FLOOR_FRICTION};
  return scene;
}

static gm_domain *build(const collapse_scene *scene) {
  gm_domain_def def = collapse_scene_domain_def(scene);
  gm_domain *domain = test_create_domain(&def);
  gm_perzyna_def material = gm_perzyna_def_default();
  material.youngs_modulus = YOUNGS_MODULUS;
  material.poisson_ratio = POISSON_RATIO;
  material.density = COLLAPSE_DENSITY;
  material.friction_angle =
      collapse_scene_dp_friction(FRICTION_DEG * COLLAPSE_PI / 180.0);
  material.fluidity = FLUIDITY;
  material.reference_stress = REFERENCE_STRESS;
  int id = -1, floor_wall = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_perzyna(domain, &material, &id));
  TEST_ASSERT_OK(domain, collapse_scene_add_walls(domain, scene, &floor_wall));
  TEST_ASSERT_OK(domain, collapse_scene_fill(domain, scene, id));
  return domain;
}

/* Front (m) of the connected deposit and highest point top (m). */
static void measure(const collapse_scene *scene, const gm_domain *domain,
                    double *positions, unsigned char *occupied, double *front,
                    double *top) {
  size_t count = gm_domain_point_count(domain);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             positions, 2 * count));
  *front = collapse_scene_front(scene, positions, count, occupied);
  double half = 0.5 * scene->cell / scene->ppc;
  *top = 0.0;
  for (size_t i = 0; i < count; i++)
    *top = fmax(*top, positions[2 * i + 1] + half);
}

static collapse_outcome run(double cell, int ppc) {
  collapse_scene scene = scene_at(cell, ppc);
  gm_domain *domain = build(&scene);
  size_t count = gm_domain_point_count(domain);
  double *positions = malloc(2 * count * sizeof *positions);
  unsigned char *occupied = malloc(collapse_scene_columns(&scene));
  ck_assert(positions && occupied);
  double t_end = RUN_TAU * collapse_scene_tau(&scene); /* s */
  double start, front = 0.0, top = 0.0, late_start = 0.0;
  measure(&scene, domain, positions, occupied, &start, &top);
  int last_tau_row = (int)floor(ROW_COUNT * (RUN_TAU - 1.0) / RUN_TAU);
  for (int row = 1; row <= ROW_COUNT; row++) {
    double target = row == ROW_COUNT ? t_end : t_end * row / ROW_COUNT;
    gm_status status = gm_domain_advance(domain, target, 0.0, NULL, NULL);
    ck_assert_msg(status == GM_OK, "cell %g m, %d x %d: failed before %g s: %s",
                  cell, ppc, ppc, target, gm_domain_last_error(domain));
    if (row == last_tau_row || row == ROW_COUNT)
      measure(&scene, domain, positions, occupied,
              row == ROW_COUNT ? &front : &late_start, &top);
  }
  collapse_outcome outcome = {(front - start) / LENGTH, top / LENGTH,
                              front - late_start};
  printf("a = %g, cell %g m (L0/%.0f), %d x %d: run-out %.4f, H_inf/L0 %.4f\n",
         ASPECT, cell, LENGTH / cell, ppc, ppc, outcome.runout, outcome.height);
  free(positions);
  free(occupied);
  gm_domain_destroy(domain);
  return outcome;
}

/* Settled, and within the law's bounds. */
static void check_against_law(const collapse_outcome *outcome, double cell,
                              int ppc) {
  double law = collapse_scene_law_runout(ASPECT);
  double law_height = collapse_scene_law_height(ASPECT);
  ck_assert_msg(fabs(outcome->late_motion) < SETTLED_FRACTION * LENGTH,
                "cell %g m, %d x %d: the front still moved %.4g L0 in the "
                "last tau_c",
                cell, ppc, ppc, outcome->late_motion / LENGTH);
  ck_assert_msg(fabs(outcome->runout / law - 1.0) <= LAW_BOUND,
                "cell %g m, %d x %d: run-out %.4f against Lube's %.4f "
                "(%+.1f %%, bound %.0f %%)",
                cell, ppc, ppc, outcome->runout, law,
                100.0 * (outcome->runout / law - 1.0), 100.0 * LAW_BOUND);
  ck_assert_msg(fabs(outcome->height / law_height - 1.0) <= HEIGHT_BOUND,
                "cell %g m, %d x %d: H_inf/L0 %.4f against Lube's %.4f "
                "(%+.1f %%, bound %.0f %%)",
                cell, ppc, ppc, outcome->height, law_height,
                100.0 * (outcome->height / law_height - 1.0),
                100.0 * HEIGHT_BOUND);
}

START_TEST(test_runout_converges_under_refinement) {
  const double coarse = LENGTH / 10.0, fine = LENGTH / 20.0; /* m */
  collapse_outcome a = run(coarse, 2), b = run(fine, 2);
  check_against_law(&a, coarse, 2);
  check_against_law(&b, fine, 2);
  double change = b.runout / a.runout - 1.0;
  ck_assert_msg(fabs(change) <= HALVING_BOUND,
                "the run-out moved %+.2f %% from L0/10 to L0/20 (%.4f -> "
                "%.4f; bound %.0f %%)",
                100.0 * change, a.runout, b.runout, 100.0 * HALVING_BOUND);
}
END_TEST

START_TEST(test_runout_independent_of_points_per_cell) {
  const double cell = LENGTH / 10.0; /* m */
  double lowest = INFINITY, highest = -INFINITY;
  for (int ppc = 2; ppc <= 4; ppc++) {
    collapse_outcome outcome = run(cell, ppc);
    check_against_law(&outcome, cell, ppc);
    lowest = fmin(lowest, outcome.runout);
    highest = fmax(highest, outcome.runout);
  }
  double spread = highest / lowest - 1.0;
  ck_assert_msg(spread <= PPC_BOUND,
                "2 x 2 to 4 x 4 points per cell spread the run-out by %.2f "
                "%% (%.4f .. %.4f; bound %.0f %%)",
                100.0 * spread, lowest, highest, 100.0 * PPC_BOUND);
}
END_TEST

static Suite *refinement_suite(void) {
  Suite *suite = suite_create("collapse_refinement");
  TCase *tcase = tcase_create("perzyna_bspline2");
  /* ~20 s and ~15 s at -O2 on one loaded core; ASan is ~3x slower. */
  tcase_set_timeout(tcase, 600);
  /* tests/README.md, "Slow cases": test_column_collapse keeps the collapse
   * under the sanitizers. */
  tcase_set_tags(tcase, "slow");
  tcase_add_test(tcase, test_runout_converges_under_refinement);
  tcase_add_test(tcase, test_runout_independent_of_points_per_cell);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(refinement_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
