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
 *    kg/m^3), 0.3 m thick (one cell of the default grid) on both sides and
 *    under the floor, 2 x 2 points per cell; "fixed at the sides": the box
 *    faces behind them are no-slip;
 *  - the scene is in metres, so --cell refines it (examples/README.md,
 *    "Refinement: one flag"): on a finer grid each released 0.15 m grain
 *    is n x n points of 0.15/n m, n = the grain over the point spacing
 *    cell / --ppc, rounded (1 on the default grid: the paper's single
 *    points), so every release carries the same 152 kg/m; the walls stay
 *    0.3 m thick and the releases 0.3 m apart, 0.15 m below the top of
 *    the walls. On a cell whose point spacing does not divide 0.3 m the
 *    wall faces round to the lattice, and the right wall reaches the box
 *    face, which the grid rounds up to whole cells. (Until 2026-11-27 the
 *    walls were one cell thick and the releases 3 points of half a cell:
 *    at 0.15 m each release carried a quarter of the mass, another
 *    scene.) --ppc sets the points per cell of fill and walls (it was
 *    ignored: always 2);
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
static const double WALL_THICKNESS = 0.3;  /* m, sides and floor */
static const double GRAIN = 0.15;          /* m, edge of a released grain */
static const double RELEASE_PITCH = 0.3;   /* m, the paper's grid cells */
static const double RELEASE_PERIOD = 0.17; /* s, Table 4 / sec 4.3 */
static const int RELEASE_COUNT = 3;        /* points per release */
static const int TOTAL_RELEASES = 168;     /* 504 points */
static const double SAMPLE_PERIOD = 0.05;  /* s between CSV rows */
static const double FRAME_PERIOD = 0.17;   /* s between VTU frames */

typedef struct silo_record {
  int fill_material;
  double max_volume_ratio; /* largest V/V0 of a fill point so far */
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

/* The walls, WALL_THICKNESS thick, n x n points per cell. The right wall
 * reaches the grid's right face, which the library rounds up to whole
 * cells (gm_domain_def.extent), so it is held at its back on every grid. */
static gm_status add_silo_walls(gm_domain *domain, double cell, int ppc,
                                double youngs) {
  gm_elastic_def steel = gm_elastic_def_default(); /* Table 4 "Silo" */
  steel.name = "silo";
  steel.youngs_modulus = youngs;
  steel.poisson_ratio = 0.3;
  steel.density = DENSITY;
  int material = -1;
  gm_status status = gm_domain_add_elastic(domain, &steel, &material);
  double wall = WALL_THICKNESS;    /* m */
  double top = wall + SILO_HEIGHT; /* m, top of the side walls */
  double right = cell * ceil((SILO_WIDTH + 2 * wall) / cell - 1e-9); /* m */
  const double boxes[3][4] = {{0.0, 0.0, wall, top}, /* left wall */
                              {wall + SILO_WIDTH, 0.0, right, top},  /* right */
                              {wall, 0.0, wall + SILO_WIDTH, wall}}; /* floor */
  for (int b = 0; b < 3 && status == GM_OK; b++) {
    gm_fill_def fill = gm_fill_def_default();
    fill.material = material;
    fill.lower[0] = boxes[b][0], fill.lower[1] = boxes[b][1];
    fill.upper[0] = boxes[b][2], fill.upper[1] = boxes[b][3];
    fill.points_per_cell_axis = ppc;
    status = gm_domain_fill_box(domain, &fill, NULL, NULL);
  }
  return status;
}

/* Points per grain edge: the grain over the point spacing, rounded. */
static int grain_points(double cell, int ppc) {
  long n = lround(GRAIN / (cell / ppc));
  return n < 1 ? 1 : (int)n;
}

static gm_status add_fill(gm_domain *domain, double cell, int ppc,
                          double youngs, int *material) {
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
  /* Grains centred in the middles of the 3 middle 0.3 m cells of the
   * paper's top cell row, each n x n points of edge GRAIN / n. */
  int middle = (int)lround(SILO_WIDTH / RELEASE_PITCH) / 2; /* cell index */
  int n = grain_points(cell, ppc);
  double size = GRAIN / n; /* m, point edge */
  size_t count = (size_t)(RELEASE_COUNT * n * n);
  double *position = malloc(2 * count * sizeof *position); /* m */
  if (!position)
    return GM_ERR_NO_MEMORY;
  for (size_t p = 0; p < count; p++) {
    int k = (int)(p / (size_t)(n * n)), i = (int)(p % (size_t)n);
    int j = (int)(p / (size_t)n % (size_t)n);
    position[2 * p] = WALL_THICKNESS + (middle - 1 + k + 0.5) * RELEASE_PITCH +
                      ((i + 0.5) * size - 0.5 * GRAIN);
    position[2 * p + 1] = WALL_THICKNESS + SILO_HEIGHT - 0.5 * RELEASE_PITCH +
                          ((j + 0.5) * size - 0.5 * GRAIN);
  }
  gm_source_def source = gm_source_def_default();
  source.material = *material;
  source.count = count;
  source.position = position;
  source.point_size = size; /* m: 0.15 m points on the 0.3 m grid */
  source.period = RELEASE_PERIOD;
  source.max_injections = TOTAL_RELEASES;
  int source_id = -1;
  status = gm_domain_add_source(domain, &source, &source_id);
  free(position);
  return status;
}

/* Average density of the fill (kg/m^3) and the height of its deposit (m
 * above the floor): the highest fill point slower than 0.5 m/s, leaving
 * out the top 0.9 m of the silo (y >= 6.9 m, 6.6 m above the floor) where
 * the points start at rest. */
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
          count ? fmax(deposit - WALL_THICKNESS, 0.0) : 0.0);
  return GM_OK;
}

static gm_domain *create_domain(const example_options *options,
                                const char *scheme) {
  gm_domain_def def = example_domain_def(options);
  def.extent[0] = SILO_WIDTH + 2 * WALL_THICKNESS;
  def.extent[1] = SILO_HEIGHT + WALL_THICKNESS + HEADROOM;
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
  silo_record record = {-1, 1.0, NULL};
  EXAMPLE_CHECK(domain, add_fill(domain, options.cell, options.ppc, youngs,
                                 &record.fill_material));
  EXAMPLE_CHECK(domain,
                add_silo_walls(domain, options.cell, options.ppc, youngs));
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
  int n = grain_points(options.cell, options.ppc);
  printf("silo_filling: %s %s, t = %.3f s; each release 3 grains of %g m, "
         "%d x %d points\n",
         example_shape_name(options.shape), example_family_name(options.family),
         time, GRAIN, n, n);
  example_print_scene(domain);
  if (status != GM_OK)
    printf("FAILED at t = %.4f s: %s (%s)\n", time, gm_strerror(status),
           gm_domain_last_error(domain));
  printf("fill points placed %zu of %ld released by t_end (%d at 28.56 s); "
         "fill density %.1f kg/m^3; deposit height %.2f m\n",
         placed, releases * RELEASE_COUNT * n * n,
         TOTAL_RELEASES * RELEASE_COUNT * n * n, average,
         fmax(deposit - WALL_THICKNESS, 0.0));
  example_result("max_volume_ratio", record.max_volume_ratio,
                 DENSITY / (CRITICAL - TOLERANCE));
  if (csv)
    fclose(csv);
  gm_series_destroy(series);
  gm_domain_destroy(domain);
  return status == GM_OK ? 0 : 3;
}
