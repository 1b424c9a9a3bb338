/*
 * common.h - what every example driver shares: the command-line options
 * (--method, --family, --ppc, --cell, --workers, --out, --t-end and the
 * example's own), the output directory, a CSV time series, a progress
 * display, the run loop every stepping driver shares (intervals, callbacks,
 * frames, the stop and the failure) and the final RESULT line.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef EXAMPLES_COMMON_H
#define EXAMPLES_COMMON_H

#include <granmpm.h>

#include <stdio.h>

typedef struct example_options {
  gm_shape shape;   /* --method linear|ugimp|cpgimp|cpdi */
  gm_family family; /* --family plain|stress_free|granular */
  int ppc;          /* --ppc N: points per cell per direction */
  double cell;      /* --cell H (m) */
  int workers;      /* --workers N */
  const char *out;  /* --out DIR: output directory, "" = none */
  double t_end;     /* --t-end T (s) */
  int quiet;        /* --quiet: no progress display */
} example_options;

/* An option of one example: --name VALUE, a number or a word. */
typedef struct example_extra {
  const char *name; /* without the dashes */
  const char *help;
  double *number;    /* set for a numeric option */
  const char **word; /* set for a word option */
} example_extra;

/* Parses argv into options (holding the example's defaults on entry) and
 * extras. Returns 0 to run, 1 after printing --help, 2 after an error
 * message (use as the exit status when nonzero). */
int example_parse(int argc, char **argv, const char *description,
                  example_options *options, const example_extra *extras,
                  int extra_count);

/* Names for messages and CSV files. */
const char *example_shape_name(gm_shape shape);
const char *example_family_name(gm_family family);

/* gm_domain_def_default() with the options' cell size, shape functions,
 * family and worker count. */
gm_domain_def example_domain_def(const example_options *options);

/* gm_domain_create, reporting a failure on stderr (NULL then). */
gm_domain *example_create_domain(const gm_domain_def *def);

/* --volumetric point|cell (gm_domain_set_volumetric: each point's own tr L,
 * or its cell's mean against volumetric locking); 0, or 2 after a
 * message on stderr. */
int example_set_volumetric(gm_domain *domain, const char *word);

/* "usl", "usf" or anything else (MUSL), for the examples' --scheme. */
gm_update_scheme example_scheme(const char *word);

/* Creates options->out (and its parents); 0 on success or when out is "". */
int example_make_output(const example_options *options);

/* Opens <out>/<file> for writing and writes the header line; NULL (with a
 * message) on failure or when out is "". */
FILE *example_open_csv(const example_options *options, const char *file,
                       const char *header);

/* CSV columns of the granular state after the last step: points per
 * gm_point_state and parallel grids (gm_domain_get_granular_summary; in the
 * plain and stress_free families every point counts as quasi-static). */
#define EXAMPLE_STATE_HEADER "quasi_static,moderate,disconnected,components"

/* Writes those four columns, each preceded by a comma, no newline. */
void example_write_states(FILE *csv, const gm_domain *domain);

/* A ParaView series <out>/<name>.pvd (with the point domains for GIMP and
 * CPDI) holding the domain's current state as its first frame; *series
 * stays NULL when out is "". */
gm_status example_open_series(const example_options *options, const char *name,
                              const gm_domain *domain, gm_series **series);

/* Prints the scene as the domain holds it, one line per material:
 * SCENE material=k points=N mass=M x=lo..hi y=lo..hi
 * (mass in kg per metre, or kg for 1D and the whole ring in axisymmetry;
 * the box the point domains cover, centre -+ half the initial domain
 * size, m). Every driver that takes --cell prints it when its scene is
 * placed, so that two cells can be compared: a refinement study changes
 * the points, not the scene (examples/README.md, "Refinement: one flag";
 * tests/scripts/example_scenes.sh). */
void example_print_scene(const gm_domain *domain);

/* gm_progress_fn printing a progress line to stderr at most every 2 % of
 * the run; user: the example_options (quiet silences it). */
int example_progress(const gm_domain *domain, double time, double end_time,
                     void *user);

/* The shared run loop of every example driver that steps a domain.
 *
 * A run is a sequence of intervals. Before each: `prepare` (place a
 * portion, a layer, reset an average); then the domain is moved through
 * the interval by `stepping`, `step` after every step; after it: `sample`
 * (a CSV row), a VTU frame when the cadence says, and `stop`. The loop
 * ends when the time reaches t_end, after interval_limit intervals, when
 * `stop` says so, or at the first failure. A driver's phases (settle
 * closed, then discharge) are one example_run_loop call each.
 * tests/unit/test_example_loop.c asserts its sample times, step and frame
 * cadence, stop and failure path.
 *
 * Every driver in examples/papers/, column_collapse.c and
 * silo_layers_janssen.c runs on it. Those that do not, and why:
 *  - minimal.c (the README's and granmpm(3)'s listing, which
 *    tests/scripts/readme_example.sh keeps identical to it; make check
 *    builds it against granmpm.h alone) and demo_bar.c (make demo-bar,
 *    "uses only the public API") are there to show the public API: their
 *    few lines of gm_domain_step are the point of the listing, and a
 *    user copying them would also need common.c;
 *  - freefall.f90 is the Fortran binding's check and cannot call C
 *    helpers that are not part of the library. */

/* Where the loop stands, handed to every callback. */
typedef struct example_run_state {
  long interval;     /* intervals done; 0 before the first */
  double target;     /* s, the end of the current interval (the start time
                        before the first; every step an interval: the time
                        reached after it) */
  double time;       /* s, the domain's time */
  double step_start; /* s, step: the time before the step */
  double dt;         /* s, step: the step taken (time - step_start when
                        gm_domain_advance chose it) */
} example_run_state;

/* Before an interval (domain at state->time) and after one (sample); a
 * status other than GM_OK ends the loop with it. */
typedef gm_status example_run_fn(gm_domain *domain,
                                 const example_run_state *state, void *user);
typedef gm_status example_sample_fn(const gm_domain *domain,
                                    const example_run_state *state, void *user);
/* After every committed step. */
typedef void example_step_fn(const gm_domain *domain,
                             const example_run_state *state, void *user);
/* After each sample and frame: nonzero ends the loop. */
typedef int example_stop_fn(const gm_domain *domain,
                            const example_run_state *state, void *user);

/* How an interval is stepped. */
typedef enum example_stepping {
  /* gm_domain_advance to the sample time: steps of dt (<= 0: the stable
   * dt), the last two evened out, landing on it exactly; the loop runs
   * while time < t_end - 1e-12 s (no sliver interval for round-off). */
  EXAMPLE_ADVANCE,
  /* gm_domain_step: steps of dt (<= 0: gm_domain_stable_dt; empty_dt
   * while the domain has no points, where the stable dt is undefined).
   * With sample times (sample_period > 0 or EXAMPLE_SAMPLE_SPLIT): each
   * step clipped to the sample time, the interval over within 1e-9 s of
   * it (no sliver step), and the loop runs while t_end - time > 1e-9 s.
   * Without (sample_period = 0): every step is an interval, the last one
   * may pass t_end, and the loop runs while time < t_end. */
  EXAMPLE_STEPS
} example_stepping;

/* Where the sample times lie (k = the interval's number, from 1). */
typedef enum example_sample_times {
  EXAMPLE_SAMPLE_AFTER,     /* the time reached + sample_period */
  EXAMPLE_SAMPLE_MULTIPLES, /* k sample_period */
  EXAMPLE_SAMPLE_SPLIT      /* t_end k / sample_count, the last t_end */
} example_sample_times;

/* What a failed step (or callback) leaves behind, beyond the status. */
typedef enum example_on_failure {
  EXAMPLE_FAILURE_STOP,        /* nothing */
  EXAMPLE_FAILURE_SAMPLE,      /* the failed interval's sample */
  EXAMPLE_FAILURE_SAMPLE_FRAME /* its sample and a frame of it */
} example_on_failure;

typedef struct example_run_schedule {
  example_stepping stepping;
  example_sample_times sample_times;
  double t_end;         /* s; INFINITY: no end but interval_limit or stop */
  double sample_period; /* s between samples (0: every step, EXAMPLE_STEPS) */
  long sample_count;    /* EXAMPLE_SAMPLE_SPLIT: intervals to t_end */
  long interval_limit;  /* > 0: at most this many intervals */
  double dt;            /* s; <= 0: the stable step */
  double empty_dt;      /* s, EXAMPLE_STEPS without points */
  int sample_at_start;  /* also sample (and frame) before interval 1 */
  /* The frame cadence: frame_every > 0: after the intervals frame_first,
   * frame_first + frame_every, ... (0 is the start); otherwise one frame
   * each time the time passes the next multiple of frame_period (within
   * 1e-9 s; a frame at t = 0 is the driver's, example_open_series writes
   * one). */
  gm_series *series;   /* NULL: no frames */
  double frame_period; /* s */
  long frame_every;
  long frame_first;
  example_on_failure on_failure;
  /* The progress display (example_progress against t_end, or against
   * options->t_end while t_end is INFINITY); NULL: none. */
  const example_options *progress;
  example_run_fn *prepare; /* each may be NULL */
  example_step_fn *step;
  example_sample_fn *sample;
  example_stop_fn *stop;
  void *user; /* handed to every callback */
} example_run_schedule;

/* Runs the schedule from the domain's time; returns GM_OK or the status
 * of the first failure (a step, a callback, a frame that could not be
 * written; GM_ERR_INVALID_ARGUMENT, with a message on stderr, for a
 * schedule that does not make sense), and the time reached in *time (s;
 * may be NULL). The domain's last error names a failed step. */
gm_status example_run_loop(gm_domain *domain,
                           const example_run_schedule *schedule, double *time);

/* The last line of every example:
 * RESULT name=value reference=value rel_error=x */
void example_result(const char *name, double value, double reference);

/* Prints the failed call and the domain's message; returns 2. */
int example_fail(const gm_domain *domain, const char *call, gm_status status);

#define EXAMPLE_CHECK(domain, call)                                            \
  do {                                                                         \
    gm_status example_status_ = (call);                                        \
    if (example_status_ != GM_OK)                                              \
      return example_fail((domain), #call, example_status_);                   \
  } while (0)

#endif
