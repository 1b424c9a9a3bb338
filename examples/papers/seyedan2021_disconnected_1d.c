/*
 * seyedan2021_disconnected_1d.c - the disconnected state in 1D (000 sec 4.1,
 * Table 2, Figs 6-8): a point just below the critical density (disconnected)
 * moves at constant speed towards two resting points of a denser body. Granular
 * MPM puts it on its own parallel grid, so its velocity stays exactly
 * what it was until its domain of interaction (length m / rho_cr) meets
 * the body's; that happens at the closed-form time gap / speed, on any
 * grid. Stress-free MPM lets it interact as soon as it shares a grid node
 * with the body, at a time that depends on the grid.
 *
 * Table 2: E = 100 kPa (nu = 0: uniaxial strain with E), rho_initial =
 * 1500 kg/m^3, rho_cr = 1400 kg/m^3, dt = 2e-5 s, 10 mm grid. Our scene
 * (the paper's point positions are only drawn, Fig 6): point masses 15
 * kg/m^2 (10 mm domains at 1500 kg/m^3); the moving point at 1399.99
 * kg/m^3 (domain of interaction 10.71 mm, as in the paper) starts at
 * 45.5 mm with --speed (default 0.5 m/s); the body's points rest at 80 and
 * 90 mm. The grid origin is offset by --shift (m) so no point starts on a
 * node. tests/physics/test_disconnected_1d.c asserts the same on three grids.
 *
 * Prints, for the chosen method and both families, the time of the first
 * velocity change of the moving point, and for the granular family the
 * time its grid merged with the body's; the RESULT line is the granular
 * merge time against gap / speed (expected within one dt, because
 * components are decided at the start of each step). Output:
 * <out>/disconnected_1d.csv (time, position and velocity of the moving
 * point, its state and component, the component count; granular run) and
 * <out>/disconnected_1d.pvd.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include "common.h"

#include <math.h>

static const double YOUNGS = 1e5;             /* Pa, Table 2 */
static const double DENSITY = 1500.0;         /* kg/m^3, Table 2 */
static const double CRITICAL = 1400.0;        /* kg/m^3, Table 2 */
static const double MOVING_DENSITY = 1399.99; /* kg/m^3, just below */
static const double TIME_STEP = 2e-5;         /* s, Table 2 */
static const double POINT_MASS = 15.0;        /* kg/m^2 */
static const double MOVING_START = 0.0455;    /* m */
static const double BODY[2] = {0.08, 0.09};   /* m */
/* kg/m^3, TOL (not in Table 2): the granular family refuses a granular
 * point placed below rho_cr - TOL (gm_granular(3)); the moving point sits
 * 0.01 kg/m^3 below rho_cr, so TOL must exceed that. */
static const double TOLERANCE = 0.02;

/* When things happened in one run (s; -1: not within the run). */
typedef struct event_times {
  double merge;  /* first step on a single grid (granular) */
  double change; /* first step after which the speed changed */
} event_times;

/* The free gap between the domains of interaction over the speed (s). In
 * 1D a point's domain of interaction is m / rho_cr long. */
static double closed_form_merge(double speed) {
  double reach = 0.5 * POINT_MASS / CRITICAL; /* m, half a domain */
  return ((BODY[0] - reach) - (MOVING_START + reach)) / speed;
}

static gm_domain *create_scene(const example_options *options, gm_family family,
                               double speed, double shift, int64_t *moving_id) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_1D;
  def.origin[0] = -shift;
  def.extent[0] = 0.15; /* m */
  def.cell_size = options->cell;
  def.shape = options->shape;
  def.family = family;
  gm_domain *domain = NULL;
  if (gm_domain_create(&def, &domain) != GM_OK)
    return NULL;
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.youngs_modulus = YOUNGS;
  elastic.poisson_ratio = 0.0;
  elastic.density = DENSITY;
  int material = -1;
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL;
  granular.tolerance = TOLERANCE;
  const double position[3] = {MOVING_START, BODY[0], BODY[1]}; /* m */
  const double velocity[3] = {speed, 0.0, 0.0};                /* m/s */
  const double mass[3] = {POINT_MASS, POINT_MASS, POINT_MASS};
  const double volume[3] = {POINT_MASS / MOVING_DENSITY, POINT_MASS / DENSITY,
                            POINT_MASS / DENSITY}; /* m */
  gm_points_def points = gm_points_def_default();
  points.count = 3;
  points.position = position;
  points.velocity = velocity;
  points.mass = mass;
  points.volume = volume;
  if (gm_domain_add_elastic(domain, &elastic, &material) != GM_OK ||
      gm_domain_set_granular(domain, material, &granular) != GM_OK ||
      (points.material = material,
       gm_domain_add_points(domain, &points, moving_id)) != GM_OK) {
    example_fail(domain, "setting up the scene", GM_ERR_INVALID_ARGUMENT);
    gm_domain_destroy(domain);
    return NULL;
  }
  return domain;
}

/* Reads one field value of the moving point. */
static double moving_value(const gm_domain *domain, int64_t id,
                           gm_field field) {
  size_t index = 0;
  double values[3];
  if (gm_domain_point_index(domain, id, &index) != GM_OK ||
      gm_domain_get_field(domain, field, values, 3) != GM_OK)
    return NAN;
  return values[index];
}

/* The moving point and what happened to it. */
typedef struct moving_run {
  int64_t id;
  double speed; /* m/s, its initial speed */
  FILE *csv;    /* NULL: none */
  event_times times;
} moving_run;

/* example_sample_fn, after every step: the events and a CSV row. */
static gm_status sample_step(const gm_domain *domain,
                             const example_run_state *state, void *user) {
  moving_run *run = user;
  double start = (double)(state->interval - 1) * TIME_STEP; /* s */
  gm_granular_summary summary = gm_granular_summary_default();
  gm_domain_get_granular_summary(domain, &summary);
  if (run->times.merge < 0 && summary.component_count == 1)
    run->times.merge = start;
  double velocity = moving_value(domain, run->id, GM_FIELD_VELOCITY); /* m/s */
  if (run->times.change < 0 && velocity != run->speed)
    run->times.change = start;
  if (run->csv)
    fprintf(run->csv, "%.5f,%.8f,%.8f,%g,%g,%zu\n", start + TIME_STEP,
            moving_value(domain, run->id, GM_FIELD_POSITION), velocity,
            moving_value(domain, run->id, GM_FIELD_STATE),
            moving_value(domain, run->id, GM_FIELD_COMPONENT),
            summary.component_count);
  return GM_OK;
}

/* Steps of TIME_STEP to t_end (as many as round to it); records the
 * events, the CSV and a frame every 100 steps if given. */
static event_times run(gm_domain *domain, int64_t id, double speed,
                       double t_end, FILE *csv, gm_series *series) {
  moving_run moving = {id, speed, csv, {-1.0, -1.0}};
  long steps = lround(t_end / TIME_STEP);
  const example_run_schedule schedule = {.stepping = EXAMPLE_STEPS,
                                         .t_end = INFINITY,
                                         .interval_limit = steps,
                                         .dt = TIME_STEP,
                                         .series = series,
                                         .frame_every = 100,
                                         .frame_first = 100,
                                         .on_failure = EXAMPLE_FAILURE_STOP,
                                         .sample = sample_step,
                                         .user = &moving};
  gm_status status =
      steps > 0 ? example_run_loop(domain, &schedule, NULL) : GM_OK;
  if (status != GM_OK)
    example_fail(domain, "gm_domain_step", status);
  return moving.times;
}

int main(int argc, char **argv) {
  example_options options = {GM_SHAPE_LINEAR,
                             GM_FAMILY_GRANULAR,
                             1,
                             0.01,
                             1,
                             "out/disconnected_1d",
                             0.06,
                             0};
  double speed = 0.5, shift = 0.003; /* m/s, m */
  const example_extra extras[] = {
      {"speed", "speed of the disconnected point, m/s", &speed, NULL},
      {"shift", "grid origin at -shift, m", &shift, NULL}};
  int parsed = example_parse(argc, argv,
                             "1D disconnected point meeting a body (000 sec "
                             "4.1): merge time against gap / speed.",
                             &options, extras, 2);
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  if (!(speed > 0.0) || example_make_output(&options) != 0)
    return 2;
  FILE *csv = example_open_csv(&options, "disconnected_1d.csv",
                               "time_s,moving_x_m,moving_velocity_m_s,"
                               "moving_state,moving_component,components");
  gm_series *series = NULL;
  if (options.out[0]) {
    char path[1100];
    snprintf(path, sizeof path, "%s/disconnected_1d.pvd", options.out);
    if (gm_series_create(path, &series) != GM_OK)
      return example_fail(NULL, "gm_series_create", GM_ERR_IO);
    gm_series_set_domains(series, 1);
  }
  const gm_family families[2] = {GM_FAMILY_STRESS_FREE, GM_FAMILY_GRANULAR};
  event_times times[2];
  for (int f = 0; f < 2; f++) {
    int64_t id = 0;
    gm_domain *domain = create_scene(&options, families[f], speed, shift, &id);
    if (!domain)
      return 2;
    if (f == 0)
      example_print_scene(domain);
    int granular = families[f] == GM_FAMILY_GRANULAR;
    times[f] = run(domain, id, speed, options.t_end, granular ? csv : NULL,
                   granular ? series : NULL);
    printf("%s %s: first velocity change at %.5f s",
           example_family_name(families[f]), example_shape_name(options.shape),
           times[f].change);
    if (granular)
      printf(", grids merged at %.5f s", times[f].merge);
    printf("\n");
    gm_domain_destroy(domain);
  }
  if (csv)
    fclose(csv);
  gm_series_destroy(series);
  double expected = closed_form_merge(speed); /* s */
  printf("gap / speed = %.5f s (dt = %g s)\n", expected, TIME_STEP);
  example_result("merge_time_s", times[1].merge, expected);
  return 0;
}
