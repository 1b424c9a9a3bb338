/*
 * test_sources.c - filling and discharge: sources and sinks.
 *
 * A source injects 3 points every 0.17 s (the rate of 000 sec 4.3); the
 * points fall under gravity into a sink box near the bottom
 * of the grid. Every point weighs exactly 1 kg per metre (point_size
 * 0.25 m, density 16 kg/m^3: 16 * 0.25^2 = 1 in binary arithmetic), so
 * the masses sum without rounding and the balance
 *   injected - discharged = mass in the domain
 * must hold EXACTLY, at every step.
 *
 * Each test runs in plane strain and in 3D (GM_GEOMETRY_3D, a chute 1 m
 * deep with slip z faces; density 64 kg/m^3, so again 1 kg per point). In
 * 3D three points per injection fall at z = 0.25 m into the sink, and a
 * fourth at z = 0.875 m, beyond the sink's z extent [0, 0.5) m: the sink
 * must leave it alone, and it comes to rest on the no-slip floor below the
 * sink. The fourth points' domains touch the slip face z = 1 m; bouncing
 * on the floor and on each other, they are pressed against it and drift
 * away from it (measured up to 0.08 m by 3 s: a slip face lets material
 * leave it, grid_update_3d.c), so the sink's edge lies 1.5 cells from them
 * (it was 0.5 cells, at 0.75 m, while the 3D faces held their nodes
 * regardless of the gap and kept z).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

static const double PERIOD = 0.17;     /* s, 000 sec 4.3 */
static const double POINT_SIZE = 0.25; /* m */
static const double DENSITY = 16.0;    /* kg/m^3: 1 kg per point per m */
static const double DENSITY_3D = 64.0; /* kg/m^3: 1 kg per point (3D) */
static const double SINK_DEPTH = 0.5;  /* m, the 3D sink's z extent */
enum { DIMENSIONS = 2 };               /* loop index 0: 2D, 1: 3D */

typedef struct scene {
  gm_domain *domain;
  int source, sink;
  int dim;       /* 2 or 3 */
  size_t stream; /* points per injection */
} scene;

static scene falling_stream(int refuse_unstable_dt, int three_d) {
  scene s;
  s.dim = three_d ? 3 : 2;
  s.stream = three_d ? 4 : 3;
  gm_domain_def def = gm_domain_def_default();
  /* MUSL: injected points are isolated, and an isolated point just past a
   * cell edge gives the far nodes a tiny mass; USL then amplifies
   * round-off there (002 eq 17: the critical dt goes to 0 with that mass),
   * MUSL's re-mapped velocity does not (gm_domain_step(3)). */
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = 0.25;
  def.extent[0] = 2.0;
  def.extent[1] = 6.0;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] =
      GM_WALL_SLIP; /* a chute */
  /* the floor below the sink: only the 3D stream's fourth point gets there */
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  if (three_d) {
    def.geometry = GM_GEOMETRY_3D;
    def.extent[2] = 1.0;
    def.walls[GM_FACE_ZMIN] = def.walls[GM_FACE_ZMAX] = GM_WALL_SLIP;
  }
  def.refuse_unstable_dt = refuse_unstable_dt;
  s.domain = test_create_domain(&def);
  double density = three_d ? DENSITY_3D : DENSITY; /* kg/m^3 */
  /* Soft (c ~ 29 m/s in 2D, 14.5 m/s in 3D) so the fixed 1 ms steps stay
   * below the stable dt (0.125 m / (c + |v|) > 2 ms while |v| < 30 m/s). */
  int material = test_add_elastic(s.domain, 1e4, 0.3, density);
  const double position_2d[6] = {0.5, 5.5, 1.0, 5.5, 1.5, 5.5};
  const double position_3d[12] = {0.5, 5.5, 0.25, 1.0, 5.5, 0.25,
                                  1.5, 5.5, 0.25, 1.0, 5.5, 0.875};
  gm_source_def source = gm_source_def_default();
  source.material = material;
  source.count = s.stream;
  source.position = three_d ? position_3d : position_2d;
  source.point_size = POINT_SIZE;
  source.density = density;
  source.period = PERIOD;
  TEST_ASSERT_OK(s.domain, gm_domain_add_source(s.domain, &source, &s.source));
  gm_sink_def sink = gm_sink_def_default();
  sink.lower[0] = 0.0;
  sink.upper[0] = 2.0;
  sink.lower[1] = 0.0;
  sink.upper[1] = 1.0;        /* the orifice: the bottom metre */
  sink.upper[2] = SINK_DEPTH; /* 3D only */
  TEST_ASSERT_OK(s.domain, gm_domain_add_sink(s.domain, &sink, &s.sink));
  return s;
}

static void check_balance(const scene *s, const char *when) {
  gm_flow_totals in = gm_flow_totals_default(), out = gm_flow_totals_default();
  TEST_ASSERT_OK(s->domain,
                 gm_domain_get_source_totals(s->domain, s->source, &in));
  TEST_ASSERT_OK(s->domain,
                 gm_domain_get_sink_totals(s->domain, s->sink, &out));
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(s->domain, gm_domain_get_summary(s->domain, &summary));
  ck_assert_msg(in.mass - out.mass == summary.mass,
                "%s: injected %.17g - discharged %.17g != domain %.17g kg",
                when, in.mass, out.mass, summary.mass);
  ck_assert_msg(in.points - out.points == gm_domain_point_count(s->domain),
                "%s: point counts do not balance", when);
}

/* Points (3D) that stay beyond the sink's z extent. */
static size_t points_beyond_sink(const scene *s) {
  if (s->dim < 3)
    return 0;
  size_t count = gm_domain_point_count(s->domain), beyond = 0;
  double *position = malloc(3 * count * sizeof *position + 1);
  ck_assert_ptr_nonnull(position);
  TEST_ASSERT_OK(s->domain, gm_domain_get_field(s->domain, GM_FIELD_POSITION,
                                                position, 3 * count));
  for (size_t i = 0; i < count; i++)
    beyond += position[3 * i + 2] >= SINK_DEPTH;
  free(position);
  return beyond;
}

START_TEST(test_mass_balance_exact) {
  scene s = falling_stream(0, _i);
  double time = 0.0;
  bool discharged = false;
  for (int step = 0; step < 4000 && time < 3.0; step++) {
    TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, 1e-3));
    TEST_ASSERT_OK(s.domain, gm_domain_get_time(s.domain, &time, NULL));
    check_balance(&s, "during the run");
    gm_flow_totals out = gm_flow_totals_default();
    TEST_ASSERT_OK(s.domain, gm_domain_get_sink_totals(s.domain, s.sink, &out));
    discharged = discharged || out.points > 0;
  }
  /* Free fall from 5.5 m to 1 m takes ~0.96 s: by 3 s points have been
   * discharged, and injections happened at 0, 0.17, ... <= t. */
  ck_assert_msg(discharged, "no point reached the sink in 3 s");
  gm_flow_totals in = gm_flow_totals_default();
  TEST_ASSERT_OK(s.domain,
                 gm_domain_get_source_totals(s.domain, s.source, &in));
  /* Injections are due at k * PERIOD and happen at the first step that
   * starts at or after that time; the last step started at t - dt. */
  double last_start = time - 1e-3;
  uint64_t injections = (uint64_t)floor(last_start / PERIOD + 1e-9) + 1;
  ck_assert_msg(in.points == s.stream * injections,
                "%llu points injected by t = %g s, expected %llu",
                (unsigned long long)in.points, time,
                (unsigned long long)(s.stream * injections));
  /* 3D: every point injected at z = 0.875 m is still there (none of them
   * crossed z = 0.5 m). */
  ck_assert_msg(s.dim < 3 || points_beyond_sink(&s) == injections,
                "%zu points beyond the sink's z extent, %llu injected there",
                points_beyond_sink(&s), (unsigned long long)injections);
  gm_domain_destroy(s.domain);
}
END_TEST

/* Removed points leave no hole: every remaining id maps to its point, and
 * removed ids are reported unknown. */
START_TEST(test_ids_after_removal) {
  scene s = falling_stream(0, _i);
  for (int step = 0; step < 1600; step++)
    TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, 1e-3));
  gm_flow_totals in = gm_flow_totals_default(), out = gm_flow_totals_default();
  TEST_ASSERT_OK(s.domain,
                 gm_domain_get_source_totals(s.domain, s.source, &in));
  TEST_ASSERT_OK(s.domain, gm_domain_get_sink_totals(s.domain, s.sink, &out));
  ck_assert_msg(out.points > 0, "nothing was discharged");
  size_t count = gm_domain_point_count(s.domain);
  const int64_t *ids = NULL;
  TEST_ASSERT_OK(s.domain, gm_domain_view_ids(s.domain, &ids));
  size_t found = 0;
  for (int64_t id = 0; id < (int64_t)in.points; id++) {
    size_t index = 0;
    gm_status status = gm_domain_point_index(s.domain, id, &index);
    if (status == GM_ERR_UNKNOWN_POINT)
      continue; /* removed */
    ck_assert_int_eq(status, GM_OK);
    ck_assert_msg(index < count && ids[index] == id,
                  "id %lld maps to index %zu holding id %lld", (long long)id,
                  index, (long long)ids[index]);
    found++;
  }
  ck_assert_msg(found == count && in.points - found == out.points,
                "%zu ids found for %zu points; %llu removed", found, count,
                (unsigned long long)out.points);
  gm_domain_destroy(s.domain);
}
END_TEST

/* An injection belongs to its step: a step that fails (here: dt above the
 * stable bound with refuse_unstable_dt) leaves no injected point behind
 * and does not advance the source's clock. */
START_TEST(test_failed_step_undoes_injection) {
  scene s = falling_stream(1, _i);
  double stable = 0.0;
  size_t before = gm_domain_point_count(s.domain); /* 0: nothing yet */
  /* Without points there is no stable dt, so a step of 1 ms injects. */
  TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, 1e-3));
  ck_assert_uint_eq(gm_domain_point_count(s.domain), before + s.stream);
  TEST_ASSERT_OK(s.domain, gm_domain_stable_dt(s.domain, &stable));
  /* Step to just before the next injection, then fail the step that would
   * inject it. */
  double time = 0.0;
  TEST_ASSERT_OK(s.domain, gm_domain_get_time(s.domain, &time, NULL));
  while (time < PERIOD) {
    double dt = fmin(0.5 * stable, PERIOD - time);
    TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, dt));
    TEST_ASSERT_OK(s.domain, gm_domain_get_time(s.domain, &time, NULL));
  }
  size_t count = gm_domain_point_count(s.domain);
  gm_flow_totals in = gm_flow_totals_default();
  TEST_ASSERT_OK(s.domain,
                 gm_domain_get_source_totals(s.domain, s.source, &in));
  ck_assert_int_eq(gm_domain_step(s.domain, 10.0), GM_ERR_UNSTABLE_DT);
  ck_assert_uint_eq(gm_domain_point_count(s.domain), count);
  gm_flow_totals after = gm_flow_totals_default();
  TEST_ASSERT_OK(s.domain,
                 gm_domain_get_source_totals(s.domain, s.source, &after));
  ck_assert(after.points == in.points && after.mass == in.mass);
  /* The next valid step injects the due points. */
  TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, 0.0));
  ck_assert_uint_eq(gm_domain_point_count(s.domain), count + s.stream);
  gm_domain_destroy(s.domain);
}
END_TEST

/* Misuse of the source and sink calls, in plane strain (_i = 0) and 3D
 * (_i = 1): in 3D the z coordinate and the sink's z extent are checked
 * too, and the message names the point with all its coordinates. */
START_TEST(test_source_and_sink_arguments) {
  int three_d = _i == 1;
  gm_domain_def def = gm_domain_def_default();
  if (three_d)
    def.geometry = GM_GEOMETRY_3D;
  gm_domain *domain = test_create_domain(&def);
  int material =
      test_add_elastic(domain, 1e5, 0.3, three_d ? DENSITY_3D : DENSITY);
  /* The box is 1 m a side: outside above it in 2D, behind it in 3D. */
  const double outside_2d[2] = {0.5, 3.0}, outside_3d[3] = {0.5, 0.5, 1.5};
  const double inside[3] = {0.5, 0.5, 0.5};
  gm_source_def source = gm_source_def_default();
  source.material = material;
  source.count = 1;
  source.position = three_d ? outside_3d : outside_2d;
  source.point_size = 0.1;
  int id = -1;
  ck_assert_int_eq(gm_domain_add_source(domain, &source, &id),
                   GM_ERR_OUT_OF_GRID);
  ck_assert_ptr_nonnull(
      strstr(gm_domain_last_error(domain),
             three_d ? "point 0 (0.5, 0.5, 1.5)" : "point 0"));
  source.position = NULL;
  ck_assert_int_eq(gm_domain_add_source(domain, &source, &id), GM_ERR_NULL);
  source.position = inside;
  source.point_size = -1.0;
  ck_assert_int_eq(gm_domain_add_source(domain, &source, &id),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_ptr_nonnull(strstr(gm_domain_last_error(domain), "point_size"));
  source.point_size = 0.1;
  source.material = 7;
  ck_assert_int_eq(gm_domain_add_source(domain, &source, &id),
                   GM_ERR_UNKNOWN_MATERIAL);
  gm_sink_def sink = gm_sink_def_default();
  sink.upper[0] = 1.0; /* upper[1] == lower[1]: empty box */
  ck_assert_int_eq(gm_domain_add_sink(domain, &sink, &id),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_ptr_nonnull(strstr(gm_domain_last_error(domain), "lower[1]"));
  if (three_d) {
    sink.upper[1] = 1.0; /* upper[2] == lower[2]: empty in z */
    ck_assert_int_eq(gm_domain_add_sink(domain, &sink, &id),
                     GM_ERR_INVALID_ARGUMENT);
    ck_assert_ptr_nonnull(strstr(gm_domain_last_error(domain), "lower[2]"));
  }
  gm_flow_totals totals = gm_flow_totals_default();
  ck_assert_int_eq(gm_domain_get_sink_totals(domain, 0, &totals),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_int_eq(gm_domain_point_count(domain), 0);
  sink.upper[1] = sink.upper[2] = 1.0;
  TEST_ASSERT_OK(domain, gm_domain_add_sink(domain, &sink, &id));
  ck_assert_int_eq(id, 0);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("sources");
  TCase *tcase = tcase_create("filling_and_discharge");
  tcase_set_timeout(tcase, 60);
  tcase_add_loop_test(tcase, test_mass_balance_exact, 0, DIMENSIONS);
  tcase_add_loop_test(tcase, test_ids_after_removal, 0, DIMENSIONS);
  tcase_add_loop_test(tcase, test_failed_step_undoes_injection, 0, DIMENSIONS);
  tcase_add_loop_test(tcase, test_source_and_sink_arguments, 0, DIMENSIONS);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
