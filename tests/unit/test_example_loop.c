/*
 * test_example_loop.c - example_run_loop (examples/common.c), the run loop
 * every example driver shares: where its intervals end, how many steps and
 * samples it takes, its frame cadence, its stop condition and what a
 * failure leaves. The drivers' outputs depend on these exactly (a sample
 * time one ulp off changes the step that ends an interval, and every bit
 * after it), so the times are compared exactly wherever the loop promises
 * an exact value: gm_domain_advance lands on its end time exactly, and the
 * split and multiple sample times are the products the loop documents.
 * Where it promises a tolerance (clipped steps stop within 1e-9 s of the
 * sample time), that tolerance is asserted.
 *
 * Scene: an elastic block (gm_elastic_def_default: E = 1 MPa, rho = 1000
 * kg/m^3; a stable dt near 1.4 ms on the 0.1 m cells) falling freely in
 * the middle of a 1 m box, 2 mm in the 20 ms the longest test runs, far
 * from every face.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "test_util.h"

#include "common.h"

#include <check.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

enum { MAX_SAMPLES = 64 };

/* What the callbacks saw. */
typedef struct seen {
  long samples;
  long interval[MAX_SAMPLES];
  double time[MAX_SAMPLES];   /* s */
  double target[MAX_SAMPLES]; /* s */
  long steps;
  double shortest_step; /* s */
  double largest_gap;   /* s, |state->time - (step_start + dt)| */
  long fail_at;         /* prepare fails before this interval; 0: never */
  long stop_at;         /* stop after this interval; 0: never */
} seen;

static gm_domain *falling_block(int refuse_unstable_dt) {
  gm_domain_def def = gm_domain_def_default();
  def.gravity[1] = -9.81;
  def.refuse_unstable_dt = refuse_unstable_dt;
  gm_domain *domain = NULL;
  TEST_ASSERT_OK(NULL, gm_domain_create(&def, &domain));
  gm_elastic_def elastic = gm_elastic_def_default();
  int material = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_elastic(domain, &elastic, &material));
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.lower[0] = fill.lower[1] = 0.4; /* m */
  fill.upper[0] = fill.upper[1] = 0.6;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  return domain;
}

static gm_status sample(const gm_domain *domain, const example_run_state *state,
                        void *user) {
  seen *s = user;
  double time = 0.0;
  gm_domain_get_time(domain, &time, NULL);
  ck_assert_msg(time == state->time, "state time %.17g, domain %.17g",
                state->time, time);
  ck_assert_int_lt(s->samples, MAX_SAMPLES);
  s->interval[s->samples] = state->interval;
  s->time[s->samples] = state->time;
  s->target[s->samples] = state->target;
  s->samples++;
  return GM_OK;
}

static void step(const gm_domain *domain, const example_run_state *state,
                 void *user) {
  (void)domain;
  seen *s = user;
  s->steps++;
  s->shortest_step = fmin(s->shortest_step, state->dt);
  s->largest_gap =
      fmax(s->largest_gap, fabs(state->time - (state->step_start + state->dt)));
}

static gm_status prepare(gm_domain *domain, const example_run_state *state,
                         void *user) {
  (void)domain;
  const seen *s = user;
  return s->fail_at > 0 && state->interval + 1 == s->fail_at
             ? GM_ERR_INVALID_ARGUMENT
             : GM_OK;
}

static int stop(const gm_domain *domain, const example_run_state *state,
                void *user) {
  (void)domain;
  const seen *s = user;
  return s->stop_at > 0 && state->interval >= s->stop_at;
}

static seen fresh(void) {
  seen s;
  memset(&s, 0, sizeof s);
  s.shortest_step = INFINITY;
  return s;
}

static uint64_t step_count(const gm_domain *domain) {
  uint64_t steps = 0;
  gm_domain_get_time(domain, NULL, &steps);
  return steps;
}

/* A series in a new temporary directory (its path in `directory`). */
static gm_series *temporary_series(char directory[28]) {
  strcpy(directory, "/tmp/gm-example-loop-XXXXXX");
  ck_assert_ptr_nonnull(mkdtemp(directory));
  char path[64];
  snprintf(path, sizeof path, "%s/loop.pvd", directory);
  gm_series *series = NULL;
  ck_assert_int_eq(gm_series_create(path, &series), GM_OK);
  return series;
}

/* Reads the frames' times (s) from <directory>/loop.pvd (written with 17
 * digits, so exact), then removes the directory; returns their number. */
static int frame_times(const char *directory, double *times, int capacity) {
  char path[512], line[256];
  snprintf(path, sizeof path, "%s/loop.pvd", directory);
  FILE *pvd = fopen(path, "r");
  ck_assert_ptr_nonnull(pvd);
  int frames = 0;
  while (fgets(line, sizeof line, pvd)) {
    const char *at = strstr(line, "timestep=\"");
    if (!at)
      continue;
    ck_assert_int_lt(frames, capacity);
    times[frames++] = strtod(at + strlen("timestep=\""), NULL);
  }
  fclose(pvd);
  DIR *folder = opendir(directory);
  ck_assert_ptr_nonnull(folder);
  for (struct dirent *entry; (entry = readdir(folder)) != NULL;) {
    if (entry->d_name[0] == '.')
      continue;
    snprintf(path, sizeof path, "%s/%s", directory, entry->d_name);
    remove(path);
  }
  closedir(folder);
  remove(directory);
  return frames;
}

/* EXAMPLE_SAMPLE_SPLIT (column_collapse): the start and 7 rows, each at
 * exactly t_end k / 7 (the last at t_end itself; t_end / 7 k differs in
 * the last bit at k = 5), and frames at rows 2 and 5 (frame_first 2,
 * frame_every 3). t_end = 0.02 s is not a multiple of the stable dt, so
 * the rows end on shortened steps. */
START_TEST(test_split_rows_land_on_their_times) {
  gm_domain *domain = falling_block(0);
  char directory[28];
  gm_series *series = temporary_series(directory);
  seen s = fresh();
  const double t_end = 0.02; /* s */
  const example_run_schedule schedule = {.stepping = EXAMPLE_ADVANCE,
                                         .sample_times = EXAMPLE_SAMPLE_SPLIT,
                                         .t_end = t_end,
                                         .sample_count = 7,
                                         .sample_at_start = 1,
                                         .series = series,
                                         .frame_every = 3,
                                         .frame_first = 2,
                                         .sample = sample,
                                         .step = step,
                                         .user = &s};
  double time = -1.0; /* s */
  TEST_ASSERT_OK(domain, example_run_loop(domain, &schedule, &time));
  gm_series_destroy(series);
  ck_assert_int_eq(s.samples, 8);
  for (long k = 0; k < 8; k++) {
    double expected = k == 7 ? t_end : t_end * (double)k / 7.0; /* s */
    ck_assert_int_eq(s.interval[k], k);
    ck_assert_msg(s.time[k] == expected && s.target[k] == expected,
                  "row %ld at %.17g (target %.17g), expected %.17g", k,
                  s.time[k], s.target[k], expected);
  }
  ck_assert(time == t_end);
  double frames[8]; /* s */
  ck_assert_int_eq(frame_times(directory, frames, 8), 2);
  ck_assert(frames[0] == s.time[2] && frames[1] == s.time[5]);
  ck_assert_uint_eq(step_count(domain), (uint64_t)s.steps);
  gm_domain_destroy(domain);
}
END_TEST

/* EXAMPLE_STEPS with sample times (wieckowski2004): steps clipped to
 * every 3 ms, each sample within the documented 1e-9 s of k 3 ms (the
 * last of t_end = 10 ms), so 4 samples; every step's dt is the one
 * reported (time = step_start + dt to within round-off of a sum, 1e-15
 * s here). */
START_TEST(test_clipped_steps_reach_each_sample) {
  gm_domain *domain = falling_block(0);
  seen s = fresh();
  const double period = 0.003, t_end = 0.01; /* s */
  const example_run_schedule schedule = {.stepping = EXAMPLE_STEPS,
                                         .sample_times =
                                             EXAMPLE_SAMPLE_MULTIPLES,
                                         .t_end = t_end,
                                         .sample_period = period,
                                         .sample = sample,
                                         .step = step,
                                         .user = &s};
  TEST_ASSERT_OK(domain, example_run_loop(domain, &schedule, NULL));
  ck_assert_int_eq(s.samples, 4);
  for (long k = 0; k < 4; k++) {
    double expected = fmin((double)(k + 1) * period, t_end); /* s */
    ck_assert_msg(fabs(s.time[k] - expected) <= 1e-9,
                  "sample %ld at %.17g, expected %.17g", k, s.time[k],
                  expected);
  }
  ck_assert_uint_eq(step_count(domain), (uint64_t)s.steps);
  ck_assert_double_le(s.largest_gap, 1e-15);
  gm_domain_destroy(domain);
}
END_TEST

/* Every step an interval (disconnected_1d, silo settling): a fixed dt and
 * an interval limit take exactly that many steps whatever t_end; the
 * stable dt and a t_end take steps until t_end is reached, the last
 * starting before it. */
START_TEST(test_every_step_an_interval) {
  gm_domain *domain = falling_block(0);
  seen s = fresh();
  example_run_schedule schedule = {.stepping = EXAMPLE_STEPS,
                                   .t_end = INFINITY,
                                   .interval_limit = 25,
                                   .dt = 1e-4,
                                   .sample = sample,
                                   .step = step,
                                   .user = &s};
  TEST_ASSERT_OK(domain, example_run_loop(domain, &schedule, NULL));
  ck_assert_int_eq(s.samples, 25);
  ck_assert_int_eq(s.steps, 25);
  ck_assert_uint_eq(step_count(domain), 25);
  ck_assert(s.shortest_step == 1e-4);
  gm_domain_destroy(domain);

  domain = falling_block(0);
  s = fresh();
  schedule.t_end = 0.01;
  schedule.interval_limit = 0;
  schedule.dt = 0.0;
  double time = 0.0; /* s */
  TEST_ASSERT_OK(domain, example_run_loop(domain, &schedule, &time));
  ck_assert_double_ge(time, 0.01);
  ck_assert_int_ge(s.samples, 2);
  ck_assert_double_lt(s.time[s.samples - 2], 0.01);
  ck_assert_int_eq(s.samples, s.steps);
  gm_domain_destroy(domain);
}
END_TEST

/* The failure path: a prepare callback failing before interval 3 ends the
 * run with its status at the time of interval 2, with no sample of the
 * failed interval (EXAMPLE_FAILURE_STOP) or with one
 * (EXAMPLE_FAILURE_SAMPLE); a step refused (dt = 1 s, which
 * gm_domain_advance shortens to the 10 ms interval, still above the stable
 * dt; refuse_unstable_dt) leaves the domain at t = 0 with no step taken,
 * and the failed interval's sample sees it there. */
START_TEST(test_failure_paths) {
  for (int keep = 0; keep < 2; keep++) {
    gm_domain *domain = falling_block(0);
    seen s = fresh();
    s.fail_at = 3;
    const example_run_schedule schedule = {
        .stepping = EXAMPLE_ADVANCE,
        .sample_times = EXAMPLE_SAMPLE_MULTIPLES,
        .t_end = 0.02,
        .sample_period = 0.002,
        .on_failure = keep ? EXAMPLE_FAILURE_SAMPLE : EXAMPLE_FAILURE_STOP,
        .prepare = prepare,
        .sample = sample,
        .user = &s};
    double time = -1.0; /* s */
    ck_assert_int_eq(example_run_loop(domain, &schedule, &time),
                     GM_ERR_INVALID_ARGUMENT);
    ck_assert(time == 2.0 * 0.002);
    ck_assert_int_eq(s.samples, keep ? 3 : 2);
    gm_domain_destroy(domain);
  }
  gm_domain *domain = falling_block(1);
  double stable = 0.0; /* s */
  TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &stable));
  ck_assert_double_lt(stable, 0.01);
  seen s = fresh();
  const example_run_schedule schedule = {.stepping = EXAMPLE_ADVANCE,
                                         .t_end = 0.02,
                                         .sample_period = 0.01,
                                         .dt = 1.0,
                                         .on_failure = EXAMPLE_FAILURE_SAMPLE,
                                         .sample = sample,
                                         .user = &s};
  double time = -1.0; /* s */
  ck_assert_int_eq(example_run_loop(domain, &schedule, &time),
                   GM_ERR_UNSTABLE_DT);
  ck_assert(time == 0.0);
  ck_assert_uint_eq(step_count(domain), 0);
  ck_assert_int_eq(s.samples, 1);
  gm_domain_destroy(domain);
}
END_TEST

/* The stop condition ends an open-ended run (wieckowski1999's discharge)
 * after the interval it says, at exactly 6 x 1.5 ms (the sum of six 1.5 ms
 * differs from it in the last bit: the sample times are products, not
 * sums), frames by time fall every 3 ms (intervals 2, 4 and 6; none at
 * the start, the driver writes that one), and a schedule that cannot end
 * is refused before any step. */
START_TEST(test_stop_and_refusal) {
  gm_domain *domain = falling_block(0);
  char directory[28];
  gm_series *series = temporary_series(directory);
  seen s = fresh();
  s.stop_at = 6;
  example_run_schedule schedule = {.stepping = EXAMPLE_ADVANCE,
                                   .sample_times = EXAMPLE_SAMPLE_MULTIPLES,
                                   .t_end = INFINITY,
                                   .sample_period = 0.0015,
                                   .sample_at_start = 1,
                                   .series = series,
                                   .frame_period = 0.003,
                                   .sample = sample,
                                   .stop = stop,
                                   .user = &s};
  double time = 0.0; /* s */
  TEST_ASSERT_OK(domain, example_run_loop(domain, &schedule, &time));
  gm_series_destroy(series);
  schedule.series = NULL;
  ck_assert_int_eq(s.samples, 7); /* the start and 6 intervals */
  ck_assert(time == 6.0 * 0.0015);
  double frames[8]; /* s */
  ck_assert_int_eq(frame_times(directory, frames, 8), 3);
  for (int k = 0; k < 3; k++)
    ck_assert(frames[k] == s.time[2 * k + 2]);
  uint64_t steps = step_count(domain);

  schedule.stop = NULL; /* no t_end, no limit, no stop */
  ck_assert_int_eq(example_run_loop(domain, &schedule, &time),
                   GM_ERR_INVALID_ARGUMENT);
  ck_assert_uint_eq(step_count(domain), steps);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *loop_suite(void) {
  Suite *suite = suite_create("example_loop");
  TCase *tcase = tcase_create("loop");
  tcase_add_test(tcase, test_split_rows_land_on_their_times);
  tcase_add_test(tcase, test_clipped_steps_reach_each_sample);
  tcase_add_test(tcase, test_every_step_an_interval);
  tcase_add_test(tcase, test_failure_paths);
  tcase_add_test(tcase, test_stop_and_refusal);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(loop_suite()) == 0 ? 0 : 1;
}
