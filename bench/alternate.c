/*
 * alternate.c - two or more builds of the library, step by step in one
 * process: the yardstick's scene (libblock.c: an elastic block, E = 1e7
 * Pa, nu = 0.3, rho = 1800 kg/m^3, on a slip floor under gravity, h =
 * 0.01 m, 2 x 2 points per cell, USL, 1 worker, dt = 0.5 h / c) is built
 * once per library, each library loaded with dlopen (RTLD_LOCAL |
 * RTLD_DEEPBIND, so each resolves its own symbols), and the domains are
 * stepped in turn, A B A B ..., the first library of each round rotated.
 * Each step is timed with the thread's CPU clock. On a shared machine a
 * slow patch then falls on every library alike, within a step or two,
 * and time spent waiting for a core is not counted: the comparison that
 * bench/yardstick.sh's interleaved processes give only over minutes.
 *
 * Usage: granmpm-alternate CELLS STEPS SHAPE LIB.so[@SHAPE] [...]
 *   CELLS: cells per side of the block (158: 99 856 points; 500: 1e6)
 *   SHAPE: gm_shape number (0 linear, 1 uGIMP, 3 CPDI, ...); a library
 *   given as LIB.so@SHAPE runs that shape instead, so one process can
 *   alternate, say, linear and uGIMP steps of one build (their ratio
 *   from one patch of load; the same file may be given twice). A letter
 *   after the shape number changes the block's material: LIB.so@0m the
 *   built-in Mohr-Coulomb model, LIB.so@0d Drucker-Prager (friction angle
 *   30 degrees, no dilation, no rate term: granmpm-bench's plastic cases),
 *   so a material's cost over the elastic step comes from one process too.
 *   LIB.so@0g: the elastic block in the granular family (rho_cr = 0.99
 *   rho0, as granmpm-bench's granular-1e5: every point connected, one
 *   parallel grid), so the family's cost over the plain step comes from
 *   one process.
 * Prints per library the median, lower quartile and mean CPU time of a
 * step, in ns per point-step. All domains are alive together: at 1e6
 * points each holds about 300 MB.
 */
#define _GNU_SOURCE
#include <granmpm.h>

#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_LIBRARIES 8

typedef gm_status init_fn(void *out, size_t struct_size);
typedef gm_status create_fn(const gm_domain_def *def, gm_domain **out);
typedef gm_status add_elastic_fn(gm_domain *domain, const gm_elastic_def *def,
                                 int *material_id);
typedef gm_status add_mohr_coulomb_fn(gm_domain *domain,
                                      const gm_mohr_coulomb_def *def,
                                      int *material_id);
typedef gm_status add_drucker_prager_fn(gm_domain *domain,
                                        const gm_drucker_prager_def *def,
                                        int *material_id);
typedef gm_status fill_fn(gm_domain *domain, const gm_fill_def *def,
                          int64_t *first_id, size_t *count);
typedef gm_status set_granular_fn(gm_domain *domain, int material,
                                  const gm_granular_def *def);
typedef gm_status step_fn(gm_domain *domain, double dt);
typedef const char *error_fn(const gm_domain *domain);
typedef void destroy_fn(gm_domain *domain);

typedef struct library {
  const char *path; /* as given, with any @SHAPE */
  char file[4096];  /* the file to load */
  int shape;        /* gm_shape of its scene */
  char material;    /* 'e' elastic, 'm' Mohr-Coulomb, 'd' Drucker-Prager,
                       'g' elastic in the granular family */
  step_fn *step;
  error_fn *last_error;
  destroy_fn *destroy;
  gm_domain *domain;
} library;

/* A function of the library (ISO C has no object-to-function pointer
 * conversion: the pointer is copied). */
static void *symbol(void *handle, const char *name, size_t size, void *out) {
  void *address = dlsym(handle, name);
  if (!address) {
    fprintf(stderr, "granmpm-alternate: %s: %s\n", name, dlerror());
    exit(1);
  }
  memcpy(out, &address, size);
  return out;
}

static double thread_seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int compare_doubles(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* The block's material, with the elastic block's constants. */
static gm_status add_material(void *handle, library *lib, int *material) {
  const double friction_angle = 30.0 * 3.14159265358979323846 / 180.0;
  init_fn *init;
  if (lib->material == 'm') {
    add_mohr_coulomb_fn *add;
    symbol(handle, "gm_mohr_coulomb_def_init", sizeof init, &init);
    symbol(handle, "gm_domain_add_mohr_coulomb", sizeof add, &add);
    gm_mohr_coulomb_def def;
    init(&def, sizeof def);
    def.youngs_modulus = 1e7;
    def.poisson_ratio = 0.3;
    def.density = 1800.0;
    def.friction_angle = friction_angle;
    def.dilation_angle = 0.0;
    def.bagnold_viscosity = 0.0;
    return add(lib->domain, &def, material);
  }
  if (lib->material == 'd') {
    add_drucker_prager_fn *add;
    symbol(handle, "gm_drucker_prager_def_init", sizeof init, &init);
    symbol(handle, "gm_domain_add_drucker_prager", sizeof add, &add);
    gm_drucker_prager_def def;
    init(&def, sizeof def);
    def.youngs_modulus = 1e7;
    def.poisson_ratio = 0.3;
    def.density = 1800.0;
    def.friction_angle = friction_angle;
    return add(lib->domain, &def, material);
  }
  add_elastic_fn *add;
  symbol(handle, "gm_elastic_def_init", sizeof init, &init);
  symbol(handle, "gm_domain_add_elastic", sizeof add, &add);
  gm_elastic_def elastic;
  init(&elastic, sizeof elastic);
  elastic.youngs_modulus = 1e7;
  elastic.poisson_ratio = 0.3;
  elastic.density = 1800.0;
  return add(lib->domain, &elastic, material);
}

static size_t open_scene(library *lib, int cells, int shape) {
  void *handle = dlopen(lib->file, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
  if (!handle) {
    fprintf(stderr, "granmpm-alternate: %s\n", dlerror());
    exit(1);
  }
  init_fn *def_init, *fill_init;
  create_fn *create;
  fill_fn *fill;
  symbol(handle, "gm_domain_def_init", sizeof def_init, &def_init);
  symbol(handle, "gm_fill_def_init", sizeof fill_init, &fill_init);
  symbol(handle, "gm_domain_create", sizeof create, &create);
  symbol(handle, "gm_domain_fill_box", sizeof fill, &fill);
  symbol(handle, "gm_domain_step", sizeof lib->step, &lib->step);
  symbol(handle, "gm_domain_last_error", sizeof lib->last_error,
         &lib->last_error);
  symbol(handle, "gm_domain_destroy", sizeof lib->destroy, &lib->destroy);
  const double h = 0.01; /* m */
  gm_domain_def def;
  def_init(&def, sizeof def);
  def.geometry = GM_GEOMETRY_PLANE_STRAIN;
  def.extent[0] = def.extent[1] = (cells + 8) * h;
  def.cell_size = h;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_YMIN] = GM_WALL_SLIP;
  def.worker_count = 1;
  def.shape = (gm_shape)shape;
  if (lib->material == 'g')
    def.family = GM_FAMILY_GRANULAR;
  if (create(&def, &lib->domain) != GM_OK) {
    fprintf(stderr, "granmpm-alternate: %s: create failed\n", lib->path);
    exit(1);
  }
  int material = -1;
  gm_fill_def box;
  fill_init(&box, sizeof box);
  int64_t first = 0;
  size_t count = 0;
  gm_status status = add_material(handle, lib, &material);
  if (status == GM_OK && lib->material == 'g') {
    init_fn *granular_init;
    set_granular_fn *set_granular;
    symbol(handle, "gm_granular_def_init", sizeof granular_init,
           &granular_init);
    symbol(handle, "gm_domain_set_granular", sizeof set_granular,
           &set_granular);
    gm_granular_def granular;
    granular_init(&granular, sizeof granular);
    granular.critical_density = 0.99 * 1800.0; /* kg/m^3: all connected */
    status = set_granular(lib->domain, material, &granular);
  }
  if (status == GM_OK) {
    box.material = material;
    box.lower[0] = 4 * h;
    box.upper[0] = (4 + cells) * h;
    box.lower[1] = 0.0;
    box.upper[1] = cells * h;
    box.points_per_cell_axis = 2;
    if (fill(lib->domain, &box, &first, &count) == GM_OK)
      return count;
  }
  fprintf(stderr, "granmpm-alternate: %s: %s\n", lib->path,
          lib->last_error(lib->domain));
  exit(1);
}

int main(int argc, char **argv) {
  if (argc < 5 || argc - 4 > MAX_LIBRARIES) {
    fprintf(stderr, "usage: granmpm-alternate CELLS STEPS SHAPE "
                    "LIB.so[@SHAPE[m|d|g]] [LIB.so[@SHAPE[m|d|g]] ...] (at "
                    "most 8)\n");
    return 2;
  }
  int cells = atoi(argv[1]), steps = atoi(argv[2]), shape = atoi(argv[3]);
  int count = argc - 4;
  if (cells < 1 || steps < 1)
    return 2;
  library libs[MAX_LIBRARIES];
  size_t points = 0;
  for (int l = 0; l < count; l++) {
    libs[l].path = argv[4 + l];
    snprintf(libs[l].file, sizeof libs[l].file, "%s", argv[4 + l]);
    libs[l].shape = shape;
    libs[l].material = 'e';
    char *at = strrchr(libs[l].file, '@');
    if (at) { /* LIB.so@SHAPE, LIB.so@SHAPEm, LIB.so@SHAPEd, @SHAPEg */
      *at = '\0';
      char *end = at + 1;
      libs[l].shape = (int)strtol(at + 1, &end, 10);
      if (*end == 'm' || *end == 'd' || *end == 'g')
        libs[l].material = *end;
    }
    points = open_scene(&libs[l], cells, libs[l].shape);
  }
  const double h = 0.01, young = 1e7, nu = 0.3, rho = 1800.0;
  double modulus = young * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
  double dt = 0.5 * h / sqrt(modulus / rho); /* s */
  double *seconds = malloc(sizeof *seconds * (size_t)count * (size_t)steps);
  if (!seconds)
    return 1;
  for (int s = -3; s < steps; s++) { /* 3 untimed warm-up steps */
    for (int k = 0; k < count; k++) {
      int l = (k + (s < 0 ? 0 : s)) % count;
      double start = thread_seconds();
      if (libs[l].step(libs[l].domain, dt) != GM_OK) {
        fprintf(stderr, "granmpm-alternate: %s: %s\n", libs[l].path,
                libs[l].last_error(libs[l].domain));
        return 1;
      }
      if (s >= 0)
        seconds[(size_t)l * (size_t)steps + (size_t)s] =
            thread_seconds() - start;
    }
  }
  printf("library,points,steps,median_cpu_ns_per_point_step,"
         "q1_cpu_ns_per_point_step,mean_cpu_ns_per_point_step\n");
  for (int l = 0; l < count; l++) {
    double *t = seconds + (size_t)l * (size_t)steps, sum = 0.0;
    for (int s = 0; s < steps; s++)
      sum += t[s];
    qsort(t, (size_t)steps, sizeof *t, compare_doubles);
    double scale = 1e9 / (double)points;
    printf("%s,%zu,%d,%.1f,%.1f,%.1f\n", libs[l].path, points, steps,
           t[steps / 2] * scale, t[steps / 4] * scale, sum / steps * scale);
    libs[l].destroy(libs[l].domain);
  }
  free(seconds);
  return 0;
}
