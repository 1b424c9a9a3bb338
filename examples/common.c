/*
 * common.c - shared parts of the example drivers (see common.h).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L /* mkdir */

#include "common.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const shape_names[] = {"linear", "ugimp",    "cpgimp",
                                          "cpdi",   "bspline2", "bspline3"};
#define SHAPE_COUNT (int)(sizeof shape_names / sizeof shape_names[0])
static const char *const family_names[] = {"plain", "stress_free", "granular"};

const char *example_shape_name(gm_shape shape) {
  return (unsigned)shape < (unsigned)SHAPE_COUNT ? shape_names[shape]
                                                 : "unknown";
}

const char *example_family_name(gm_family family) {
  return (unsigned)family < 3 ? family_names[family] : "unknown";
}

static int find_word(const char *word, const char *const *names, int count) {
  for (int k = 0; k < count; k++)
    if (strcmp(word, names[k]) == 0)
      return k;
  return -1;
}

static void print_help(const char *program, const char *description,
                       const example_options *defaults,
                       const example_extra *extras, int extra_count) {
  printf("usage: %s [options]\n%s\n\noptions:\n", program, description);
  printf("  --method linear|ugimp|cpgimp|cpdi|bspline2|bspline3  shape "
         "functions (default %s)\n",
         example_shape_name(defaults->shape));
  printf("  --family plain|stress_free|granular  algorithm family (default "
         "%s)\n",
         example_family_name(defaults->family));
  printf("  --ppc N        points per cell per direction (default %d)\n",
         defaults->ppc);
  printf("  --cell H       cell size, m (default %g)\n", defaults->cell);
  printf("  --workers N    worker threads (default %d)\n", defaults->workers);
  printf("  --out DIR      output directory, '' for none (default %s)\n",
         defaults->out[0] ? defaults->out : "''");
  printf("  --t-end T      simulated time, s (default %g)\n", defaults->t_end);
  printf("  --quiet        no progress display\n");
  for (int k = 0; k < extra_count; k++) {
    if (extras[k].number)
      printf("  --%-13s %s (default %g)\n", extras[k].name, extras[k].help,
             *extras[k].number);
    else
      printf("  --%-13s %s (default %s)\n", extras[k].name, extras[k].help,
             *extras[k].word);
  }
  printf("  --help         this text\n");
}

/* Reads a number for --name; 0 on success. */
static int read_number(const char *name, const char *text, double *value) {
  char *end = NULL;
  errno = 0;
  double parsed = strtod(text, &end);
  if (errno != 0 || end == text || *end != '\0' || !isfinite(parsed)) {
    fprintf(stderr, "--%s: '%s' is not a number\n", name, text);
    return 1;
  }
  *value = parsed;
  return 0;
}

/* One standard option; returns 0 if handled, 1 if unknown, 2 on error. */
static int parse_standard(const char *name, const char *value,
                          example_options *options) {
  double number = 0.0;
  if (strcmp(name, "method") == 0) {
    int k = find_word(value, shape_names, SHAPE_COUNT);
    if (k < 0) {
      fprintf(stderr,
              "--method: '%s' is not linear, ugimp, cpgimp, cpdi, bspline2 "
              "or bspline3\n",
              value);
      return 2;
    }
    options->shape = (gm_shape)k;
  } else if (strcmp(name, "family") == 0) {
    int k = find_word(value, family_names, 3);
    if (k < 0) {
      fprintf(stderr, "--family: '%s' is not plain, stress_free or granular\n",
              value);
      return 2;
    }
    options->family = (gm_family)k;
  } else if (strcmp(name, "out") == 0) {
    options->out = value;
  } else if (strcmp(name, "ppc") == 0 || strcmp(name, "workers") == 0) {
    if (read_number(name, value, &number) != 0 || number < 1 || number > 256 ||
        number != floor(number)) {
      fprintf(stderr, "--%s: '%s' must be an integer in 1..256\n", name, value);
      return 2;
    }
    *(strcmp(name, "ppc") == 0 ? &options->ppc : &options->workers) =
        (int)number;
  } else if (strcmp(name, "cell") == 0 || strcmp(name, "t-end") == 0) {
    if (read_number(name, value, &number) != 0 || !(number > 0.0)) {
      fprintf(stderr, "--%s: '%s' must be a number > 0\n", name, value);
      return 2;
    }
    *(strcmp(name, "cell") == 0 ? &options->cell : &options->t_end) = number;
  } else {
    return 1;
  }
  return 0;
}

int example_parse(int argc, char **argv, const char *description,
                  example_options *options, const example_extra *extras,
                  int extra_count) {
  example_options defaults = *options;
  for (int i = 1; i < argc; i++) {
    const char *argument = argv[i];
    if (strcmp(argument, "--help") == 0 || strcmp(argument, "-h") == 0) {
      print_help(argv[0], description, &defaults, extras, extra_count);
      return 1;
    }
    if (strcmp(argument, "--quiet") == 0) {
      options->quiet = 1;
      continue;
    }
    if (strncmp(argument, "--", 2) != 0 || i + 1 >= argc) {
      fprintf(stderr, "%s: unexpected '%s' (see --help)\n", argv[0], argument);
      return 2;
    }
    const char *name = argument + 2, *value = argv[++i];
    int handled = parse_standard(name, value, options);
    if (handled == 2)
      return 2;
    if (handled == 0)
      continue;
    int k = 0;
    while (k < extra_count && strcmp(extras[k].name, name) != 0)
      k++;
    if (k == extra_count) {
      fprintf(stderr, "%s: unknown option --%s (see --help)\n", argv[0], name);
      return 2;
    }
    if (extras[k].number) {
      if (read_number(name, value, extras[k].number) != 0)
        return 2;
    } else {
      *extras[k].word = value;
    }
  }
  return 0;
}

gm_domain_def example_domain_def(const example_options *options) {
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = options->cell;
  def.shape = options->shape;
  def.family = options->family;
  def.worker_count = options->workers;
  return def;
}

gm_domain *example_create_domain(const gm_domain_def *def) {
  gm_domain *domain = NULL;
  gm_status status = gm_domain_create(def, &domain);
  if (status != GM_OK)
    example_fail(NULL, "gm_domain_create", status);
  return domain;
}

int example_set_volumetric(gm_domain *domain, const char *word) {
  gm_volumetric volumetric = GM_VOLUMETRIC_POINT;
  if (strcmp(word, "cell") == 0)
    volumetric = GM_VOLUMETRIC_CELL_MEAN;
  else if (strcmp(word, "point") != 0) {
    fprintf(stderr, "--volumetric: '%s' is not point or cell\n", word);
    return 2;
  }
  if (gm_domain_set_volumetric(domain, volumetric) != GM_OK) {
    fprintf(stderr, "%s\n", gm_domain_last_error(domain));
    return 2;
  }
  return 0;
}

gm_update_scheme example_scheme(const char *word) {
  if (strcmp(word, "usl") == 0)
    return GM_SCHEME_USL;
  return strcmp(word, "usf") == 0 ? GM_SCHEME_USF : GM_SCHEME_MUSL;
}

int example_make_output(const example_options *options) {
  if (!options->out[0])
    return 0;
  char path[1024];
  if (snprintf(path, sizeof path, "%s", options->out) >= (int)sizeof path) {
    fprintf(stderr, "--out: path too long\n");
    return 1;
  }
  for (char *slash = path + 1;; slash++) { /* mkdir -p */
    char saved = *slash;
    if (saved != '/' && saved != '\0')
      continue;
    *slash = '\0';
    if (mkdir(path, 0777) != 0 && errno != EEXIST) {
      fprintf(stderr, "cannot create directory %s: %s\n", path,
              strerror(errno));
      return 1;
    }
    *slash = saved;
    if (saved == '\0')
      return 0;
  }
}

FILE *example_open_csv(const example_options *options, const char *file,
                       const char *header) {
  if (!options->out[0])
    return NULL;
  char path[1200];
  snprintf(path, sizeof path, "%s/%s", options->out, file);
  FILE *csv = fopen(path, "w");
  if (!csv) {
    fprintf(stderr, "cannot write %s: %s\n", path, strerror(errno));
    return NULL;
  }
  fprintf(csv, "%s\n", header);
  return csv;
}

gm_status example_open_series(const example_options *options, const char *name,
                              const gm_domain *domain, gm_series **series) {
  *series = NULL;
  if (!options->out[0])
    return GM_OK;
  char path[1200];
  snprintf(path, sizeof path, "%s/%s.pvd", options->out, name);
  gm_status status = gm_series_create(path, series);
  if (status == GM_OK && options->shape != GM_SHAPE_LINEAR)
    status = gm_series_set_domains(*series, 1);
  if (status == GM_OK)
    status = gm_series_write(*series, domain);
  if (status != GM_OK) {
    gm_series_destroy(*series);
    *series = NULL;
  }
  return status;
}

void example_write_states(FILE *csv, const gm_domain *domain) {
  gm_granular_summary granular = gm_granular_summary_default();
  if (gm_domain_get_granular_summary(domain, &granular) != GM_OK)
    granular.state_count[GM_STATE_QUASI_STATIC] = gm_domain_point_count(domain);
  fprintf(csv, ",%zu,%zu,%zu,%zu", granular.state_count[GM_STATE_QUASI_STATIC],
          granular.state_count[GM_STATE_MODERATE],
          granular.state_count[GM_STATE_DISCONNECTED],
          granular.component_count);
}

/* One SCENE line per material id below MAX_MATERIALS that has points. */
void example_print_scene(const gm_domain *domain) {
  enum { MAX_MATERIALS = 16 };
  size_t count = gm_domain_point_count(domain), dim = 0;
  if (gm_domain_field_components(domain, GM_FIELD_POSITION, &dim) != GM_OK ||
      dim < 1 || dim > 3)
    return;
  double *fields = malloc((count ? count : 1) * (2 + 2 * dim) * sizeof *fields);
  double *material = fields, *mass = fields + count; /* id, kg */
  double *position = fields + 2 * count, *size = position + dim * count; /* m */
  if (!fields ||
      gm_domain_get_field(domain, GM_FIELD_MATERIAL, material, count) !=
          GM_OK ||
      gm_domain_get_field(domain, GM_FIELD_MASS, mass, count) != GM_OK ||
      gm_domain_get_field(domain, GM_FIELD_POSITION, position, dim * count) !=
          GM_OK ||
      gm_domain_get_field(domain, GM_FIELD_DOMAIN_SIZE, size, dim * count) !=
          GM_OK) {
    free(fields);
    return;
  }
  for (int m = 0; m < MAX_MATERIALS; m++) {
    size_t points = 0;
    double total = 0.0, low[3], high[3]; /* kg, m */
    for (size_t p = 0; p < count; p++) {
      if ((int)material[p] != m)
        continue;
      for (size_t k = 0; k < dim; k++) {
        double lo = position[dim * p + k] - 0.5 * size[dim * p + k];
        double hi = position[dim * p + k] + 0.5 * size[dim * p + k];
        low[k] = points ? fmin(low[k], lo) : lo;
        high[k] = points ? fmax(high[k], hi) : hi;
      }
      total += mass[p];
      points++;
    }
    if (!points)
      continue;
    printf("SCENE material=%d points=%zu mass=%.9g", m, points, total);
    for (size_t k = 0; k < dim; k++)
      printf(" %c=%.9g..%.9g", "xyz"[k], low[k], high[k]);
    printf("\n");
  }
  free(fields);
}

int example_progress(const gm_domain *domain, double time, double end_time,
                     void *user) {
  (void)domain;
  const example_options *options = user;
  static double next_report = 0.0; /* fraction of the run */
  double fraction = end_time > 0.0 ? time / end_time : 1.0;
  if (options && options->quiet)
    return 0;
  if (fraction < next_report && fraction < 1.0)
    return 0;
  next_report = fraction + 0.02;
  fprintf(stderr, "\r  t = %8.4f s of %g s  [%3.0f %%]", time, end_time,
          100.0 * fraction);
  if (fraction >= 1.0) {
    fprintf(stderr, "\n");
    next_report = 0.0;
  }
  return 0;
}

void example_result(const char *name, double value, double reference) {
  double error = reference != 0.0 ? fabs(value - reference) / fabs(reference)
                                  : fabs(value);
  printf("RESULT %s=%.6g reference=%.6g rel_error=%.4g\n", name, value,
         reference, error);
}

int example_fail(const gm_domain *domain, const char *call, gm_status status) {
  fprintf(stderr, "%s failed: %s\n  %s\n", call, gm_strerror(status),
          domain ? gm_domain_last_error(domain) : gm_last_create_error());
  return 2;
}

/* What the step callbacks need while gm_domain_advance runs. */
typedef struct run_context {
  const example_run_schedule *schedule;
  example_run_state *state;
  int display_done; /* the 100 % line has been shown */
} run_context;

/* After every committed step: the state, the step callback, the display
 * (against t_end, or the options' t_end for an open-ended run; after that
 * end only the 100 % line, once). */
static void after_step(const gm_domain *domain, run_context *context) {
  const example_run_schedule *schedule = context->schedule;
  example_run_state *state = context->state;
  if (schedule->step)
    schedule->step(domain, state, schedule->user);
  if (!schedule->progress)
    return;
  double end = isfinite(schedule->t_end) ? schedule->t_end
                                         : schedule->progress->t_end; /* s */
  if (state->time < end)
    example_progress(domain, state->time, end, (void *)schedule->progress);
  else if (!context->display_done)
    example_progress(domain, end, end, (void *)schedule->progress);
  context->display_done = state->time >= end;
}

/* gm_progress_fn for gm_domain_advance. */
static int advanced_step(const gm_domain *domain, double time, double end_time,
                         void *user) {
  (void)end_time;
  run_context *context = user;
  example_run_state *state = context->state;
  state->step_start = state->time;
  state->time = time;
  state->dt = time - state->step_start;
  after_step(domain, context);
  return 0;
}

/* Whether every step is an interval (EXAMPLE_STEPS, no sample times). */
static int every_step(const example_run_schedule *schedule) {
  return schedule->stepping == EXAMPLE_STEPS &&
         schedule->sample_times != EXAMPLE_SAMPLE_SPLIT &&
         schedule->sample_period == 0.0;
}

/* EXAMPLE_STEPS: one step, or steps clipped to the sample time until
 * within 1e-9 s of it. */
static gm_status take_steps(gm_domain *domain, run_context *context) {
  const example_run_schedule *schedule = context->schedule;
  example_run_state *state = context->state;
  int clipped = !every_step(schedule);
  gm_status status = GM_OK;
  do {
    if (clipped && !(state->target - state->time > 1e-9))
      break;
    double dt = schedule->dt; /* s */
    if (!(dt > 0.0) && gm_domain_point_count(domain) > 0)
      status = gm_domain_stable_dt(domain, &dt);
    if (!(dt > 0.0) && gm_domain_point_count(domain) == 0)
      dt = schedule->empty_dt;
    if (clipped)
      dt = fmin(dt, state->target - state->time);
    if (status == GM_OK)
      status = gm_domain_step(domain, dt);
    if (status != GM_OK)
      return status;
    state->step_start = state->time;
    gm_domain_get_time(domain, &state->time, NULL);
    state->dt = dt;
    after_step(domain, context);
  } while (clipped);
  return GM_OK;
}

/* The end of interval `k` (s). */
static double sample_time(const example_run_schedule *schedule,
                          const example_run_state *state, long k) {
  switch (schedule->sample_times) {
  case EXAMPLE_SAMPLE_MULTIPLES:
    return fmin((double)k * schedule->sample_period, schedule->t_end);
  case EXAMPLE_SAMPLE_SPLIT: /* the last exactly t_end, whatever round-off */
    return k >= schedule->sample_count
               ? schedule->t_end
               : schedule->t_end * (double)k / (double)schedule->sample_count;
  default:
    return fmin(state->time + schedule->sample_period, schedule->t_end);
  }
}

/* Whether the time is short of t_end, by the stepping's tolerance (see
 * example_stepping). */
static int before_end(const example_run_schedule *schedule, double time) {
  if (schedule->stepping == EXAMPLE_ADVANCE)
    return time < schedule->t_end - 1e-12;
  if (every_step(schedule))
    return time < schedule->t_end;
  return schedule->t_end - time > 1e-9;
}

static int schedule_is_valid(const example_run_schedule *s) {
  const char *problem = NULL;
  if (!(s->t_end > 0.0))
    problem = "t_end must be > 0";
  else if (s->sample_times != EXAMPLE_SAMPLE_SPLIT &&
           (!(s->sample_period >= 0.0) || !isfinite(s->sample_period) ||
            (s->sample_period == 0.0 && s->stepping == EXAMPLE_ADVANCE)))
    problem = "sample_period must be finite, and > 0 unless EXAMPLE_STEPS "
              "samples every step";
  else if (s->sample_times == EXAMPLE_SAMPLE_SPLIT &&
           (s->sample_count < 1 || !isfinite(s->t_end)))
    problem = "EXAMPLE_SAMPLE_SPLIT needs sample_count >= 1 and a finite "
              "t_end";
  else if (!isfinite(s->t_end) && s->interval_limit <= 0 && !s->stop)
    problem = "an open-ended run (t_end INFINITY) needs interval_limit or "
              "stop";
  else if (s->progress && !isfinite(s->t_end) && !(s->progress->t_end > 0.0))
    problem = "the progress display of an open-ended run needs "
              "options->t_end > 0";
  if (problem)
    fprintf(stderr, "example_run_loop: %s\n", problem);
  return problem == NULL;
}

/* The sample and frame after interval state->interval (0: the start). */
static gm_status record(const gm_domain *domain,
                        const example_run_schedule *schedule,
                        const example_run_state *state, int failed,
                        double *next_frame) {
  gm_status status = GM_OK;
  if (failed && schedule->on_failure == EXAMPLE_FAILURE_STOP)
    return GM_OK;
  if (schedule->sample)
    status = schedule->sample(domain, state, schedule->user);
  if (!schedule->series)
    return status;
  int due = 0;
  long k = state->interval;
  if (schedule->frame_every > 0)
    due = k >= schedule->frame_first &&
          (k - schedule->frame_first) % schedule->frame_every == 0;
  else
    due = schedule->frame_period > 0.0 && k > 0 &&
          state->time >= *next_frame - 1e-9;
  if (failed && schedule->on_failure == EXAMPLE_FAILURE_SAMPLE_FRAME)
    due = 1;
  if (!due)
    return status;
  if (schedule->frame_every <= 0)
    *next_frame += schedule->frame_period;
  return status == GM_OK ? gm_series_write(schedule->series, domain) : status;
}

gm_status example_run_loop(gm_domain *domain,
                           const example_run_schedule *schedule, double *time) {
  example_run_state state = {0, 0.0, 0.0, 0.0, 0.0};
  run_context context = {schedule, &state, 0};
  gm_domain_get_time(domain, &state.time, NULL);
  state.target = state.time;
  if (time)
    *time = state.time;
  if (!schedule_is_valid(schedule))
    return GM_ERR_INVALID_ARGUMENT;
  double next_frame = state.time + schedule->frame_period; /* s */
  long limit = schedule->interval_limit;
  if (schedule->sample_times == EXAMPLE_SAMPLE_SPLIT &&
      (limit <= 0 || limit > schedule->sample_count))
    limit = schedule->sample_count;
  gm_status status = GM_OK;
  int stopped = 0;
  if (schedule->sample_at_start) {
    status = record(domain, schedule, &state, 0, &next_frame);
    stopped = schedule->stop && schedule->stop(domain, &state, schedule->user);
  }
  while (status == GM_OK && !stopped && before_end(schedule, state.time) &&
         (limit <= 0 || state.interval < limit)) {
    long k = state.interval + 1;
    state.target =
        every_step(schedule) ? state.time : sample_time(schedule, &state, k);
    if (schedule->prepare)
      status = schedule->prepare(domain, &state, schedule->user);
    if (status == GM_OK && schedule->stepping == EXAMPLE_ADVANCE)
      status = gm_domain_advance(domain, state.target, schedule->dt,
                                 advanced_step, &context);
    else if (status == GM_OK)
      status = take_steps(domain, &context);
    gm_domain_get_time(domain, &state.time, NULL);
    if (every_step(schedule))
      state.target = state.time;
    state.interval = k;
    gm_status recorded =
        record(domain, schedule, &state, status != GM_OK, &next_frame);
    if (status == GM_OK)
      status = recorded;
    if (status == GM_OK && schedule->stop)
      stopped = schedule->stop(domain, &state, schedule->user);
  }
  if (time)
    *time = state.time;
  return status;
}
