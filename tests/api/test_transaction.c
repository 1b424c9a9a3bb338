/*
 * test_transaction.c - a failed gm_domain_step() leaves the domain exactly
 * as it was (bitwise: every field, the ids, the time and the step count),
 * the error names the point at fault, and the domain stays usable. Also the
 * retry of recoverable material failures with dt halved, and step hooks.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_restart.h"
#include "test_util.h"

#include <check.h>
#include <ctype.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------- snapshots */

/* Asserts the domain is bitwise identical to the snapshot before
 * (test_restart.h: every field, the ids, the time and step count, the
 * granular counts; memcmp, not ==, so NaNs compare and -0.0 differs from
 * +0.0): "exactly as before". */
static void check_unchanged(const gm_domain *domain,
                            const test_snapshot *before, const char *label) {
  test_snapshot after = test_snapshot_take(domain, NULL, NULL);
  test_snapshot_assert_same(before, &after, label);
  test_snapshot_free(&after);
}

/* Does text mention the integer as a whole token (not inside 17 or 0.7)? */
static bool mentions_integer(const char *text, long long value) {
  char token[32];
  snprintf(token, sizeof token, "%lld", value);
  size_t length = strlen(token);
  for (const char *hit = strstr(text, token); hit;
       hit = strstr(hit + 1, token)) {
    bool before_ok = hit == text || (!isdigit((unsigned char)hit[-1]) &&
                                     hit[-1] != '.' && hit[-1] != '-');
    char next = hit[length];
    bool after_ok = !isdigit((unsigned char)next) && next != 'e' &&
                    !(next == '.' && isdigit((unsigned char)hit[length + 1]));
    if (before_ok && after_ok) {
      return true;
    }
  }
  return false;
}

static void check_message_names_id(const gm_domain *domain, int64_t id,
                                   const char *label) {
  const char *message = gm_domain_last_error(domain);
  ck_assert_msg(message && mentions_integer(message, id),
                "%s: message \"%s\" does not name point id %lld", label,
                message ? message : "(null)", (long long)id);
}

/* ---------------------------------------------- a material that can fail */

enum {
  MATERIAL_OK = 0,
  MATERIAL_FATAL = 1,             /* every call returns -1 */
  MATERIAL_RECOVERABLE_ONCE = 2,  /* first call returns 1, then 0 */
  MATERIAL_RECOVERABLE_ALWAYS = 3 /* every call returns 1 */
};
#define REFUSAL_TEXT "tracked material refuses on purpose"

/* Linear elasticity (the built-in update) plus a switchable failure and a
 * record of the dt each call saw. The transaction tests use one worker, so
 * the calls never overlap and plain fields suffice. */
typedef struct tracked_material {
  gm_elastic_def elastic;
  int mode;
  int calls;
  bool failed;         /* a recoverable failure was returned */
  double failed_dt;    /* s, dt of the call that failed first */
  double min_dt_after; /* s, over calls after that failure */
  double max_dt_after; /* s */
  double min_dt;       /* s, over all calls since reset */
} tracked_material;

static void tracked_reset(tracked_material *tracked, int mode) {
  tracked->mode = mode;
  tracked->calls = 0;
  tracked->failed = false;
  tracked->failed_dt = 0.0;
  tracked->min_dt_after = INFINITY;
  tracked->max_dt_after = -INFINITY;
  tracked->min_dt = INFINITY;
}

static int tracked_update(const gm_material_batch *batch, void *user,
                          char *message, size_t message_size) {
  tracked_material *tracked = user;
  tracked->calls++;
  if (batch->dt < tracked->min_dt) {
    tracked->min_dt = batch->dt;
  }
  if (tracked->failed) {
    tracked->min_dt_after = fmin(tracked->min_dt_after, batch->dt);
    tracked->max_dt_after = fmax(tracked->max_dt_after, batch->dt);
  }
  bool refuse_fatal = tracked->mode == MATERIAL_FATAL;
  bool refuse_recoverable =
      tracked->mode == MATERIAL_RECOVERABLE_ALWAYS ||
      (tracked->mode == MATERIAL_RECOVERABLE_ONCE && !tracked->failed);
  if (refuse_fatal || refuse_recoverable) {
    snprintf(message, message_size, "%s", REFUSAL_TEXT);
    if (refuse_recoverable && !tracked->failed) {
      tracked->failed = true;
      tracked->failed_dt = batch->dt;
    }
    return refuse_fatal ? -1 : 1;
  }
  return gm_elastic_update(batch, &tracked->elastic, message, message_size);
}

/* P-wave modulus M = K + 4G/3 = E (1 - nu) / ((1 + nu)(1 - 2 nu)), Pa. */
static double p_wave_modulus(const gm_elastic_def *elastic) {
  double nu = elastic->poisson_ratio;
  return elastic->youngs_modulus * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

/* ------------------------------------------------------------- the scene */

/* Plane strain box 1 m x 1 m, 0.05 m cells, fixed bottom, gravity: an
 * elastic block 0.3 m x 0.3 m resting on the bottom (so it carries stress
 * after a few steps), and optionally a projectile point far from it. */
typedef struct scene {
  gm_domain *domain;
  tracked_material material_data;
  int material;
  size_t block_count;
  int64_t projectile_id; /* -1 if none */
} scene;

static const double scene_cell = 0.05; /* m */

static void scene_create(scene *s, int refuse_unstable_dt, int max_retries) {
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = scene_cell;
  def.gravity[1] = -9.81; /* m/s^2 */
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  def.refuse_unstable_dt = refuse_unstable_dt;
  def.max_retries = max_retries;
  s->domain = test_create_domain(&def);

  s->material_data.elastic = gm_elastic_def_default(); /* E = 1 MPa */
  tracked_reset(&s->material_data, MATERIAL_OK);
  gm_material_def material = gm_material_def_default();
  material.name = "tracked";
  material.update = tracked_update;
  material.user = &s->material_data;
  material.p_wave_modulus = p_wave_modulus(&s->material_data.elastic);
  material.density = s->material_data.elastic.density;
  TEST_ASSERT_OK(s->domain,
                 gm_domain_add_material(s->domain, &material, &s->material));

  const double lower[3] = {0.2, 0.0, 0.0}, upper[3] = {0.5, 0.3, 0.0};
  int64_t first_id = -1;
  s->block_count =
      test_fill_box(s->domain, s->material, lower, upper, 2, &first_id);
  ck_assert_int_eq(first_id, 0);
  s->projectile_id = -1;
}

/* One point at (x, 0.7125) m moving at vx m/s, alone in its cells (off the
 * grid lines: a point exactly on one has zero-mass nodes in its cell). */
static void scene_add_projectile(scene *s, double x, double vx) {
  const double position[2] = {x, 0.7125};
  const double velocity[2] = {vx, 0.0};
  const double volume = 0.025 * 0.025; /* m^2 per unit thickness */
  gm_points_def points = gm_points_def_default();
  points.count = 1;
  points.material = s->material;
  points.position = position;
  points.velocity = velocity;
  points.volume = &volume;
  TEST_ASSERT_OK(s->domain,
                 gm_domain_add_points(s->domain, &points, &s->projectile_id));
}

static void scene_steps(scene *s, int count, double dt) {
  for (int k = 0; k < count; k++) {
    TEST_ASSERT_OK(s->domain, gm_domain_step(s->domain, dt));
  }
}

/* Writes one velocity component of the point with that id. */
static void set_velocity(gm_domain *domain, int64_t id, size_t component,
                         double value) {
  size_t index = 0;
  double *velocity = NULL;
  TEST_ASSERT_OK(domain, gm_domain_point_index(domain, id, &index));
  TEST_ASSERT_OK(domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY,
                                              component, &velocity));
  velocity[index] = value;
}

static double get_time(const gm_domain *domain) {
  double time = -1.0;
  uint64_t steps = 0;
  TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &time, &steps));
  return time;
}

/* -------------------------------------------------------------- (a) grid */

START_TEST(test_point_leaving_grid) {
  scene s;
  scene_create(&s, 0, 4);
  /* 300 m/s toward the open x-max face with dt = 1e-4 s: 0.03 m per step
   * from x = 0.845 m: inside after 5 steps (0.995 m), out at the 6th. The
   * block's stable dt is ~7e-4 s; refuse_unstable_dt is off, so the
   * projectile's own CFL excess is allowed. */
  scene_add_projectile(&s, 0.845, 300.0);
  const double dt = 1e-4; /* s */
  scene_steps(&s, 5, dt);

  test_snapshot before = test_snapshot_take(s.domain, NULL, NULL);
  gm_status status = gm_domain_step(s.domain, dt);
  ck_assert_msg(status == GM_ERR_OUT_OF_GRID, "step returned %d (%s): %s",
                (int)status, gm_strerror(status),
                gm_domain_last_error(s.domain));
  check_message_names_id(s.domain, s.projectile_id, "out of grid");
  check_unchanged(s.domain, &before, "out of grid");
  test_snapshot_free(&before);

  /* Stopping the projectile makes the next step valid again. */
  set_velocity(s.domain, s.projectile_id, 0, 0.0);
  scene_steps(&s, 2, dt);
  gm_domain_destroy(s.domain);
}
END_TEST

/* ---------------------------------------------------------- (b) callback */

START_TEST(test_fatal_material_failure) {
  scene s;
  scene_create(&s, 0, 4);
  const double dt = 1e-4; /* s */
  scene_steps(&s, 4, dt);

  test_snapshot before = test_snapshot_take(s.domain, NULL, NULL);
  tracked_reset(&s.material_data, MATERIAL_FATAL);
  gm_status status = gm_domain_step(s.domain, dt);
  ck_assert_msg(status == GM_ERR_CALLBACK, "step returned %d (%s)", (int)status,
                gm_strerror(status));
  ck_assert_int_gt(s.material_data.calls, 0);
  /* The material's own message must reach the host. */
  const char *message = gm_domain_last_error(s.domain);
  ck_assert_msg(strstr(message, REFUSAL_TEXT) != NULL,
                "message \"%s\" lacks the material's text", message);
  check_unchanged(s.domain, &before, "fatal material failure");
  test_snapshot_free(&before);

  tracked_reset(&s.material_data, MATERIAL_OK);
  scene_steps(&s, 2, dt);
  gm_domain_destroy(s.domain);
}
END_TEST

/* ------------------------------------------------------------ (c) NaN */

START_TEST(test_nan_velocity_edit) {
  scene s;
  scene_create(&s, 0, 4);
  const double dt = 1e-4; /* s */
  scene_steps(&s, 3, dt);
  const int64_t victim = 37;
  ck_assert_uint_gt(s.block_count, (size_t)victim);

  size_t index = 0;
  TEST_ASSERT_OK(s.domain, gm_domain_point_index(s.domain, victim, &index));
  const double *velocity_x = NULL;
  TEST_ASSERT_OK(s.domain, gm_domain_view_field(s.domain, GM_FIELD_VELOCITY, 0,
                                                &velocity_x));
  double finite_value = velocity_x[index]; /* m/s */
  set_velocity(s.domain, victim, 0, NAN);

  /* The snapshot includes the NaN: the host's write stays. */
  test_snapshot before = test_snapshot_take(s.domain, NULL, NULL);
  gm_status status = gm_domain_step(s.domain, dt);
  ck_assert_msg(status == GM_ERR_NOT_FINITE, "step returned %d (%s)",
                (int)status, gm_strerror(status));
  check_message_names_id(s.domain, victim, "NaN velocity");
  check_unchanged(s.domain, &before, "NaN velocity");
  test_snapshot_free(&before);

  set_velocity(s.domain, victim, 0, finite_value);
  scene_steps(&s, 2, dt);
  gm_domain_destroy(s.domain);
}
END_TEST

/* -------------------------------------------------------- (d) stable dt */

START_TEST(test_unstable_dt_refused) {
  scene s;
  scene_create(&s, 1, 4);
  scene_steps(&s, 3, 0.0); /* dt <= 0: the largest stable dt */
  double stable_dt = 0.0;
  TEST_ASSERT_OK(s.domain, gm_domain_stable_dt(s.domain, &stable_dt));
  ck_assert_double_gt(stable_dt, 0.0);

  test_snapshot before = test_snapshot_take(s.domain, NULL, NULL);
  gm_status status = gm_domain_step(s.domain, 2.0 * stable_dt);
  ck_assert_msg(status == GM_ERR_UNSTABLE_DT, "step returned %d (%s)",
                (int)status, gm_strerror(status));
  const char *message = gm_domain_last_error(s.domain);
  ck_assert_msg(message[0] != '\0', "empty message");
  check_unchanged(s.domain, &before, "unstable dt");
  test_snapshot_free(&before);

  /* The bound itself is not "above the bound". */
  double time_before = get_time(s.domain);
  TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, stable_dt));
  ck_assert_double_eq(get_time(s.domain), time_before + stable_dt);
  gm_domain_destroy(s.domain);
}
END_TEST

/* ------------------------------------------------ (e) recoverable retries */

/* dt = 2^-12 s: well under the stable ~7e-4 s, and a power of two so that
 * t + dt/2 + dt/2 == t + dt exactly in binary. */
static const double dyadic_dt = 1.0 / 4096.0;

START_TEST(test_recoverable_failure_once) {
  scene s;
  scene_create(&s, 0, 4);
  scene_steps(&s, 3, dyadic_dt);
  double time_before = get_time(s.domain);

  tracked_reset(&s.material_data, MATERIAL_RECOVERABLE_ONCE);
  TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, dyadic_dt));
  ck_assert(s.material_data.failed);
  ck_assert_double_eq(s.material_data.failed_dt, dyadic_dt);
  /* The retry ran with dt/2 and needed no further halving. Batches of the
   * failed attempt may still run with the full dt after the refusal (the
   * library may finish the parallel loop before collecting errors), so dt
   * itself is allowed after the failure, but nothing else is. */
  ck_assert_double_eq(s.material_data.min_dt_after, dyadic_dt / 2.0);
  ck_assert_double_le(s.material_data.max_dt_after, dyadic_dt);
  ck_assert_double_eq(s.material_data.min_dt, dyadic_dt / 2.0);
  ck_assert_double_eq(get_time(s.domain), time_before + dyadic_dt);

  tracked_reset(&s.material_data, MATERIAL_OK);
  scene_steps(&s, 2, dyadic_dt);
  gm_domain_destroy(s.domain);
}
END_TEST

/* The same with dt = 1e-4 s, not a power of two: the host asked to advance
 * by dt, so the time must be the very double t + dt that an unretried step
 * gives. Summing two halves, (t + dt/2) + dt/2, rounds differently here
 * (t = 3e-4 s: 4.0000000000000007e-4 instead of 4.0000000000000002e-4),
 * and fixed-interval output times would drift. */
START_TEST(test_recoverable_failure_time_exact) {
  scene s;
  scene_create(&s, 0, 4);
  const double dt = 1e-4; /* s */
  scene_steps(&s, 3, dt);
  double time_before = get_time(s.domain);

  tracked_reset(&s.material_data, MATERIAL_RECOVERABLE_ONCE);
  TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, dt));
  ck_assert(s.material_data.failed);
  double time_after = get_time(s.domain);
  ck_assert_msg(time_after == time_before + dt,
                "time after the retried step %.17g s, expected t + dt = "
                "%.17g s",
                time_after, time_before + dt);
  gm_domain_destroy(s.domain);
}
END_TEST

START_TEST(test_recoverable_failure_always) {
  const int max_retries = 3;
  scene s;
  scene_create(&s, 0, max_retries);
  scene_steps(&s, 3, dyadic_dt);

  test_snapshot before = test_snapshot_take(s.domain, NULL, NULL);
  tracked_reset(&s.material_data, MATERIAL_RECOVERABLE_ALWAYS);
  gm_status status = gm_domain_step(s.domain, dyadic_dt);
  ck_assert_msg(status == GM_ERR_CALLBACK, "step returned %d (%s)", (int)status,
                gm_strerror(status));
  /* max_retries halvings: the smallest dt tried is dt / 2^3, no smaller. */
  ck_assert_double_eq(s.material_data.min_dt, dyadic_dt / 8.0);
  check_unchanged(s.domain, &before, "recoverable failure always");
  test_snapshot_free(&before);

  tracked_reset(&s.material_data, MATERIAL_OK);
  scene_steps(&s, 2, dyadic_dt);
  gm_domain_destroy(s.domain);
}
END_TEST

/* Nested retries: the first half of a halved step commits, then the second
 * half keeps failing through its own halvings. The failed step must still
 * restore the state from before the whole interval (a regression: a nested
 * retry used to overwrite the retry snapshot with the mid-interval state). */
static double nested_full_dt; /* s, the dt of the step under test */

static int fail_after_one_success(const gm_material_batch *batch, void *user,
                                  char *message, size_t message_size) {
  (void)user;
  (void)message;
  (void)message_size;
  for (size_t i = 0; i < batch->count; i++)
    if (batch->state[0][i] >= 1.0 || batch->dt > 0.75 * nested_full_dt)
      return 1; /* recoverable: the full dt, or anything after a success */
  for (size_t i = 0; i < batch->count; i++)
    batch->state[0][i] += 1.0; /* one successful update seen */
  return 0;
}

START_TEST(test_nested_retry_failure_restores) {
  gm_domain_def def = gm_domain_def_default();
  def.max_retries = 3;
  gm_domain *domain = test_create_domain(&def);
  gm_material_def material = gm_material_def_default();
  material.update = fail_after_one_success;
  material.state_count = 1;
  material.p_wave_modulus = 1e6;
  material.density = 1000.0;
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_material(domain, &material, &id));
  gm_fill_def fill = gm_fill_def_default();
  fill.material = id;
  fill.lower[0] = fill.lower[1] = 0.3;
  fill.upper[0] = fill.upper[1] = 0.6;
  fill.velocity[0] = 1.0; /* m/s: a committed half step visibly moves */
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &nested_full_dt));
  test_snapshot before = test_snapshot_take(domain, NULL, NULL);
  gm_status status = gm_domain_step(domain, nested_full_dt);
  ck_assert_msg(status == GM_ERR_CALLBACK, "step returned %d (%s)", (int)status,
                gm_strerror(status));
  check_unchanged(domain, &before, "nested retry failure");
  test_snapshot_free(&before);
  gm_domain_destroy(domain);
}
END_TEST

/* -------------------------------------------------------------- (f) hooks */

/* What a hook does and what it saw. */
typedef struct hook_script {
  int before_result; /* returned at GM_HOOK_BEFORE_STEP */
  int64_t edit_id;   /* -1: no velocity edit */
  double edit_value; /* m/s, written to velocity x of edit_id */
  double force[2];   /* N, external force written when set_force */
  bool set_force;
  bool try_busy_calls;
  gm_status step_status; /* gm_domain_step from inside the hook */
  gm_status add_points_status;
  gm_status add_material_status;
  gm_status get_field_status;
  int before_calls;
  int after_calls;
} hook_script;

static void hook_script_init(hook_script *script) {
  memset(script, 0, sizeof *script);
  script->edit_id = -1;
  script->step_status = script->add_points_status = GM_OK;
}

static void hook_try_busy_calls(gm_domain *domain, hook_script *script) {
  script->step_status = gm_domain_step(domain, 1e-5);
  const double position[2] = {0.5, 0.5};
  const double volume = 1e-4;
  gm_points_def points = gm_points_def_default();
  points.count = 1;
  points.position = position;
  points.volume = &volume;
  int64_t first_id = -1;
  script->add_points_status = gm_domain_add_points(domain, &points, &first_id);
  gm_elastic_def elastic = gm_elastic_def_default();
  int material = -1;
  script->add_material_status =
      gm_domain_add_elastic(domain, &elastic, &material);
  double mass[4096];
  script->get_field_status =
      gm_domain_get_field(domain, GM_FIELD_MASS, mass, 4096);
}

static int scripted_hook(gm_domain *domain, gm_hook_stage stage, void *user) {
  hook_script *script = user;
  if (stage == GM_HOOK_AFTER_STEP) {
    script->after_calls++;
    return 0;
  }
  script->before_calls++;
  if (script->edit_id >= 0) {
    size_t index = 0;
    double *velocity = NULL;
    if (gm_domain_point_index(domain, script->edit_id, &index) == GM_OK &&
        gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity) ==
            GM_OK) {
      velocity[index] = script->edit_value;
    }
  }
  if (script->set_force) {
    for (size_t k = 0; k < 2; k++) {
      double *force = NULL;
      if (gm_domain_edit_field(domain, GM_FIELD_EXTERNAL_FORCE, k, &force) ==
          GM_OK) {
        force[0] = script->force[k]; /* the only point has index 0 */
      }
    }
  }
  if (script->try_busy_calls) {
    hook_try_busy_calls(domain, script);
  }
  return script->before_result;
}

START_TEST(test_hook_cancels_step) {
  scene s;
  scene_create(&s, 0, 4);
  const double dt = 1e-4; /* s */
  scene_steps(&s, 3, dt);
  hook_script script;
  hook_script_init(&script);
  script.before_result = 1;
  TEST_ASSERT_OK(s.domain,
                 gm_domain_set_step_hook(s.domain, scripted_hook, &script));

  test_snapshot before = test_snapshot_take(s.domain, NULL, NULL);
  gm_status status = gm_domain_step(s.domain, dt);
  ck_assert_msg(status == GM_ERR_CALLBACK, "step returned %d (%s)", (int)status,
                gm_strerror(status));
  ck_assert_int_eq(script.before_calls, 1);
  ck_assert_int_eq(script.after_calls, 0);
  check_unchanged(s.domain, &before, "hook cancel");
  test_snapshot_free(&before);

  /* A cancelling hook's own edit stays; nothing else changes. */
  const int64_t edited = 11;
  script.edit_id = edited;
  script.edit_value = 0.25; /* m/s */
  set_velocity(s.domain, edited, 0, script.edit_value);
  before = test_snapshot_take(s.domain, NULL,
                              NULL);       /* expected state: edit applied */
  set_velocity(s.domain, edited, 0, -1.0); /* the hook must overwrite this */
  status = gm_domain_step(s.domain, dt);
  ck_assert_int_eq(status, GM_ERR_CALLBACK);
  check_unchanged(s.domain, &before, "hook edit then cancel");
  test_snapshot_free(&before);

  script.before_result = 0;
  script.edit_id = -1;
  scene_steps(&s, 2, dt);
  ck_assert_int_eq(script.after_calls, 2);
  gm_domain_destroy(s.domain);
}
END_TEST

START_TEST(test_hook_busy_calls) {
  scene s;
  scene_create(&s, 0, 4);
  hook_script script;
  hook_script_init(&script);
  script.try_busy_calls = true;
  TEST_ASSERT_OK(s.domain,
                 gm_domain_set_step_hook(s.domain, scripted_hook, &script));
  size_t count_before = gm_domain_point_count(s.domain);
  TEST_ASSERT_OK(s.domain, gm_domain_step(s.domain, 1e-4));
  ck_assert_int_eq(script.step_status, GM_ERR_BUSY);
  ck_assert_int_eq(script.add_points_status, GM_ERR_BUSY);
  ck_assert_int_eq(script.add_material_status, GM_ERR_BUSY);
  ck_assert_int_eq(script.get_field_status, GM_OK); /* reading is allowed */
  ck_assert_uint_eq(gm_domain_point_count(s.domain), count_before);
  double time = 0.0;
  uint64_t steps = 0;
  TEST_ASSERT_OK(s.domain, gm_domain_get_time(s.domain, &time, &steps));
  ck_assert_uint_eq(steps, 1); /* the nested step did not run */
  gm_domain_destroy(s.domain);
}
END_TEST

/* A single free point (no gravity, no stress, open walls) with an external
 * force F set by the hook: every node it touches gets mass N_i m and force
 * N_i F, so its velocity changes by F / m dt in every scheme. */
START_TEST(test_hook_sets_external_force) {
  const gm_update_scheme scheme = (gm_update_scheme)_i;
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double position[2] = {0.52, 0.47}; /* m */
  const double velocity[2] = {0.2, 0.1};   /* m/s */
  const double volume = 0.05 * 0.05;       /* m^2 per unit thickness */
  gm_points_def points = gm_points_def_default();
  points.count = 1;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = &volume;
  int64_t id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, &id));
  double mass = 0.0; /* kg per unit thickness */
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_MASS, &mass, 1));

  hook_script script;
  hook_script_init(&script);
  script.set_force = true;
  script.force[0] = 3.0;  /* N */
  script.force[1] = -1.5; /* N */
  TEST_ASSERT_OK(domain,
                 gm_domain_set_step_hook(domain, scripted_hook, &script));
  const double dt = 1e-4; /* s */
  double expected[2] = {velocity[0], velocity[1]};
  for (int step = 0; step < 2; step++) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    /* The force persists: the hook is removed after the first step. */
    TEST_ASSERT_OK(domain, gm_domain_set_step_hook(domain, NULL, NULL));
    double got[2];
    TEST_ASSERT_OK(domain,
                   gm_domain_get_field(domain, GM_FIELD_VELOCITY, got, 2));
    for (int k = 0; k < 2; k++) {
      expected[k] += script.force[k] / mass * dt;
      /* A handful of roundings of O(|v|) values: 1e-12 relative. */
      ck_assert_msg(fabs(got[k] - expected[k]) <= 1e-12 * fabs(expected[k]),
                    "%s step %d: v[%d] = %.17g, expected %.17g",
                    test_scheme_name(scheme), step, k, got[k], expected[k]);
    }
  }
  ck_assert_int_eq(script.before_calls, 1);
  ck_assert_int_eq(script.after_calls, 1);
  gm_domain_destroy(domain);
}
END_TEST

/* ------------------------------------------------------------------ main */

static Suite *transaction_suite(void) {
  Suite *suite = suite_create("transaction");
  TCase *failures = tcase_create("failed_steps");
  tcase_set_timeout(failures, 30.0);
  tcase_add_test(failures, test_point_leaving_grid);
  tcase_add_test(failures, test_fatal_material_failure);
  tcase_add_test(failures, test_nan_velocity_edit);
  tcase_add_test(failures, test_unstable_dt_refused);
  tcase_add_test(failures, test_recoverable_failure_once);
  tcase_add_test(failures, test_recoverable_failure_time_exact);
  tcase_add_test(failures, test_recoverable_failure_always);
  tcase_add_test(failures, test_nested_retry_failure_restores);
  suite_add_tcase(suite, failures);

  TCase *hooks = tcase_create("hooks");
  tcase_set_timeout(hooks, 30.0);
  tcase_add_test(hooks, test_hook_cancels_step);
  tcase_add_test(hooks, test_hook_busy_calls);
  tcase_add_loop_test(hooks, test_hook_sets_external_force, GM_SCHEME_USL,
                      GM_SCHEME_USF + 1);
  suite_add_tcase(suite, hooks);
  return suite;
}

int main(void) {
  return test_run_suite(transaction_suite()) == 0 ? 0 : 1;
}
