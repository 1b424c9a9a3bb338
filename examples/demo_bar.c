/*
 * demo_bar.c - the libgranmpm demo: a vibrating elastic bar, checked against
 * its closed-form period.
 *
 * A bar of length L is clamped at x = 0 and free at x = L (fixed-free). It
 * starts in its first vibration mode, v(x) = v0 sin(pi x / 2L), and
 * oscillates with angular frequency omega = (pi / 2L) sqrt(M / rho)
 * (docs/references.md, "Fixed-free elastic bar"; Sulsky/Bardenhagen's standard
 * case L = 25 m, E = 100 Pa, rho = 1 kg/m^3, v0 = 0.1 m/s). Its centre of
 * mass then moves with velocity (2 v0 / pi) cos(omega t): the time between
 * two zero crossings of that velocity is half a period.
 *
 * The bar is simulated in 2D plane strain, lying between two frictionless
 * (slip) walls at its bottom and top faces. Why 2D rather than 1D: it
 * exercises the 2D machinery (2D shape functions, slip walls, the plane
 * strain stress state) and makes a nicer picture in ParaView. The walls stop
 * the bar from getting thinner as it stretches, so the strain is uniaxial and
 * the modulus that sets the wave speed is not E but the constrained (P-wave)
 * modulus M = E (1 - nu) / ((1 + nu)(1 - 2 nu)). With nu = 0.3 that is 35%
 * stiffer than E, which the closed form below takes into account.
 *
 * Usage: demo_bar OUTDIR. Writes OUTDIR/bar.pvd plus ~60 .vtu frames, prints
 * the closed-form and measured periods, exits nonzero if they differ by more
 * than 1%. Uses only the public API (granmpm.h).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The standard case (docs/references.md). */
static const double bar_length = 25.0;      /* m, L */
static const double youngs_modulus = 100.0; /* Pa, E */
static const double poisson_ratio = 0.3;    /* nu */
static const double density = 1.0;          /* kg/m^3, rho */
static const double initial_speed = 0.1;    /* m/s, v0 (mode amplitude) */

/* The discretisation. The bar's points stay inside the cells they start in:
 * the free end moves by at most v0 / omega (about 0.16 m), less than the
 * quarter cell between the last point and the bar's end. This matters with
 * USL: a point entering an empty cell gives a node a tiny mass, and USL's
 * nodal velocity (p + f dt) / m there can be huge (the known small-mass
 * weakness of USL); MUSL and USF do not have it. */
static const double bar_height = 3.0;      /* m, fills the gap between walls */
static const double cell_size = 1.0;       /* m: 25 cells along the bar */
static const int points_per_cell_axis = 2; /* 4 points per cell */
static const int periods_to_run = 3;
static const int frames_to_write = 60;     /* plus the initial state */
static const double pass_tolerance = 0.01; /* relative error of the period */

static const double pi = 3.14159265358979323846;

/* Prints what failed and why; returns the exit status of main(). */
static int report_failure(const gm_domain *domain, const char *call,
                          gm_status status) {
  fprintf(stderr, "demo_bar: %s failed: %s\n  %s\n", call, gm_strerror(status),
          domain ? gm_domain_last_error(domain) : gm_last_create_error());
  return EXIT_FAILURE;
}

/* Evaluates a gm_* call in main(); on error reports it, frees main's domain
 * and series, and returns from main() with a failure status. */
#define CHECK(call)                                                            \
  do {                                                                         \
    gm_status check_status_ = (call);                                          \
    if (check_status_ != GM_OK) {                                              \
      int exit_status_ = report_failure(domain, #call, check_status_);         \
      gm_series_destroy(series);                                               \
      gm_domain_destroy(domain);                                               \
      return exit_status_;                                                     \
    }                                                                          \
  } while (0)

/* Constrained modulus (Pa): axial stiffness when lateral strain is zero. */
static double constrained_modulus(double young, double poisson) {
  return young * (1.0 - poisson) / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
}

/* Grid box just around the bar: its bottom and top faces coincide with
 * the bar's (bar_height is a whole number of cells, so the box is not
 * rounded up), so the slip walls touch it; there is room beyond the free end
 * (the end moves by v0 / omega, about 0.16 m). */
static gm_domain_def bar_domain_def(void) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_PLANE_STRAIN;
  def.extent[0] = bar_length + 5.0 * cell_size; /* m */
  def.extent[1] = bar_height;                   /* m */
  def.cell_size = cell_size;
  def.scheme = GM_SCHEME_USL;
  def.walls[GM_FACE_XMIN] = GM_WALL_FIXED; /* the clamped end */
  def.walls[GM_FACE_YMIN] = GM_WALL_SLIP;
  def.walls[GM_FACE_YMAX] = GM_WALL_SLIP;
  return def;
}

/* Sets every point's velocity to mode 1: v_x = v0 sin(pi x / 2L). */
static gm_status set_mode_one_velocity(gm_domain *domain) {
  const double *position_x = NULL;
  double *velocity_x = NULL;
  gm_status status =
      gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &position_x);
  if (status == GM_OK)
    status = gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity_x);
  if (status != GM_OK)
    return status;
  size_t count = gm_domain_point_count(domain);
  for (size_t i = 0; i < count; i++)
    velocity_x[i] = initial_speed * sin(pi * position_x[i] / (2 * bar_length));
  return GM_OK;
}

/* Zero crossings of the centre-of-mass velocity, found by linear
 * interpolation between steps. */
typedef struct crossing_log {
  double previous_time;     /* s */
  double previous_velocity; /* m/s */
  int count;
  double first; /* s, time of the first crossing */
  double last;  /* s, time of the latest crossing */
} crossing_log;

static void log_velocity(crossing_log *log, double time, double velocity) {
  double before = log->previous_velocity;
  if ((before > 0.0 && velocity <= 0.0) || (before < 0.0 && velocity >= 0.0)) {
    double fraction = before / (before - velocity);
    double crossing =
        log->previous_time + fraction * (time - log->previous_time);
    if (log->count == 0)
      log->first = crossing;
    log->last = crossing;
    log->count++;
  }
  log->previous_time = time;
  log->previous_velocity = velocity;
}

/* Centre-of-mass velocity along the bar (m/s): momentum / mass. */
static gm_status centre_of_mass_velocity(const gm_domain *domain,
                                         double *velocity) {
  gm_summary summary = gm_summary_default();
  gm_status status = gm_domain_get_summary(domain, &summary);
  if (status == GM_OK)
    *velocity = summary.momentum[0] / summary.mass;
  return status;
}

int main(int argc, char **argv) {
  bool help = argc == 2 &&
              (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0);
  if (argc != 2 || help) {
    fprintf(help ? stdout : stderr,
            "usage: %s OUTDIR (must exist)\n"
            "Vibrating elastic bar, fixed at x = 0 and free at x = L: its "
            "first-mode\nperiod against the closed form; VTU series in "
            "OUTDIR/bar.pvd.\n",
            argv[0]);
    return help ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  char pvd_path[4096];
  if (snprintf(pvd_path, sizeof pvd_path, "%s/bar.pvd", argv[1]) >=
      (int)sizeof pvd_path) {
    fprintf(stderr, "demo_bar: output directory name too long\n");
    return EXIT_FAILURE;
  }

  gm_domain *domain = NULL;
  gm_series *series = NULL;
  gm_domain_def def = bar_domain_def();
  CHECK(gm_domain_create(&def, &domain));

  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.youngs_modulus = youngs_modulus;
  elastic.poisson_ratio = poisson_ratio;
  elastic.density = density;
  int material = -1;
  CHECK(gm_domain_add_elastic(domain, &elastic, &material));

  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.upper[0] = bar_length; /* m; lower corner is the origin */
  fill.upper[1] = bar_height;
  fill.points_per_cell_axis = points_per_cell_axis;
  size_t point_count = 0;
  CHECK(gm_domain_fill_box(domain, &fill, NULL, &point_count));
  CHECK(set_mode_one_velocity(domain));

  /* Closed form: omega = beta_1 sqrt(M / rho), beta_1 = pi / 2L. */
  double modulus = constrained_modulus(youngs_modulus, poisson_ratio);
  double wave_speed = sqrt(modulus / density); /* m/s */
  double omega = pi / (2 * bar_length) * wave_speed;
  double expected_period = 2 * pi / omega; /* s */

  /* A fixed dt, a whole number of steps per frame, at most the stable dt. */
  double end_time = periods_to_run * expected_period; /* s */
  double stable_dt = 0.0;
  CHECK(gm_domain_stable_dt(domain, &stable_dt));
  int steps_per_frame = (int)ceil(end_time / frames_to_write / stable_dt);
  int step_count = steps_per_frame * frames_to_write;
  double dt = end_time / step_count; /* s */

  printf("libgranmpm %s demo: vibrating elastic bar, fixed at x = 0, free at "
         "x = L\n",
         gm_version());
  printf("  bar %g m x %g m, plane strain between frictionless walls\n",
         bar_length, bar_height);
  printf("  E = %g Pa, nu = %g, rho = %g kg/m^3: constrained modulus M = %.4g "
         "Pa\n",
         youngs_modulus, poisson_ratio, density, modulus);
  printf("  mode 1 start, v = %g sin(pi x / 2L) m/s; %zu points, %g m cells, "
         "USL, %d steps of %.4g s\n",
         initial_speed, point_count, cell_size, step_count, dt);

  /* gm_series_create has no domain to hold a message: explain it here. */
  gm_status series_status = gm_series_create(pvd_path, &series);
  if (series_status != GM_OK) {
    fprintf(stderr, "demo_bar: cannot start the series %s: %s\n", pvd_path,
            gm_strerror(series_status));
    gm_domain_destroy(domain);
    return EXIT_FAILURE;
  }
  CHECK(gm_series_write(series, domain));
  crossing_log crossings = {0};
  CHECK(centre_of_mass_velocity(domain, &crossings.previous_velocity));
  for (int step = 1; step <= step_count; step++) {
    CHECK(gm_domain_step(domain, dt));
    double time = 0.0, velocity = 0.0;
    CHECK(gm_domain_get_time(domain, &time, NULL));
    CHECK(centre_of_mass_velocity(domain, &velocity));
    log_velocity(&crossings, time, velocity);
    if (step % steps_per_frame == 0)
      CHECK(gm_series_write(series, domain));
  }
  gm_series_destroy(series);
  gm_domain_destroy(domain);

  /* Consecutive crossings are half a period apart. */
  if (crossings.count < 2) {
    printf("  FAIL: only %d zero crossing(s) of the centre-of-mass velocity\n",
           crossings.count);
    return EXIT_FAILURE;
  }
  double measured_period =
      2 * (crossings.last - crossings.first) / (crossings.count - 1);
  double relative_error =
      fabs(measured_period - expected_period) / expected_period;
  bool passed = relative_error <= pass_tolerance;
  printf("  period, closed form 4 L / sqrt(M / rho): %.5f s\n",
         expected_period);
  printf("  period, measured (%d zero crossings of the centre-of-mass "
         "velocity): %.5f s\n",
         crossings.count, measured_period);
  printf("  relative error %.3f %% (limit %g %%): %s\n", 100 * relative_error,
         100 * pass_tolerance, passed ? "PASS" : "FAIL");
  printf("  wrote %d frames to %s (open it in ParaView)\n", frames_to_write + 1,
         pvd_path);
  return passed ? EXIT_SUCCESS : EXIT_FAILURE;
}
