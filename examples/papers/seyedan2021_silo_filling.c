/*
 * seyedan2021_silo_filling.c - the silo filling of Seyedan & Solowski 2021 (000
 * sec 4.3, Table 4, Figs 14-16): a flat-bottomed planar silo 2.7 m wide and 7.5
 * m high, with elastic walls, filled by releasing 3 granular points every 0.17
 * s at its top, 504 points in 28.56 s. The points fall disconnected, meet the
 * material already in the silo, slow down and settle. The paper reports that
 * plain MPM fills the silo with too few points (the falling points interact
 * over grid nodes) and fails near 9.9 s, stress-free CPDI fails shortly
 * after 6.31 s (points breach the boundary), plain CPDI has breached it
 * by 14.32 s, while the granular family runs to the end with undistorted,
 * tightly packed points.
 *
 * Setup (Table 4; where the text is silent, our choice):
 *  - 0.3 m grid; fill points of 0.15 m (2 x 2 per cell), released at rest
 *    in the middle of the 3 middle cells of the silo's top cell row;
 *  - silo walls: linear elastic points (E = 1 GPa, nu = 0.3, rho = 2250
 *    kg/m^3), one cell (0.3 m) thick on both sides and under the floor,
 *    2 x 2 points per cell; "fixed at the sides": the box faces behind
 *    them are no-slip;
 *  - fill: Mohr-Coulomb with the Bagnold term, Table 4 (= Table 3);
 *  - dt: the stable step (the paper's 5e-5 s is four times smaller; --dt
 *    5e-5 runs it) and MUSL (--scheme usl for the paper's USL);
 *  - default t_end = 8 s (48 releases, 144 points; about a minute with
 *    CPDI on one core here); --t-end 28.56 runs the paper's whole filling.
 *
 * Prints the points placed against the releases expected by t_end and the
 * largest V/V0 of any fill point; the RESULT line compares that with
 * rho_initial / (rho_cr - TOL), the bound the granular family keeps
 * (density control, eqs 13-15). Output: <out>/silo_filling.pvd (with
 * domains for GIMP/CPDI) and <out>/silo_filling.csv.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include "common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double GRAVITY = 9.81;        /* m/s^2 */
static const double DENSITY = 2250.0;      /* kg/m^3, fill and silo */
static const double CRITICAL = 2235.0;     /* kg/m^3, rho_cr of the fill */
static const double TOLERANCE = 1e-6;      /* kg/m^3, TOL */
static const double SILO_WIDTH = 2.7;      /* m, inside */
static const double SILO_HEIGHT = 7.5;     /* m, inside */
static const double HEADROOM = 0.6;        /* m of grid above the silo */
static const double RELEASE_PERIOD = 0.17; /* s, Table 4 / sec 4.3 */
static const int RELEASE_COUNT = 3;        /* points per release */
static const int TOTAL_RELEASES = 168;     /* 504 points */
static const double SAMPLE_PERIOD = 0.05;  /* s between CSV rows */
static const double FRAME_PERIOD = 0.17;   /* s between VTU frames */

typedef struct silo_record {
  int fill_material;
  double max_volume_ratio; /* largest V/V0 of a fill point so far */
  double cell;             /* m */
  FILE *csv;               /* NULL: no CSV */
} silo_record;

/* The material id of every point (computed, so copied, not viewed);
 * free() the result. NULL if out of memory. */
static double *material_ids(const gm_domain *domain) {
  size_t count = gm_domain_point_count(domain);
  double *id = malloc((count ? count : 1) * sizeof *id);
  if (id && gm_domain_get_field(domain, GM_FIELD_MATERIAL, id, count) != GM_OK)
    free(id), id = NULL;
  return id;
}

/* Largest V/V0 over the points of `material`. */
static double largest_volume_ratio(const gm_domain *domain, int material) {
  const double *volume = NULL, *initial = NULL;
  size_t count = gm_domain_point_count(domain);
  double *id = material_ids(domain);
  gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume);
  gm_domain_view_field(domain, GM_FIELD_INITIAL_VOLUME, 0, &initial);
  double largest = 1.0;
  for (size_t p = 0; id && p < count; p++)
    if (id[p] == material)
      largest = fmax(largest, volume[p] / initial[p]);
  free(id);
  return largest;
}

/* example_step_fn: tracks the largest V/V0 of the fill. */
static void track_step(const gm_domain *domain, const example_run_state *state,
                       void *user) {
  (void)state;
  silo_record *record = user;
  record->max_volume_ratio =
      fmax(record->max_volume_ratio,
           largest_volume_ratio(domain, record->fill_material));
}

/* Wall thickness = one cell: the walls fill the grid's outer cells. */
static gm_status add_silo_walls(gm_domain *domain, double cell, double youngs) {
  gm_elastic_def steel = gm_elastic_def_default(); /* Table 4 "Silo" */
  steel.name = "silo";
  steel.youngs_modulus = youngs;
  steel.poisson_ratio = 0.3;
  steel.density = DENSITY;
  int material = -1;
  gm_status status = gm_domain_add_elastic(domain, &steel, &material);
  double top = cell + SILO_HEIGHT; /* m, top of the side walls */
  const double boxes[3][4] = {
      {0.0, 0.0, cell, top},                                /* left wall */
      {cell + SILO_WIDTH, 0.0, 2 * cell + SILO_WIDTH, top}, /* right */
      {cell, 0.0, cell + SILO_WIDTH, cell}};                /* floor */
  for (int b = 0; b < 3 && status == GM_OK; b++) {
    gm_fill_def fill = gm_fill_def_default();
    fill.material = material;
    fill.lower[0] = boxes[b][0], fill.lower[1] = boxes[b][1];
    fill.upper[0] = boxes[b][2], fill.upper[1] = boxes[b][3];
    fill.points_per_cell_axis = 2;
    status = gm_domain_fill_box(domain, &fill, NULL, NULL);
  }
  return status;
}

static gm_status add_fill(gm_domain *domain, double cell, double youngs,
                          int *material) {
  gm_mohr_coulomb_def soil = gm_mohr_coulomb_def_default(); /* Table 4 */
  soil.name = "fill";
  soil.youngs_modulus = youngs;
  soil.density = DENSITY;
  gm_status status = gm_domain_add_mohr_coulomb(domain, &soil, material);
  if (status != GM_OK)
    return status;
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL;
  granular.tolerance = TOLERANCE;
  status = gm_domain_set_granular(domain, *material, &granular);
  if (status != GM_OK)
    return status;
  /* The middles of the 3 middle cells of the silo's top cell row. */
  int middle = (int)lround(SILO_WIDTH / cell) / 2; /* cell index */
  double position[2 * 3];                          /* m */
  for (int k = 0; k < RELEASE_COUNT; k++) {
    position[2 * k] = cell + (middle - 1 + k + 0.5) * cell;
    position[2 * k + 1] = cell + SILO_HEIGHT - 0.5 * cell;
  }
  gm_source_def source = gm_source_def_default();
  source.material = *material;
  source.count = RELEASE_COUNT;
  source.position = position;
  source.point_size = 0.5 * cell; /* m: 0.15 m points on the 0.3 m grid */
  source.period = RELEASE_PERIOD;
  source.max_injections = TOTAL_RELEASES;
  int source_id = -1;
  return gm_domain_add_source(domain, &source, &source_id);
}

/* Average density of the fill (kg/m^3) and the height of its deposit (m
 * above the floor): the highest fill point slower than 0.5 m/s, leaving
 * out the top 0.6 m of the silo where the points start at rest. */
static void measure_fill(const gm_domain *domain, int material, double *average,
                         double *deposit, size_t *count) {
  const double *mass = NULL, *volume = NULL, *y = NULL;
  const double *vx = NULL, *vy = NULL;
  size_t total = gm_domain_point_count(domain);
  double *id = material_ids(domain);
  gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass);
  gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume);
  gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y);
  gm_domain_view_field(domain, GM_FIELD_VELOCITY, 0, &vx);
  gm_domain_view_field(domain, GM_FIELD_VELOCITY, 1, &vy);
  double total_mass = 0.0, total_volume = 0.0;
  *deposit = 0.0, *count = 0;
  for (size_t p = 0; id && p < total; p++) {
    if (id[p] != material)
      continue;
    ++*count;
    total_mass += mass[p];
    total_volume += volume[p];
    if (hypot(vx[p], vy[p]) < 0.5 && y[p] < SILO_HEIGHT - HEADROOM)
      *deposit = fmax(*deposit, y[p]);
  }
  *average = *count ? total_mass / total_volume : 0.0;
  free(id);
}

/* example_sample_fn: one CSV row to the record's CSV (NULL: none). */
static gm_status write_row(const gm_domain *domain,
                           const example_run_state *state, void *user) {
  (void)state;
  const silo_record *record = user;
  FILE *csv = record->csv;
  int material = record->fill_material;
  double cell = record->cell; /* m */
  if (!csv)
    return GM_OK;
  double time = 0.0, average = 0.0, deposit = 0.0;
  size_t count = 0;
  gm_domain_get_time(domain, &time, NULL);
  gm_summary summary = gm_summary_default();
  gm_domain_get_summary(domain, &summary);
  gm_granular_summary granular = gm_granular_summary_default();
  gm_domain_get_granular_summary(domain, &granular);
  measure_fill(domain, material, &average, &deposit, &count);
  fprintf(csv, "%.4f,%.6e,%zu,%zu,%zu,%zu,%zu,%.3f,%.6f,%.3f\n", time,
          summary.kinetic_energy, granular.state_count[0],
          granular.state_count[1], granular.state_count[2],
          granular.component_count, count, average,
          largest_volume_ratio(domain, material),
          count ? fmax(deposit - cell, 0.0) : 0.0);
  return GM_OK;
}

static gm_domain *create_domain(const example_options *options,
                                const char *scheme) {
  gm_domain_def def = example_domain_def(options);
  def.extent[0] = SILO_WIDTH + 2 * options->cell;
  def.extent[1] = SILO_HEIGHT + options->cell + HEADROOM;
  def.gravity[1] = -GRAVITY;
  for (int face = GM_FACE_XMIN; face <= GM_FACE_YMAX; face++)
    def.walls[face] = GM_WALL_FIXED;
  def.scheme = example_scheme(scheme);
  return example_create_domain(&def);
}

/* Runs to t_end: a CSV row per sample, a frame per frame period (the
 * series has no frame at t = 0) and one of a failed state. */
static gm_status run(gm_domain *domain, const example_options *options,
                     double dt, gm_series *series, silo_record *record) {
  const example_run_schedule schedule = {.stepping = EXAMPLE_ADVANCE,
                                         .sample_times = EXAMPLE_SAMPLE_AFTER,
                                         .t_end = options->t_end,
                                         .sample_period = SAMPLE_PERIOD,
                                         .dt = dt,
                                         .series = series,
                                         .frame_period = FRAME_PERIOD,
                                         .on_failure =
                                             EXAMPLE_FAILURE_SAMPLE_FRAME,
                                         .progress = options,
                                         .step = track_step,
                                         .sample = write_row,
                                         .user = record};
  return example_run_loop(domain, &schedule, NULL);
}

int main(int argc, char **argv) {
  example_options options = {
      GM_SHAPE_CPDI, GM_FAMILY_GRANULAR, 2, 0.3, 1, "out/silo_filling", 8.0, 0};
  double dt = 0.0, youngs = 1e9; /* s (stable), Pa (Table 4) */
  const char *scheme = "musl";
  const example_extra extras[] = {
      {"dt", "time step, s (<= 0: the stable step)", &dt, NULL},
      {"youngs", "Young's modulus of fill and silo, Pa", &youngs, NULL},
      {"scheme", "update scheme usl|musl|usf", NULL, &scheme}};
  int parsed = example_parse(argc, argv,
                             "Silo filling of 000 sec 4.3: 3 points every "
                             "0.17 s into a 2.7 m x 7.5 m elastic silo.",
                             &options, extras, 3);
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  if (example_make_output(&options) != 0)
    return 2;
  gm_domain *domain = create_domain(&options, scheme);
  if (!domain)
    return 2;
  silo_record record = {-1, 1.0, options.cell, NULL};
  EXAMPLE_CHECK(domain,
                add_fill(domain, options.cell, youngs, &record.fill_material));
  EXAMPLE_CHECK(domain, add_silo_walls(domain, options.cell, youngs));
  FILE *csv = example_open_csv(
      &options, "silo_filling.csv",
      "time_s,kinetic_energy_J,quasi_static,moderate,disconnected,"
      "components,fill_points,fill_density_kg_m3,max_volume_ratio,"
      "deposit_height_m");
  gm_series *series = NULL;
  if (options.out[0]) {
    char path[1100];
    snprintf(path, sizeof path, "%s/silo_filling.pvd", options.out);
    EXAMPLE_CHECK(domain, gm_series_create(path, &series));
    if (options.shape != GM_SHAPE_LINEAR)
      gm_series_set_domains(series, 1);
  }
  record.csv = csv;
  gm_status status = run(domain, &options, dt, series, &record);
  double time = 0.0, average = 0.0, deposit = 0.0;
  size_t placed = 0;
  gm_domain_get_time(domain, &time, NULL);
  measure_fill(domain, record.fill_material, &average, &deposit, &placed);
  /* Releases at 0, 0.17, ... up to t_end (at most 168). */
  long releases = lround(floor(options.t_end / RELEASE_PERIOD + 1e-9)) + 1;
  if (releases > TOTAL_RELEASES)
    releases = TOTAL_RELEASES;
  printf("silo_filling: %s %s, t = %.3f s\n", example_shape_name(options.shape),
         example_family_name(options.family), time);
  if (status != GM_OK)
    printf("FAILED at t = %.4f s: %s (%s)\n", time, gm_strerror(status),
           gm_domain_last_error(domain));
  printf("fill points placed %zu of %ld released by t_end (504 at 28.56 s); "
         "fill density %.1f kg/m^3; deposit height %.2f m\n",
         placed, releases * RELEASE_COUNT, average,
         fmax(deposit - options.cell, 0.0));
  example_result("max_volume_ratio", record.max_volume_ratio,
                 DENSITY / (CRITICAL - TOLERANCE));
  if (csv)
    fclose(csv);
  gm_series_destroy(series);
  gm_domain_destroy(domain);
  return status == GM_OK ? 0 : 3;
}
