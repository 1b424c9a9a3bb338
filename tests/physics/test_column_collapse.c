/*
 * test_column_collapse.c - planar granular column collapse against the
 * experimental run-out law of Lube, Huppert, Sparks & Freundt (2005, PRE
 * 72:041301; docs/references.md):
 *   (L_inf - L0)/L0 ~ 1.2 a           for a <~ 1.8,
 *                   ~ 1.9 a^(2/3)     for a >~ 2.8,   a = H0/L0,
 * at one aspect ratio in each regime (a = 1 and a = 3), with the scene of
 * examples/column_collapse.c: a column at rest against a frictionless back
 * wall (the symmetry plane of Lube's channel) on a rough floor, Granular
 * uGIMP, Mohr-Coulomb with phi = 35 degrees (the upper end of Lube's
 * sands, rices and sugars, 30-35 degrees; at 30 degrees the run-out is
 * 11-20 % long, see examples/README.md), psi = 0, no rate term, floor
 * friction tan(phi). One material for both columns: nothing is tuned per
 * case.
 *
 * Why uGIMP, 10 cm columns and 1 cm cells: uGIMP is the reference variant;
 * Granular CPDI runs the a = 3 and a = 6 columns next to it
 * (test_cpdi_as_close_as_ugimp): before its domains were reset under
 * shear (lib/points/cpdi_reset.c) it left the grid in both (a point thrown out
 * at t = 0.42 s and 0.48 s). 2 x 2 points per cell and 5 to 30 cells per
 * column side keep each case under ~10 s at -O2. CPDI_MARGIN: measured,
 * CPDI is -0.2 %/+2.0 % (uGIMP/CPDI) off the law at a = 3 and
 * -3.8 %/-0.0 % at a = 6; 5 % allows CPDI to differ from uGIMP by a third
 * of the experimental scatter. E = 0.5 MPa
 * (softer than the example's default) halves the number of steps; the
 * elastic settlement rho g H0 / E stays ~1 % of H0.
 *
 * The axisymmetric column of examples/column_collapse --geometry axisym
 * (a cylinder of radius R0 about the axis x = r = 0, which replaces the
 * back wall) is checked the same way against Lube, Huppert, Sparks &
 * Hallworth (2004, JFM 508:175): (r_inf - R0)/R0 ~ 1.6 a^(1/2) at a = 3
 * (form confirmed, coefficient only in secondary quotations:
 * docs/references.md). Measured
 * when added: 2.734 against 2.771 (-1.3 %) at R0/10. With the example's
 * defaults at a = 3 every run of docs/convergence.md sec. 16 lies within
 * -1 ... +12 % of the fit (2.805, 2.923, 3.038 on R0/10, R0/20, R0/40;
 * 2.73-3.09 over 1 x 1 to 4 x 4 at R0/20), inside the 15 %. The run-out
 * is not converged (+4 % per halving), so this checks the scene and the
 * geometry (the planar a = 3 columns above run 43-51 % beyond this law), not a
 * converged answer; a = 1 is left out (-13 % at R0/10, growing).
 *
 * Asserted, for each column:
 *  - the deposit has stopped: the front moved less than 1 % of L0 in the
 *    last tau_c (tau_c = sqrt(H0/g)) of a 6 tau_c run, so the measured
 *    run-out is the final one to well within the tolerance below;
 *  - the run-out is within +-15 % of the law: the scatter of Lube's
 *    measurements about their fits (the design's validation target,
 *    design.md sec 5).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collapse_laws.h"
#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;                   /* m/s^2 */
static const double DENSITY = 1800.0;                 /* kg/m^3 */
static const double CRITICAL_RATIO = 2235.0 / 2250.0; /* 000 Table 1 */
static const double YOUNGS_MODULUS = 5e5;             /* Pa */
static const double POISSON_RATIO = 0.3;              /* - */
static const double FRICTION_DEG = 35.0;              /* phi and floor */
static const double CELL = 0.01;                      /* m */
static const int POINTS_PER_CELL_AXIS = 2;
static const double RUN_TAU = 6.0;           /* run length, tau_c */
static const double SETTLED_FRACTION = 0.01; /* of L0, over the last tau_c */
static const double LAW_TOLERANCE = 0.15;    /* relative, see the top */
static const double CPDI_MARGIN = 0.05;      /* relative, see the top */
enum { ROW_COUNT = 60 };

typedef struct collapse_case {
  double aspect;    /* a = H0 / L0 (H0 / R0 in axisymmetry) */
  double length;    /* L0, m (the radius R0 in axisymmetry) */
  int axisymmetric; /* nonzero: a cylinder about the axis x = r = 0 */
} collapse_case;

/* a = 1 in the linear regime (uGIMP only); a = 3 and a = 6 in the
 * a^(2/3) one, each with uGIMP and CPDI (test_cpdi_as_close_as_ugimp).
 * The a = 6 column is 5 cells wide so that it fits the time budget. */
static const collapse_case CASES[] = {{1.0, 0.15, 0}};
enum { CASE_COUNT = sizeof CASES / sizeof CASES[0] };
static const collapse_case TALL_CASES[] = {{3.0, 0.1, 0}, {6.0, 0.05, 0}};
enum { TALL_COUNT = sizeof TALL_CASES / sizeof TALL_CASES[0] };
/* Granular quadratic B-splines (the domains of interaction are the points'
 * initial rectangles scaled, as uGIMP's) at a = 1 and a = 3. Measured
 * run-outs when they were added: 1.178 and 3.752 (uGIMP 1.170 and 3.944,
 * law 1.2 and 3.952). The cubic B-spline is not run here: it pushed a point
 * through the planar floor (gm_walls(3)). */
/* a = 1 is left out: after the merge with the stored CPDI domains its front
 * still moved 0.037 L0 in the last tau_c of this test's run (open). */
static const collapse_case BSPLINE_CASES[] = {{3.0, 0.1, 0}};
enum { BSPLINE_COUNT = sizeof BSPLINE_CASES / sizeof BSPLINE_CASES[0] };
/* The axisymmetric collapse (examples/column_collapse --geometry axisym),
 * uGIMP, against Lube et al. 2004 in its a^(1/2) regime: a = 3 only. At
 * a = 1 the run-out is 13 % short at L0/10 and grows under refinement and
 * with the points per cell (docs/convergence.md sec. 16), so a check there
 * would not hold clearly. */
static const collapse_case AXISYMMETRIC_CASES[] = {{3.0, 0.1, 1}};
enum {
  AXISYMMETRIC_COUNT = sizeof AXISYMMETRIC_CASES / sizeof AXISYMMETRIC_CASES[0]
};

/* Lube et al. 2005 (examples/collapse_laws.h), in the two fitted regimes
 * only. */
static double lube_runout(double aspect) {
  ck_assert_msg(aspect <= LUBE2005_LINEAR_END || aspect >= LUBE2005_POWER_START,
                "a = %g lies between the fitted regimes", aspect);
  return lube2005_runout(aspect);
}

static double law_runout(const collapse_case *scene) {
  return scene->axisymmetric ? lube2004_runout(scene->aspect)
                             : lube_runout(scene->aspect);
}

static const char *law_name(const collapse_case *scene) {
  return scene->axisymmetric ? "Lube et al. 2004" : "Lube et al. 2005";
}

static gm_domain *build_collapse(const collapse_case *scene, gm_shape shape) {
  double height = scene->aspect * scene->length; /* H0, m */
  gm_domain_def def = gm_domain_def_default();
  /* Twice the law's run-out, and room above the column. */
  def.extent[0] = scene->length * (2.0 + 2.0 * law_runout(scene));
  def.extent[1] = 1.25 * height + 4.0 * CELL;
  def.cell_size = CELL;
  def.gravity[1] = -GRAVITY;
  def.shape = shape;
  def.family = GM_FAMILY_GRANULAR;
  /* The axis replaces the back wall: its nodes' radial velocity is held
   * at zero (gm_domain_create(3)). */
  if (scene->axisymmetric) {
    def.geometry = GM_GEOMETRY_AXISYMMETRIC;
    def.walls[GM_FACE_XMIN] = GM_WALL_SLIP;
  }
  gm_domain *domain = test_create_domain(&def);

  gm_mohr_coulomb_def material = gm_mohr_coulomb_def_default();
  material.youngs_modulus = YOUNGS_MODULUS;
  material.poisson_ratio = POISSON_RATIO;
  material.density = DENSITY;
  material.friction_angle = FRICTION_DEG * PI / 180.0;
  material.dilation_angle = 0.0;
  material.bagnold_viscosity = 0.0;
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_mohr_coulomb(domain, &material, &id));
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL_RATIO * DENSITY;
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, id, &granular));

  int wall_id = -1;
  gm_wall_def floor = gm_wall_def_default(); /* y = 0, normal +y */
  floor.friction_static = floor.friction_kinetic =
      tan(FRICTION_DEG * PI / 180.0);
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &floor, &wall_id));
  if (!scene->axisymmetric) {
    gm_wall_def back = gm_wall_def_default(); /* x = 0, frictionless */
    back.normal[0] = 1.0;
    back.normal[1] = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &back, &wall_id));
  }

  gm_fill_def fill = gm_fill_def_default();
  fill.material = id;
  fill.upper[0] = scene->length;
  fill.upper[1] = height;
  fill.points_per_cell_axis = POINTS_PER_CELL_AXIS;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  return domain;
}

/* Right edge (m) of the deposit connected to the back wall: cell columns
 * are walked from x = 0 to the first empty one (grains thrown ahead are
 * not part of the deposit); the edge is half a point spacing beyond the
 * outermost point centre, so the front is exactly L0 at t = 0. */
static double deposit_front(const gm_domain *domain, double extent) {
  size_t count = gm_domain_point_count(domain);
  size_t columns = (size_t)ceil(extent / CELL) + 2;
  double *position = malloc(2 * count * sizeof *position);
  unsigned char *occupied = calloc(columns, 1);
  ck_assert(position && occupied);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             position, 2 * count));
  for (size_t i = 0; i < count; i++) {
    double column = floor(position[2 * i] / CELL);
    if (column >= 0.0 && column < (double)columns)
      occupied[(size_t)column] = 1;
  }
  size_t first_empty = 0;
  while (first_empty < columns && occupied[first_empty])
    first_empty++;
  double limit = (double)first_empty * CELL, front = 0.0;
  double half_spacing = 0.5 * CELL / POINTS_PER_CELL_AXIS;
  for (size_t i = 0; i < count; i++)
    if (position[2 * i] < limit)
      front = fmax(front, position[2 * i] + half_spacing);
  free(position);
  free(occupied);
  return front;
}

/* What a collapse run gave. */
typedef struct collapse_result {
  gm_status status;   /* of the first failed advance, GM_OK if none */
  double end_time;    /* s, reached */
  double runout;      /* (L_inf - L0) / L0 */
  double late_motion; /* m, of the front over the last tau_c */
  char message[512];
} collapse_result;

static collapse_result run_collapse(const collapse_case *scene,
                                    gm_shape shape) {
  collapse_result result = {GM_OK, 0.0, 0.0, 0.0, ""};
  double height = scene->aspect * scene->length;
  double tau_c = sqrt(height / GRAVITY); /* s */
  double extent = scene->length * (2.0 + 2.0 * law_runout(scene));
  gm_domain *domain = build_collapse(scene, shape);
  double front[ROW_COUNT + 1]; /* m, at t = k RUN_TAU tau_c / ROW_COUNT */
  front[0] = deposit_front(domain, extent);
  ck_assert_msg(fabs(front[0] - scene->length) < 1e-9 * scene->length,
                "initial front %.9g m is not L0 = %g m", front[0],
                scene->length);
  for (int row = 1; row <= ROW_COUNT; row++) {
    double time = RUN_TAU * tau_c * row / ROW_COUNT;
    result.status = gm_domain_advance(domain, time, 0.0, NULL, NULL);
    TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &result.end_time, NULL));
    if (result.status != GM_OK) {
      snprintf(result.message, sizeof result.message, "%s",
               gm_domain_last_error(domain));
      gm_domain_destroy(domain);
      return result;
    }
    front[row] = deposit_front(domain, extent);
  }
  gm_domain_destroy(domain);
  int last_tau = (int)(ROW_COUNT / RUN_TAU); /* rows in one tau_c */
  result.late_motion = front[ROW_COUNT] - front[ROW_COUNT - last_tau];
  result.runout = (front[ROW_COUNT] - scene->length) / scene->length;
  return result;
}

/* Completed, settled, and within LAW_TOLERANCE of the law; returns the
 * relative error of the run-out. */
static double check_against_law(const collapse_case *scene, gm_shape shape,
                                const collapse_result *result) {
  const char *name = test_shape_name(shape);
  ck_assert_msg(result->status == GM_OK, "a = %g, %s: failed at t = %.4f s: %s",
                scene->aspect, name, result->end_time, result->message);
  double law = law_runout(scene);
  double error = (result->runout - law) / law;
  printf("a = %g, %s%s, L0 = %g m, cell %g m: run-out %.4f, %s %.4f (%+.1f "
         "%%)\n",
         scene->aspect, name, scene->axisymmetric ? " axisymmetric" : "",
         scene->length, CELL, result->runout, law_name(scene), law,
         100.0 * error);
  ck_assert_msg(fabs(result->late_motion) < SETTLED_FRACTION * scene->length,
                "a = %g, %s: the front still moved %.4g L0 in the last tau_c",
                scene->aspect, name, result->late_motion / scene->length);
  ck_assert_msg(fabs(error) <= LAW_TOLERANCE,
                "a = %g, %s: run-out (L_inf - L0)/L0 = %.4f, %s %.4f (%+.1f "
                "%%, tolerance %.0f %%)",
                scene->aspect, name, result->runout, law_name(scene), law,
                100.0 * error, 100.0 * LAW_TOLERANCE);
  return error;
}

START_TEST(test_runout_follows_lube) {
  const collapse_case *scene = &CASES[_i];
  collapse_result result = run_collapse(scene, GM_SHAPE_UGIMP);
  check_against_law(scene, GM_SHAPE_UGIMP, &result);
}
END_TEST

/* Tall columns, where the CPDI domains shear into slivers unless they
 * are reset (cpdi_reset.c; before the reset, granular CPDI stopped with an
 * inverted point in the a = 3 column): granular CPDI completes, and its
 * run-out is as close to the law as uGIMP's at the same resolution, to
 * within CPDI_MARGIN. */
START_TEST(test_cpdi_as_close_as_ugimp) {
  const collapse_case *scene = &TALL_CASES[_i];
  collapse_result ugimp = run_collapse(scene, GM_SHAPE_UGIMP);
  double ugimp_error = check_against_law(scene, GM_SHAPE_UGIMP, &ugimp);
  collapse_result cpdi = run_collapse(scene, GM_SHAPE_CPDI);
  double cpdi_error = check_against_law(scene, GM_SHAPE_CPDI, &cpdi);
  ck_assert_msg(fabs(cpdi_error) <= fabs(ugimp_error) + CPDI_MARGIN,
                "a = %g: CPDI run-out %+.1f %% off the law, uGIMP %+.1f %% "
                "(margin %.0f %%)",
                scene->aspect, 100.0 * cpdi_error, 100.0 * ugimp_error,
                100.0 * CPDI_MARGIN);
}
END_TEST

START_TEST(test_bspline_runout) {
  const collapse_case *scene = &BSPLINE_CASES[_i];
  collapse_result result = run_collapse(scene, GM_SHAPE_BSPLINE2);
  check_against_law(scene, GM_SHAPE_BSPLINE2, &result);
}
END_TEST

START_TEST(test_axisymmetric_runout) {
  const collapse_case *scene = &AXISYMMETRIC_CASES[_i];
  collapse_result result = run_collapse(scene, GM_SHAPE_UGIMP);
  check_against_law(scene, GM_SHAPE_UGIMP, &result);
}
END_TEST

static Suite *collapse_suite(void) {
  Suite *suite = suite_create("column_collapse");
  TCase *tcase = tcase_create("lube_2005");
  /* ~4 s (a = 0.5) and ~9 s (a = 3) at -O2; ASan is ~3x slower. */
  tcase_set_timeout(tcase, 300);
  tcase_add_loop_test(tcase, test_runout_follows_lube, 0, CASE_COUNT);
  suite_add_tcase(suite, tcase);
  /* The other shapes and the axisymmetric column (tests/README.md, "Slow
   * cases": test_cpdi_*, test_bspline and test_axisymmetric keep those
   * paths under the sanitizers). */
  TCase *shapes = tcase_create("other shapes and geometries");
  tcase_set_timeout(shapes, 300);
  tcase_set_tags(shapes, "slow");
  tcase_add_loop_test(shapes, test_cpdi_as_close_as_ugimp, 0, TALL_COUNT);
  tcase_add_loop_test(shapes, test_bspline_runout, 0, BSPLINE_COUNT);
  tcase_add_loop_test(shapes, test_axisymmetric_runout, 0, AXISYMMETRIC_COUNT);
  suite_add_tcase(suite, shapes);
  return suite;
}

int main(void) {
  return test_run_suite(collapse_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
