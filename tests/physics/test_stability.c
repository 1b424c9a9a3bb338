/*
 * test_stability.c - stability where methods fail (issue 6), in the two
 * scenes of Seyedan & Solowski 2021 (000) where the paper shows plain and
 * stress-free CPDI breaking down: the granular avalanche (sec 4.2) and the
 * silo filling (sec 4.3). The scenes are those of
 * examples/papers/seyedan2021_avalanche.c and
 * examples/papers/seyedan2021_silo_filling.c (see their header comments for the
 * geometry), rebuilt here, with two changes to fit a test's budget: the Young's
 * modulus of every material is 1e7 Pa instead of 1 GPa (the stable time
 * step grows with 1/sqrt(E), so the runs take ~9 times fewer steps), and
 * the runs are shorter (avalanche 2 s, silo 4 s): about 14 s of CPU at
 * -O2 for the whole program instead of many minutes. Measured with the
 * examples at 1 GPa (before the CPDI domain reset of cpdi_reset.c), the
 * outcomes are the same kind: avalanche plain CPDI V/V0 up to
 * 6.0, stress-free CPDI out of the grid at 1.50 s; silo plain CPDI out of
 * the grid at 1.72 s, stress-free CPDI at 5.53 s (the paper: stress-free
 * CPDI fails "shortly after 6.31 s"); granular CPDI bounded in both.
 *
 * Asserted, per scene (all CPDI, MUSL, the stable time step):
 *  - granular: the run completes (every step GM_OK), every point stays in
 *    the grid box, every field stays finite, and no granular point's
 *    volume ratio V/V0 exceeds rho_0 / (rho_cr - TOL): density control
 *    (eqs 13-15) keeps every connected point at rho >= rho_cr - TOL and
 *    disconnected points keep their density (F frozen), so this bound is
 *    exact, up to the rounding of m/V (1e-9 relative allowed);
 *  - plain and stress_free: the outcome measured with this library, which
 *    the test pins down exactly (a change of outcome is a change of
 *    behaviour to look at, not noise): either the run fails with
 *    GM_ERR_OUT_OF_GRID (a swollen point's domain reaches past the grid)
 *    and a message naming the point, the domain left as after the last
 *    good step (fields finite), or it completes having lost the flow: some
 *    V/V0 above VOLUME_BLOW_UP. A granular material's packing varies by a
 *    few tens of per cent between its loosest and densest states, so a
 *    point that doubled its volume has left the continuum.
 * And for the time step: with refuse_unstable_dt a step above the stable
 * bound is refused with GM_ERR_UNSTABLE_DT and changes nothing; without
 * it, steps far above the bound either succeed with finite fields or fail
 * with a status and leave the domain finite and unchanged, and stable
 * steps afterwards recover.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;     /* m/s^2 */
static const double YOUNGS = 1e7;       /* Pa, see the top of this file */
static const double DENSITY = 2250.0;   /* kg/m^3, Tables 3 and 4 */
static const double CRITICAL = 2235.0;  /* kg/m^3, rho_cr */
static const double TOLERANCE = 1e-6;   /* kg/m^3, TOL */
static const double VOLUME_BLOW_UP = 2; /* V/V0: the flow is lost */

/* Avalanche (000 sec 4.2 as rebuilt in
 * examples/papers/seyedan2021_avalanche.c). */
static const double AVALANCHE_CELL = 0.1;          /* m */
static const double AVALANCHE_BOX[2] = {5.0, 2.5}; /* m */
static const double SLOPE = 15.0;                  /* deg, lower plane */
static const double STEEPER = 20.0;       /* deg, upper vs lower plane */
static const double FLOOR_Y = 0.2;        /* m */
static const double KINK_X = 2.5;         /* m */
static const double END_WALL_X = 4.8;     /* m */
static const double WALL_FRICTION = 0.3;  /* mu */
static const double AVALANCHE_TIME = 2.0; /* s: the front is at the wall */

/* Silo filling (000 sec 4.3 as in examples/papers/seyedan2021_silo_filling.c).
 */
static const double SILO_CELL = 0.3;       /* m */
static const double SILO_WIDTH = 2.7;      /* m, inside */
static const double SILO_HEIGHT = 7.5;     /* m, inside */
static const double SILO_HEADROOM = 0.6;   /* m */
static const double RELEASE_PERIOD = 0.17; /* s */
static const double SILO_TIME = 4.0;       /* s: 24 releases, 72 points */

typedef enum scene { AVALANCHE = 0, SILO = 1 } scene;

/* What a run ended with. */
typedef struct run_record {
  gm_status status;        /* of the failed step, GM_OK if none */
  double end_time;         /* s, time reached */
  double max_volume_ratio; /* largest V/V0 of a granular point */
  bool fields_finite;      /* every field of every point, every check */
  bool inside_box;         /* every position inside the grid box */
  size_t initial_points;   /* after the setup */
  size_t points;           /* at the end */
  uint64_t injected;       /* points the silo's source placed */
  char message[512];       /* gm_domain_last_error of the failure */
} run_record;

static void add_wall(gm_domain *domain, double x, double y, double nx,
                     double ny) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = x, wall.point[1] = y;
  wall.normal[0] = nx, wall.normal[1] = ny;
  wall.friction_static = wall.friction_kinetic = WALL_FRICTION;
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &id));
}

static int add_granular(gm_domain *domain) {
  gm_mohr_coulomb_def soil = gm_mohr_coulomb_def_default(); /* Table 3 */
  soil.youngs_modulus = YOUNGS;
  soil.density = DENSITY;
  int material = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_mohr_coulomb(domain, &soil, &material));
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL;
  granular.tolerance = TOLERANCE;
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &granular));
  return material;
}

static gm_domain_def scene_def(gm_family family, double cell, double width,
                               double height) {
  gm_domain_def def = gm_domain_def_default();
  def.extent[0] = width, def.extent[1] = height;
  def.cell_size = cell;
  for (int face = GM_FACE_XMIN; face <= GM_FACE_YMAX; face++)
    def.walls[face] = GM_WALL_FIXED;
  def.scheme = GM_SCHEME_MUSL;
  def.shape = GM_SHAPE_CPDI;
  def.family = family;
  return def;
}

/* A 1.0 m x 0.4 m block, 2 x 2 points per cell, on the upper plane,
 * moving down it at 1 m/s. */
static gm_domain *create_avalanche(gm_family family, int refuse) {
  gm_domain_def def =
      scene_def(family, AVALANCHE_CELL, AVALANCHE_BOX[0], AVALANCHE_BOX[1]);
  double slope = SLOPE * PI / 180.0, steeper = STEEPER * PI / 180.0; /* rad */
  def.gravity[0] = GRAVITY * sin(slope);
  def.gravity[1] = -GRAVITY * cos(slope);
  def.refuse_unstable_dt = refuse;
  gm_domain *domain = test_create_domain(&def);
  int material = add_granular(domain);
  add_wall(domain, 0.0, FLOOR_Y, 0.0, 1.0);
  add_wall(domain, KINK_X, FLOOR_Y, sin(steeper), cos(steeper));
  add_wall(domain, END_WALL_X, 0.0, -1.0, 0.0);
  enum { ALONG = 20, ACROSS = 8, COUNT = ALONG * ACROSS };
  double spacing = 0.5 * AVALANCHE_CELL; /* m */
  double up[2] = {-cos(steeper), sin(steeper)},
         out[2] = {sin(steeper), cos(steeper)};
  double position[2 * COUNT], velocity[2 * COUNT], volume[COUNT];
  for (int p = 0; p < COUNT; p++) {
    double s = 1.0 + (p % ALONG + 0.5) * spacing; /* m up the plane */
    double n = (p / ALONG + 0.5) * spacing;       /* m off the plane */
    for (int k = 0; k < 2; k++) {
      position[2 * p + k] = (k ? FLOOR_Y : KINK_X) + s * up[k] + n * out[k];
      velocity[2 * p + k] = -1.0 * up[k]; /* 1 m/s down the plane */
    }
    volume[p] = spacing * spacing;
  }
  test_add_points(domain, material, COUNT, position, velocity, volume);
  return domain;
}

/* Elastic walls one cell thick at the sides and under the floor; 3 points
 * of 0.15 m released every 0.17 s in the middle of the top cell row. */
static gm_domain *create_silo(gm_family family, int *source) {
  gm_domain_def def = scene_def(family, SILO_CELL, SILO_WIDTH + 2 * SILO_CELL,
                                SILO_HEIGHT + SILO_CELL + SILO_HEADROOM);
  def.gravity[1] = -GRAVITY;
  gm_domain *domain = test_create_domain(&def);
  int fill = add_granular(domain);
  double top = SILO_CELL + SILO_HEIGHT; /* m */
  double release[6];                    /* m */
  for (int k = 0; k < 3; k++) {
    release[2 * k] = SILO_CELL + (3 + k + 0.5) * SILO_CELL;
    release[2 * k + 1] = top - 0.5 * SILO_CELL;
  }
  gm_source_def def_source = gm_source_def_default();
  def_source.material = fill;
  def_source.count = 3;
  def_source.position = release;
  def_source.point_size = 0.5 * SILO_CELL;
  def_source.period = RELEASE_PERIOD;
  TEST_ASSERT_OK(domain, gm_domain_add_source(domain, &def_source, source));
  int silo = test_add_elastic(domain, YOUNGS, 0.3, DENSITY);
  const double lower[3][3] = {
      {0, 0, 0}, {SILO_CELL + SILO_WIDTH, 0, 0}, {SILO_CELL, 0, 0}};
  const double upper[3][3] = {{SILO_CELL, top, 0},
                              {2 * SILO_CELL + SILO_WIDTH, top, 0},
                              {SILO_CELL + SILO_WIDTH, SILO_CELL, 0}};
  for (int b = 0; b < 3; b++)
    test_fill_box(domain, silo, lower[b], upper[b], 2, NULL);
  return domain;
}

/* Are all values of every field finite? */
static bool all_fields_finite(const gm_domain *domain) {
  size_t count = gm_domain_point_count(domain);
  double *values = malloc((count ? count : 1) * 9 * sizeof *values);
  ck_assert_ptr_nonnull(values);
  bool finite = true;
  for (int field = GM_FIELD_POSITION; field <= GM_FIELD_COMPONENT; field++) {
    size_t components = 0;
    TEST_ASSERT_OK(domain, gm_domain_field_components(domain, (gm_field)field,
                                                      &components));
    ck_assert_uint_le(components, 9);
    TEST_ASSERT_OK(domain, gm_domain_get_field(domain, (gm_field)field, values,
                                               count * 9));
    for (size_t i = 0; i < count * components; i++)
      finite = finite && isfinite(values[i]);
  }
  free(values);
  return finite;
}

/* Largest V/V0 over the granular points (material `granular`) and
 * whether every position lies in the box [0, extent). */
static double volume_ratio(const gm_domain *domain, int granular,
                           const double extent[2], bool *inside) {
  size_t count = gm_domain_point_count(domain);
  double *material = malloc((count ? count : 1) * sizeof *material);
  ck_assert_ptr_nonnull(material);
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_MATERIAL, material, count));
  const double *volume = NULL, *initial = NULL, *x = NULL, *y = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume));
  TEST_ASSERT_OK(domain, gm_domain_view_field(domain, GM_FIELD_INITIAL_VOLUME,
                                              0, &initial));
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  double largest = 1.0;
  for (size_t p = 0; p < count; p++) {
    if (material[p] == granular)
      largest = fmax(largest, volume[p] / initial[p]);
    *inside = *inside && x[p] >= 0.0 && x[p] < extent[0] && y[p] >= 0.0 &&
              y[p] < extent[1];
  }
  free(material);
  return largest;
}

/* Steps with the stable dt until end_time or the first failed step. */
static run_record run_scene(scene which, gm_family family) {
  int source = -1;
  gm_domain *domain = which == AVALANCHE ? create_avalanche(family, 0)
                                         : create_silo(family, &source);
  const double extent[2] = {
      which == AVALANCHE ? AVALANCHE_BOX[0] : SILO_WIDTH + 2 * SILO_CELL,
      which == AVALANCHE ? AVALANCHE_BOX[1]
                         : SILO_HEIGHT + SILO_CELL + SILO_HEADROOM};
  double end_time = which == AVALANCHE ? AVALANCHE_TIME : SILO_TIME; /* s */
  run_record record = {GM_OK, 0.0, 1.0, true, true, 0, 0, 0, ""};
  record.initial_points = gm_domain_point_count(domain);
  for (uint64_t step = 0; record.end_time < end_time; step++) {
    gm_status status = gm_domain_step(domain, 0.0);
    TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &record.end_time, NULL));
    if (status != GM_OK) {
      record.status = status;
      snprintf(record.message, sizeof record.message, "%s",
               gm_domain_last_error(domain));
      break;
    }
    /* Material 0 is the granular one in both scenes. */
    record.max_volume_ratio =
        fmax(record.max_volume_ratio,
             volume_ratio(domain, 0, extent, &record.inside_box));
    if (step % 25 == 0)
      record.fields_finite = record.fields_finite && all_fields_finite(domain);
  }
  record.fields_finite = record.fields_finite && all_fields_finite(domain);
  record.points = gm_domain_point_count(domain);
  if (source >= 0) {
    gm_flow_totals totals = gm_flow_totals_default();
    TEST_ASSERT_OK(domain,
                   gm_domain_get_source_totals(domain, source, &totals));
    record.injected = totals.points;
  }
  gm_domain_destroy(domain);
  return record;
}

static const char *scene_name(scene which) {
  return which == AVALANCHE ? "avalanche" : "silo";
}

/* Granular CPDI: completes, stays in the grid, finite, bounded volumes. */
START_TEST(test_granular_completes_bounded) {
  scene which = (scene)_i;
  run_record run = run_scene(which, GM_FAMILY_GRANULAR);
  const char *name = scene_name(which);
  ck_assert_msg(run.status == GM_OK, "%s granular failed at %.4f s: %s (%s)",
                name, run.end_time, gm_strerror(run.status), run.message);
  ck_assert_msg(run.fields_finite && run.inside_box,
                "%s granular: finite %d, inside the box %d", name,
                run.fields_finite, run.inside_box);
  double bound = DENSITY / (CRITICAL - TOLERANCE); /* V/V0 */
  ck_assert_msg(run.max_volume_ratio <= bound * (1.0 + 1e-9),
                "%s granular: V/V0 reached %.9f > rho0/(rho_cr - TOL) = %.9f",
                name, run.max_volume_ratio, bound);
  /* Every release (at 0, 0.17, ... s) placed and still there. */
  uint64_t releases = (uint64_t)floor(SILO_TIME / RELEASE_PERIOD) + 1;
  if (which == SILO)
    ck_assert_msg(run.injected == 3 * releases &&
                      run.points == run.initial_points + run.injected,
                  "silo granular: %llu injected, %zu + %zu points",
                  (unsigned long long)run.injected, run.initial_points,
                  run.points - run.initial_points);
}
END_TEST

/* The measured outcome of a family that loses the flow. */
typedef struct expected_loss {
  scene which;
  gm_family family;
  gm_status status; /* GM_ERR_OUT_OF_GRID, or GM_OK: completes blown up */
  double measured;  /* as measured: s of the failure, or max V/V0 */
} expected_loss;

/* Measured at E = 1e7 Pa with this library and exactly this sequence of
 * stable steps, with the CPDI domain reset (cpdi_reset.c): in the
 * avalanche plain CPDI completes with V/V0 = 14.2, stress-free CPDI with
 * 12.1; in the silo plain CPDI completes to 4 s with V/V0 = 13.8,
 * stress-free CPDI with 16.6. Before the reset (domains F r0, slivers
 * under shear) the same runs gave 5.64, 7.21, 21.1 and, for the silo
 * stress-free one, a domain leaving the grid at 2.89 s (V/V0 49): the
 * reset keeps the swollen points' domains compact (a square of area V),
 * so they now stay in the grid for these 4 s, but the flow is lost just
 * the same (the paper's failure: disconnected points swell, 000 sec 4).
 * Whether a run dies or limps on is sensitive to the step sequence: the
 * silo example, whose output sampling shortens some steps, sees plain CPDI
 * leave the grid at 4.97 s. The blow-up itself is not sensitive: every
 * measured run exceeds VOLUME_BLOW_UP by a factor of 2.8 or more. */
static const expected_loss LOSSES[] = {
    {AVALANCHE, GM_FAMILY_PLAIN, GM_OK, 14.2},
    {AVALANCHE, GM_FAMILY_STRESS_FREE, GM_OK, 12.1},
    {SILO, GM_FAMILY_PLAIN, GM_OK, 13.8},
    {SILO, GM_FAMILY_STRESS_FREE, GM_OK, 16.6},
};
enum { LOSS_COUNT = sizeof LOSSES / sizeof LOSSES[0] };

START_TEST(test_plain_and_stress_free_lose_the_flow) {
  const expected_loss *expected = &LOSSES[_i];
  run_record run = run_scene(expected->which, expected->family);
  const char *name = scene_name(expected->which);
  const char *family =
      expected->family == GM_FAMILY_PLAIN ? "plain" : "stress_free";
  ck_assert_msg(run.status == expected->status,
                "%s %s: status %s at %.4f s (V/V0 %.3f), expected %s", name,
                family, gm_strerror(run.status), run.end_time,
                run.max_volume_ratio, gm_strerror(expected->status));
  printf("%s %s: %s at %.4f s, max V/V0 %.3f (recorded: %g)\n", name, family,
         gm_strerror(run.status), run.end_time, run.max_volume_ratio,
         expected->measured);
  /* Whichever way it went, the domain holds no NaN. */
  ck_assert_msg(run.fields_finite, "%s %s: a field is not finite", name,
                family);
  if (expected->status == GM_OK) {
    ck_assert_msg(run.max_volume_ratio > VOLUME_BLOW_UP,
                  "%s %s: completed with V/V0 at most %.3f: the flow was not "
                  "lost",
                  name, family, run.max_volume_ratio);
  } else {
    /* A clear status: the message names the point that left. */
    ck_assert_msg(strstr(run.message, "point id") != NULL,
                  "%s %s: message '%s' names no point", name, family,
                  run.message);
    ck_assert_msg(run.max_volume_ratio > VOLUME_BLOW_UP,
                  "%s %s: failed with V/V0 only %.3f", name, family,
                  run.max_volume_ratio);
  }
}
END_TEST

/* Positions and time, to compare a domain before and after a call. */
static void snapshot(const gm_domain *domain, double *positions, double *time) {
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             positions, 2 * 160));
  TEST_ASSERT_OK(domain, gm_domain_get_time(domain, time, NULL));
}

/* refuse_unstable_dt: a step 4x the bound fails and changes nothing. */
START_TEST(test_unstable_dt_refused) {
  gm_domain *domain = create_avalanche(GM_FAMILY_GRANULAR, 1);
  for (int step = 0; step < 50; step++) /* some flow first */
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
  double bound = 0.0, before[320], after[320], time_before = 0, time_after = 0;
  TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &bound));
  snapshot(domain, before, &time_before);
  ck_assert_int_eq(gm_domain_step(domain, 4.0 * bound), GM_ERR_UNSTABLE_DT);
  snapshot(domain, after, &time_after);
  ck_assert(time_after == time_before);
  ck_assert(memcmp(before, after, sizeof before) == 0);
  TEST_ASSERT_OK(domain, gm_domain_step(domain, bound)); /* at the bound */
  gm_domain_destroy(domain);
}
END_TEST

/* Without refuse_unstable_dt the library takes steps above the bound (as
 * documented in gm_domain_step(3)). Steps 10x the bound: every step that
 * succeeds leaves finite fields, and the damage they do is caught as a
 * failed step with a status (non-finite value or a point out of the grid)
 * that leaves the domain unchanged and finite, never as a silent NaN.
 * Measured: the plain run fails at its 1578th such step (its 316th when
 * MUSL updated its stress last, step.c; its 23rd before the CPDI domains
 * were reset, cpdi_reset.c: the slivers failed it sooner), the granular
 * one at its 10th (12th); up to 2000 are taken. The state those
 * steps committed is already damaged, so a stable step does not recover it
 * (measured: it fails too, with a status): recovery is the host's job, from a
 * checkpoint or with refuse_unstable_dt, and is not asserted here. */
START_TEST(test_unstable_dt_never_silent_nan) {
  gm_family family = _i ? GM_FAMILY_GRANULAR : GM_FAMILY_PLAIN;
  const char *name = _i ? "granular" : "plain";
  gm_domain *domain = create_avalanche(family, 0);
  int failed_step = -1;
  for (int step = 0; step < 2000 && failed_step < 0; step++) {
    double bound = 0.0, before[320], after[320], t0 = 0, t1 = 0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &bound));
    snapshot(domain, before, &t0);
    gm_status status = gm_domain_step(domain, 10.0 * bound);
    ck_assert_msg(all_fields_finite(domain),
                  "%s step %d (status %s): a field is not finite", name, step,
                  gm_strerror(status));
    if (status == GM_OK)
      continue;
    failed_step = step;
    ck_assert_msg(status == GM_ERR_NOT_FINITE || status == GM_ERR_OUT_OF_GRID,
                  "%s step %d: unexpected status %s", name, step,
                  gm_strerror(status));
    snapshot(domain, after, &t1);
    ck_assert_msg(t1 == t0 && memcmp(before, after, sizeof before) == 0,
                  "%s step %d failed (%s) but changed the domain", name, step,
                  gm_strerror(status));
  }
  gm_domain_destroy(domain);
  ck_assert_msg(failed_step >= 0,
                "%s: 2000 steps at 10x the stable dt all succeeded", name);
  printf("unstable dt, %s: the over-large step %d failed with a status\n", name,
         failed_step);
}
END_TEST

static Suite *stability_suite(void) {
  Suite *suite = suite_create("stability");
  TCase *scenes = tcase_create("scenes");
  tcase_set_timeout(scenes, 300); /* ~15 s at -O2, ~3x under ASan */
  tcase_add_loop_test(scenes, test_granular_completes_bounded, AVALANCHE,
                      SILO + 1);
  tcase_add_loop_test(scenes, test_plain_and_stress_free_lose_the_flow, 0,
                      LOSS_COUNT);
  suite_add_tcase(suite, scenes);
  TCase *time_step = tcase_create("time_step");
  tcase_set_timeout(time_step, 120);
  tcase_add_test(time_step, test_unstable_dt_refused);
  tcase_add_loop_test(time_step, test_unstable_dt_never_silent_nan, 0, 2);
  suite_add_tcase(suite, time_step);
  return suite;
}

int main(void) {
  return test_run_suite(stability_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
