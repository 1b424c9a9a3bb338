/*
 * column_collapse_3d.c - granular column collapse in three dimensions
 * (GM_GEOMETRY_3D, docs/3d.md) against the axisymmetric law of Lube,
 * Huppert, Sparks & Hallworth (2004, JFM 508:175; examples/collapse_laws.h):
 *   run-out       (r_inf - R0)/R0 ~ 1.24 a for a <~ 1.7, ~ 1.6 a^(1/2) above,
 *   final height  H_inf/R0 ~ a, then ~ 0.88 a^(1/6) (recalled),
 * a = H0/R0, and against the library's own axisymmetric run of the same
 * column (examples/column_collapse --geometry axisym: issue 16 item 3).
 *
 * Scene: a column of height H0 = a R0 on a floor at z = 0 collapses under
 * gravity (-z) when released at t = 0. --section cylinder: a circular
 * cylinder of radius R0 = --length; --section square: a square column of
 * half-width L0 = --length. Only the quarter x >= 0, y >= 0 is simulated:
 * the planes x = 0 and y = 0 are symmetry planes of both columns and of
 * their collapse, and slip box faces (normal velocity zero, no friction)
 * are exactly those symmetry conditions. The floor: --floor wall, a planar
 * wall at z = 0 with Coulomb friction --floor-mu (gm_walls(3); in 3D
 * planar walls take every shape, the B-splines since 2026-11-29 on this
 * open floor face); --floor face,
 * the fixed (no-slip) box face, which every 3D shape takes.
 *
 * Material: by default docs/convergence.md sec. 20's recommended setting,
 * Perzyna Drucker-Prager (001 sec 5.1.1) with psi = 0, N = 1, fluidity 300
 * 1/s, reference stress 1795 Pa, its cone matched to phi = 37 degrees in
 * plane strain exactly as examples/column_collapse does (matched_cone_
 * friction there; kept the same so that the 3D and axisymmetric runs use
 * one material), floor friction 0.45, the plain family (--family granular
 * runs the granular method, rho_cr = 2235/2250 rho as in 2D). E = 0.5 MPa, nu =
 * 0.3, rho = 1800 kg/m^3 as in the 2D example.
 *
 * Measured: the deposit is the points connected to the column's axis, cut
 * at the first empty radial shell one cell wide (grains thrown ahead are
 * left out, as column_collapse does along x). Fronts are edges: the
 * outermost point centre plus half a point spacing.
 *  - cylinder: the radial front in each of SECTOR_COUNT sectors of the
 *    quarter, averaged (RESULT runout; the farthest sector also printed);
 *  - square: the front along the side (points within a cell of the
 *    symmetry plane y = 0, front in x) and along the diagonal (points
 *    within a cell of x = y, front in (x + y)/sqrt 2), each as
 *    (front_inf - front_0)/L0;
 * run-outs are (front_inf - front_0)/R0 with front_0 the same measure at
 * t = 0 (R0 along the axes; the lattice's staircase elsewhere); the
 * height is the deposit's top over R0.
 *
 * Output in --out (default out/column_collapse_3d): collapse.pvd + VTU
 * frames (with the point domains for GIMP), collapse.csv (time, kinetic
 * energy, fronts, height), profile.png (the deposit's height along x near
 * y = 0 and along the diagonal, at t = 0 and at the end, with the law's
 * run-out) and top.png (the deposit seen from above, coloured by height);
 * both need gnuplot. RESULT lines last, the run-out the very last.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L /* popen, pclose, clock_gettime */

#include <granmpm.h>

#include "collapse_laws.h"
#include "collapse_material.h"
#include "common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;   /* m/s^2 */
static const double DENSITY = 1800.0; /* kg/m^3, column_collapse's sand */
static const double CRITICAL_RATIO = 2235.0 / 2250.0; /* 000 Table 1 */
static const double POISSON_RATIO = 0.3;
enum { ROW_COUNT = 100, ROWS_PER_FRAME = 10, SECTOR_COUNT = 6 };

typedef struct scene3d {
  double length;         /* R0 (cylinder) or half-width L0 (square), m */
  double aspect;         /* a = H0 / length */
  double height;         /* H0, m */
  double tau_c;          /* sqrt(H0 / g), s */
  double spacing;        /* point spacing, m */
  double extent_xy;      /* grid box along x and y, m */
  double extent_z;       /* along z, m */
  const char *section;   /* cylinder | square */
  int square;            /* nonzero for the square column */
  const char *material;  /* perzyna | mohr_coulomb | drucker_prager */
  double friction_deg;   /* phi, degrees */
  double youngs_modulus; /* E, Pa */
  double floor_mu;       /* Coulomb friction of the floor wall */
  const char *floor;     /* wall | face */
  double fluidity;       /* perzyna gamma, 1/s */
  double reference;      /* perzyna sigma_n floor, Pa */
  const char *scheme;    /* usl | musl | usf */
} scene3d;

/* The deposit at one instant (m). */
typedef struct deposit3d {
  double sector_mean; /* mean over the sectors of their radial front */
  double sector_max;  /* the farthest sector's front */
  double side;        /* front in x near y = 0 */
  double diagonal;    /* front along x = y, (x + y) / sqrt 2 */
  double height;      /* top of the deposit */
  double kinetic;     /* J, the quarter's kinetic energy */
} deposit3d;

typedef struct run3d {
  example_options *options;
  const scene3d *scene;
  gm_domain *domain;
  int floor_wall;
  double *positions, *velocities, *masses; /* scratch */
  unsigned char *shells;                   /* scratch, one per radial cell */
  size_t shell_count;
  deposit3d start, last;
  double late_front; /* sector mean at 90 % of the run, m */
  FILE *csv;
  gm_series *series;
} run3d;

static double seconds_now(void) {
  struct timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

/* Registers the material; returns its id or -1. */
static int add_material(gm_domain *domain, const scene3d *scene) {
  int material = -1;
  gm_status status;
  double phi = scene->friction_deg * PI / 180.0;
  if (strcmp(scene->material, "perzyna") == 0) {
    gm_perzyna_def def = gm_perzyna_def_default();
    def.youngs_modulus = scene->youngs_modulus;
    def.poisson_ratio = POISSON_RATIO;
    def.density = DENSITY;
    def.friction_angle = collapse_matched_cone_friction(phi);
    def.exponent = 1.0;
    def.fluidity = scene->fluidity;
    def.reference_stress = scene->reference;
    status = gm_domain_add_perzyna(domain, &def, &material);
  } else if (strcmp(scene->material, "mohr_coulomb") == 0) {
    gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
    def.youngs_modulus = scene->youngs_modulus;
    def.poisson_ratio = POISSON_RATIO;
    def.density = DENSITY;
    def.friction_angle = phi;
    def.bagnold_viscosity = 0.0; /* rate-free, as column_collapse */
    status = gm_domain_add_mohr_coulomb(domain, &def, &material);
  } else if (strcmp(scene->material, "drucker_prager") == 0) {
    gm_drucker_prager_def def = gm_drucker_prager_def_default();
    def.youngs_modulus = scene->youngs_modulus;
    def.poisson_ratio = POISSON_RATIO;
    def.density = DENSITY;
    def.friction_angle = phi;
    status = gm_domain_add_drucker_prager(domain, &def, &material);
  } else {
    fprintf(stderr,
            "--material: '%s' is not perzyna, mohr_coulomb or "
            "drucker_prager\n",
            scene->material);
    return -1;
  }
  if (status != GM_OK) {
    example_fail(domain, "adding the material", status);
    return -1;
  }
  /* The granular family's critical density, as examples/column_collapse
   * sets it (000 Table 1's ratio; the plain family does not read it).
   * Without it --family granular ran the plain family's digits: no point
   * of a material without granular settings takes part in the method. */
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL_RATIO * DENSITY;
  status = gm_domain_set_granular(domain, material, &granular);
  if (status != GM_OK) {
    example_fail(domain, "gm_domain_set_granular", status);
    return -1;
  }
  return material;
}

/* The quarter column's points: a lattice of spacing s, centres at
 * (i + 1/2) s; the cylinder keeps the centres with x^2 + y^2 < R0^2. */
static int add_column(run3d *run, int material) {
  const scene3d *scene = run->scene;
  double s = scene->spacing;
  size_t across = (size_t)llround(scene->length / s);
  size_t up = (size_t)llround(scene->height / s);
  double *position = malloc(3 * across * across * up * sizeof *position);
  double *volume = malloc(across * across * up * sizeof *volume);
  if (!position || !volume) {
    free(position);
    free(volume);
    fprintf(stderr, "out of memory\n");
    return 2;
  }
  size_t count = 0;
  for (size_t k = 0; k < up; k++)
    for (size_t j = 0; j < across; j++)
      for (size_t i = 0; i < across; i++) {
        double x = (i + 0.5) * s, y = (j + 0.5) * s, z = (k + 0.5) * s;
        if (!scene->square && x * x + y * y >= scene->length * scene->length)
          continue;
        position[3 * count] = x;
        position[3 * count + 1] = y;
        position[3 * count + 2] = z;
        volume[count++] = s * s * s;
      }
  gm_points_def def = gm_points_def_default();
  def.count = count;
  def.material = material;
  def.position = position;
  def.volume = volume;
  gm_status status = gm_domain_add_points(run->domain, &def, NULL);
  free(position);
  free(volume);
  if (status != GM_OK)
    return example_fail(run->domain, "gm_domain_add_points", status);
  return 0;
}

/* The domain: the quarter box, slip x = 0 and y = 0 faces, the floor. */
static int build_scene(run3d *run) {
  const scene3d *scene = run->scene;
  gm_domain_def def = example_domain_def(run->options);
  def.geometry = GM_GEOMETRY_3D;
  def.extent[0] = def.extent[1] = scene->extent_xy;
  def.extent[2] = scene->extent_z;
  def.gravity[2] = -GRAVITY;
  def.scheme = example_scheme(scene->scheme);
  def.walls[GM_FACE_XMIN] = GM_WALL_SYMMETRY; /* symmetry planes */
  def.walls[GM_FACE_YMIN] = GM_WALL_SYMMETRY;
  int face_floor = strcmp(scene->floor, "face") == 0;
  if (!face_floor && strcmp(scene->floor, "wall") != 0) {
    fprintf(stderr, "--floor: '%s' is not wall or face\n", scene->floor);
    return 2;
  }
  if (face_floor)
    def.walls[GM_FACE_ZMIN] = GM_WALL_FIXED;
  EXAMPLE_CHECK(NULL, gm_domain_create(&def, &run->domain));
  int material = add_material(run->domain, scene);
  if (material < 0)
    return 2;
  run->floor_wall = -1;
  if (!face_floor) {
    gm_wall_def wall = gm_wall_def_default();
    wall.normal[0] = 0.0;
    wall.normal[1] = 0.0;
    wall.normal[2] = 1.0;
    wall.friction_static = wall.friction_kinetic = scene->floor_mu;
    EXAMPLE_CHECK(run->domain,
                  gm_domain_add_wall(run->domain, &wall, &run->floor_wall));
  }
  return add_column(run, material);
}

/* Fetches positions (and velocities, masses when asked); 0 on success. */
static int fetch(run3d *run, int with_motion) {
  size_t count = gm_domain_point_count(run->domain);
  if (gm_domain_get_field(run->domain, GM_FIELD_POSITION, run->positions,
                          3 * count) != GM_OK)
    return 1;
  if (!with_motion)
    return 0;
  if (gm_domain_get_field(run->domain, GM_FIELD_VELOCITY, run->velocities,
                          3 * count) != GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_MASS, run->masses, count) !=
          GM_OK)
    return 1;
  return 0;
}

/* The radius (m) below which the deposit is connected: the first radial
 * shell one cell wide that holds no point ends it. */
static double connected_radius(run3d *run, size_t count) {
  double cell = run->options->cell;
  memset(run->shells, 0, run->shell_count);
  for (size_t i = 0; i < count; i++) {
    double r = hypot(run->positions[3 * i], run->positions[3 * i + 1]);
    double shell = floor(r / cell);
    if (shell >= 0.0 && shell < (double)run->shell_count)
      run->shells[(size_t)shell] = 1;
  }
  size_t first_empty = 0;
  while (first_empty < run->shell_count && run->shells[first_empty])
    first_empty++;
  return (double)first_empty * cell;
}

/* The fronts and top of the connected deposit (see the top of the file)
 * and the kinetic energy. */
static deposit3d measure(run3d *run) {
  deposit3d result = {0};
  if (fetch(run, 1) != 0)
    return result;
  size_t count = gm_domain_point_count(run->domain);
  double cell = run->options->cell, half = 0.5 * run->scene->spacing;
  double limit = connected_radius(run, count);
  double sector[SECTOR_COUNT] = {0};
  for (size_t i = 0; i < count; i++) {
    double x = run->positions[3 * i], y = run->positions[3 * i + 1],
           z = run->positions[3 * i + 2];
    const double *v = run->velocities + 3 * i;
    result.kinetic +=
        0.5 * run->masses[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double r = hypot(x, y);
    if (r >= limit)
      continue;
    result.height = fmax(result.height, z + half);
    double angle = atan2(y, x); /* 0 .. pi/2 */
    int k = (int)(angle / (0.5 * PI) * SECTOR_COUNT);
    k = k < 0 ? 0 : (k >= SECTOR_COUNT ? SECTOR_COUNT - 1 : k);
    sector[k] = fmax(sector[k], r + half);
    if (y < cell)
      result.side = fmax(result.side, x + half);
    if (fabs(x - y) < cell)
      result.diagonal = fmax(result.diagonal, (x + y) / sqrt(2.0) + half);
  }
  for (int k = 0; k < SECTOR_COUNT; k++) {
    result.sector_mean += sector[k] / SECTOR_COUNT;
    result.sector_max = fmax(result.sector_max, sector[k]);
  }
  return result;
}

/* The deposit's height (top of the points plus half a spacing) in bins of
 * one cell along x near y = 0 and along the diagonal, into a data file
 * for gnuplot: columns distance (m), side height, diagonal height (m;
 * 0 where the bin is empty). Returns 0 on success. */
static int write_profile(run3d *run, const char *path) {
  if (fetch(run, 0) != 0)
    return 1;
  size_t count = gm_domain_point_count(run->domain);
  double cell = run->options->cell, half = 0.5 * run->scene->spacing;
  size_t bins = run->shell_count;
  double *side = calloc(2 * bins, sizeof *side);
  if (!side)
    return 1;
  double *diagonal = side + bins;
  for (size_t i = 0; i < count; i++) {
    double x = run->positions[3 * i], y = run->positions[3 * i + 1],
           z = run->positions[3 * i + 2];
    if (y < cell) {
      size_t b = (size_t)(x / cell);
      if (b < bins)
        side[b] = fmax(side[b], z + half);
    }
    if (fabs(x - y) < cell) {
      size_t b = (size_t)((x + y) / sqrt(2.0) / cell);
      if (b < bins)
        diagonal[b] = fmax(diagonal[b], z + half);
    }
  }
  FILE *file = fopen(path, "w");
  if (file) {
    for (size_t b = 0; b < bins; b++)
      fprintf(file, "%g %g %g\n", (b + 0.5) * cell, side[b], diagonal[b]);
    fclose(file);
  }
  free(side);
  return file ? 0 : 1;
}

/* profile.png: the height profiles at t = 0 and at the end, the law's
 * run-out marked; top.png: the final deposit from above. */
static void write_pictures(run3d *run) {
  const example_options *options = run->options;
  const scene3d *scene = run->scene;
  if (!options->out[0] || system("command -v gnuplot > /dev/null 2>&1") != 0) {
    if (options->out[0])
      fprintf(stderr, "gnuplot not found: no PNG (apt-get install "
                      "gnuplot-nox)\n");
    return;
  }
  char path[1200];
  snprintf(path, sizeof path, "%s/profile_end.dat", options->out);
  if (write_profile(run, path) != 0)
    return;
  double law_front = scene->length * (1.0 + lube2004_runout(scene->aspect));
  double range = fmin(scene->extent_xy, 1.3 * law_front + scene->length);
  FILE *plot = popen("gnuplot", "w");
  if (!plot)
    return;
  double time = 0.0;
  gm_domain_get_time(run->domain, &time, NULL);
  fprintf(plot, "set terminal pngcairo size 1200,500 font 'sans,11'\n");
  fprintf(plot, "set output '%s/profile.png'\n", options->out);
  fprintf(plot,
          "set title '3D %s column collapse, a = %g, %s = %g m: deposit height "
          "at t = %.3f s = %.1f tau_c (%s, cell %g m)'\n",
          scene->section, scene->aspect, scene->square ? "L0" : "R0",
          scene->length, time, time / scene->tau_c,
          example_shape_name(options->shape), options->cell);
  fprintf(plot, "set xlabel 'distance from the axis (m)'\nset ylabel "
                "'height (m)'\nset size ratio -1\nset key top right\n");
  fprintf(plot, "set xrange [0:%g]\nset yrange [0:%g]\n", range,
          1.15 * scene->height);
  fprintf(plot,
          "set arrow from %g,0 to %g,%g nohead dt 2 lc rgb 'black'\n"
          "set label 'Lube et al. 2004 run-out%s' at %g,%g\n",
          law_front, law_front, 0.5 * scene->height,
          scene->square ? " (cylinder, R0 = L0)" : "", law_front,
          0.55 * scene->height);
  fprintf(plot,
          "plot '%s/profile_start.dat' using 1:($2 > 0 ? $2 : 1/0) with "
          "histeps lw 1.5 lc rgb 'black' dt 2 title 't = 0 along x', "
          "'%s/profile_start.dat' using 1:($3 > 0 ? $3 : 1/0) with "
          "histeps lw 1.5 lc rgb 'gray50' dt 3 title 't = 0 along the "
          "diagonal', "
          "'%s' using 1:($2 > 0 ? $2 : 1/0) with histeps lw 2 lc rgb "
          "'#1f77b4' title 'along x (y < one cell)', "
          "'%s' using 1:($3 > 0 ? $3 : 1/0) with histeps lw 2 lc rgb "
          "'#d62728' title 'along the diagonal x = y'\n",
          options->out, options->out, path, path);
  pclose(plot);
  plot = popen("gnuplot", "w");
  if (!plot || fetch(run, 0) != 0) {
    if (plot)
      pclose(plot);
    return;
  }
  size_t count = gm_domain_point_count(run->domain);
  fprintf(plot, "set terminal pngcairo size 900,800 font 'sans,11'\n");
  fprintf(plot, "set output '%s/top.png'\n", options->out);
  fprintf(plot,
          "set title 'deposit from above at t = %.3f s (quarter x, y >= 0; "
          "dashed: Lube et al. 2004 run-out)'\n",
          time);
  fprintf(plot, "set xlabel 'x (m)'\nset ylabel 'y (m)'\nset size ratio -1\n");
  double top_range = 1.15 * fmax(law_front, run->last.sector_max);
  fprintf(plot, "set xrange [0:%g]\nset yrange [0:%g]\n", top_range, top_range);
  fprintf(plot, "set cblabel 'height z (m)'\nset palette rgb 33,13,10\n");
  fprintf(plot, "set parametric\nset trange [0:pi/2]\n");
  fprintf(plot,
          "plot '-' using 1:2:3 with points pt 7 ps 0.4 lc palette notitle, "
          "%g*cos(t),%g*sin(t) with lines dt 2 lc rgb 'black' notitle\n",
          law_front, law_front);
  for (size_t i = 0; i < count; i++)
    fprintf(plot, "%g %g %g\n", run->positions[3 * i],
            run->positions[3 * i + 1], run->positions[3 * i + 2]);
  fprintf(plot, "e\n");
  if (pclose(plot) != 0)
    fprintf(stderr, "gnuplot failed on top.png\n");
}

/* example_sample_fn: one CSV row per interval (0: the start). */
static gm_status sample_row(const gm_domain *domain,
                            const example_run_state *state, void *user) {
  (void)domain;
  run3d *run = user;
  run->last = measure(run);
  if (state->interval == 0)
    run->start = run->last;
  if (state->interval == ROW_COUNT - ROW_COUNT / 10)
    run->late_front = run->last.sector_mean;
  if (run->csv)
    fprintf(run->csv, "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", state->time,
            run->last.kinetic, run->last.sector_mean, run->last.sector_max,
            run->last.side, run->last.diagonal, run->last.height);
  return GM_OK;
}

static int open_outputs(run3d *run) {
  const example_options *options = run->options;
  if (!options->out[0])
    return 0;
  if (example_make_output(options) != 0)
    return 2;
  run->csv = example_open_csv(options, "collapse.csv",
                              "time_s,kinetic_energy_J,front_sector_mean_m,"
                              "front_sector_max_m,front_side_m,front_"
                              "diagonal_m,height_m");
  char path[1200];
  snprintf(path, sizeof path, "%s/collapse.pvd", options->out);
  EXAMPLE_CHECK(NULL, gm_series_create(path, &run->series));
  if (options->shape != GM_SHAPE_LINEAR)
    EXAMPLE_CHECK(NULL, gm_series_set_domains(run->series, 1));
  snprintf(path, sizeof path, "%s/profile_start.dat", options->out);
  write_profile(run, path);
  return 0;
}

static int run_collapse(run3d *run) {
  const example_run_schedule schedule = {.stepping = EXAMPLE_ADVANCE,
                                         .sample_times = EXAMPLE_SAMPLE_SPLIT,
                                         .t_end = run->options->t_end,
                                         .sample_count = ROW_COUNT,
                                         .sample_at_start = 1,
                                         .series = run->series,
                                         .frame_every = ROWS_PER_FRAME,
                                         .on_failure = EXAMPLE_FAILURE_STOP,
                                         .progress = run->options,
                                         .sample = sample_row,
                                         .user = run};
  gm_status status = example_run_loop(run->domain, &schedule, NULL);
  return status == GM_OK
             ? 0
             : example_fail(run->domain, "example_run_loop", status);
}

/* Run-out of one front measure, (front_inf - front_0) / length. */
static double runout(const run3d *run, double start, double end) {
  return (end - start) / run->scene->length;
}

static void report(run3d *run, double seconds) {
  const scene3d *scene = run->scene;
  size_t points = gm_domain_point_count(run->domain);
  uint64_t steps = 0;
  gm_domain_get_time(run->domain, NULL, &steps);
  const deposit3d *s = &run->start, *e = &run->last;
  if (e->sector_mean - run->late_front > 0.01 * scene->length)
    printf("note: the front still moved %.3g R0 in the last 10 %% of the "
           "run; try a longer --t-end\n",
           (e->sector_mean - run->late_front) / scene->length);
  if (e->sector_max > scene->extent_xy - 2.0 * run->options->cell)
    printf("note: the deposit reached the end of the grid\n");
  printf("STATS points=%zu steps=%llu seconds=%.3f ns_per_point_step=%.1f\n",
         points, (unsigned long long)steps, seconds,
         1e9 * seconds / ((double)points * (double)(steps ? steps : 1)));
  double law = lube2004_runout(scene->aspect);
  example_result("final_height_over_R0", e->height / scene->length,
                 lube2004_final_height(scene->aspect));
  example_result("runout_side", runout(run, s->side, e->side), law);
  example_result("runout_diagonal", runout(run, s->diagonal, e->diagonal), law);
  example_result("runout_farthest_sector",
                 runout(run, s->sector_max, e->sector_max), law);
  /* The square column has no axisymmetric law: its side and diagonal are
   * printed against the cylinder's law with R0 = L0, for scale only. */
  example_result(scene->square ? "runout_sector_mean_square" : "runout",
                 runout(run, s->sector_mean, e->sector_mean), law);
}

static int size_scene(scene3d *scene, run3d *run) {
  const example_options *options = run->options;
  if (!(scene->aspect > 0.0) || !(scene->length > 0.0)) {
    fprintf(stderr, "--aspect and --length must be > 0\n");
    return 2;
  }
  scene->square = strcmp(scene->section, "square") == 0;
  if (!scene->square && strcmp(scene->section, "cylinder") != 0) {
    fprintf(stderr, "--section: '%s' is not cylinder or square\n",
            scene->section);
    return 2;
  }
  scene->height = scene->aspect * scene->length;
  scene->tau_c = sqrt(scene->height / GRAVITY);
  scene->spacing = options->cell / options->ppc;
  double across = scene->length / scene->spacing,
         up = scene->height / scene->spacing;
  if (fabs(across - round(across)) > 1e-6 || fabs(up - round(up)) > 1e-6) {
    fprintf(stderr,
            "--length (%g m) and H0 = a --length (%g m) must be multiples "
            "of the point spacing --cell / --ppc (%g m)\n",
            scene->length, scene->height, scene->spacing);
    return 2;
  }
  /* Room for a run-out twice the law's (the diagonal of the square goes
   * sqrt 2 further); the top leaves room for the point domains. */
  scene->extent_xy =
      scene->length * (1.5 + 2.0 * lube2004_runout(scene->aspect));
  scene->extent_z = 1.25 * scene->height + 4.0 * options->cell;
  run->shell_count =
      (size_t)ceil(sqrt(2.0) * scene->extent_xy / options->cell) + 2;
  return 0;
}

static int allocate_scratch(run3d *run) {
  size_t count = gm_domain_point_count(run->domain);
  run->positions = malloc(3 * count * sizeof *run->positions);
  run->velocities = malloc(3 * count * sizeof *run->velocities);
  run->masses = malloc(count * sizeof *run->masses);
  run->shells = malloc(run->shell_count);
  if (!run->positions || !run->velocities || !run->masses || !run->shells) {
    fprintf(stderr, "out of memory\n");
    return 2;
  }
  return 0;
}

static void release(run3d *run) {
  if (run->csv)
    fclose(run->csv);
  gm_series_destroy(run->series);
  gm_domain_destroy(run->domain);
  free(run->positions);
  free(run->velocities);
  free(run->masses);
  free(run->shells);
}

int main(int argc, char **argv) {
  example_options options = {GM_SHAPE_LINEAR,
                             GM_FAMILY_PLAIN,
                             2,
                             0.0125,
                             1,
                             "out/column_collapse_3d",
                             0.0,
                             0};
  scene3d scene = {0};
  scene.length = 0.1;
  scene.aspect = 1.0;
  scene.section = "cylinder";
  scene.material = "perzyna";
  scene.friction_deg = 37.0;
  scene.youngs_modulus = 5e5;
  scene.floor_mu = 0.45;
  scene.floor = "wall";
  scene.fluidity = 300.0;
  scene.reference = 1795.0;
  scene.scheme = "usl";
  const example_extra extras[] = {
      {"aspect", "aspect ratio a = H0 / --length", &scene.aspect, NULL},
      {"length", "cylinder radius R0 or square half-width L0, m", &scene.length,
       NULL},
      {"section", "cylinder | square", NULL, &scene.section},
      {"material",
       "perzyna (cone matched to --friction in plane strain, psi = 0, "
       "N = 1) | mohr_coulomb | drucker_prager",
       NULL, &scene.material},
      {"friction", "friction angle phi of the material, deg",
       &scene.friction_deg, NULL},
      {"youngs", "Young's modulus E, Pa", &scene.youngs_modulus, NULL},
      {"floor",
       "wall (Coulomb planar wall on the open floor face, any method) | "
       "face (no-slip box face, any method)",
       NULL, &scene.floor},
      {"floor-mu", "Coulomb friction of the floor wall", &scene.floor_mu, NULL},
      {"fluidity", "perzyna: fluidity gamma, 1/s", &scene.fluidity, NULL},
      {"reference-stress",
       "perzyna: sigma_n = max(m p, this) normalises the overstress, Pa",
       &scene.reference, NULL},
      {"scheme", "update scheme usl|musl|usf", NULL, &scene.scheme}};
  int parsed = example_parse(
      argc, argv,
      "Granular column collapse in 3D (a quarter column between two slip\n"
      "symmetry faces), cylinder or square, against Lube et al. (2004) and\n"
      "examples/column_collapse --geometry axisym. The defaults are the\n"
      "family and method 3D runs with a Coulomb floor (plain, linear).\n"
      "--t-end 0 (the default) runs 6 tau_c, tau_c = sqrt(H0/g).",
      &options, extras, (int)(sizeof extras / sizeof extras[0]));
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  run3d run = {0};
  run.options = &options;
  run.scene = &scene;
  int status = size_scene(&scene, &run);
  if (options.t_end <= 0.0)
    options.t_end = 6.0 * scene.tau_c;
  if (status == 0)
    status = build_scene(&run);
  if (status == 0) {
    example_print_scene(run.domain);
    status = allocate_scratch(&run);
  }
  if (status == 0)
    status = open_outputs(&run);
  if (status == 0) {
    printf("3D column collapse (quarter): %s, a = %g, %s = %g m, H0 = %g m, "
           "tau_c = %.4g s, t_end = %.4g s; %s %s %s, floor %s, cell %g m, "
           "%dx%dx%d points per cell, %zu points\n",
           scene.section, scene.aspect, scene.square ? "L0" : "R0",
           scene.length, scene.height, scene.tau_c, options.t_end,
           example_family_name(options.family),
           example_shape_name(options.shape), scene.material, scene.floor,
           options.cell, options.ppc, options.ppc, options.ppc,
           gm_domain_point_count(run.domain));
    double start = seconds_now();
    status = run_collapse(&run);
    if (status == 0) {
      report(&run, seconds_now() - start);
      write_pictures(&run);
    }
  }
  release(&run);
  return status;
}
