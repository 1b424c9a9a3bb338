/*
 * common.h - what every example driver shares: the command-line options
 * (--method, --family, --ppc, --cell, --workers, --out, --t-end and the
 * example's own), the output directory, a CSV time series, a progress
 * display for gm_domain_advance, the run loop (advance, sample, frame) and
 * the final RESULT line.
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

/* gm_progress_fn printing a progress line to stderr at most every 2 % of
 * the run; user: the example_options (quiet silences it). */
int example_progress(const gm_domain *domain, double time, double end_time,
                     void *user);

/* Called after every sample interval of example_run_loop with the domain
 * at the time reached; user is example_run_schedule.sample_user. */
typedef void (*example_sample_fn)(const gm_domain *domain, void *user);

/* What the shared run loop does: advance to t_end in intervals of
 * sample_period, each with gm_domain_advance (step dt, <= 0 for the stable
 * step; progress called after every step), then sample, and write a frame
 * to series (if not NULL) every frame_period. */
typedef struct example_run_schedule {
  double t_end;           /* s */
  double sample_period;   /* s between samples (CSV rows) */
  double frame_period;    /* s between VTU frames */
  double dt;              /* s; <= 0: the stable step */
  gm_progress_fn *progress; /* NULL: none */
  void *progress_user;
  example_sample_fn sample; /* NULL: none */
  void *sample_user;
  gm_series *series;      /* NULL: no frames */
  int frame_on_failure;   /* also write a frame of the failed state */
} example_run_schedule;

/* Runs the schedule from t = 0; returns the status of the first failed
 * advance (GM_OK if none) and the time reached in *time (s). Does not
 * print anything itself. */
gm_status example_run_loop(gm_domain *domain,
                           const example_run_schedule *schedule,
                           double *time);

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
