/*
 * wieckowski2004_silo_filling_janssen.c - filling a planar silo with the
 * pressure-volume model (Wieckowski 2004 = 001, sec 5.1.2, eq 24), then the
 * wall pressure at rest against Janssen (docs/references.md, "Silo discharge
 * and silo pressure"): sigma_v(z) = rho g (A/U) / (mu_w K) (1 - exp(-mu_w K z /
 * (A/U))), sigma_h = K sigma_v,  A/U = B (half the silo width) for a planar
 * silo.
 *
 * Scene (001 text; its Fig 6 with the silo dimensions is lost in the text
 * extraction): half of a planar silo (the axis is a slip face), B = 0.6 m,
 * Coulomb side wall and floor with phi_w = 20 deg. Every 0.2 s a source
 * releases a 0.3 m x 0.3 m block of points just above the free surface
 * (001: 144 points a portion, one portion every 0.2 s, which is 12 x 12 at
 * the default 2.5 cm spacing; the block keeps its size in metres when
 * --cell or --ppc change it into more or fewer points, so a refinement
 * study fills the same silo); the material is the filling
 * model with the paper's data (gm_filling_def_default: kappa = 0.02, nu =
 * 0.3, e0 = 0.9, p0 = 600 Pa, phi = 30 deg, mu = 1e4 Pa s, gamma = 1e4
 * 1/s, N = 1, rho0 = 2850 / 1.9 = 1500 kg/m^3). Smaller than the paper's
 * silo: 24 portions (--portions) fill it to about 2.5 m in about a minute.
 * After the last portion the fill settles and the wall loads are averaged
 * over 0.2 s.
 *
 * Our choices, where 001 is silent or the granular method needs one:
 *  - rho_cr (granular family, the default) = 1431 kg/m^3, where eq 24's
 *    pressure has dropped to p0/100; the portions are released at rho_cr,
 *    the loosest packing the method represents (see main());
 *  - 2 % PIC in the velocity update (gm_domain_def.pic_fraction, --pic):
 *    with 4 points per cell, pure FLIP keeps ~190 J/m of point velocity
 *    noise the grid cannot see for ever, and the fill never comes to rest
 *    (the local damping of 0.05 acts on nodal forces only);
 *  - the portions are dropped just above the free surface, their bottom
 *    DROP_GAP = 12.5 mm above the top of the highest point (001 gives no
 *    height; from the top of the silo, the first block met the floor at
 *    6.5 m/s and eq 24's stiffening inverted it). Like the portion's
 *    edge, the gap is in metres, so --cell and --ppc refine one scene
 *    (examples/README.md, "Refinement: one flag"); it was half a point
 *    spacing until 2026-11-27, the same at the default 2.5 cm spacing.
 *
 * Against Janssen (K = 0.5, Jaky's 1 - sin(phi), fixed before the run; mu_w =
 * tan 20 deg; A/U = B; the bulk density is the settled fill's own, its
 * mass over B times its mean height):
 *  - the vertical stress of each cell row, the force the row transmits,
 *    -sum(V_p sigma_yy) / (h B) (tests/physics/test_janssen.c explains why
 * rows);
 *  - the side-wall pressure in 0.25 m bands (single node rows alternate:
 *    the poured packing touches the wall at some nodes and not others);
 *  - RESULT: the total normal force on the side wall (N per metre of
 *    silo), against Janssen's integral of K sigma_v over the fill height.
 * Measured (24 portions, 2.5 cm spacing, 5 cm cells): see examples/README.md.
 *
 * Writes <out>/filling.csv (time, kinetic energy, points, wall and floor
 * forces), <out>/rest_wall.csv (per node row: depth, vertical stress, wall
 * pressure, Janssen's) and <out>/filling.pvd.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include "common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;       /* m/s^2 */
static const double HALF_WIDTH = 0.6;     /* m, B */
static const double SILO_HEIGHT = 5.0;    /* m, top of the grid box */
static const double WALL_ANGLE = 20.0;    /* deg, phi_w of 001 */
static const double PERIOD = 0.2;         /* s between portions (001) */
static const double SETTLE_TIME = 1.5;    /* s after the last portion */
static const double AVERAGING_TIME = 0.2; /* s, wall loads at rest */
static const double SAMPLE = 0.02;        /* s between CSV rows */
static const double DAMPING = 0.05;       /* -, local damping */
static const double MAX_PRESSURE = 1e6;   /* Pa, bounds the wave speed */
static const double BAND = 0.25;          /* m, wall pressure bands */
static const double PORTION_EDGE = 0.3;   /* m, 001's 12 x 12 at 2.5 cm */
/* m, from the free surface (or the floor) to the bottom of a portion:
 * half the default 2.5 cm spacing, in metres on every grid (it was half a
 * spacing, 6 mm at 0.025 m cells: a lower drop, another scene). */
static const double DROP_GAP = 0.0125;

enum { MAX_ROWS = 1024, MAX_TRACTIONS = 4096 };

typedef struct filling {
  example_options options;
  double portions; /* number of PORTION_EDGE square blocks dropped */
  int walls[2];    /* side wall, floor */
  int material;
  double portion_density;    /* kg/m^3, of a released portion */
  int placed;                /* portions placed so far */
  double pic_fraction;       /* -, gm_domain_def.pic_fraction */
  double janssen_k;          /* -, Janssen's stress ratio (main()) */
  double pressure[MAX_ROWS]; /* Pa s, side wall, by node row */
  double wall_impulse;       /* N s per m, side wall normal force */
  double averaged;           /* s */
  double end;                /* s, the last portion plus SETTLE_TIME */
  FILE *csv;                 /* filling.csv, NULL: none */
} filling;

static int add_wall(gm_domain *domain, double x, double normal_x,
                    double normal_y, int *id) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = x;
  wall.normal[0] = normal_x;
  wall.normal[1] = normal_y;
  wall.friction_static = wall.friction_kinetic = tan(WALL_ANGLE * PI / 180);
  return gm_domain_add_wall(domain, &wall, id);
}

/* Height of the settled free surface (m): the highest point plus half a
 * spacing (0 without points: the floor). */
static double free_surface(const gm_domain *domain, double spacing);

/* The next portion: a square lattice of points of edge `spacing` filling
 * PORTION_EDGE x PORTION_EDGE against the axis (block x block points, the
 * edge rounded to whole spacings), released now DROP_GAP above the
 * current free surface (a source injecting once). Dropping it from the top of
 * the silo made the filling model's exponential stiffening meet a 6.5 m/s
 * impact, which inverted or threw out points; 001 does not give the drop
 * height. */
static gm_status add_portion(gm_domain *domain, filling *f, double time) {
  double spacing = f->options.cell / f->options.ppc;        /* m */
  double bottom = free_surface(domain, spacing) + DROP_GAP; /* m */
  long block = lround(PORTION_EDGE / spacing);
  if (block < 1)
    block = 1;
  size_t count = (size_t)(block * block);
  double *position = malloc(2 * count * sizeof *position);
  if (!position)
    return GM_ERR_NO_MEMORY;
  for (size_t i = 0; i < count; i++) {
    position[2 * i] = ((double)(i % (size_t)block) + 0.5) * spacing;
    position[2 * i + 1] =
        bottom + ((double)(i / (size_t)block) + 0.5) * spacing;
  }
  gm_source_def source = gm_source_def_default();
  source.material = f->material;
  source.count = count;
  source.position = position;
  source.point_size = spacing;
  source.density = f->portion_density;
  source.start_time = time;
  int id = -1;
  gm_status status = gm_domain_add_source(domain, &source, &id);
  free(position);
  f->placed += status == GM_OK;
  return status;
}

/* Adds dt times each side-wall node's traction (Pa) by node row, and the
 * wall's normal impulse. The wall normal is (-1, 0), so
 * positions along it are heights. */
static void record_tractions(const gm_domain *domain, filling *f, double dt) {
  static gm_wall_traction profile[MAX_TRACTIONS];
  size_t count = 0;
  if (gm_domain_get_wall_tractions(domain, f->walls[0], profile, MAX_TRACTIONS,
                                   &count) != GM_OK)
    return;
  for (size_t i = 0; i < count; i++) {
    long row = lround(profile[i].position / f->options.cell);
    if (row >= 0 && row < MAX_ROWS)
      f->pressure[row] += dt * profile[i].normal;
  }
  gm_wall_force side = gm_wall_force_default();
  if (gm_domain_get_wall_force(domain, f->walls[0], &side) == GM_OK)
    f->wall_impulse += side.normal_impulse;
  f->averaged += dt;
}

static double free_surface(const gm_domain *domain, double spacing) {
  size_t count = gm_domain_point_count(domain);
  const double *height = NULL;
  if (count == 0 ||
      gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &height) != GM_OK)
    return 0.0;
  double top = height[0];
  for (size_t i = 1; i < count; i++)
    top = fmax(top, height[i]);
  return top + 0.5 * spacing;
}

/* Janssen's vertical stress (Pa) at depth z (m) for bulk density rho
 * (kg/m^3) and stress ratio k, and the integral of k sigma_v from 0 to z
 * (N/m): the load on the side wall above depth z. */
static double janssen_vertical(double k, double rho, double z) {
  double decay = tan(WALL_ANGLE * PI / 180.0) * k / HALF_WIDTH; /* 1/m */
  return rho * GRAVITY / decay * (1.0 - exp(-decay * z));
}

static double janssen_wall_force(double k, double rho, double z) {
  double decay = tan(WALL_ANGLE * PI / 180.0) * k / HALF_WIDTH; /* 1/m */
  return k * rho * GRAVITY / decay * (z - (1.0 - exp(-decay * z)) / decay);
}

/* example_run_fn: the next portion, once its time has come. */
static gm_status place_portion(gm_domain *domain,
                               const example_run_state *state, void *user) {
  filling *f = user;
  if (f->placed < (int)f->portions && state->time >= f->placed * PERIOD - 1e-9)
    return add_portion(domain, f, state->time);
  return GM_OK;
}

/* example_step_fn: the wall loads over the last AVERAGING_TIME. */
static void record_step(const gm_domain *domain, const example_run_state *state,
                        void *user) {
  filling *f = user;
  if (state->time > f->end - AVERAGING_TIME)
    record_tractions(domain, f, state->time - state->step_start);
}

/* example_sample_fn: a CSV row. The forces are the smoothed ones
 * (gm_walls(3)), which a short last step could not make spike anyway. */
static gm_status write_row(const gm_domain *domain,
                           const example_run_state *state, void *user) {
  const filling *f = user;
  gm_summary summary = gm_summary_default();
  gm_wall_force side = gm_wall_force_default(), floor = side;
  gm_status status = gm_domain_get_summary(domain, &summary);
  if (status == GM_OK)
    status = gm_domain_get_wall_force(domain, f->walls[0], &side);
  if (status == GM_OK)
    status = gm_domain_get_wall_force(domain, f->walls[1], &floor);
  if (status == GM_OK && f->csv) {
    fprintf(f->csv, "%g,%g,%zu,%g,%g,%g", state->time, summary.kinetic_energy,
            gm_domain_point_count(domain), side.smoothed_normal,
            side.smoothed_tangential, floor.smoothed_normal);
    example_write_states(f->csv, domain);
    fputc('\n', f->csv);
  }
  return status;
}

/* Runs the filling and settling, writing CSV and VTU on the way. */
static int run(gm_domain *domain, filling *f) {
  double end = f->portions * PERIOD + SETTLE_TIME; /* s */
  if (f->options.t_end > 0.0 && f->options.t_end < end)
    end = f->options.t_end; /* a quick look: the fill is not at rest */
  f->end = end;
  gm_series *series = NULL;
  if (f->options.out[0]) {
    char pvd[1200];
    snprintf(pvd, sizeof pvd, "%s/filling.pvd", f->options.out);
    EXAMPLE_CHECK(NULL, gm_series_create(pvd, &series));
    gm_series_set_domains(series, f->options.shape != GM_SHAPE_LINEAR);
  }
  FILE *csv = example_open_csv(
      &f->options, "filling.csv",
      "time_s,kinetic_energy_J,points,"
      "wall_normal_N,wall_tangential_N,floor_normal_N," EXAMPLE_STATE_HEADER);
  f->csv = csv;
  /* Stable steps clipped to every SAMPLE (down to a nanosecond of it: no
   * sliver step), 1e-4 s before the first portion has points; a portion
   * at the start of the interval where its time has come, a frame every
   * 10 samples. */
  const example_run_schedule schedule = {.stepping = EXAMPLE_STEPS,
                                         .sample_times =
                                             EXAMPLE_SAMPLE_MULTIPLES,
                                         .t_end = end,
                                         .sample_period = SAMPLE,
                                         .empty_dt = 1e-4,
                                         .series = series,
                                         .frame_every = 10,
                                         .frame_first = 10,
                                         .on_failure = EXAMPLE_FAILURE_STOP,
                                         .progress = &f->options,
                                         .prepare = place_portion,
                                         .step = record_step,
                                         .sample = write_row,
                                         .user = f};
  gm_status status = example_run_loop(domain, &schedule, NULL);
  if (csv)
    fclose(csv);
  f->csv = NULL;
  gm_series_destroy(series);
  return status == GM_OK ? 0 : example_fail(domain, "example_run_loop", status);
}

/* The settled fill: its mean height (m, the mean over cell-wide columns
 * of the highest point plus half a spacing), its bulk density (kg/m^3,
 * mass over B times that height) and the vertical stress each cell row
 * transmits (Pa), -sum(V_p sigma_yy) / (h B), by row of the point. */
typedef struct settled_fill {
  double height;               /* m */
  double bulk_density;         /* kg/m^3 */
  double row_stress[MAX_ROWS]; /* Pa */
} settled_fill;

static int measure_fill(const gm_domain *domain, const filling *f,
                        settled_fill *fill) {
  double cell = f->options.cell, spacing = cell / f->options.ppc; /* m */
  const double *x = NULL, *y = NULL, *mass = NULL, *volume = NULL;
  const double *sigma_yy = NULL;
  if (gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x) != GM_OK ||
      gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y) != GM_OK ||
      gm_domain_view_field(domain, GM_FIELD_MASS, 0, &mass) != GM_OK ||
      gm_domain_view_field(domain, GM_FIELD_VOLUME, 0, &volume) != GM_OK ||
      gm_domain_view_field(domain, GM_FIELD_STRESS, GM_YY, &sigma_yy) != GM_OK)
    return 1;
  enum { COLUMNS = 64 };
  double column_top[COLUMNS] = {0}, total_mass = 0.0; /* m, kg */
  int columns = (int)ceil(HALF_WIDTH / cell - 1e-9);
  for (size_t i = 0; i < gm_domain_point_count(domain); i++) {
    int column = (int)(x[i] / cell), row = (int)floor(y[i] / cell);
    if (column >= 0 && column < columns && column < COLUMNS)
      column_top[column] = fmax(column_top[column], y[i] + 0.5 * spacing);
    if (row >= 0 && row < MAX_ROWS)
      fill->row_stress[row] -= volume[i] * sigma_yy[i] / (cell * HALF_WIDTH);
    total_mass += mass[i];
  }
  for (int c = 0; c < columns && c < COLUMNS; c++)
    fill->height += column_top[c] / columns;
  fill->bulk_density = total_mass / (HALF_WIDTH * fill->height);
  return 0;
}

/* Prints the profiles against Janssen, writes rest_wall.csv; returns the
 * time-averaged side-wall normal force (N/m) and sets *reference to
 * Janssen's. */
static double report(const gm_domain *domain, const filling *f,
                     double *reference) {
  static settled_fill fill;
  double cell = f->options.cell;
  if (measure_fill(domain, f, &fill) != 0 || !(f->averaged > 0.0))
    return NAN;
  double rho = fill.bulk_density, top = fill.height, k = f->janssen_k;
  printf("settled fill: mean height %.3f m, bulk density %.0f kg/m^3; "
         "Janssen with K = %.3f\n",
         top, rho, k);
  FILE *csv = example_open_csv(&f->options, "rest_wall.csv",
                               "depth_m,vertical_stress_Pa,janssen_vertical_Pa,"
                               "wall_pressure_Pa,janssen_wall_Pa");
  printf("vertical stress by cell row: depth (m), measured, Janssen (Pa)\n");
  for (long row = 0; row < MAX_ROWS && (row + 1) * cell < top; row++) {
    double depth = top - (row + 0.5) * cell; /* m, row centre */
    double wall_depth = top - row * cell;    /* m, node row */
    double wall = f->pressure[row] / f->averaged;
    if (csv)
      fprintf(csv, "%g,%g,%g,%g,%g\n", depth, fill.row_stress[row],
              janssen_vertical(k, rho, depth), wall,
              k * janssen_vertical(k, rho, wall_depth));
    if (row % 4 == 0)
      printf("  %6.3f  %9.1f  %9.1f\n", depth, fill.row_stress[row],
             janssen_vertical(k, rho, depth));
  }
  if (csv)
    fclose(csv);
  printf("side-wall pressure in %.2f m bands: depths (m), measured, Janssen "
         "(Pa)\n",
         BAND);
  for (double upper = top; upper > 1e-9; upper -= BAND) {
    double lower = fmax(upper - BAND, 0.0), force = 0.0; /* m, N/m */
    for (long row = 0; row < MAX_ROWS && row * cell <= top; row++) {
      double height = row * cell; /* m, node row; each carries h of wall */
      if (height >= lower && height < upper)
        force += cell * f->pressure[row] / f->averaged;
    }
    double expected = janssen_wall_force(k, rho, top - lower) -
                      janssen_wall_force(k, rho, top - upper); /* N/m */
    printf("  %5.2f-%5.2f  %9.1f  %9.1f\n", top - upper, top - lower,
           force / (upper - lower), expected / (upper - lower));
  }
  *reference = janssen_wall_force(k, rho, top);
  double jaky = 1.0 - sin(30.0 * PI / 180.0); /* - */
  printf("for the record: with Jaky's K = 1 - sin(phi) = %.2f instead, "
         "Janssen's wall load is %.0f N/m and the vertical stress at the "
         "bottom %.0f Pa\n",
         jaky, janssen_wall_force(jaky, rho, top),
         janssen_vertical(jaky, rho, top));
  return f->wall_impulse / f->averaged;
}

int main(int argc, char **argv) {
  filling f = {0};
  f.options = (example_options){GM_SHAPE_LINEAR,
                                GM_FAMILY_GRANULAR,
                                2,
                                0.05,
                                1,
                                "out/silo_filling_janssen",
                                0.0,
                                0};
  f.portions = 24;
  f.pic_fraction = 0.02;
  example_extra extras[] = {
      {"portions", "number of 0.3 m x 0.3 m blocks dropped (one per 0.2 s)",
       &f.portions, NULL},
      {"pic", "PIC share of the velocity update, 0..1 (0 = FLIP)",
       &f.pic_fraction, NULL}};
  int parsed = example_parse(argc, argv,
                             "Silo filling with the pressure-volume model "
                             "(001 sec 5.1.2); wall pressure against Janssen. "
                             "--t-end T stops the run at T s for a quick look "
                             "(default 0: the whole filling and settling).",
                             &f.options, extras, 2);
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  if (f.portions < 1 || f.portions > 1000 || example_make_output(&f.options))
    return 2;
  gm_domain_def def = gm_domain_def_default();
  def.shape = f.options.shape;
  def.family = f.options.family;
  def.scheme = GM_SCHEME_MUSL; /* sources need MUSL (gm_sources(3)) */
  def.cell_size = f.options.cell;
  def.origin[1] = -2.0 * f.options.cell;
  def.extent[0] = HALF_WIDTH + 2.0 * f.options.cell;
  def.extent[1] = SILO_HEIGHT + 2.0 * f.options.cell;
  def.gravity[1] = -GRAVITY;
  def.walls[GM_FACE_XMIN] = GM_WALL_SLIP; /* the axis */
  def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  def.damping = DAMPING;
  def.pic_fraction = f.pic_fraction;
  /* The bulk viscosity mu = 1e4 Pa s adds the explicit limit dt < ~rho h^2
   * / (2 mu) (filling.h), about 1.9e-4 s for 0.05 m cells, which the
   * stable-dt bound does not see; MAX_PRESSURE = 1 MPa makes the elastic
   * bound (about 8e-5 s) the smaller one. */
  def.worker_count = f.options.workers;
  gm_domain *domain = NULL;
  EXAMPLE_CHECK(NULL, gm_domain_create(&def, &domain));
  /* Side wall shifted 1e-9 cells inwards: see silo_discharge.c. */
  EXAMPLE_CHECK(domain, add_wall(domain, HALF_WIDTH - 1e-9 * f.options.cell,
                                 -1.0, 0.0, &f.walls[0]));
  EXAMPLE_CHECK(domain, add_wall(domain, 0.0, 0.0, 1.0, &f.walls[1]));
  gm_filling_def model = gm_filling_def_default();
  model.max_pressure = MAX_PRESSURE;
  /* Janssen's K, fixed before the run: the at-rest ratio of an elastic
   * fill in confined compression, nu / (1 - nu) = 0.43 for 001's nu = 0.3.
   * The fill stays elastic on that path: q/p = 3 (1 - K)/(1 + 2 K) = 0.92,
   * 1.02 with the fully mobilised wall shear added, below the cone's m =
   * 1.03 (granmpm/perzyna.h, phi = 30 deg); tests/physics/test_janssen.c makes
   * the same argument. Jaky's 1 - sin(phi) = 0.5 is printed for the record. */
  f.janssen_k = model.poisson_ratio / (1.0 - model.poisson_ratio);
  int material = -1;
  EXAMPLE_CHECK(domain, gm_domain_add_filling(domain, &model, &material));
  gm_granular_def granular = gm_granular_def_default();
  /* Disconnected below the density at which eq 24's pressure has dropped
   * to p0/100: e - e0 = -kappa ln(p/p0) gives e_cr = e0 + kappa ln 100,
   * rho_cr = rho0 (1 + e0)/(1 + e_cr) = 1431 kg/m^3. At rho0 itself the
   * density control would hand every returned point p0 = 600 Pa, which
   * pushes a free surface apart. The portions are released at rho_cr, the
   * loosest packing the granular method represents (000 sec 3.3: V_cr is
   * the largest volume a point can have), not at 001's 1000 kg/m^3 (20 kg
   * in 20 x 10 x 100 cm^3): a looser point would be frozen by the density
   * control and its domain of interaction, smaller than the point, would
   * meet no neighbour (granmpm/filling.h). */
  granular.critical_density =
      model.density * (1.0 + model.void_ratio) /
      (1.0 + model.void_ratio + model.kappa * log(100.0));
  f.portion_density = granular.critical_density;
  EXAMPLE_CHECK(domain, gm_domain_set_granular(domain, material, &granular));
  f.material = material; /* the portions are placed by run() */
  int failed = run(domain, &f);
  if (failed)
    return failed;
  example_print_scene(domain);
  double reference = 0.0, wall_force = report(domain, &f, &reference);
  gm_domain_destroy(domain);
  example_result("wall_normal_force_N_per_m", wall_force, reference);
  return 0;
}
