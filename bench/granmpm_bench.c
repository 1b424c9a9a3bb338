/*
 * granmpm_bench.c - speed and memory of the explicit step, as CSV on stdout.
 *
 * Scene: a square elastic block (plane strain, linear shape functions, USL,
 * 2x2 points per cell) resting on a fixed (no-slip) bottom wall under
 * gravity, so the step does real work (stress waves from the wall), not
 * just a free fall. Cases, in increasing size:
 *
 *   block-1e4, block-1e5, block-1e6   ~1e4, 1e5, 1e6 points, box just
 *                                     around the block
 *   empty-1e5                         the 1e5 block in a box 10x larger
 *                                     per axis (100x the area): checks that
 *                                     empty grid space costs nothing
 *   block3d-1e5, ugimp3d-1e5,         GM_GEOMETRY_3D: a cube of 2x2x2
 *   block3d-1e6                       points per cell (97 336 and 1 000 000
 *                                     points), linear and uGIMP (issue 16
 *                                     item 5)
 *   granular3d-1e5,                   the same cube with the granular
 *   plain-cloud3d-1e5,                family, and a cube of 70 % of the
 *   granular-cloud3d-1e5              points under a cloud of the other
 *                                     30 % (plain and granular), as in 2D
 *
 * each with 1 and 2 workers (the built-in pool). Every case runs in its own
 * forked process, so peak_rss_mb is that case's peak (not the peak of all
 * cases so far) and bytes_per_point is the peak RSS increase over the
 * process's RSS before the domain was created, divided by the points: it
 * includes the grid, the scratch and the transient peaks of creation.
 *
 * Usage: granmpm-bench [--quick] [--case NAME] [--apic] [--workers N]
 *   --quick      only the 1e4 and 1e5 cases (block-1e4, block-1e5,
 *                empty-1e5)
 *   --case NAME  only that case (both worker counts)
 *   --apic       the APIC velocity transfer (gm_domain_def.transfer)
 *                instead of FLIP
 *   --workers N  only that worker count (default: 1 and 2)
 *
 * Timing: a few warm-up steps (first-touch allocation of the grid and
 * scratch happens there), then the step count is chosen so each case takes
 * about target_seconds. CLOCK_MONOTONIC wall time. See bench/README.md.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L

#include <granmpm.h>

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* The block's material: the material's own cost shows next to the grid
 * transfers when the same scene runs with a plasticity model. */
typedef enum bench_material {
  MATERIAL_ELASTIC,
  MATERIAL_MOHR_COULOMB,
  MATERIAL_DRUCKER_PRAGER
} bench_material;

typedef struct bench_case {
  const char *name;
  double target_points;
  double box_scale; /* box size / compact box size, per axis */
  bool quick;       /* part of --quick */
  bench_material material;
  gm_shape shape; /* shape functions: 4, up to 9 or up to 16 nodes */
  gm_family family;
  /* Granular cases: share of all points that are disconnected, placed as
   * a sparse cloud above the block (0 = none). */
  double disconnected_share;
  /* GM_GEOMETRY_3D: a cube of 2 x 2 x 2 points per cell (issue 16 item 5);
   * false: the plane-strain square. */
  bool three_d;
} bench_case;

/* In increasing size order. */
static const bench_case bench_cases[] = {
#define PLAIN   GM_FAMILY_PLAIN, 0.0, false
#define PLAIN3D GM_FAMILY_PLAIN, 0.0, true
    {"block-1e4", 1e4, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR, PLAIN},
    {"block-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR, PLAIN},
    {"ugimp-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_UGIMP, PLAIN},
    {"cpgimp-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_CPGIMP, PLAIN},
    {"cpdi-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_CPDI, PLAIN},
    {"bspline2-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_BSPLINE2,
     PLAIN},
    {"bspline3-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_BSPLINE3,
     PLAIN},
    {"granular-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR,
     GM_FAMILY_GRANULAR, 0.0, false},
    {"plain-cloud-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR,
     GM_FAMILY_PLAIN, 0.3, false},
    {"granular-cloud-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR,
     GM_FAMILY_GRANULAR, 0.3, false},
    {"granular-cpdi-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_CPDI,
     GM_FAMILY_GRANULAR, 0.0, false},
    {"empty-1e5", 1e5, 10.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR, PLAIN},
    {"mohr-coulomb-1e5", 1e5, 1.0, true, MATERIAL_MOHR_COULOMB, GM_SHAPE_LINEAR,
     PLAIN},
    {"drucker-prager-1e5", 1e5, 1.0, true, MATERIAL_DRUCKER_PRAGER,
     GM_SHAPE_LINEAR, PLAIN},
    {"block3d-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR, PLAIN3D},
    {"ugimp3d-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_UGIMP, PLAIN3D},
    {"granular3d-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR,
     GM_FAMILY_GRANULAR, 0.0, true},
    {"plain-cloud3d-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR,
     GM_FAMILY_PLAIN, 0.3, true},
    {"granular-cloud3d-1e5", 1e5, 1.0, true, MATERIAL_ELASTIC, GM_SHAPE_LINEAR,
     GM_FAMILY_GRANULAR, 0.3, true},
    {"block-1e6", 1e6, 1.0, false, MATERIAL_ELASTIC, GM_SHAPE_LINEAR, PLAIN},
    {"block3d-1e6", 1e6, 1.0, false, MATERIAL_ELASTIC, GM_SHAPE_LINEAR,
     PLAIN3D},
#undef PLAIN
#undef PLAIN3D
};
enum { CASE_COUNT = sizeof bench_cases / sizeof bench_cases[0] };
static const int worker_counts[] = {1, 2};

static const double block_side = 5.0;     /* m, whatever the resolution */
static const double youngs_modulus = 1e7; /* Pa */
static const double poisson_ratio = 0.3;
static const double block_density = 2000.0; /* kg/m^3 */
static const double gravity = -9.81;        /* m/s^2, along y */
static const int margin_cells = 4;          /* free cells around the block */
static const int warm_up_steps = 3;
static const int calibration_steps = 2;
static const double target_seconds = 1.5; /* per case */
static const int min_steps = 3, max_steps = 5000;

/* What one case measured. */
typedef struct bench_result {
  size_t points;
  int steps;
  double seconds;
  double cpu_seconds; /* process CPU time of the same steps, all threads */
  double peak_rss_bytes;
  double rss_increase_bytes;
  /* granular family: summed phase times (s) from the step summaries,
   * geometry, pair search, labels, layers, density control */
  double granular_seconds[5];
  int forest_reused_steps;
} bench_result;

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of the process (all its threads): with 1 worker the time the
 * step actually ran, which other processes on a loaded machine do not
 * stretch as they stretch the wall time (they still share the caches). */
static double cpu_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Current resident set (bytes) from /proc/self/statm; -1 if unavailable. */
static double current_rss_bytes(void) {
  FILE *file = fopen("/proc/self/statm", "r");
  if (!file)
    return -1.0;
  unsigned long total_pages = 0, resident_pages = 0;
  int read = fscanf(file, "%lu %lu", &total_pages, &resident_pages);
  fclose(file);
  if (read != 2)
    return -1.0;
  return (double)resident_pages * (double)sysconf(_SC_PAGESIZE);
}

/* Peak resident set of this process (bytes); Linux reports KiB. */
static double peak_rss_bytes(void) {
  struct rusage usage;
  if (getrusage(RUSAGE_SELF, &usage) != 0)
    return -1.0;
  return 1024.0 * (double)usage.ru_maxrss;
}

static int report_failure(const gm_domain *domain, const char *call,
                          gm_status status) {
  fprintf(stderr, "granmpm-bench: %s failed: %s\n  %s\n", call,
          gm_strerror(status),
          domain ? gm_domain_last_error(domain) : gm_last_create_error());
  return 1;
}

/* Evaluates a gm_* call; on error reports it and returns 1. */
#define CHECK(domain, call)                                                    \
  do {                                                                         \
    gm_status check_status_ = (call);                                          \
    if (check_status_ != GM_OK)                                                \
      return report_failure(domain, #call, check_status_);                     \
  } while (0)

/* The case's material, with the same elastic constants for every model
 * (friction angle 30 degrees, no dilation, no rate term for the plastic
 * ones: the block yields near its base and corners). */
static gm_status add_material(gm_domain *domain, bench_material kind,
                              int *material) {
  const double friction_angle = 30.0 * 3.14159265358979323846 / 180.0;
  if (kind == MATERIAL_MOHR_COULOMB) {
    gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
    def.youngs_modulus = youngs_modulus;
    def.poisson_ratio = poisson_ratio;
    def.density = block_density;
    def.friction_angle = friction_angle;
    def.dilation_angle = 0.0;
    def.bagnold_viscosity = 0.0;
    return gm_domain_add_mohr_coulomb(domain, &def, material);
  }
  if (kind == MATERIAL_DRUCKER_PRAGER) {
    gm_drucker_prager_def def = gm_drucker_prager_def_default();
    def.youngs_modulus = youngs_modulus;
    def.poisson_ratio = poisson_ratio;
    def.density = block_density;
    def.friction_angle = friction_angle;
    return gm_domain_add_drucker_prager(domain, &def, material);
  }
  gm_elastic_def def = gm_elastic_def_default();
  def.youngs_modulus = youngs_modulus;
  def.poisson_ratio = poisson_ratio;
  def.density = block_density;
  return gm_domain_add_elastic(domain, &def, material);
}

/* A falling cloud of points 1.5 cells apart above the block: each point is
 * disconnected (its domain of interaction meets no other), while linear
 * supports of neighbours still share nodes. Rows along y of columns along x
 * (and, in 3D, of the same number of columns along z). */
static int add_cloud(gm_domain *domain, int material, double cell_size,
                     int rows, int columns, bool three_d) {
  int dim = three_d ? 3 : 2, depth = three_d ? columns : 1;
  size_t count = (size_t)rows * (size_t)columns * (size_t)depth;
  double *position = malloc((size_t)dim * count * sizeof *position);
  double *volume = malloc(count * sizeof *volume);
  if (!position || !volume) {
    free(position);
    free(volume);
    fprintf(stderr, "granmpm-bench: out of memory for the cloud\n");
    return 1;
  }
  double spacing = 1.5 * cell_size; /* m */
  /* m^3 (m^2 in plane strain): a block point's, 2 per cell and axis */
  double point_volume = pow(0.5 * cell_size, dim);
  size_t i = 0;
  for (int row = 0; row < rows; row++)
    for (int layer = 0; layer < depth; layer++)
      for (int column = 0; column < columns; column++, i++) {
        double *x = position + (size_t)dim * i;
        x[0] = (column + 0.5) * spacing;
        x[1] = block_side + (row + 1.0) * spacing;
        if (three_d)
          x[2] = (layer + 0.5) * spacing;
        volume[i] = point_volume;
      }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.volume = volume;
  gm_status status = gm_domain_add_points(domain, &points, NULL);
  free(position);
  free(volume);
  CHECK(domain, status);
  return 0;
}

/* The velocity transfer of every case (--apic). */
static gm_transfer bench_transfer = GM_TRANSFER_FLIP;

/* Creates the domain and the block for one case. */
static int build_scene(const bench_case *scene, int workers,
                       gm_domain **domain) {
  /* n^2 cells of 4 points each give target_points (block and cloud); in
   * 3D n^3 cells of 8. */
  double block_points =
      scene->target_points * (1.0 - scene->disconnected_share);
  int cells_per_side = scene->three_d ? (int)lround(cbrt(block_points / 8.0))
                                      : (int)lround(sqrt(block_points / 4.0));
  double cell_size = block_side / cells_per_side; /* m */
  double margin = margin_cells * cell_size;       /* m */
  gm_domain_def def = gm_domain_def_default();
  def.geometry = scene->three_d ? GM_GEOMETRY_3D : GM_GEOMETRY_PLANE_STRAIN;
  def.origin[0] = -margin;
  if (scene->three_d) { /* z as x: margins on both sides */
    def.origin[2] = -margin;
    def.extent[2] = scene->box_scale * (block_side + 2 * margin);
  }
  def.origin[1] = 0.0; /* the bottom wall carries the block */
  def.extent[0] = scene->box_scale * (block_side + 2 * margin);
  def.extent[1] = scene->box_scale * (block_side + margin);
  int cloud_rows = 0, cloud_columns = cells_per_side * 2 / 3;
  if (scene->disconnected_share > 0.0) { /* 1.5 cells apart: disconnected */
    double cloud_points = scene->target_points * scene->disconnected_share;
    double per_row = scene->three_d ? (double)cloud_columns * cloud_columns
                                    : (double)cloud_columns;
    cloud_rows = (int)ceil(cloud_points / per_row);
    def.extent[1] += 1.5 * cell_size * (cloud_rows + 2);
  }
  def.family = scene->family;
  def.cell_size = cell_size;
  def.gravity[1] = gravity;
  def.scheme = GM_SCHEME_USL;
  def.shape = scene->shape;
  def.transfer = bench_transfer;
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  def.worker_count = workers;
  CHECK(*domain, gm_domain_create(&def, domain));

  int material = -1;
  CHECK(*domain, add_material(*domain, scene->material, &material));

  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.upper[0] = block_side;
  fill.upper[1] = block_side;
  if (scene->three_d)
    fill.upper[2] = block_side;
  fill.points_per_cell_axis = 2;
  CHECK(*domain, gm_domain_fill_box(*domain, &fill, NULL, NULL));
  if (scene->family != GM_FAMILY_PLAIN || scene->disconnected_share > 0.0) {
    /* rho_cr 1% below rho0: neighbours in the block interact. */
    gm_granular_def granular = gm_granular_def_default();
    granular.critical_density = 0.99 * block_density;
    CHECK(*domain, gm_domain_set_granular(*domain, material, &granular));
  }
  if (cloud_rows > 0)
    return add_cloud(*domain, material, cell_size, cloud_rows, cloud_columns,
                     scene->three_d);
  return 0;
}

/* Runs `steps` stable steps, adding the time spent in gm_domain_step and
 * the granular phase times to result (if not NULL; the summary query
 * itself, an O(N) count of states, stays out of the timing); returns 0 or
 * 1 after reporting an error. */
static int run_steps(gm_domain *domain, int steps, bench_result *result) {
  for (int step = 0; step < steps; step++) {
    double start = now_seconds(), cpu_start = cpu_seconds();
    CHECK(domain, gm_domain_step(domain, 0.0)); /* dt <= 0: the stable dt */
    if (!result)
      continue;
    result->seconds += now_seconds() - start;
    result->cpu_seconds += cpu_seconds() - cpu_start;
    gm_granular_summary summary = gm_granular_summary_default();
    CHECK(domain, gm_domain_get_granular_summary(domain, &summary));
    const double phases[5] = {summary.geometry_seconds,
                              summary.pair_search_seconds,
                              summary.label_seconds, summary.layer_seconds,
                              summary.density_control_seconds};
    for (int k = 0; k < 5; k++)
      result->granular_seconds[k] += phases[k];
    result->forest_reused_steps += summary.forest_reused;
  }
  return 0;
}

/* Builds, warms up, calibrates and times one case. */
static int measure_case(const bench_case *scene, int workers,
                        bench_result *result) {
  double baseline_rss = current_rss_bytes();
  gm_domain *domain = NULL;
  int failed = build_scene(scene, workers, &domain);
  if (!failed)
    failed = run_steps(domain, warm_up_steps, NULL);
  double start = now_seconds();
  if (!failed)
    failed = run_steps(domain, calibration_steps, NULL);
  double per_step = (now_seconds() - start) / calibration_steps;
  int steps = (int)(target_seconds / fmax(per_step, 1e-9));
  steps = steps < min_steps ? min_steps : steps > max_steps ? max_steps : steps;
  result->seconds = 0.0;
  if (!failed)
    failed = run_steps(domain, steps, result);
  result->steps = steps;
  result->points = gm_domain_point_count(domain);
  result->peak_rss_bytes = peak_rss_bytes();
  result->rss_increase_bytes =
      baseline_rss >= 0 ? result->peak_rss_bytes - baseline_rss : -1.0;
  gm_domain_destroy(domain);
  return failed;
}

/* Child process: one case, one CSV row. */
static int run_case(const bench_case *scene, int workers) {
  bench_result result = {0};
  if (measure_case(scene, workers, &result) != 0)
    return 1;
  double point_steps = (double)result.points * result.steps;
  printf("%s,%zu,%d,%d,%.3f,%.2f,%.1f,%.0f,%.2f\n", scene->name, result.points,
         workers, result.steps, result.seconds,
         1e9 * result.seconds / point_steps,
         result.peak_rss_bytes / (1024.0 * 1024.0),
         result.rss_increase_bytes / (double)result.points,
         1e9 * result.cpu_seconds / point_steps);
  if (scene->family == GM_FAMILY_GRANULAR) { /* the split, ns/point-step */
    static const char *const names[5] = {"geometry", "pair_search", "labels",
                                         "layers", "density_control"};
    fprintf(stderr, "# %s %d worker(s) granular split:", scene->name, workers);
    for (int k = 0; k < 5; k++)
      fprintf(stderr, " %s %.1f", names[k],
              1e9 * result.granular_seconds[k] / point_steps);
    fprintf(stderr, " (forest reused in %d of %d steps)\n",
            result.forest_reused_steps, result.steps);
  }
  return 0;
}

/* Runs a case in a forked child so its memory numbers are its own. */
static bool run_case_isolated(const bench_case *scene, int workers) {
  fflush(stdout);
  fflush(stderr);
  pid_t child = fork();
  if (child < 0) {
    perror("granmpm-bench: fork");
    return false;
  }
  if (child == 0)
    exit(run_case(scene, workers));
  int wait_status = 0;
  if (waitpid(child, &wait_status, 0) != child)
    return false;
  if (WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0)
    return true;
  fprintf(stderr, "granmpm-bench: case %s with %d worker(s) failed\n",
          scene->name, workers);
  return false;
}

static void print_usage(FILE *stream) {
  fprintf(stream, "usage: granmpm-bench [--quick] [--case NAME] [--apic] "
                  "[--workers N]\ncases:");
  for (int c = 0; c < CASE_COUNT; c++)
    fprintf(stream, " %s", bench_cases[c].name);
  fprintf(stream, "\n");
}

int main(int argc, char **argv) {
  bool quick = false;
  const char *only_case = NULL;
  int only_workers = 0; /* 0: every count of worker_counts */
  for (int a = 1; a < argc; a++) {
    if (strcmp(argv[a], "--quick") == 0) {
      quick = true;
    } else if (strcmp(argv[a], "--case") == 0 && a + 1 < argc) {
      only_case = argv[++a];
    } else if (strcmp(argv[a], "--workers") == 0 && a + 1 < argc) {
      only_workers = atoi(argv[++a]);
      if (only_workers < 1) {
        fprintf(stderr, "granmpm-bench: --workers needs a count >= 1\n");
        return 2;
      }
    } else if (strcmp(argv[a], "--apic") == 0) {
      bench_transfer = GM_TRANSFER_APIC;
    } else if (strcmp(argv[a], "--help") == 0) {
      print_usage(stdout);
      return 0;
    } else {
      print_usage(stderr);
      return 2;
    }
  }
  bool known = only_case == NULL;
  for (int c = 0; c < CASE_COUNT; c++)
    known = known || strcmp(bench_cases[c].name, only_case) == 0;
  if (!known) {
    fprintf(stderr, "granmpm-bench: unknown case '%s'\n", only_case);
    print_usage(stderr);
    return 2;
  }

  printf("case,points,workers,steps,seconds,ns_per_point_step,peak_rss_mb,"
         "bytes_per_point,cpu_ns_per_point_step\n");
  bool all_ok = true;
  for (int c = 0; c < CASE_COUNT; c++) {
    const bench_case *scene = &bench_cases[c];
    if ((quick && !scene->quick) ||
        (only_case && strcmp(scene->name, only_case) != 0))
      continue;
    if (only_workers > 0) {
      all_ok = run_case_isolated(scene, only_workers) && all_ok;
      continue;
    }
    for (size_t w = 0; w < sizeof worker_counts / sizeof worker_counts[0]; w++)
      all_ok = run_case_isolated(scene, worker_counts[w]) && all_ok;
  }
  return all_ok ? 0 : 1;
}
