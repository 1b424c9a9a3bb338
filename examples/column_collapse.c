/*
 * column_collapse.c - planar granular column collapse (004 sec 3.3.6) against
 * the experimental laws of Lube, Huppert, Sparks & Freundt (2005, PRE
 * 72:041301; docs/references.md, "Granular column collapse"):
 *   run-out       (L_inf - L0)/L0 ~ 1.2 a          for a <~ 1.8,
 *                                 ~ 1.9 a^(2/3)    for a >~ 2.8,
 *   final height  H_inf/L0 ~ a for a <~ 1.15, ~ a^0.4 above,
 *   the front stops after ~ 3 tau_c, tau_c = sqrt(H0/g),
 * with a = H0/L0 the aspect ratio of the column.
 *
 * --geometry axisym: the same material on the same floor, but the column
 * is a cylinder of radius R0 = --length and height H0 = a R0 standing on
 * the axis x = r = 0, which replaces the back wall (no wall force there),
 * against Lube, Huppert, Sparks & Hallworth (2004, JFM 508:175; see
 * examples/collapse_laws.h for what was verified):
 *   run-out       (r_inf - R0)/R0 ~ 1.24 a         for a <~ 1.7,
 *                                 ~ 1.6 a^(1/2)    above,
 *   final height  H_inf/R0 ~ a, then ~ 0.88 a^(1/6) (recalled),
 * measured as the planar ones (the RESULT names keep "L0"; read R0), with
 * tau_c = sqrt(H0/g). Masses, energies and floor forces are then those of
 * the whole ring (kg, J, N), not per metre.
 *
 * Scene (plane strain): a column L0 wide and H0 = a L0 high stands at rest
 * against a frictionless back wall at x = 0 on a rough floor at y = 0, and
 * collapses to the right under gravity when released at t = 0 (the lifted
 * gate of the experiments). The frictionless back wall is the symmetry
 * plane of a column 2 L0 wide, which is how Lube's channel experiments are
 * reported. Both walls are planar walls (gm_walls(3)), so their forces are
 * in the CSV; the floor has Coulomb friction mu = tan(phi): a rough floor
 * holds the grains as strongly as they hold each other.
 *
 * Material: Mohr-Coulomb (000 eqs 16-17) with phi = 35 degrees, the upper
 * end of Lube's sands, rices and sugars (30-35 degrees; at 30 degrees the
 * run-out is 11-20 % longer than the law, see examples/README.md), psi = 0
 * and no Bagnold term (the law is rate-free and the columns are decimetres
 * tall, where eta gammadot^2 of 000 Table 3 would act as a cohesion
 * comparable with rho g H0). E = 0.5 MPa: soft for a large stable time
 * step, stiff enough that the elastic settlement rho g H0 / E stays ~1 %.
 * Critical density ratio of 000 Table 1 (2235 / 2250). One material for
 * every aspect ratio: nothing is tuned per case. Defaults: a = 1, L0 =
 * 0.15 m, Granular uGIMP (Granular CPDI fails tall columns, see
 * examples/README.md), 7.5 mm cells, 2 x 2 points per cell: 1600 points,
 * about 20 s on one core.
 *
 * Measured: the front is the right edge of the deposit, grains that flew
 * ahead of it excluded (see measure_deposit); the height is the top of the
 * same connected deposit; the stop time is when the front reached 98 % of
 * its final run-out.
 *
 * For the convergence study (docs/convergence.md) the run also prints the
 * run-out by other measures of the front (the farthest point, connected or
 * not; where the deposit thins below 1, 2 and 5 % of L0) and the share of
 * the kinetic energy the grid cannot see (ENERGY line, measure_energy), and
 * takes the options --transfer flip|apic, --pic (FLIP-PIC blend), --floor
 * wall|face|rigid (Coulomb wall, no-slip box face, no-slip rigid points),
 * --floor-mu, --dilation (psi), --material mu_i (mu_s = sin phi), --grain
 * --scheme usl|musl|usf and --cfl; --material perzyna (Perzyna
 * Drucker-Prager, 001 sec 5.1.1: psi = 0, N = 1, cone matched to --friction
 * in plane strain) with --fluidity (gamma, 1/s) and --reference-stress
 * (sigma_n = max(m p, it), Pa), defaults docs/convergence.md sec. 20's
 * 300 1/s and 1795 Pa; sec. 20's setting is --material perzyna --method
 * bspline2 --family plain --friction 37 --floor wall --floor-mu 0.45.
 *
 * Output in --out (default out/column_collapse): collapse.pvd + VTU frames
 * (with the point domains for GIMP and CPDI), collapse.csv (time, kinetic
 * energy, front, height, points per state, parallel grids, wall forces),
 * snapshot_N.png at 0, 1, 2, 3 tau_c and the end (points coloured by speed;
 * needs gnuplot). Prints a STATS line (for bench/chart.sh) and RESULT
 * lines; the last one is the run-out against the law.
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
static const double DENSITY = 1800.0; /* kg/m^3, dry sand, loose */
static const double CRITICAL_RATIO = 2235.0 / 2250.0; /* 000 Table 1 */
static const double POISSON_RATIO = 0.3;              /* - */
static const double STOP_FRACTION = 0.98;             /* of the final run-out */
enum { ROW_COUNT = 200, ROWS_PER_FRAME = 10, SNAPSHOT_COUNT = 5 };

/* The constants of --material perzyna that the other materials lack (its
 * friction angle, E, nu and rho are the scene's). To add one: a field
 * here, its default in perzyna_defaults, a row in main's extras (after
 * --reference-stress) and a line in add_perzyna. */
typedef struct perzyna_options {
  double fluidity;         /* gamma of 001 eq 18, 1/s */
  double reference_stress; /* sigma_n = max(m p, this), Pa */
} perzyna_options;

/* docs/convergence.md sec. 20's material constants (chosen at a = 1.3). */
static perzyna_options perzyna_defaults(void) {
  return (perzyna_options){.fluidity = 300.0, .reference_stress = 1795.0};
}

/* The scene, from the options (lengths in m, times in s). */
typedef struct collapse_scene {
  double length;   /* L0 */
  double aspect;   /* a = H0 / L0 */
  double height;   /* H0 */
  double tau_c;    /* sqrt(H0 / g) */
  double spacing;  /* initial point spacing, cell / ppc */
  double extent_x; /* grid box */
  double extent_y;
  const char *material;    /* mohr_coulomb | drucker_prager | mu_i | perzyna */
  double friction_deg;     /* phi of the material and of the floor, degrees */
  double youngs_modulus;   /* E, Pa */
  double dilation_deg;     /* psi of Mohr-Coulomb, degrees */
  double floor_friction;   /* mu of the floor; < 0: tan(phi) */
  double back_friction;    /* mu of the back wall (0: the symmetry plane) */
  const char *floor;       /* wall | face | rigid */
  const char *transfer;    /* flip | apic */
  const char *volumetric;  /* point | cell */
  double pic_fraction;     /* FLIP-PIC blend, 0 = FLIP */
  double grain_diameter;   /* mu(I): d, m */
  double regularise;       /* mu(I): nonzero = Barker & Gray's low-I branch */
  const char *scheme;      /* usl | musl | usf */
  double cfl;              /* Courant number, 0 = the library's default */
  const char *geometry;    /* plane | axisym */
  int axisymmetric;        /* nonzero: x is the radius, length is R0 */
  perzyna_options perzyna; /* --material perzyna's own constants */
} collapse_scene;

/* Thickness thresholds of the front measures, in L0 (front_thick). */
enum { THICK_COUNT = 3 };
static const double THICK_FRACTION[THICK_COUNT] = {0.01, 0.02, 0.05};

/* The deposit at one instant (m). */
typedef struct deposit {
  double front;    /* right edge of the connected deposit */
  double height;   /* its top */
  double farthest; /* right edge of the farthest point, connected or not */
  /* right edge of the rightmost point of the connected deposit whose top
   * (y + half a spacing) is at least THICK_FRACTION[k] L0 above the
   * floor: where the deposit thins below that thickness */
  double thick[THICK_COUNT];
} deposit;

/* Everything the output rows need while the run goes on. */
typedef struct collapse_run {
  example_options *options;
  const collapse_scene *scene;
  gm_domain *domain;
  int floor_wall, back_wall;
  double *positions, *velocities; /* scratch, count * 2 */
  double *masses;                 /* scratch, count */
  unsigned char *occupied;        /* scratch, one flag per cell column */
  size_t column_count;
  double *nodes; /* scratch: mass, x and y momentum per node of the cells */
  size_t node_columns, node_rows;
  double kinetic_integral, hidden_integral; /* J s, over the rows */
  double hidden_peak_fraction;              /* max hidden / point KE */
  double *stresses, *volumes;               /* scratch, count * 6, count */
  double potential_start;                   /* J/m, sum m g y at t = 0 */
  double elastic_peak;                      /* J/m, max over the rows */
  double elastic_peak_time;                 /* s */
  double last_potential, last_elastic;      /* J/m, the last row */
  FILE *csv;
  gm_series *series;
  int gnuplot; /* nonzero when gnuplot is installed */
  int snapshots_done;
  double row_time[ROW_COUNT + 1], row_front[ROW_COUNT + 1]; /* s, m */
} collapse_run;

/* The law's run-out and final height for the scene's geometry. */
static double law_runout(const collapse_scene *scene) {
  return scene->axisymmetric ? lube2004_runout(scene->aspect)
                             : lube2005_runout(scene->aspect);
}

static double law_final_height(const collapse_scene *scene) {
  return scene->axisymmetric ? lube2004_final_height(scene->aspect)
                             : lube2005_final_height(scene->aspect);
}

static double seconds_now(void) {
  struct timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

/* --material perzyna: the Perzyna Drucker-Prager material of 001 sec 5.1.1
 * (gm_perzyna), psi = 0, N = 1, its cone matched to --friction
 * (collapse_material.h); docs/convergence.md sec. 20. gm_domain_add_perzyna
 * checks the values. */
static gm_status add_perzyna(gm_domain *domain, const collapse_scene *scene,
                             int *material) {
  gm_perzyna_def def = gm_perzyna_def_default();
  def.youngs_modulus = scene->youngs_modulus;
  def.poisson_ratio = POISSON_RATIO;
  def.density = DENSITY;
  def.friction_angle =
      collapse_matched_cone_friction(scene->friction_deg * PI / 180.0);
  def.exponent = 1.0;
  def.fluidity = scene->perzyna.fluidity;
  def.reference_stress = scene->perzyna.reference_stress;
  return gm_domain_add_perzyna(domain, &def, material);
}

/* Registers the granular material; returns its id or -1. */
static int add_material(gm_domain *domain, const collapse_scene *scene) {
  int material = -1;
  gm_status status;
  if (strcmp(scene->material, "drucker_prager") == 0) {
    gm_drucker_prager_def def = gm_drucker_prager_def_default();
    def.youngs_modulus = scene->youngs_modulus;
    def.poisson_ratio = POISSON_RATIO;
    def.density = DENSITY;
    def.friction_angle = scene->friction_deg * PI / 180.0;
    status = gm_domain_add_drucker_prager(domain, &def, &material);
  } else if (strcmp(scene->material, "mohr_coulomb") == 0) {
    gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
    def.youngs_modulus = scene->youngs_modulus;
    def.poisson_ratio = POISSON_RATIO;
    def.density = DENSITY;
    def.friction_angle = scene->friction_deg * PI / 180.0;
    def.dilation_angle = scene->dilation_deg * PI / 180.0;
    def.bagnold_viscosity = 0.0; /* rate-free, see the top of the file */
    status = gm_domain_add_mohr_coulomb(domain, &def, &material);
  } else if (strcmp(scene->material, "mu_i") == 0) {
    /* mu_s = sin(phi): in plane strain with no plastic volume change the
     * Mohr-Coulomb yield (s1 - s3)/2 = sin(phi) (s1 + s3)/2 is
     * tau = mu p with tau = sqrt(s:s/2), the mu(I) stress measure; mu_2 - mu_s
     * and I_0 from Jop et al. (2006, glass beads). */
    gm_mu_i_def def = gm_mu_i_def_default();
    def.youngs_modulus = scene->youngs_modulus;
    def.poisson_ratio = POISSON_RATIO;
    def.density = DENSITY;
    def.grain_density = 2650.0;
    def.grain_diameter = scene->grain_diameter;
    def.static_friction = sin(scene->friction_deg * PI / 180.0);
    def.limit_friction = def.static_friction + (0.6435 - 0.3819);
    /* By default Jop's curve with its yield stress mu_s p, as Mohr-Coulomb
     * has: Barker & Gray's regularisation has no well-posed range for
     * mu_s = sin 35 deg with these mu_2 - mu_s, I_0 (gm_domain_add_mu_i
     * refuses them). --regularise 1 asks for it, for a mu_s that has one
     * (Jop's glass beads: --friction 22.46, mu_s = tan 20.9 deg). */
    def.regularise = scene->regularise != 0.0;
    status = gm_domain_add_mu_i(domain, &def, &material);
  } else if (strcmp(scene->material, "perzyna") == 0) {
    status = add_perzyna(domain, scene, &material);
  } else {
    fprintf(stderr,
            "--material: '%s' is not mohr_coulomb, drucker_prager, mu_i or "
            "perzyna\n",
            scene->material);
    return -1;
  }
  if (status != GM_OK) {
    example_fail(domain, "adding the material", status);
    return -1;
  }
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = CRITICAL_RATIO * DENSITY;
  status = gm_domain_set_granular(domain, material, &granular);
  if (status != GM_OK) {
    example_fail(domain, "gm_domain_set_granular", status);
    return -1;
  }
  return material;
}

/* Adds a planar wall through `point` with inward `normal` and friction mu. */
static gm_status add_wall(gm_domain *domain, double point_x, double normal_x,
                          double normal_y, double friction, int *wall_id) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = point_x;
  wall.normal[0] = normal_x;
  wall.normal[1] = normal_y;
  wall.friction_static = wall.friction_kinetic = friction;
  return gm_domain_add_wall(domain, &wall, wall_id);
}

/* Builds the domain, its walls and the column of points. Returns 0. */
static int build_scene(collapse_run *run) {
  const example_options *options = run->options;
  const collapse_scene *scene = run->scene;
  gm_domain_def def = example_domain_def(options);
  def.extent[0] = scene->extent_x;
  def.extent[1] = scene->extent_y;
  def.gravity[1] = -GRAVITY;
  def.pic_fraction = scene->pic_fraction;
  /* In axisymmetry x is the radius and the axis x = 0 replaces the back
   * wall: the library holds the radial velocity of the axis nodes at zero
   * (gm_domain_create(3)); the slip face says so explicitly. */
  if (scene->axisymmetric) {
    def.geometry = GM_GEOMETRY_AXISYMMETRIC;
    def.walls[GM_FACE_XMIN] = GM_WALL_SLIP;
  }
  def.scheme = example_scheme(scene->scheme);
  if (scene->cfl > 0.0)
    def.cfl = scene->cfl;
  if (strcmp(scene->transfer, "apic") == 0)
    def.transfer = GM_TRANSFER_APIC;
  else if (strcmp(scene->transfer, "flip") != 0) {
    fprintf(stderr, "--transfer: '%s' is not flip or apic\n", scene->transfer);
    return 2;
  }
  int rigid_floor = strcmp(scene->floor, "rigid") == 0;
  int face_floor = strcmp(scene->floor, "face") == 0;
  if (!rigid_floor && !face_floor && strcmp(scene->floor, "wall") != 0) {
    fprintf(stderr, "--floor: '%s' is not wall, face or rigid\n", scene->floor);
    return 2;
  }
  /* A rigid floor: two cells of rigid points below y = 0 (no-slip on every
   * node they touch). A face floor: the box face y = 0, no-slip. */
  if (rigid_floor) {
    def.origin[1] = -2.0 * options->cell;
    def.extent[1] += 2.0 * options->cell;
  }
  if (face_floor)
    def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  /* The walls below hold the material; a point reaching an open face (the
   * far right or the top) has left the scene and fails the step. */
  EXAMPLE_CHECK(NULL, gm_domain_create(&def, &run->domain));
  if (example_set_volumetric(run->domain, scene->volumetric) != 0)
    return 2;
  gm_domain *domain = run->domain;
  int material = add_material(domain, scene);
  if (material < 0)
    return 2;
  double floor_mu = scene->floor_friction >= 0.0
                        ? scene->floor_friction
                        : tan(scene->friction_deg * PI / 180.0);
  run->floor_wall = -1;
  if (!rigid_floor && !face_floor)
    EXAMPLE_CHECK(domain,
                  add_wall(domain, 0.0, 0.0, 1.0, floor_mu, &run->floor_wall));
  run->back_wall = -1;
  if (!scene->axisymmetric)
    EXAMPLE_CHECK(domain, add_wall(domain, 0.0, 1.0, 0.0, scene->back_friction,
                                   &run->back_wall));
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.upper[0] = scene->length;
  fill.upper[1] = scene->height;
  fill.points_per_cell_axis = options->ppc;
  EXAMPLE_CHECK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  if (rigid_floor) {
    gm_rigid_def rigid = gm_rigid_def_default();
    int rigid_material = -1;
    EXAMPLE_CHECK(domain, gm_domain_add_rigid(domain, &rigid, &rigid_material));
    gm_fill_def slab = gm_fill_def_default();
    slab.material = rigid_material;
    slab.lower[1] = -2.0 * options->cell;
    slab.upper[0] = scene->extent_x;
    slab.points_per_cell_axis = options->ppc;
    EXAMPLE_CHECK(domain, gm_domain_fill_box(domain, &slab, NULL, NULL));
  }
  return 0;
}

/* Front and top of the deposit. Grains can fly ahead of the front; the
 * experiments measure the run-out of the continuous deposit, so walk the
 * cell columns from the back wall and stop at the first empty one (an empty
 * column means no grid node links the material on either side). Edges are
 * half a point spacing beyond the outermost point centres, so at t = 0 the
 * front is exactly L0 and the top exactly H0. */
static deposit measure_deposit(collapse_run *run) {
  size_t count = gm_domain_point_count(run->domain);
  double cell = run->options->cell, half = 0.5 * run->scene->spacing;
  deposit result = {0.0, 0.0, 0.0, {0.0, 0.0, 0.0}};
  if (gm_domain_get_field(run->domain, GM_FIELD_POSITION, run->positions,
                          2 * count) != GM_OK)
    return result;
  memset(run->occupied, 0, run->column_count);
  for (size_t i = 0; i < count; i++) {
    if (run->positions[2 * i + 1] < 0.0)
      continue; /* a rigid floor point */
    double column = floor(run->positions[2 * i] / cell);
    if (column >= 0.0 && column < (double)run->column_count)
      run->occupied[(size_t)column] = 1;
  }
  size_t first_empty = 0;
  while (first_empty < run->column_count && run->occupied[first_empty])
    first_empty++;
  double limit = (double)first_empty * cell;
  for (size_t i = 0; i < count; i++) {
    double x = run->positions[2 * i], y = run->positions[2 * i + 1];
    if (y < 0.0)
      continue;
    result.farthest = fmax(result.farthest, x + half);
    if (x >= limit)
      continue;
    result.front = fmax(result.front, x + half);
    result.height = fmax(result.height, y + half);
    for (int k = 0; k < THICK_COUNT; k++)
      if (y + half >= THICK_FRACTION[k] * run->scene->length)
        result.thick[k] = fmax(result.thick[k], x + half);
  }
  return result;
}

/* Kinetic energy of the points and the part of it the grid cannot see
 * (J/m): the points' momenta and masses mapped to the nodes of the cells
 * with linear tents, then KE_points - sum_i |p_i|^2 / (2 m_i). By Jensen's
 * inequality the difference is >= 0; it is the energy of velocity patterns
 * finer than the nodes (FLIP keeps them, PIC removes them), plus an O(h^2)
 * share of a smooth velocity gradient. */
static void measure_energy(collapse_run *run, double *kinetic, double *hidden) {
  size_t count = gm_domain_point_count(run->domain);
  double cell = run->options->cell;
  *kinetic = *hidden = 0.0;
  if (gm_domain_get_field(run->domain, GM_FIELD_POSITION, run->positions,
                          2 * count) != GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_VELOCITY, run->velocities,
                          2 * count) != GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_MASS, run->masses, count) !=
          GM_OK)
    return;
  size_t columns = run->node_columns, rows = run->node_rows;
  memset(run->nodes, 0, 3 * columns * rows * sizeof *run->nodes);
  double point_energy = 0.0;
  for (size_t i = 0; i < count; i++) {
    double x = run->positions[2 * i] / cell,
           y = run->positions[2 * i + 1] / cell;
    if (y < 0.0)
      continue; /* rigid floor */
    double vx = run->velocities[2 * i], vy = run->velocities[2 * i + 1];
    double m = run->masses[i];
    point_energy += 0.5 * m * (vx * vx + vy * vy);
    size_t cx = (size_t)x, cy = (size_t)y;
    if (cx + 1 >= columns || cy + 1 >= rows)
      continue;
    double fx = x - (double)cx, fy = y - (double)cy;
    for (int a = 0; a < 2; a++)
      for (int b = 0; b < 2; b++) {
        double w = (a ? fx : 1.0 - fx) * (b ? fy : 1.0 - fy);
        double *node =
            run->nodes + 3 * ((cy + (size_t)b) * columns + cx + (size_t)a);
        node[0] += w * m;
        node[1] += w * m * vx;
        node[2] += w * m * vy;
      }
  }
  double grid_energy = 0.0;
  for (size_t k = 0; k < columns * rows; k++) {
    const double *node = run->nodes + 3 * k;
    if (node[0] > 0.0)
      grid_energy += 0.5 * (node[1] * node[1] + node[2] * node[2]) / node[0];
  }
  *kinetic = point_energy;
  *hidden = point_energy - grid_energy;
}

/* Potential energy sum m g y and elastic energy sum V w of the
 * deformable points (J/m), w = ((1 + nu) s:s - nu (tr s)^2) / (2 E) the
 * isotropic strain energy density of the stress s (all six components). */
static void measure_stored_energy(collapse_run *run, double *potential,
                                  double *elastic) {
  size_t count = gm_domain_point_count(run->domain);
  double modulus = run->scene->youngs_modulus, nu = POISSON_RATIO;
  *potential = *elastic = 0.0;
  if (gm_domain_get_field(run->domain, GM_FIELD_POSITION, run->positions,
                          2 * count) != GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_MASS, run->masses, count) !=
          GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_STRESS, run->stresses,
                          6 * count) != GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_VOLUME, run->volumes, count) !=
          GM_OK)
    return;
  for (size_t i = 0; i < count; i++) {
    if (run->positions[2 * i + 1] < 0.0)
      continue; /* rigid floor */
    const double *t = run->stresses + 6 * i;
    double trace = t[0] + t[1] + t[2];
    double squares = t[0] * t[0] + t[1] * t[1] + t[2] * t[2] +
                     2.0 * (t[3] * t[3] + t[4] * t[4] + t[5] * t[5]);
    *potential += run->masses[i] * GRAVITY * run->positions[2 * i + 1];
    *elastic += run->volumes[i] * ((1.0 + nu) * squares - nu * trace * trace) /
                (2.0 * modulus);
  }
}

/* Draws the points coloured by speed into <out>/snapshot_N.png. */
static void write_snapshot(collapse_run *run, int index) {
  const collapse_scene *scene = run->scene;
  size_t count = gm_domain_point_count(run->domain);
  double time = 0.0;
  gm_domain_get_time(run->domain, &time, NULL);
  if (gm_domain_get_field(run->domain, GM_FIELD_POSITION, run->positions,
                          2 * count) != GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_VELOCITY, run->velocities,
                          2 * count) != GM_OK)
    return;
  FILE *plot = popen("gnuplot", "w");
  if (!plot)
    return;
  double x_range =
      fmin(scene->extent_x, scene->length * (1.6 + 1.3 * law_runout(scene)));
  double y_range = 1.1 * scene->height;
  int width = 1200, height = 150 + (int)(1000.0 * y_range / x_range);
  double law_front = scene->length * (1.0 + law_runout(scene));
  fprintf(plot, "set terminal pngcairo size %d,%d font 'sans,11'\n", width,
          height);
  fprintf(plot, "set output '%s/snapshot_%d.png'\n", run->options->out, index);
  fprintf(plot,
          "set title 'column collapse a = %g: t = %.3f s = %.2f tau_c (%s "
          "%s)'\n",
          scene->aspect, time, time / scene->tau_c,
          example_family_name(run->options->family),
          example_shape_name(run->options->shape));
  fprintf(plot, "set xlabel '%s'\nset ylabel 'y (m)'\nset size ratio -1\n",
          scene->axisymmetric ? "r (m)" : "x (m)");
  fprintf(plot, "set xrange [0:%g]\nset yrange [0:%g]\n", x_range, y_range);
  /* Colour scale: the free-fall speed from the column top, sqrt(2 g H0). */
  fprintf(plot, "set cbrange [0:%g]\nset cblabel '|v| (m/s)'\n",
          sqrt(2.0 * GRAVITY * scene->height));
  fprintf(plot, "set palette rgb 33,13,10\n");
  fprintf(plot,
          "set arrow from %g,0 to %g,%g nohead dt 2 lc rgb 'black'\n"
          "set label 'Lube et al. %s run-out' at %g,%g\n",
          law_front, law_front, 0.5 * scene->height,
          scene->axisymmetric ? "2004" : "2005", law_front,
          0.55 * scene->height);
  fprintf(plot, "plot '-' using 1:2:3 with points pt 7 ps 0.6 lc palette "
                "notitle\n");
  for (size_t i = 0; i < count; i++) {
    double vx = run->velocities[2 * i], vy = run->velocities[2 * i + 1];
    fprintf(plot, "%g %g %g\n", run->positions[2 * i],
            run->positions[2 * i + 1], sqrt(vx * vx + vy * vy));
  }
  fprintf(plot, "e\n");
  if (pclose(plot) != 0)
    fprintf(stderr, "gnuplot failed on snapshot %d\n", index);
}

/* Takes every snapshot whose time has come: 0, 1, 2, 3 tau_c, the end. */
static void take_snapshots(collapse_run *run, double time) {
  if (!run->gnuplot)
    return;
  while (run->snapshots_done < SNAPSHOT_COUNT) {
    int k = run->snapshots_done;
    double due =
        k + 1 < SNAPSHOT_COUNT ? k * run->scene->tau_c : run->options->t_end;
    if (due > run->options->t_end + 1e-12 && k + 1 < SNAPSHOT_COUNT) {
      run->snapshots_done = SNAPSHOT_COUNT - 1; /* skip to the end one */
      continue;
    }
    if (time < due - 1e-12)
      return;
    write_snapshot(run, k);
    run->snapshots_done++;
  }
}

/* Appends one CSV row and records the front for the stop time. */
static void write_row(collapse_run *run, int row) {
  double time = 0.0;
  gm_domain_get_time(run->domain, &time, NULL);
  deposit now = measure_deposit(run);
  double kinetic = 0.0, hidden = 0.0;
  measure_energy(run, &kinetic, &hidden);
  double potential = 0.0, elastic = 0.0;
  measure_stored_energy(run, &potential, &elastic);
  if (row == 0)
    run->potential_start = potential;
  if (elastic > run->elastic_peak) {
    run->elastic_peak = elastic;
    run->elastic_peak_time = time;
  }
  run->last_potential = potential;
  run->last_elastic = elastic;
  run->kinetic_integral += kinetic;
  run->hidden_integral += hidden;
  if (kinetic > 0.0 && time <= 3.0 * run->scene->tau_c)
    run->hidden_peak_fraction =
        fmax(run->hidden_peak_fraction, hidden / kinetic);
  run->row_time[row] = time;
  run->row_front[row] = now.front;
  if (!run->csv)
    return;
  gm_summary summary = gm_summary_default();
  gm_granular_summary granular = gm_granular_summary_default();
  gm_wall_force floor = gm_wall_force_default(), back = floor;
  gm_domain_get_summary(run->domain, &summary);
  gm_domain_get_granular_summary(run->domain, &granular);
  if (run->floor_wall >= 0)
    gm_domain_get_wall_force(run->domain, run->floor_wall, &floor);
  if (run->back_wall >= 0) /* none in axisymmetry: the axis, 0 N */
    gm_domain_get_wall_force(run->domain, run->back_wall, &back);
  fprintf(run->csv, "%.6g,%.6g,%.6g,%.6g,%.6g,%zu,%zu,%zu,%zu,%.6g,%.6g,%.6g\n",
          time, summary.kinetic_energy, now.front, now.height,
          (now.front - run->scene->length) / run->scene->length,
          granular.state_count[GM_STATE_QUASI_STATIC],
          granular.state_count[GM_STATE_MODERATE],
          granular.state_count[GM_STATE_DISCONNECTED], granular.component_count,
          floor.smoothed_normal, floor.smoothed_tangential,
          back.smoothed_normal); /* the last step to a row may be short */
}

/* example_sample_fn: the row of interval `state->interval` (0: the start)
 * and the snapshots due by its time. */
static gm_status sample_row(const gm_domain *domain,
                            const example_run_state *state, void *user) {
  (void)domain;
  collapse_run *run = user;
  write_row(run, (int)state->interval);
  if (run->options->out[0])
    take_snapshots(run, state->target);
  return GM_OK;
}

/* Opens the CSV and the VTU series in <out>; returns 0. */
static int open_outputs(collapse_run *run) {
  const example_options *options = run->options;
  if (!options->out[0])
    return 0;
  if (example_make_output(options) != 0)
    return 2;
  run->csv = example_open_csv(
      options, "collapse.csv",
      "time_s,kinetic_energy_J,front_m,height_m,runout,quasi_static,"
      "moderate,disconnected,components,floor_normal_N,floor_tangential_N,"
      "back_wall_normal_N");
  char path[1200];
  snprintf(path, sizeof path, "%s/collapse.pvd", options->out);
  EXAMPLE_CHECK(NULL, gm_series_create(path, &run->series));
  if (options->shape != GM_SHAPE_LINEAR)
    EXAMPLE_CHECK(NULL, gm_series_set_domains(run->series, 1));
  run->gnuplot = system("command -v gnuplot > /dev/null 2>&1") == 0;
  if (!run->gnuplot)
    fprintf(stderr, "gnuplot not found: no PNG snapshots "
                    "(apt-get install gnuplot-nox)\n");
  return 0;
}

/* Runs to t_end in ROW_COUNT rows (row 0 at the start), a frame every
 * ROWS_PER_FRAME rows; returns 0 or the exit status. */
static int run_collapse(collapse_run *run) {
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

/* First recorded time at which the front reached STOP_FRACTION of its
 * final run-out (s). */
static double stop_time(const collapse_run *run) {
  double start = run->row_front[0], final = run->row_front[ROW_COUNT];
  double threshold = start + STOP_FRACTION * (final - start);
  for (int row = 0; row <= ROW_COUNT; row++)
    if (run->row_front[row] >= threshold)
      return run->row_time[row];
  return run->row_time[ROW_COUNT];
}

/* Prints the STATS line and the RESULT lines (run-out last). */
static void report(collapse_run *run, double seconds) {
  const collapse_scene *scene = run->scene;
  size_t points = gm_domain_point_count(run->domain);
  uint64_t steps = 0;
  gm_domain_get_time(run->domain, NULL, &steps);
  double final_front = run->row_front[ROW_COUNT];
  double late_front = run->row_front[ROW_COUNT - ROW_COUNT / 10];
  if (final_front - late_front > 0.01 * scene->length)
    printf("note: the front still moved %.3g L0 in the last 10 %% of the "
           "run; try a longer --t-end\n",
           (final_front - late_front) / scene->length);
  if (final_front > scene->extent_x - 2.0 * run->options->cell)
    printf("note: the deposit reached the end of the grid\n");
  printf("STATS points=%zu steps=%llu seconds=%.3f ns_per_point_step=%.1f\n",
         points, (unsigned long long)steps, seconds,
         1e9 * seconds / ((double)points * (double)(steps ? steps : 1)));
  deposit final = measure_deposit(run);
  example_result("stop_time_over_tau_c", stop_time(run) / scene->tau_c, 3.0);
  example_result("final_height_over_L0", final.height / scene->length,
                 law_final_height(scene));
  /* The other measures of the front (see measure_deposit), the points
   * left out of the connected deposit, and the kinetic energy the grid
   * cannot see (measure_energy), as a share of the whole over the run. */
  double law = law_runout(scene);
  example_result("runout_farthest_point",
                 (final.farthest - scene->length) / scene->length, law);
  for (int k = 0; k < THICK_COUNT; k++) {
    char name[64];
    snprintf(name, sizeof name, "runout_thickness_%g_L0", THICK_FRACTION[k]);
    example_result(name, (final.thick[k] - scene->length) / scene->length, law);
  }
  printf("ENERGY hidden_over_kinetic_integral=%.4f "
         "hidden_over_kinetic_peak_to_3tau=%.4f\n",
         run->kinetic_integral > 0.0
             ? run->hidden_integral / run->kinetic_integral
             : 0.0,
         run->hidden_peak_fraction);
  /* Energy released by the collapse (potential at the start minus at the
   * end) and how much of it the elastic strain held at its peak. */
  double released = run->potential_start - run->last_potential;
  printf("ENERGY released_J=%.5g elastic_peak_J=%.5g elastic_peak_over_"
         "released=%.4f elastic_peak_time_over_tau_c=%.3f elastic_end_J=%.5g\n",
         released, run->elastic_peak,
         released > 0.0 ? run->elastic_peak / released : 0.0,
         run->elastic_peak_time / scene->tau_c, run->last_elastic);
  example_result("runout", (final_front - scene->length) / scene->length, law);
}

/* Sizes the grid box and the scratch buffers from the options. */
static int size_scene(collapse_scene *scene, collapse_run *run) {
  const example_options *options = run->options;
  if (!(scene->aspect > 0.0) || !(scene->length > 0.0)) {
    fprintf(stderr, "--aspect and --length must be > 0\n");
    return 2;
  }
  scene->axisymmetric = strcmp(scene->geometry, "axisym") == 0;
  if (!scene->axisymmetric && strcmp(scene->geometry, "plane") != 0) {
    fprintf(stderr, "--geometry: '%s' is not plane or axisym\n",
            scene->geometry);
    return 2;
  }
  scene->height = scene->aspect * scene->length;
  scene->tau_c = sqrt(scene->height / GRAVITY);
  scene->spacing = options->cell / options->ppc;
  /* Twice the law's run-out leaves room for a longer simulated one; the top
   * leaves room for grains thrown up, and for the point domains. */
  scene->extent_x = scene->length * (2.0 + 2.0 * law_runout(scene));
  scene->extent_y = 1.25 * scene->height + 4.0 * options->cell;
  run->column_count = (size_t)ceil(scene->extent_x / options->cell) + 2;
  return 0;
}

static int allocate_scratch(collapse_run *run) {
  size_t count = gm_domain_point_count(run->domain);
  run->positions = malloc(2 * count * sizeof *run->positions);
  run->velocities = malloc(2 * count * sizeof *run->velocities);
  run->masses = malloc(count * sizeof *run->masses);
  run->stresses = malloc(6 * count * sizeof *run->stresses);
  run->volumes = malloc(count * sizeof *run->volumes);
  run->occupied = malloc(run->column_count);
  run->node_columns = run->column_count + 1;
  run->node_rows = (size_t)ceil(run->scene->extent_y / run->options->cell) + 2;
  run->nodes =
      malloc(3 * run->node_columns * run->node_rows * sizeof *run->nodes);
  if (!run->positions || !run->velocities || !run->occupied || !run->masses ||
      !run->nodes || !run->stresses || !run->volumes) {
    fprintf(stderr, "out of memory\n");
    return 2;
  }
  return 0;
}

static void release(collapse_run *run) {
  if (run->csv)
    fclose(run->csv);
  gm_series_destroy(run->series);
  gm_domain_destroy(run->domain);
  free(run->positions);
  free(run->velocities);
  free(run->occupied);
  free(run->masses);
  free(run->nodes);
  free(run->stresses);
  free(run->volumes);
}

int main(int argc, char **argv) {
  example_options options = {GM_SHAPE_UGIMP,
                             GM_FAMILY_GRANULAR,
                             2,
                             0.0075,
                             1,
                             "out/column_collapse",
                             0.0,
                             0};
  collapse_scene scene = {0};
  scene.length = 0.15;
  scene.aspect = 1.0;
  scene.material = "mohr_coulomb";
  scene.friction_deg = 35.0;
  scene.youngs_modulus = 5e5;
  scene.floor_friction = -1.0;
  scene.floor = "wall";
  scene.transfer = "flip";
  scene.volumetric = "point";
  scene.grain_diameter = 0.5e-3;
  scene.scheme = "usl";
  scene.geometry = "plane";
  scene.perzyna = perzyna_defaults();
  const example_extra extras[] = {
      {"aspect", "aspect ratio a = H0/L0", &scene.aspect, NULL},
      {"length", "column width L0, m", &scene.length, NULL},
      {"material",
       "mohr_coulomb|drucker_prager|mu_i|perzyna (perzyna: Drucker-Prager "
       "cone matched to --friction in plane strain, psi = 0, N = 1)",
       NULL, &scene.material},
      {"friction", "friction angle of material and floor, deg",
       &scene.friction_deg, NULL},
      {"youngs", "Young's modulus E, Pa", &scene.youngs_modulus, NULL},
      {"dilation", "dilation angle psi of mohr_coulomb, deg",
       &scene.dilation_deg, NULL},
      {"floor",
       "wall (Coulomb wall) | face (no-slip box face) | rigid "
       "(no-slip rigid points)",
       NULL, &scene.floor},
      {"floor-mu", "friction of the floor wall (< 0: tan phi)",
       &scene.floor_friction, NULL},
      {"back-mu",
       "friction of the back wall, planar only (0: the symmetry plane of a "
       "column 2 L0 wide; > 0: a column against a tank's end wall)",
       &scene.back_friction, NULL},
      {"transfer", "flip | apic", NULL, &scene.transfer},
      {"volumetric",
       "point | cell (tr L averaged over each cell's points against "
       "volumetric locking, gm_domain_set_volumetric)",
       NULL, &scene.volumetric},
      {"pic", "PIC share of the FLIP-PIC blend, 0..1", &scene.pic_fraction,
       NULL},
      {"grain", "mu_i grain diameter d, m", &scene.grain_diameter, NULL},
      {"regularise", "mu_i: 1 = Barker & Gray's well-posed low-I branch",
       &scene.regularise, NULL},
      {"fluidity", "perzyna: fluidity gamma, 1/s", &scene.perzyna.fluidity,
       NULL},
      {"reference-stress",
       "perzyna: sigma_n = max(m p, this) normalises the overstress, Pa",
       &scene.perzyna.reference_stress, NULL},
      {"scheme", "update scheme usl|musl|usf", NULL, &scene.scheme},
      {"cfl", "Courant number (0: the library's 0.5)", &scene.cfl, NULL},
      {"geometry",
       "plane (plane strain, against Lube et al. 2005) | axisym (a cylinder "
       "of radius R0 = --length about the axis x = 0, against Lube et al. "
       "2004)",
       NULL, &scene.geometry}};
  int parsed = example_parse(
      argc, argv,
      "Granular column collapse, planar against Lube et al. (2005) or\n"
      "axisymmetric (--geometry axisym) against Lube et al. (2004).\n"
      "--t-end 0 (the default) runs 6 tau_c, tau_c = sqrt(H0/g).",
      &options, extras, (int)(sizeof extras / sizeof extras[0]));
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  collapse_run run = {0};
  run.options = &options;
  run.scene = &scene;
  int status = size_scene(&scene, &run);
  if (options.t_end <= 0.0)
    options.t_end = 6.0 * scene.tau_c;
  if (status == 0)
    status = build_scene(&run);
  if (status == 0)
    status = allocate_scratch(&run);
  if (status == 0)
    status = open_outputs(&run);
  if (status == 0) {
    printf("%scolumn collapse: a = %g, %s = %g m, H0 = %g m, tau_c = %.4g s, "
           "t_end = %.4g s; %s %s %s, cell %g m, %dx%d points per cell, %zu "
           "points\n",
           scene.axisymmetric ? "axisymmetric " : "", scene.aspect,
           scene.axisymmetric ? "R0" : "L0", scene.length, scene.height,
           scene.tau_c, options.t_end, example_family_name(options.family),
           example_shape_name(options.shape), scene.material, options.cell,
           options.ppc, options.ppc, gm_domain_point_count(run.domain));
    double start = seconds_now();
    status = run_collapse(&run);
    if (status == 0)
      report(&run, seconds_now() - start);
  }
  release(&run);
  return status;
}
