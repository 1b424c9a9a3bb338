/*
 * test_restart.h - the "a restart is bitwise" check shared by the Check
 * programs (gm_domain_save / gm_domain_load), and the snapshot of a
 * domain's observable state it compares. Uses only the public API; a test
 * adds white-box values through its own callback.
 *
 * test_restart_check(run) does, in this order:
 *  1. run A: run->build(workers_before) makes the scene; it takes
 *     steps_before steps; run->before_save (if any) may assert on it or
 *     edit it (host edits pending at the save must travel with the file);
 *     it is saved to the checkpoint file and snapshot "at the save"; it
 *     takes steps_after steps and is snapshot "at the end".
 *  2. run B: run->build(workers_after) makes the same scene afresh; it
 *     takes stale_steps steps of its own (so every cache it keeps between
 *     steps is stale when the file arrives); it loads the file, and its
 *     snapshot must equal A's at the save; it takes steps_after steps, and
 *     its snapshot must equal A's at the end.
 *  3. run->check (if any) sees A's two snapshots (what the scene really
 *     exercised); then every snapshot is freed, both domains destroyed and
 *     the file removed (unless the caller named it: then it is the
 *     caller's, left in place, e.g. to load it into another domain).
 * A step is gm_domain_step(domain, run->dt) (dt <= 0: the stable dt), or
 * run->step(domain, phase, steps) where the phases differ.
 *
 * A snapshot holds the point count, the time and step count, the ids, every
 * gm_field with gm_domain_field_components' components (whatever the
 * geometry and shape: the superset the public API shows), the granular
 * summary's counts, and the test's extra values (run->extra: a malloc'd
 * array, NULL for none). Two snapshots are the same when every value is
 * the same bit for bit (memcmp: -0.0 differs from 0.0, NaN payloads
 * count); there is no tolerance, a restart is exact.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_TEST_RESTART_H
#define GM_TEST_RESTART_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "test_util.h"

/* Every gm_field (GM_FIELD_AFFINE is the last). */
#define TEST_FIELD_COUNT (GM_FIELD_AFFINE + 1)

/* TEST_ASSERT_OK for hot paths: Check reports every ck_assert to its
 * parent process (a pipe write per call), so assert only on failure. */
#define TEST_REQUIRE_OK(domain, call)                                          \
  do {                                                                         \
    gm_status test_require_status_ = (call);                                   \
    REQUIRE(test_require_status_ == GM_OK, "%s failed: %s (%s)", #call,        \
            gm_strerror(test_require_status_), gm_domain_last_error(domain));  \
  } while (0)

/* The test's own values of a domain (white box, totals): a malloc'd array
 * of *length values, or NULL. */
typedef double *test_snapshot_extra_fn(const gm_domain *domain, size_t *length,
                                       void *context);

typedef struct test_snapshot {
  size_t count; /* points */
  double time;  /* s */
  uint64_t step_count;
  int64_t *ids;
  double *field[TEST_FIELD_COUNT]; /* point-index order */
  size_t length[TEST_FIELD_COUNT]; /* values in field[f] */
  gm_granular_summary granular;    /* counts compared, timings not */
  double *extra;                   /* the test's own values, or NULL */
  size_t extra_length;
} test_snapshot;

/* Everything the public API shows of `domain`, and extra's values. */
static inline test_snapshot test_snapshot_take(const gm_domain *domain,
                                               test_snapshot_extra_fn *extra,
                                               void *context) {
  test_snapshot s;
  memset(&s, 0, sizeof s);
  s.count = gm_domain_point_count(domain);
  TEST_REQUIRE_OK(domain, gm_domain_get_time(domain, &s.time, &s.step_count));
  s.ids = calloc(s.count + 1, sizeof *s.ids);
  REQUIRE(s.ids != NULL, "out of memory");
  TEST_REQUIRE_OK(domain, gm_domain_get_ids(domain, s.ids, s.count));
  for (int f = 0; f < TEST_FIELD_COUNT; f++) {
    size_t components = 0;
    TEST_REQUIRE_OK(
        domain, gm_domain_field_components(domain, (gm_field)f, &components));
    s.length[f] = components * s.count;
    s.field[f] = calloc(s.length[f] + 1, sizeof(double));
    REQUIRE(s.field[f] != NULL, "out of memory");
    TEST_REQUIRE_OK(domain, gm_domain_get_field(domain, (gm_field)f, s.field[f],
                                                s.length[f]));
  }
  s.granular = gm_granular_summary_default();
  TEST_REQUIRE_OK(domain, gm_domain_get_granular_summary(domain, &s.granular));
  if (extra)
    s.extra = extra(domain, &s.extra_length, context);
  return s;
}

static inline void test_snapshot_free(test_snapshot *s) {
  free(s->ids);
  for (int f = 0; f < TEST_FIELD_COUNT; f++)
    free(s->field[f]);
  free(s->extra);
  memset(s, 0, sizeof *s);
}

/* Index of the first value where a and b differ bitwise, or count. */
static inline size_t test_first_difference(const double *a, const double *b,
                                           size_t count) {
  for (size_t i = 0; i < count; i++)
    if (memcmp(&a[i], &b[i], sizeof(double)) != 0)
      return i;
  return count;
}

/* Fails the test, naming `what` and the first difference, unless a and b
 * are the same bit for bit. */
static inline void test_snapshot_assert_same(const test_snapshot *a,
                                             const test_snapshot *b,
                                             const char *what) {
  REQUIRE(a->count == b->count, "%s: %zu points vs %zu", what, a->count,
          b->count);
  REQUIRE(a->step_count == b->step_count, "%s: step count %llu vs %llu", what,
          (unsigned long long)a->step_count, (unsigned long long)b->step_count);
  REQUIRE(memcmp(&a->time, &b->time, sizeof a->time) == 0,
          "%s: time %.17g vs %.17g s", what, a->time, b->time);
  REQUIRE(memcmp(a->ids, b->ids, a->count * sizeof *a->ids) == 0,
          "%s: ids differ", what);
  for (int f = 0; f < TEST_FIELD_COUNT; f++) {
    REQUIRE(a->length[f] == b->length[f], "%s: field %d has %zu vs %zu values",
            what, f, a->length[f], b->length[f]);
    size_t i = test_first_difference(a->field[f], b->field[f], a->length[f]);
    REQUIRE(i == a->length[f], "%s: field %d value %zu: %.17g vs %.17g", what,
            f, i, a->field[f][i], b->field[f][i]);
  }
  const gm_granular_summary *x = &a->granular, *y = &b->granular;
  REQUIRE(x->component_count == y->component_count &&
              x->layer_count == y->layer_count &&
              memcmp(x->state_count, y->state_count, sizeof x->state_count) ==
                  0,
          "%s: granular summary differs", what);
  REQUIRE(a->extra_length == b->extra_length, "%s: %zu vs %zu extra values",
          what, a->extra_length, b->extra_length);
  size_t k = test_first_difference(a->extra, b->extra, a->extra_length);
  REQUIRE(k == a->extra_length, "%s: extra value %zu: %.17g vs %.17g", what, k,
          a->extra[k], b->extra[k]);
}

/* The stretches of steps a restart check takes. */
typedef enum test_restart_phase {
  TEST_RESTART_BEFORE_SAVE, /* run A, up to the save */
  TEST_RESTART_AFTER_SAVE,  /* run A, from the save on */
  TEST_RESTART_STALE,       /* run B, on its own before the load */
  TEST_RESTART_AFTER_LOAD   /* run B, from the load on */
} test_restart_phase;

typedef struct test_restart_run {
  const char *what; /* the scene, for failure messages */
  /* A fresh domain of the scene on `workers` workers, the same setup on
   * every call. */
  gm_domain *(*build)(int workers, void *context);
  void *context; /* handed to every callback */
  int workers_before, workers_after;
  int steps_before; /* run A, before the save */
  int steps_after;  /* both runs, after the save or load */
  int stale_steps;  /* run B, before the load */
  double dt;        /* s, each step's; <= 0: the stable dt */
  /* Optional. Takes `steps` steps of `phase` in place of dt's. */
  void (*step)(gm_domain *domain, test_restart_phase phase, int steps,
               void *context);
  /* Optional. Run A right before the save: assert, or edit. */
  void (*before_save)(gm_domain *domain, void *context);
  /* Optional. The test's own values of each snapshot. */
  test_snapshot_extra_fn *extra;
  /* Optional. Run A's snapshots at the save and at the end. */
  void (*check)(const test_snapshot *at_save, const test_snapshot *at_end,
                void *context);
  /* Optional. The checkpoint file (the caller removes it); NULL: a file
   * in /tmp that the check removes. */
  const char *path;
} test_restart_run;

static inline void test_restart_steps(const test_restart_run *run,
                                      gm_domain *domain,
                                      test_restart_phase phase, int steps) {
  if (run->step) {
    run->step(domain, phase, steps, run->context);
    return;
  }
  for (int k = 0; k < steps; k++)
    TEST_REQUIRE_OK(domain, gm_domain_step(domain, run->dt));
}

/* The check described at the top of this file. */
static inline void test_restart_check(const test_restart_run *run) {
  static int files = 0; /* this process's; Check forks each test */
  char own_path[96];
  snprintf(own_path, sizeof own_path, "/tmp/gm_restart_%ld_%d.ckpt",
           (long)getpid(), files++);
  const char *path = run->path ? run->path : own_path;
  const char *what = run->what ? run->what : "restart";
  char message[160];

  gm_domain *a = run->build(run->workers_before, run->context);
  test_restart_steps(run, a, TEST_RESTART_BEFORE_SAVE, run->steps_before);
  if (run->before_save)
    run->before_save(a, run->context);
  TEST_ASSERT_OK(a, gm_domain_save(a, path));
  test_snapshot at_save = test_snapshot_take(a, run->extra, run->context);
  test_restart_steps(run, a, TEST_RESTART_AFTER_SAVE, run->steps_after);
  test_snapshot end_a = test_snapshot_take(a, run->extra, run->context);

  gm_domain *b = run->build(run->workers_after, run->context);
  test_restart_steps(run, b, TEST_RESTART_STALE, run->stale_steps);
  TEST_ASSERT_OK(b, gm_domain_load(b, path));
  test_snapshot loaded = test_snapshot_take(b, run->extra, run->context);
  snprintf(message, sizeof message, "%s: right after the load", what);
  test_snapshot_assert_same(&at_save, &loaded, message);
  test_restart_steps(run, b, TEST_RESTART_AFTER_LOAD, run->steps_after);
  test_snapshot end_b = test_snapshot_take(b, run->extra, run->context);
  snprintf(message, sizeof message, "%s: after the restarted steps", what);
  test_snapshot_assert_same(&end_a, &end_b, message);

  if (run->check)
    run->check(&at_save, &end_a, run->context);
  test_snapshot_free(&at_save);
  test_snapshot_free(&end_a);
  test_snapshot_free(&loaded);
  test_snapshot_free(&end_b);
  gm_domain_destroy(a);
  gm_domain_destroy(b);
  if (!run->path)
    remove(path);
}

#endif /* GM_TEST_RESTART_H */
