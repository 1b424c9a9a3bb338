/*
 * test_disconnected_1d.c - the 1D disconnected state of Granular MPM (000
 * sec 4.1, Table 2): a disconnected point (density just below rho_cr)
 * moves at a constant speed towards a resting pair of connected points.
 *
 *  - granular family: the moving point sits on its own parallel grid, so
 *    its velocity stays bitwise what it was until its domain of
 *    interaction (length m / rho_cr in 1D) meets the pair's. That merge
 *    happens at the closed-form time gap / speed whatever the grid, and
 *    the velocity changes right after it (one step to build stress);
 *  - stress_free family: one grid for everybody, so the velocity changes
 *    as soon as the moving point and the pair share a grid node, a time
 *    that depends on the grid and comes before the granular merge.
 * Both with linear MPM, cpGIMP and the quadratic and cubic B-splines.
 *
 * A subtlety of linear MPM: the pre-task of 000 (Table A1) only looks for
 * interactions between points whose supports share a node, and with
 * linear shape functions the support is the point's cell. The interaction
 * domains here (10.71 mm) are longer than a 10 mm cell, so on a grid where
 * the moving point reaches the pair's neighbouring cell only after the
 * domains of interaction meet, nothing can happen before that: the merge
 * and the velocity change come at the first shared node instead. Such a
 * grid (LATE_GRID) is kept and asserted on that later time.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#include "test_util.h"

static const double YOUNGS_MODULUS = 1e5;     /* Pa, Table 2 */
static const double DENSITY = 1500.0;         /* kg/m^3, rho_initial */
static const double CRITICAL = 1400.0;        /* kg/m^3, rho_cr */
static const double MOVING_DENSITY = 1399.99; /* kg/m^3, just disconnected */
static const double TIME_STEP = 2e-5;         /* s, Table 2 */
static const double POINT_MASS = 15.0;        /* kg/m^2 (mass per unit area) */
static const double SPEED = 0.5;              /* m/s, of the moving point */
static const double MOVING_START = 0.0455;    /* m */
static const double PAIR[2] = {0.08, 0.09};   /* m, the resting pair */
/* kg/m^3, TOL (not in Table 2): the granular family refuses a granular
 * point placed below rho_cr - TOL (gm_granular(3)), and the paper's moving
 * point sits 0.01 kg/m^3 below rho_cr, so TOL must exceed 0.01. Both
 * families see the same scene: stress_free ignores TOL (stress-free below
 * rho_cr itself). The steps of merge, first shared node and velocity change
 * are those the test saw with the default TOL before the refusal existed. */
static const double TOLERANCE = 0.02;

/* A background grid: node k at origin + k * cell_size. None puts a point
 * exactly on a node at the start (a point on a node has a zero weight on
 * one of its nodes, which is a different, degenerate case). */
typedef struct grid_case {
  double cell_size; /* m */
  double origin;    /* m */
} grid_case;

/* The three grids of the grid-independence check: on each of them the
 * moving point and the pair already share a node when their domains of
 * interaction meet (verified by the test itself). */
static const grid_case GRIDS[] = {
    {0.010, -0.0030}, /* nodes ... 0.067, 0.077, 0.087 */
    {0.010, -0.0071}, /* nodes ... 0.0629, 0.0729, 0.0829 */
    {0.008, -0.0055}, /* nodes ... 0.0665, 0.0745, 0.0825 */
};
enum { GRID_COUNT = sizeof GRIDS / sizeof GRIDS[0] };
/* Nodes ... 0.0695, 0.0795: with linear MPM the moving point reaches the
 * pair's neighbouring cell (x = 0.0695 m, t = 0.048 s) after the domains
 * of interaction meet (t = 0.04757 s). */
static const grid_case LATE_GRID = {0.010, -0.0005};

enum { MOVING = 0, PAIR_LEFT = 1, POINTS = 3 };

/* What one run observed; steps are counted from 0, step n starts at
 * n * TIME_STEP. -1 = never within the run. */
typedef struct run_record {
  int merge_step;  /* first step that used one grid (component_count 1) */
  int share_step;  /* first step starting with a node shared by the
                      moving point and the pair (computed here) */
  int change_step; /* first step after which the velocity is not SPEED */
} run_record;

/* Length (m) of the domain of interaction of a 1D point: its domain
 * length scaled to the critical volume, A0 (m / V0) / rho_cr (000 sec 3.3),
 * which for A0 = V0 (the 1D default domain) is m / rho_cr. */
static double interaction_length(double domain_length, double mass,
                                 double volume) {
  return domain_length * (mass / volume) / CRITICAL;
}

/* Closed-form start of the granular merge (s): the free gap between the
 * two domains of interaction closed at SPEED. */
static double expected_merge_time(void) {
  double moving_volume = POINT_MASS / MOVING_DENSITY; /* m */
  double pair_volume = POINT_MASS / DENSITY;          /* m */
  double moving_reach =
      0.5 * interaction_length(moving_volume, POINT_MASS, moving_volume);
  double pair_reach =
      0.5 * interaction_length(pair_volume, POINT_MASS, pair_volume);
  double gap = (PAIR[0] - pair_reach) - (MOVING_START + moving_reach); /* m */
  return gap / SPEED;
}

static gm_domain *create_scene(const grid_case *grid, gm_shape shape,
                               gm_family family, int64_t *first_id) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_1D;
  def.origin[0] = grid->origin;
  def.extent[0] = 0.15; /* m: the pair ends at 0.095 m */
  def.cell_size = grid->cell_size;
  def.shape = shape;
  def.family = family;
  gm_domain *domain = test_create_domain(&def);
  /* nu = 0: uniaxial strain with the plain Young's modulus (Table 2). */
  int material = test_add_elastic(domain, YOUNGS_MODULUS, 0.0, DENSITY);
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL;
  granular.tolerance = TOLERANCE;
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &granular));
  const double position[POINTS] = {MOVING_START, PAIR[0], PAIR[1]}; /* m */
  const double velocity[POINTS] = {SPEED, 0.0, 0.0};                /* m/s */
  const double mass[POINTS] = {POINT_MASS, POINT_MASS, POINT_MASS};
  /* m (volume per unit area); the domain length defaults to it. */
  const double volume[POINTS] = {POINT_MASS / MOVING_DENSITY,
                                 POINT_MASS / DENSITY, POINT_MASS / DENSITY};
  gm_points_def points = gm_points_def_default();
  points.count = POINTS;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.mass = mass;
  points.volume = volume;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, first_id));
  return domain;
}

/* Lowest and highest node index the support of a point with the domain
 * [left, right] (m) at x reaches, as the library's shape functions do
 * (support.h): the point's cell for linear MPM, the cells its domain
 * touches plus the next node for GIMP, the nodes within 1.5 (quadratic
 * B-spline) or 2 cells (cubic) of x. */
static void support_nodes(const grid_case *grid, gm_shape shape, double x,
                          double left, double right, double nodes[2]) {
  double s = (x - grid->origin) / grid->cell_size; /* cells from node 0 */
  if (shape == GM_SHAPE_BSPLINE2 || shape == GM_SHAPE_BSPLINE3) {
    bool quadratic = shape == GM_SHAPE_BSPLINE2;
    nodes[0] = quadratic ? floor(s - 0.5) : floor(s) - 1.0;
    nodes[1] = nodes[0] + (quadratic ? 2.0 : 3.0);
    return;
  }
  double low = shape == GM_SHAPE_LINEAR ? x : left;
  double high = shape == GM_SHAPE_LINEAR ? x : right;
  nodes[0] = floor((low - grid->origin) / grid->cell_size);
  nodes[1] = floor((high - grid->origin) / grid->cell_size) + 1.0;
}

/* Do the moving point and the pair's nearer point share a node now? */
static bool moving_shares_node(const gm_domain *domain, const grid_case *grid,
                               gm_shape shape, int64_t first_id) {
  double position[POINTS], corners[2 * POINTS];
  test_get_field_by_id(domain, GM_FIELD_POSITION, first_id, position);
  test_get_field_by_id(domain, GM_FIELD_DOMAIN_CORNERS, first_id, corners);
  double moving[2], pair[2];
  support_nodes(grid, shape, position[MOVING], corners[2 * MOVING],
                corners[2 * MOVING + 1], moving);
  support_nodes(grid, shape, position[PAIR_LEFT], corners[2 * PAIR_LEFT],
                corners[2 * PAIR_LEFT + 1], pair);
  return moving[1] >= pair[0];
}

/* Before the merge the moving point is alone on grid 0 (smallest id) and
 * disconnected; the pair is connected on grid 1 (density 1500 > rho_cr,
 * so quasi-static). */
static void check_separate_grids(const gm_domain *domain, int64_t first_id,
                                 int step) {
  double state[POINTS], component[POINTS];
  test_get_field_by_id(domain, GM_FIELD_STATE, first_id, state);
  test_get_field_by_id(domain, GM_FIELD_COMPONENT, first_id, component);
  ck_assert_msg(state[MOVING] == GM_STATE_DISCONNECTED &&
                    state[PAIR_LEFT] == GM_STATE_QUASI_STATIC &&
                    state[2] == GM_STATE_QUASI_STATIC,
                "step %d: states %g %g %g", step, state[0], state[1], state[2]);
  ck_assert_msg(component[MOVING] == 0.0 && component[PAIR_LEFT] == 1.0 &&
                    component[2] == 1.0,
                "step %d: components %g %g %g", step, component[0],
                component[1], component[2]);
  /* Stored as a byte and an int32 (gm_fields(3)): copies only, no view. */
  const double *view = NULL;
  ck_assert_int_eq(gm_domain_view_field(domain, GM_FIELD_STATE, 0, &view),
                   GM_ERR_UNSUPPORTED);
  ck_assert_int_eq(gm_domain_view_field(domain, GM_FIELD_COMPONENT, 0, &view),
                   GM_ERR_UNSUPPORTED);
}

/* Steps until the velocity has changed and the grids merged (granular),
 * a few steps beyond, or max_steps. */
static run_record run_scene(const grid_case *grid, gm_shape shape,
                            gm_family family, int max_steps) {
  int64_t first_id = 0;
  gm_domain *domain = create_scene(grid, shape, family, &first_id);
  run_record record = {-1, -1, -1};
  bool granular = family == GM_FAMILY_GRANULAR;
  for (int step = 0; step < max_steps; step++) {
    if (record.share_step < 0 &&
        moving_shares_node(domain, grid, shape, first_id))
      record.share_step = step;
    TEST_ASSERT_OK(domain, gm_domain_step(domain, TIME_STEP));
    gm_granular_summary summary = gm_granular_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
    if (granular && record.merge_step < 0) {
      if (summary.component_count == 1)
        record.merge_step = step;
      else
        check_separate_grids(domain, first_id, step);
    }
    double velocity[POINTS]; /* m/s */
    test_get_field_by_id(domain, GM_FIELD_VELOCITY, first_id, velocity);
    if (record.change_step < 0 && velocity[MOVING] != SPEED)
      record.change_step = step;
    bool done =
        record.change_step >= 0 && (!granular || record.merge_step >= 0);
    if (done && step >= record.change_step + 2)
      break;
  }
  gm_domain_destroy(domain);
  return record;
}

/* The step whose start time first exceeds `time` (s): the one that sees
 * the domains overlap (strictly) when they meet at `time`. */
static int first_step_after(double time) {
  return (int)floor(time / TIME_STEP) + 1;
}

/* Enough steps to pass the merge and the latest first shared node. */
static int step_limit(void) {
  return first_step_after(expected_merge_time()) + 200;
}

/* The B-splines' domains of interaction are their initial domains scaled,
 * as uGIMP's: the merge must come at the same closed-form time. */
static const gm_shape SHAPES[] = {GM_SHAPE_LINEAR, GM_SHAPE_CPGIMP,
                                  GM_SHAPE_BSPLINE2, GM_SHAPE_BSPLINE3};
enum { SHAPE_COUNT = sizeof SHAPES / sizeof SHAPES[0] };

/* (a) and (b): granular family, one shape per loop index, all grids. */
START_TEST(test_granular_merge_is_grid_independent) {
  gm_shape shape = SHAPES[_i];
  double merge_time = expected_merge_time(); /* s */
  int merge_step = first_step_after(merge_time);
  int reference_step = -1;
  for (int g = 0; g < GRID_COUNT; g++) {
    run_record run =
        run_scene(&GRIDS[g], shape, GM_FAMILY_GRANULAR, step_limit());
    const char *name = test_shape_name(shape);
    /* The grids were chosen to share a node by the merge: a setup check. */
    ck_assert_msg(run.share_step >= 0 && run.share_step <= merge_step,
                  "%s grid %d: first shared node at step %d, after the merge",
                  name, g, run.share_step);
    ck_assert_msg(run.merge_step >= 0, "%s grid %d: no merge", name, g);
    /* Components are decided at step starts, so the merge is seen at the
     * first start after the domains meet: within one dt of gap / speed
     * (positions advance by v dt with round-off ~1e-17 m, far below
     * v dt = 1e-5 m). */
    double start = run.merge_step * TIME_STEP; /* s */
    ck_assert_msg(fabs(start - merge_time) <= TIME_STEP,
                  "%s grid %d: merge at %.6f s, gap / speed = %.6f s", name, g,
                  start, merge_time);
    /* gap / speed is 2378.6 steps, far from a step boundary, so the merge
     * step must be the same step on every grid, not just within dt. */
    if (reference_step < 0)
      reference_step = run.merge_step;
    ck_assert_msg(run.merge_step == reference_step,
                  "%s grid %d: merge at step %d, grid 0 at step %d", name, g,
                  run.merge_step, reference_step);
    /* Bitwise SPEED through every step before the merge (change_step is
     * the first step that altered it); then stress needs one step to
     * build in the pair before it pushes back: within two steps. */
    ck_assert_msg(run.change_step >= run.merge_step &&
                      run.change_step <= run.merge_step + 2,
                  "%s grid %d: velocity changed at step %d, merge at %d", name,
                  g, run.change_step, run.merge_step);
  }
}
END_TEST

/* The linear-MPM grid that shares no node at the merge: merge and velocity
 * change wait for the first shared node (see the top of this file). */
START_TEST(test_granular_late_shared_node) {
  int merge_step = first_step_after(expected_merge_time());
  run_record run =
      run_scene(&LATE_GRID, GM_SHAPE_LINEAR, GM_FAMILY_GRANULAR, step_limit());
  ck_assert_msg(run.share_step > merge_step,
                "setup: first shared node at step %d, merge at step %d",
                run.share_step, merge_step);
  /* The pre-task finds no candidate pair before a shared node. */
  ck_assert_int_eq(run.merge_step, run.share_step);
  ck_assert_msg(run.change_step >= run.share_step &&
                    run.change_step <= run.share_step + 2,
                "velocity changed at step %d, first shared node at %d",
                run.change_step, run.share_step);
}
END_TEST

/* (c): stress_free family on the same grids. The velocity changes one step
 * after the first shared node (the pair first needs stress), before the
 * granular merge time: the grid-dependent interaction Granular MPM
 * removes. */
START_TEST(test_stress_free_interacts_at_first_shared_node) {
  gm_shape shape = SHAPES[_i];
  int merge_step = first_step_after(expected_merge_time());
  for (int g = 0; g < GRID_COUNT; g++) {
    run_record run =
        run_scene(&GRIDS[g], shape, GM_FAMILY_STRESS_FREE, step_limit());
    const char *name = test_shape_name(shape);
    ck_assert_msg(run.share_step >= 0 && run.change_step >= 0,
                  "%s grid %d: shared node at step %d, change at step %d", name,
                  g, run.share_step, run.change_step);
    /* A shared node's tent or GIMP weight grows linearly from zero, and
     * the change shows the next step. A B-spline's grows as d^2/2
     * (quadratic) or d^3/6 (cubic) in the cells d moved past sharing, 1e-3
     * cells per step here, so the first changes hide below the round-off
     * of SPEED for a few steps: measured 2 (quadratic) and 9 (cubic).
     * 20 steps (2e-4 s) is still the first shared node, two thousand steps
     * before the granular merge. */
    bool bspline = shape == GM_SHAPE_BSPLINE2 || shape == GM_SHAPE_BSPLINE3;
    int delay = bspline ? 20 : 1;
    ck_assert_msg(run.change_step >= run.share_step &&
                      run.change_step <= run.share_step + delay,
                  "%s grid %d: velocity changed at step %d, first shared "
                  "node at step %d",
                  name, g, run.change_step, run.share_step);
    ck_assert_msg(run.change_step < merge_step,
                  "%s grid %d: stress-free change at step %d is not before "
                  "the granular merge at step %d",
                  name, g, run.change_step, merge_step);
  }
}
END_TEST

static Suite *disconnected_suite(void) {
  Suite *suite = suite_create("disconnected_1d");
  TCase *granular = tcase_create("granular");
  tcase_add_loop_test(granular, test_granular_merge_is_grid_independent, 0,
                      SHAPE_COUNT);
  tcase_add_test(granular, test_granular_late_shared_node);
  suite_add_tcase(suite, granular);
  TCase *stress_free = tcase_create("stress_free");
  tcase_add_loop_test(stress_free,
                      test_stress_free_interacts_at_first_shared_node, 0,
                      SHAPE_COUNT);
  suite_add_tcase(suite, stress_free);
  return suite;
}

int main(void) {
  return test_run_suite(disconnected_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
