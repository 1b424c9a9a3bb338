/*
 * silo_layers_janssen.c - filling a planar silo layer by layer and comparing
 * the settled stresses with Janssen's formula (docs/references.md, "Silo
 * discharge and silo pressure"): sigma_v(z) = rho g W / (2 mu_w K) (1 - exp(-2
 * mu_w K z / W)), sigma_h(z) = K sigma_v(z).
 *
 * A 1 m wide silo with Coulomb walls (mu_w = 0.3) and a rough floor is
 * filled to 3 m with a Drucker-Prager material (phi = 30 degrees): every
 * 0.05 s a layer one cell thick is placed at rest on the current free
 * surface (no drop, so no impact), then a little local damping lets the
 * fill settle. K is the elastic at-rest ratio nu / (1 - nu): confined
 * between rigid walls the fill stays inside the yield surface, and nu = 1/3
 * makes it equal Jaky's 1 - sin(phi) = 0.5. tests/physics/test_janssen.c
 * asserts the same comparison.
 *
 * How it is measured, and why:
 *  - the vertical stress of a cell row is the force it transmits,
 *    -sum(V sigma_yy) / (h W). Per-point averages over a depth window are
 *    misleading once points cross cells: the two point rows of a cell share
 *    dN/dy, so only their sum is fixed by equilibrium (the dip that an
 *    earlier version of this example showed at 2.25 m depth);
 *  - wall loads are averaged over the last 0.2 s, both walls: with damping,
 *    each node's load swings by +-damping of itself from step to step;
 *  - damping stays small (0.05): its force is a load the library does not
 *    report, and it takes a share of the weight while the fill creeps.
 *
 * The planar walls are gap-aware (gm_walls(3)): material that moved away
 * from a wall can come back to it. Without that, every small vibration
 * ratcheted the fill's lateral stress up (wall pressure 1.16-1.26 x
 * K sigma_v before the fix; within 10 % now).
 *
 * Usage: silo_layers_janssen [OUTDIR]   (writes OUTDIR/silo.pvd if given)
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include "common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;
static const double WIDTH = 1.0;          /* m */
static const double FILL_HEIGHT = 3.0;    /* m */
static const double CELL = 0.05;          /* m, also the layer thickness */
static const double LAYER_PERIOD = 0.05;  /* s between layers */
static const double SETTLE_TIME = 2.0;    /* s after the last layer */
static const double AVERAGING_TIME = 0.2; /* s */
static const double DENSITY = 1500.0;     /* kg/m^3 */
static const double GRAVITY = 9.81;       /* m/s^2 */
static const double WALL_FRICTION = 0.3;  /* mu_w */
static const double POISSON_RATIO = 1.0 / 3.0;
static const double FRICTION_ANGLE = 30.0 * PI / 180.0; /* rad */
/* 2 x 2 points per cell: COLUMNS = 2 WIDTH / CELL, 2 point rows a layer. */
enum { COLUMNS = 40, ROWS_PER_LAYER = 2, MAX_ROWS = 256 };

#define CHECK(domain, call)                                                    \
  do {                                                                         \
    gm_status check_status_ = (call);                                          \
    if (check_status_ != GM_OK) {                                              \
      fprintf(stderr, "silo_layers_janssen: %s failed: %s\n", #call,           \
              (domain) ? gm_domain_last_error(domain)                          \
                       : gm_last_create_error());                              \
      exit(1);                                                                 \
    }                                                                          \
  } while (0)

static double janssen_k(void) {
  return POISSON_RATIO / (1.0 - POISSON_RATIO);
}

/* Janssen's vertical stress (Pa) at depth z (m), planar silo. */
static double janssen(double z) {
  double decay = 2.0 * WALL_FRICTION * janssen_k() / WIDTH; /* 1/m */
  return DENSITY * GRAVITY / decay * (1.0 - exp(-decay * z));
}

static int add_wall(gm_domain *domain, double x, double y, double normal_x,
                    double normal_y, double friction) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = x;
  wall.point[1] = y;
  wall.normal[0] = normal_x;
  wall.normal[1] = normal_y;
  wall.friction_static = wall.friction_kinetic = friction;
  int id = -1;
  CHECK(domain, gm_domain_add_wall(domain, &wall, &id));
  return id;
}

/* Height of the free surface (m): the top point plus half a spacing. */
static double free_surface(const gm_domain *domain) {
  size_t count = gm_domain_point_count(domain);
  const double *height = NULL;
  if (count == 0)
    return 0.0;
  CHECK(domain, gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &height));
  double top = height[0];
  for (size_t i = 1; i < count; i++)
    top = fmax(top, height[i]);
  return top + 0.5 * WIDTH / COLUMNS;
}

/* A layer of ROWS_PER_LAYER x COLUMNS points at rest on the surface. */
static void place_layer(gm_domain *domain, int material) {
  double spacing = WIDTH / COLUMNS, base = free_surface(domain); /* m */
  double position[2 * ROWS_PER_LAYER * COLUMNS];
  double volume[ROWS_PER_LAYER * COLUMNS]; /* m^2 per unit thickness */
  for (int i = 0; i < ROWS_PER_LAYER * COLUMNS; i++) {
    position[2 * i] = (i % COLUMNS + 0.5) * spacing;
    position[2 * i + 1] = base + (i / COLUMNS + 0.5) * spacing;
    volume[i] = spacing * spacing;
  }
  gm_points_def points = gm_points_def_default();
  points.count = ROWS_PER_LAYER * COLUMNS;
  points.material = material;
  points.position = position;
  points.volume = volume;
  CHECK(domain, gm_domain_add_points(domain, &points, NULL));
}

/* Adds dt times each wall node's pressure (Pa), by node row, both walls. */
static void record_pressure(const gm_domain *domain, const int walls[2],
                            double dt, double *pressure) {
  static gm_wall_traction profile[4 * MAX_ROWS];
  for (int side = 0; side < 2; side++) {
    size_t count = 0;
    CHECK(domain, gm_domain_get_wall_tractions(domain, walls[side], profile,
                                               4 * MAX_ROWS, &count));
    for (size_t i = 0; i < count; i++) { /* down the left, up the right */
      double y = side == 0 ? -profile[i].position : profile[i].position;
      long row = lround(y / CELL);
      if (row >= 0 && row < MAX_ROWS)
        pressure[row] += 0.5 * dt * profile[i].normal;
    }
  }
}

/* The filling: layers placed so far, and the wall pressures summed over
 * the last AVERAGING_TIME. */
typedef struct layer_run {
  int material;
  int layers, placed;
  int walls[2];
  double end;                /* s, the last layer plus SETTLE_TIME */
  double pressure[MAX_ROWS]; /* Pa s, by node row */
  double averaged;           /* s */
} layer_run;

/* example_run_fn, before every step: the next layer once its time has
 * come. */
static gm_status place_due_layer(gm_domain *domain,
                                 const example_run_state *state, void *user) {
  layer_run *run = user;
  if (run->placed < run->layers && state->time >= run->placed * LAYER_PERIOD) {
    place_layer(domain, run->material);
    run->placed++;
  }
  return GM_OK;
}

/* example_step_fn: the wall pressures over the last AVERAGING_TIME. */
static void record_step(const gm_domain *domain, const example_run_state *state,
                        void *user) {
  layer_run *run = user;
  if (state->time > run->end - AVERAGING_TIME) {
    record_pressure(domain, run->walls, state->dt, run->pressure);
    run->averaged += state->dt;
  }
}

/* Vertical stress (Pa) of each cell row as the force it transmits. */
static void row_stress(const gm_domain *domain, double *stress) {
  size_t count = gm_domain_point_count(domain);
  const double *y = NULL, *sigma_yy = NULL, *volume = NULL;
  CHECK(domain, gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  CHECK(domain,
        gm_domain_view_field(domain, GM_FIELD_STRESS, GM_YY, &sigma_yy));
  CHECK(domain, gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume));
  memset(stress, 0, MAX_ROWS * sizeof *stress);
  for (size_t i = 0; i < count; i++) {
    long row = (long)floor(y[i] / CELL);
    if (row >= 0 && row < MAX_ROWS)
      stress[row] -= volume[i] * sigma_yy[i] / (CELL * WIDTH);
  }
}

int main(int argc, char **argv) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = CELL;
  def.origin[1] = -2.0 * CELL; /* room below the floor wall */
  def.extent[0] = WIDTH;
  def.extent[1] = FILL_HEIGHT + 1.0;
  def.gravity[1] = -GRAVITY;
  def.damping = 0.05;
  gm_domain *domain = NULL;
  CHECK(domain, gm_domain_create(&def, &domain));
  static layer_run run; /* static: the pressure rows */
  run.walls[0] = add_wall(domain, 0.0, 0.0, 1.0, 0.0, WALL_FRICTION);
  run.walls[1] = add_wall(domain, WIDTH, 0.0, -1.0, 0.0, WALL_FRICTION);
  add_wall(domain, 0.0, 0.0, 0.0, 1.0, 1.0); /* rough floor */
  gm_drucker_prager_def granular = gm_drucker_prager_def_default();
  granular.poisson_ratio = POISSON_RATIO;
  granular.density = DENSITY;
  granular.friction_angle = FRICTION_ANGLE;
  CHECK(domain, gm_domain_add_drucker_prager(domain, &granular, &run.material));

  gm_series *series = NULL;
  if (argc > 1) {
    char pvd[1024];
    snprintf(pvd, sizeof pvd, "%s/silo.pvd", argv[1]);
    CHECK(NULL, gm_series_create(pvd, &series));
  }
  run.layers = (int)lround(FILL_HEIGHT / CELL);
  run.end = run.layers * LAYER_PERIOD + SETTLE_TIME; /* s */
  /* Stable steps up to the end (the last may pass it), a layer before the
   * step where its time has come, a frame after steps 1, 201, 401, ... */
  const example_run_schedule schedule = {.stepping = EXAMPLE_STEPS,
                                         .t_end = run.end,
                                         .series = series,
                                         .frame_every = 200,
                                         .frame_first = 1,
                                         .on_failure = EXAMPLE_FAILURE_STOP,
                                         .prepare = place_due_layer,
                                         .step = record_step,
                                         .user = &run};
  CHECK(domain, example_run_loop(domain, &schedule, NULL));
  gm_series_destroy(series);
  const double *pressure = run.pressure;
  double averaged = run.averaged; /* s */

  static double stress[MAX_ROWS];
  row_stress(domain, stress);
  double top = free_surface(domain), k = janssen_k();
  printf("planar silo %.1f m wide filled to %.2f m (%zu points), K = %.2f\n",
         WIDTH, top, gm_domain_point_count(domain), k);
  printf("depth (m)  sigma_v (Pa)  Janssen  ratio   wall p (Pa)  K*Janssen  "
         "ratio\n");
  for (int row = (int)(top / CELL) - 3; row > 0; row -= 5) {
    double z = top - (row + 0.5) * CELL; /* m, at the row centre */
    double wall = 0.0;                   /* Pa, the two nodes' mean */
    for (int node = row; node <= row + 1; node++)
      wall += 0.5 * pressure[node] / averaged;
    printf("%9.3f  %12.0f  %7.0f  %5.3f  %11.0f  %9.0f  %5.3f\n", z,
           stress[row], janssen(z), stress[row] / janssen(z), wall,
           k * janssen(z), wall / (k * janssen(z)));
  }
  gm_domain_destroy(domain);
  return 0;
}
