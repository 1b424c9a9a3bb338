/*
 * seyedan2021_avalanche.c - the granular avalanche of Seyedan & Solowski 2021
 * (000 sec 4.2, Table 3, Figs 9-13): a granular block slides down an upper
 * plane with an initial velocity of 1 m/s, runs onto a lower plane and stops
 * against a wall at its end. The paper compares plain, stress-free and Granular
 * MPM with original MPM and CPDI; plain and stress-free CPDI stop when a
 * swollen point's corner leaves the grid, Granular CPDI keeps every volume
 * bounded and finishes.
 *
 * Geometry (Fig 9 is not in the text; our reconstruction). As in the paper
 * the lower plane is "horizontal" and gravity is rotated by its inclination
 * (15 degrees, Table 3). The upper plane rises from a kink at x = 2.5 m to
 * the left, 20 degrees steeper than the lower one (35 degrees in reality):
 * the region above both planes is convex, so two planar walls
 * (gm_domain_add_wall) describe it exactly, and a third wall is the end
 * wall. The paper uses no-slip ("fixed") planes; planar walls are Coulomb
 * walls, and we choose mu = 0.3 so that the block accelerates on the upper
 * plane and reaches the end wall (the paper's front reaches it at about
 * 1.2 s). The block is 1.0 m x 0.4 m (10 x 4 cells of 100 mm, 2 x 2 points
 * per cell = 160 points, as in the paper), on a lattice aligned with the
 * upper plane, starting 1 m above the kink.
 *
 * Material (Table 3): Mohr-Coulomb with the Bagnold rate term (eqs 16-17),
 * E = 1 GPa, nu = 0.3, phi = 30 deg, psi = 0, eta = 0.15 Pa s^2,
 * rho_initial = 2250 kg/m^3, rho_cr = 2235 kg/m^3. Time step: the stable
 * one (about 6e-5 s; --dt 1e-5 runs Table 3's, 6 times slower: about four
 * minutes instead of 40 s here). Scheme: MUSL (the library's
 * advice for free surfaces; --scheme usl gives the paper's USL).
 *
 * Prints the average density, the largest volume ratio V/V0 reached and the
 * final front position; the RESULT line is the largest V/V0 against the
 * bound the granular family guarantees, rho_initial / (rho_cr - TOL)
 * (density control, eqs 13-15, keeps every point at rho >= rho_cr - TOL).
 * The paper reports this qualitatively (Fig 10: average density near
 * rho_cr for Granular MPM, a large drop for the others; Fig 12: no volume
 * increase in Granular CPDI). Output: <out>/avalanche.pvd (+ domains for
 * GIMP/CPDI) and <out>/avalanche.csv.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include "common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;        /* m/s^2 */
static const double DENSITY = 2250.0;      /* kg/m^3, Table 3 */
static const double CRITICAL = 2235.0;     /* kg/m^3, Table 3 */
static const double TOLERANCE = 1e-6;      /* kg/m^3, TOL (000 sec 3.2) */
static const double BOX_LENGTH = 5.0;      /* m */
static const double BOX_HEIGHT = 2.5;      /* m */
static const double FLOOR_Y = 0.2;         /* m, lower plane above the face */
static const double KINK_X = 2.5;          /* m, where the planes meet */
static const double END_WALL_X = 4.8;      /* m */
static const double STEEPER = 20.0;        /* deg, upper plane vs lower */
static const double WALL_FRICTION = 0.3;   /* mu, all three walls */
static const double BLOCK_LENGTH = 1.0;    /* m, along the upper plane */
static const double BLOCK_THICKNESS = 0.4; /* m */
static const double BLOCK_START = 1.0;     /* m up the plane from the kink */
static const double START_SPEED = 1.0;     /* m/s, down the upper plane */
static const double SAMPLE_PERIOD = 0.01;  /* s between CSV rows */
static const double FRAME_PERIOD = 0.05;   /* s between VTU frames */

enum { WALL_LOWER = 0, WALL_UPPER = 1, WALL_END = 2, WALL_COUNT = 3 };

/* What the run measured; updated after every step. */
typedef struct avalanche_record {
  double max_volume_ratio; /* largest V/V0 of any point so far */
  FILE *csv;               /* NULL: no CSV */
} avalanche_record;

static double largest_volume_ratio(const gm_domain *domain) {
  const double *volume = NULL, *initial = NULL; /* m^2 per unit thickness */
  size_t count = gm_domain_point_count(domain);
  if (gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume) != GM_OK ||
      gm_domain_view_field(domain, GM_FIELD_INITIAL_VOLUME, 0, &initial) !=
          GM_OK)
    return NAN;
  double largest = 0.0;
  for (size_t p = 0; p < count; p++)
    largest = fmax(largest, volume[p] / initial[p]);
  return largest;
}

/* example_step_fn: tracks the largest V/V0. */
static void track_step(const gm_domain *domain, const example_run_state *state,
                       void *user) {
  (void)state;
  avalanche_record *record = user;
  record->max_volume_ratio =
      fmax(record->max_volume_ratio, largest_volume_ratio(domain));
}

static int add_wall(gm_domain *domain, double x, double y, double normal_x,
                    double normal_y) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = x;
  wall.point[1] = y;
  wall.normal[0] = normal_x;
  wall.normal[1] = normal_y;
  wall.friction_static = wall.friction_kinetic = WALL_FRICTION;
  int id = -1;
  gm_status status = gm_domain_add_wall(domain, &wall, &id);
  return status == GM_OK ? id : -1;
}

/* The lower plane, the upper plane rising left of the kink, the end wall;
 * ids WALL_LOWER, WALL_UPPER, WALL_END. */
static int add_planes(gm_domain *domain) {
  double steeper = STEEPER * PI / 180.0; /* rad */
  if (add_wall(domain, 0.0, FLOOR_Y, 0.0, 1.0) != WALL_LOWER ||
      add_wall(domain, KINK_X, FLOOR_Y, sin(steeper), cos(steeper)) !=
          WALL_UPPER ||
      add_wall(domain, END_WALL_X, 0.0, -1.0, 0.0) != WALL_END)
    return -1;
  return 0;
}

/* The block: a lattice aligned with the upper plane, moving down it. */
static gm_status add_block(gm_domain *domain, int material, int ppc,
                           double cell) {
  double steeper = STEEPER * PI / 180.0;               /* rad */
  double up[2] = {-cos(steeper), sin(steeper)};        /* along the plane */
  double out[2] = {sin(steeper), cos(steeper)};        /* plane normal */
  double spacing = cell / ppc;                         /* m */
  int along = (int)lround(BLOCK_LENGTH / spacing);     /* points */
  int across = (int)lround(BLOCK_THICKNESS / spacing); /* points */
  size_t count = (size_t)along * (size_t)across;
  double *position = malloc(2 * count * sizeof *position); /* m */
  double *velocity = malloc(2 * count * sizeof *velocity); /* m/s */
  double *volume = malloc(count * sizeof *volume); /* m^2 per thickness */
  if (!position || !velocity || !volume) {
    free(position), free(velocity), free(volume);
    return GM_ERR_NO_MEMORY;
  }
  for (size_t p = 0; p < count; p++) {
    double s = BLOCK_START + ((double)(p % (size_t)along) + 0.5) * spacing;
    double n = ((double)(p / (size_t)along) + 0.5) * spacing;
    for (int k = 0; k < 2; k++) {
      position[2 * p + k] = (k ? FLOOR_Y : KINK_X) + s * up[k] + n * out[k];
      velocity[2 * p + k] = -START_SPEED * up[k];
    }
    volume[p] = spacing * spacing;
  }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  gm_status status = gm_domain_add_points(domain, &points, NULL);
  free(position), free(velocity), free(volume);
  return status;
}

static gm_status add_granular_material(gm_domain *domain, double youngs,
                                       int *material) {
  gm_mohr_coulomb_def soil = gm_mohr_coulomb_def_default(); /* Table 3 */
  soil.youngs_modulus = youngs;
  soil.density = DENSITY;
  gm_status status = gm_domain_add_mohr_coulomb(domain, &soil, material);
  if (status != GM_OK)
    return status;
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL;
  granular.tolerance = TOLERANCE;
  return gm_domain_set_granular(domain, *material, &granular);
}

/* Average density (kg/m^3, total mass / total volume) and the largest x
 * of any point (m). */
static void measure(const gm_domain *domain, double *average, double *front) {
  const double *mass = NULL, *volume = NULL, *x = NULL;
  size_t count = gm_domain_point_count(domain);
  gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass);
  gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume);
  gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x);
  double total_mass = 0.0, total_volume = 0.0;
  *front = -INFINITY;
  for (size_t p = 0; p < count; p++) {
    total_mass += mass[p];
    total_volume += volume[p];
    *front = fmax(*front, x[p]);
  }
  *average = total_mass / total_volume;
}

/* example_sample_fn: one CSV row to the record's CSV (NULL: none). */
static gm_status write_row(const gm_domain *domain,
                           const example_run_state *state, void *user) {
  (void)state;
  FILE *csv = ((const avalanche_record *)user)->csv;
  if (!csv)
    return GM_OK;
  double time = 0.0, average = 0.0, front = 0.0;
  gm_domain_get_time(domain, &time, NULL);
  gm_summary summary = gm_summary_default();
  gm_domain_get_summary(domain, &summary);
  gm_granular_summary granular = gm_granular_summary_default();
  gm_domain_get_granular_summary(domain, &granular);
  measure(domain, &average, &front);
  fprintf(csv, "%.5f,%.6e,%zu,%zu,%zu,%zu,%.3f,%.6f,%.4f", time,
          summary.kinetic_energy, granular.state_count[0],
          granular.state_count[1], granular.state_count[2],
          granular.component_count, average, largest_volume_ratio(domain),
          front);
  for (int wall = 0; wall < WALL_COUNT; wall++) {
    gm_wall_force force = gm_wall_force_default();
    gm_domain_get_wall_force(domain, wall, &force);
    /* Smoothed (gm_walls(3)): the step that ends a row may be short. */
    fprintf(csv, ",%.4e,%.4e", force.smoothed_normal,
            force.smoothed_tangential);
  }
  fprintf(csv, "\n");
  return GM_OK;
}

static gm_domain *create_domain(const example_options *options,
                                const char *scheme, double slope) {
  gm_domain_def def = example_domain_def(options);
  def.extent[0] = BOX_LENGTH;
  def.extent[1] = BOX_HEIGHT;
  double angle = slope * PI / 180.0; /* rad */
  def.gravity[0] = GRAVITY * sin(angle);
  def.gravity[1] = -GRAVITY * cos(angle);
  for (int face = GM_FACE_XMIN; face <= GM_FACE_YMAX; face++)
    def.walls[face] = GM_WALL_FIXED; /* "fixed on all the sides" */
  /* The lower plane and the end wall lie 0.2 m inside the ymin and xmax
   * faces, and the B-splines mirror a fixed face: gm_domain_add_wall
   * refuses a parallel wall less than 1.5 (2) cells from it, whose friction
   * the mirror would undo (gm_walls(3)), as 0.2 m is on cells over 0.133
   * (0.1) m. With them the faces behind those walls are left open; no
   * material reaches them. */
  if (options->shape == GM_SHAPE_BSPLINE2 ||
      options->shape == GM_SHAPE_BSPLINE3)
    def.walls[GM_FACE_YMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_OPEN;
  def.scheme = example_scheme(scheme);
  return example_create_domain(&def);
}

/* Runs to t_end writing samples and frames; returns the status of the
 * first failed step (GM_OK if none). */
static gm_status run(gm_domain *domain, const example_options *options,
                     double dt, gm_series *series, avalanche_record *record) {
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
      GM_SHAPE_CPDI, GM_FAMILY_GRANULAR, 2, 0.1, 1, "out/avalanche", 3.0, 0};
  double dt = 0.0, slope = 15.0, youngs = 1e9; /* s, deg, Pa: Table 3 */
  const char *scheme = "musl";
  const example_extra extras[] = {
      {"dt", "time step, s (<= 0: the stable step)", &dt, NULL},
      {"slope", "inclination of the lower plane, degrees", &slope, NULL},
      {"youngs", "Young's modulus of the granular material, Pa", &youngs, NULL},
      {"scheme", "update scheme usl|musl|usf", NULL, &scheme}};
  int parsed = example_parse(argc, argv,
                             "Granular avalanche of 000 sec 4.2: a block "
                             "down two planes against a wall.",
                             &options, extras, 4);
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  if (example_make_output(&options) != 0)
    return 2;
  gm_domain *domain = create_domain(&options, scheme, slope);
  if (!domain)
    return 2;
  int material = -1;
  EXAMPLE_CHECK(domain, add_granular_material(domain, youngs, &material));
  if (add_planes(domain) != 0)
    return example_fail(domain, "add_planes", GM_ERR_INVALID_ARGUMENT);
  EXAMPLE_CHECK(domain, add_block(domain, material, options.ppc, options.cell));
  example_print_scene(domain);
  FILE *csv = example_open_csv(
      &options, "avalanche.csv",
      "time_s,kinetic_energy_J,quasi_static,moderate,disconnected,"
      "components,average_density_kg_m3,max_volume_ratio,front_x_m,"
      "lower_normal_N,lower_tangential_N,upper_normal_N,"
      "upper_tangential_N,end_normal_N,end_tangential_N");
  gm_series *series = NULL;
  EXAMPLE_CHECK(domain,
                example_open_series(&options, "avalanche", domain, &series));
  avalanche_record record = {1.0, csv};
  gm_status status = run(domain, &options, dt, series, &record);
  double time = 0.0, average = 0.0, front = 0.0;
  gm_domain_get_time(domain, &time, NULL);
  measure(domain, &average, &front);
  printf("avalanche: %s %s, %zu points, t = %.3f s\n",
         example_shape_name(options.shape), example_family_name(options.family),
         gm_domain_point_count(domain), time);
  if (status != GM_OK)
    printf("FAILED at t = %.4f s: %s (%s)\n", time, gm_strerror(status),
           gm_domain_last_error(domain));
  printf("average density %.2f kg/m^3 (rho_cr %.0f), front x = %.3f m "
         "(end wall %.1f m)\n",
         average, CRITICAL, front, END_WALL_X);
  example_result("max_volume_ratio", record.max_volume_ratio,
                 DENSITY / (CRITICAL - TOLERANCE));
  if (csv)
    fclose(csv);
  gm_series_destroy(series);
  gm_domain_destroy(domain);
  return status == GM_OK ? 0 : 3;
}
