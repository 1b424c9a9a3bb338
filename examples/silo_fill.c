/*
 * silo_fill.c - filling a planar silo layer by layer and comparing the
 * settled stresses with Janssen's formula (references.md, "Silo discharge
 * and silo pressure").
 *
 * A 1 m wide silo with frictional walls (mu_w = 0.3) is filled to 3 m with
 * a Drucker-Prager granular material (phi = 30 degrees): one source per
 * 0.05 m layer places its points at rest on top of the previous layers,
 * every 0.05 s (staged filling, as the papers fill silos incrementally;
 * dropping the material from above makes impacts that an explicit scheme
 * resolves only with much smaller steps). Local damping then lets the fill
 * settle. The program prints the vertical stress and the wall pressure
 * against Janssen,
 *   sigma_v(z) = rho g W / (2 mu_w K) (1 - exp(-2 mu_w K z / W)),
 * with Jaky's K = 1 - sin(phi), and writes a ParaView series.
 *
 * This is a demonstration, not a validation: the vertical stress follows
 * Janssen closely, while the simulated lateral stress ratio at the wall is
 * higher than Jaky's K (see the closing note of the session that added
 * it).
 *
 * Usage: silo_fill [OUTDIR]   (default: no output files)
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;
static const double WIDTH = 1.0;         /* m */
static const double FILL_HEIGHT = 3.0;   /* m */
static const double LAYER = 0.05;        /* m, layer thickness = cell size */
static const double LAYER_PERIOD = 0.05; /* s between layers */
static const double SETTLE_TIME = 2.0;   /* s after the last layer */
static const double DENSITY = 1500.0;    /* kg/m^3 */
static const double GRAVITY = 9.81;      /* m/s^2 */
static const double WALL_FRICTION = 0.3;
static const double FRICTION_ANGLE = 30.0 * PI / 180.0; /* rad */
enum { COLUMNS = 40, LAYERS = 60 }; /* 2 rows of 40 points per layer */

#define CHECK(domain, call)                                                    \
  do {                                                                         \
    gm_status check_status_ = (call);                                          \
    if (check_status_ != GM_OK) {                                              \
      fprintf(stderr, "silo_fill: %s failed: %s\n", #call,                     \
              (domain) ? gm_domain_last_error(domain)                          \
                       : gm_last_create_error());                              \
      return 1;                                                                \
    }                                                                          \
  } while (0)

static gm_wall_def side_wall(double x, double normal_x) {
  gm_wall_def wall = gm_wall_def_default();
  wall.point[0] = x;
  wall.normal[0] = normal_x;
  wall.normal[1] = 0.0;
  wall.friction_static = wall.friction_kinetic = WALL_FRICTION;
  return wall;
}

/* Janssen's vertical stress at depth z (Pa), planar silo (A/U = W/2). */
static double janssen(double z) {
  double k = 1.0 - sin(FRICTION_ANGLE);
  return DENSITY * GRAVITY * WIDTH / (2.0 * WALL_FRICTION * k) *
         (1.0 - exp(-2.0 * WALL_FRICTION * k * z / WIDTH));
}

/* One source per layer, placing 2 rows of COLUMNS points at rest. */
static int add_layers(gm_domain *domain, int material,
                      double positions[LAYERS][4 * COLUMNS]) {
  double spacing = WIDTH / COLUMNS; /* m */
  for (int layer = 0; layer < LAYERS; layer++) {
    for (int row = 0; row < 2; row++) {
      for (int column = 0; column < COLUMNS; column++) {
        double *point = positions[layer] + 2 * (row * COLUMNS + column);
        point[0] = (column + 0.5) * spacing;
        point[1] = layer * LAYER + (row + 0.5) * spacing;
      }
    }
    gm_source_def source = gm_source_def_default();
    source.material = material;
    source.count = 2 * COLUMNS;
    source.position = positions[layer];
    source.point_size = spacing;
    source.density = DENSITY;
    source.start_time = layer * LAYER_PERIOD; /* once, at that time */
    int id = -1;
    CHECK(domain, gm_domain_add_source(domain, &source, &id));
  }
  return 0;
}

/* Vertical stress averaged over the points at depth z +- LAYER/2. */
static double vertical_stress(const double *position, const double *stress,
                              size_t count, double top, double z) {
  double sum = 0.0;
  int found = 0;
  for (size_t i = 0; i < count; i++) {
    if (fabs(top - position[2 * i + 1] - z) >= 0.5 * LAYER)
      continue;
    sum -= stress[6 * i + GM_YY];
    found++;
  }
  return found ? sum / found : 0.0;
}

/* Wall pressure averaged over the wall nodes at depth z +- 0.125 m. */
static double wall_pressure(const gm_wall_traction *profile, size_t count,
                            double top, double z) {
  double sum = 0.0;
  int found = 0;
  for (size_t i = 0; i < count; i++) {
    /* The left wall's tangent (normal_y, -normal_x) = (0, -1): height is
     * minus the position. */
    double depth = top + profile[i].position;
    if (fabs(depth - z) >= 0.125)
      continue;
    sum += profile[i].normal;
    found++;
  }
  return found ? sum / found : 0.0;
}

int main(int argc, char **argv) {
  const char *outdir = argc > 1 ? argv[1] : NULL;
  gm_domain_def def = gm_domain_def_default();
  def.scheme = GM_SCHEME_MUSL; /* placed points start isolated */
  def.cell_size = LAYER;
  def.extent[0] = WIDTH;
  def.extent[1] = FILL_HEIGHT + 1.0;
  def.gravity[1] = -GRAVITY;
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  def.damping = 0.3;
  gm_domain *domain = NULL;
  CHECK(domain, gm_domain_create(&def, &domain));
  gm_wall_def left = side_wall(0.0, 1.0), right = side_wall(WIDTH, -1.0);
  int left_id = -1, right_id = -1;
  CHECK(domain, gm_domain_add_wall(domain, &left, &left_id));
  CHECK(domain, gm_domain_add_wall(domain, &right, &right_id));
  gm_drucker_prager_def granular = gm_drucker_prager_def_default();
  granular.youngs_modulus = 1e6;
  granular.density = DENSITY;
  granular.friction_angle = FRICTION_ANGLE;
  int material = -1;
  CHECK(domain, gm_domain_add_drucker_prager(domain, &granular, &material));
  static double positions[LAYERS][4 * COLUMNS];
  if (add_layers(domain, material, positions) != 0)
    return 1;

  gm_series *series = NULL;
  char pvd[1024];
  if (outdir) {
    snprintf(pvd, sizeof pvd, "%s/silo.pvd", outdir);
    CHECK(NULL, gm_series_create(pvd, &series));
  }
  const double dt = 5e-4; /* s, below the stable dt of the DP material */
  double end = LAYERS * LAYER_PERIOD + SETTLE_TIME, time = 0.0;
  for (int step = 0; time < end; step++) {
    CHECK(domain, gm_domain_step(domain, dt));
    time += dt;
    if (series && step % 200 == 0)
      CHECK(domain, gm_series_write(series, domain));
  }
  gm_series_destroy(series);

  size_t count = gm_domain_point_count(domain);
  double *position = malloc(2 * count * sizeof(double));
  double *stress = malloc(6 * count * sizeof(double));
  gm_wall_traction *profile = malloc(400 * sizeof *profile);
  size_t profile_count = 0;
  if (!position || !stress || !profile)
    return 1;
  CHECK(domain,
        gm_domain_get_field(domain, GM_FIELD_POSITION, position, 2 * count));
  CHECK(domain,
        gm_domain_get_field(domain, GM_FIELD_STRESS, stress, 6 * count));
  CHECK(domain, gm_domain_get_wall_tractions(domain, left_id, profile, 400,
                                             &profile_count));
  double top = 0.0;
  for (size_t i = 0; i < count; i++)
    top = fmax(top, position[2 * i + 1]);
  printf("planar silo %.1f m wide, filled to %.2f m in %d layers (%zu "
         "points), settled %.1f s\n",
         WIDTH, top, LAYERS, count, SETTLE_TIME);
  printf("depth (m)  sigma_v (Pa)  Janssen  ratio   wall p (Pa)  K*Janssen  "
         "ratio\n");
  double k = 1.0 - sin(FRICTION_ANGLE);
  for (double z = 0.25; z < top; z += 0.25) {
    double vertical = vertical_stress(position, stress, count, top, z);
    double wall = wall_pressure(profile, profile_count, top, z);
    printf("%9.2f  %12.0f  %7.0f  %5.3f  %11.0f  %9.0f  %5.3f\n", z, vertical,
           janssen(z), vertical / janssen(z), wall, k * janssen(z),
           wall / (k * janssen(z)));
  }
  free(position);
  free(stress);
  free(profile);
  gm_domain_destroy(domain);
  return 0;
}
