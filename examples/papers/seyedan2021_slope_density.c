/*
 * seyedan2021_slope_density.c - moderate flow down a slope (000 sec 2.3, Table
 * 1, Figs 1-2): a Mohr-Coulomb block (psi = 0) flows down a 30 degree slope. In
 * a moderate flow the packing stays at the critical state, so the average
 * density should stay at rho_cr; the paper shows plain and stress-free MPM
 * losing density while Granular MPM's density control (eqs 13-15) holds it.
 *
 * Table 1: 10 mm grid, dt = 7e-6 s, t_total = 0.25 s, slope 30 degrees, E
 * = 1 GPa, nu = 0.3, phi = 30 deg, psi = 0, rho_initial = 2250 kg/m^3,
 * rho_cr = 2235 kg/m^3; 4 points per cell. Our choices: the block is 10 x 3
 * cells (0.1 m x 0.03 m) on the floor, 0.02 m from the upper end of a 0.4
 * m long grid, fixed on all sides ("fixed on all the sides"), gravity
 * rotated by the slope; no rate term (sec 2.3 has none); USL as in the
 * paper (the flow never leaves the floor). tests/physics/test_slope_density.c
 * asserts the comparison between families.
 *
 * Prints the average density (total mass / total volume) at the end, a
 * STATS line (points, steps, seconds of the time loop: for bench/chart.sh)
 * and the RESULT line comparing the average density with rho_cr. Output:
 * <out>/slope_density.csv (time, kinetic energy, state counts, components,
 * average density, lowest point density, front position) and
 * <out>/slope_density.pvd.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */

#include <granmpm.h>

#include "common.h"

#include <math.h>
#include <time.h>

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;         /* m/s^2 */
static const double SLOPE = 30.0;           /* deg, Table 1 */
static const double TIME_STEP = 7e-6;       /* s, Table 1 */
static const double DENSITY = 2250.0;       /* kg/m^3 */
static const double CRITICAL = 2235.0;      /* kg/m^3 */
static const double SAMPLE_PERIOD = 0.0025; /* s between CSV rows */
static const double FRAME_PERIOD = 0.01;    /* s between VTU frames */

/* Average density (kg/m^3), lowest point density (kg/m^3), front (m). */
static void measure(const gm_domain *domain, double *average, double *lowest,
                    double *front) {
  const double *mass = NULL, *volume = NULL, *x = NULL;
  gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass);
  gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume);
  gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x);
  double total_mass = 0.0, total_volume = 0.0;
  *lowest = INFINITY, *front = -INFINITY;
  for (size_t p = 0; p < gm_domain_point_count(domain); p++) {
    total_mass += mass[p], total_volume += volume[p];
    *lowest = fmin(*lowest, mass[p] / volume[p]);
    *front = fmax(*front, x[p]);
  }
  *average = total_mass / total_volume;
}

static gm_domain *create_slope(const example_options *options) {
  gm_domain_def def = example_domain_def(options);
  def.extent[0] = 0.4, def.extent[1] = 0.1; /* m */
  double angle = SLOPE * PI / 180.0;        /* rad */
  def.gravity[0] = GRAVITY * sin(angle);
  def.gravity[1] = -GRAVITY * cos(angle);
  for (int face = GM_FACE_XMIN; face <= GM_FACE_YMAX; face++)
    def.walls[face] = GM_WALL_FIXED;
  gm_domain *domain = example_create_domain(&def);
  if (!domain)
    return NULL;
  gm_mohr_coulomb_def soil = gm_mohr_coulomb_def_default(); /* Table 1 */
  soil.bagnold_viscosity = 0.0;
  int material = -1;
  gm_status status = GM_OK;
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL;
  gm_fill_def block = gm_fill_def_default();
  block.lower[0] = 0.02, block.upper[0] = 0.12; /* m */
  block.upper[1] = 0.03;                        /* m */
  block.points_per_cell_axis = options->ppc;
  if ((status = gm_domain_add_mohr_coulomb(domain, &soil, &material)) !=
          GM_OK ||
      (status = gm_domain_set_granular(domain, material, &granular)) != GM_OK ||
      (block.material = material,
       status = gm_domain_fill_box(domain, &block, NULL, NULL)) != GM_OK) {
    example_fail(domain, "setting up the slope", status);
    gm_domain_destroy(domain);
    return NULL;
  }
  return domain;
}

/* example_sample_fn: one CSV row; user is the FILE (NULL: none). */
static gm_status write_row(const gm_domain *domain,
                           const example_run_state *state, void *user) {
  (void)state;
  FILE *csv = user;
  if (!csv)
    return GM_OK;
  double time = 0.0, average = 0.0, lowest = 0.0, front = 0.0;
  gm_domain_get_time(domain, &time, NULL);
  gm_summary summary = gm_summary_default();
  gm_domain_get_summary(domain, &summary);
  gm_granular_summary granular = gm_granular_summary_default();
  gm_domain_get_granular_summary(domain, &granular);
  measure(domain, &average, &lowest, &front);
  fprintf(csv, "%.5f,%.6e,%zu,%zu,%zu,%zu,%.4f,%.4f,%.5f\n", time,
          summary.kinetic_energy, granular.state_count[0],
          granular.state_count[1], granular.state_count[2],
          granular.component_count, average, lowest, front);
  return GM_OK;
}

int main(int argc, char **argv) {
  example_options options = {GM_SHAPE_LINEAR,
                             GM_FAMILY_GRANULAR,
                             2,
                             0.01,
                             1,
                             "out/slope_density",
                             0.25,
                             0};
  int parsed = example_parse(argc, argv,
                             "Average density of a moderate flow down a 30 "
                             "degree slope (000 sec 2.3, Table 1).",
                             &options, NULL, 0);
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  if (example_make_output(&options) != 0)
    return 2;
  gm_domain *domain = create_slope(&options);
  if (!domain)
    return 2;
  example_print_scene(domain);
  FILE *csv = example_open_csv(&options, "slope_density.csv",
                               "time_s,kinetic_energy_J,quasi_static,"
                               "moderate,disconnected,components,"
                               "average_density_kg_m3,lowest_density_kg_m3,"
                               "front_x_m");
  gm_series *series = NULL;
  EXAMPLE_CHECK(
      domain, example_open_series(&options, "slope_density", domain, &series));
  double time = 0.0; /* s */
  struct timespec wall_start, wall_end;
  clock_gettime(CLOCK_MONOTONIC, &wall_start);
  const example_run_schedule schedule = {.stepping = EXAMPLE_ADVANCE,
                                         .sample_times = EXAMPLE_SAMPLE_AFTER,
                                         .t_end = options.t_end,
                                         .sample_period = SAMPLE_PERIOD,
                                         .dt = TIME_STEP,
                                         .series = series,
                                         .frame_period = FRAME_PERIOD,
                                         .on_failure = EXAMPLE_FAILURE_SAMPLE,
                                         .progress = &options,
                                         .sample = write_row,
                                         .user = csv};
  gm_status status = example_run_loop(domain, &schedule, &time);
  if (status != GM_OK)
    printf("FAILED at t = %.4f s: %s (%s)\n", time, gm_strerror(status),
           gm_domain_last_error(domain));
  clock_gettime(CLOCK_MONOTONIC, &wall_end);
  double seconds = (double)(wall_end.tv_sec - wall_start.tv_sec) +
                   1e-9 * (double)(wall_end.tv_nsec - wall_start.tv_nsec);
  size_t points = gm_domain_point_count(domain);
  uint64_t steps = 0;
  gm_domain_get_time(domain, NULL, &steps);
  printf("STATS points=%zu steps=%llu seconds=%.3f ns_per_point_step=%.1f\n",
         points, (unsigned long long)steps, seconds,
         1e9 * seconds / ((double)points * (double)(steps ? steps : 1)));
  double average = 0.0, lowest = 0.0, front = 0.0;
  measure(domain, &average, &lowest, &front);
  printf("slope_density: %s %s, t = %.3f s: average density %.2f kg/m^3, "
         "lowest point %.2f kg/m^3 (rho_0 %.0f, rho_cr %.0f)\n",
         example_shape_name(options.shape), example_family_name(options.family),
         time, average, lowest, DENSITY, CRITICAL);
  example_result("average_density", average, CRITICAL);
  if (csv)
    fclose(csv);
  gm_series_destroy(series);
  gm_domain_destroy(domain);
  return status == GM_OK ? 0 : 3;
}
