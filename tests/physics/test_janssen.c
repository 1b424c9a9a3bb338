/*
 * test_janssen.c - a planar silo at rest against Janssen's formula (issue
 * 3; docs/references.md, "Silo discharge and silo pressure"):
 *
 *   sigma_v(z) = rho g (A/U) / (mu_w K) (1 - exp(-mu_w K z U / A)),
 *   sigma_h(z) = K sigma_v(z),   A/U = W/2 between two planar walls,
 *
 * z the depth below the free surface. A 1 m wide silo with Coulomb walls
 * (mu_w = 0.3) is filled to 3 m layer by layer, each layer placed at rest on
 * the current free surface, and settled with a little local damping. We
 * check the cross-section vertical stress, the wall pressure, and that the
 * walls and the floor carry the weight.
 *
 * Which K. Janssen takes K constant and the wall friction fully mobilised.
 * Between rigid walls the fill is loaded in confined (uniaxial) compression;
 * on that path its stress ratio q/p = 3 (1 - K0) / (1 + 2 K0) = 0.75 stays
 * inside the Drucker-Prager surface (m = 1.03 for phi = 30 degrees), and
 * with the wall shear mu_w K0 sigma_v added it is still 0.85 < m: the fill
 * is elastic, so its lateral stress ratio is the at-rest value of an
 * elastic solid, K0 = nu / (1 - nu). We choose nu = 1/3, which makes K0 =
 * 0.5 = Jaky's 1 - sin(phi) for phi = 30 degrees, the value usually paired
 * with Janssen: both estimates give the same K, fixed before the run.
 *
 * Measuring. The vertical stress of a cell row is the force the row
 * transmits, -sum(V_p sigma_yy,p) / (h W): for linear shape functions it is
 * exactly what the nodal equilibrium determines (points of one cell share
 * dN/dy, so only the sum over a row is constrained; the split between
 * points is a zero-energy mode that cell crossing excites: the dip to 0.71
 * of Janssen at 2.25 m depth that per-point depth averages showed in the
 * first version of examples/silo_layers_janssen.c). Wall loads are averaged
 * over the last 0.2 s of settling.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_util.h"

static const double PI = 3.14159265358979323846;
static const double SILO_WIDTH = 1.0;          /* m, W */
static const double FILL_HEIGHT = 3.0;         /* m */
static const double DENSITY = 1500.0;          /* kg/m^3 */
static const double GRAVITY = 9.81;            /* m/s^2 */
static const double WALL_FRICTION = 0.3;       /* mu_w, static = kinetic */
static const double FLOOR_FRICTION = 1.0;      /* a rough floor */
static const double FRICTION_ANGLE = 30.0;     /* phi, degrees */
static const double YOUNGS_MODULUS = 1e6;      /* Pa */
static const double POISSON_RATIO = 1.0 / 3.0; /* K0 = nu/(1-nu) = 0.5 */
static const double LAYER_PERIOD = 0.05;       /* s between layers */
static const double SETTLE_TIME = 2.0;         /* s after the last layer */
static const double AVERAGING_TIME = 0.2;      /* s, wall loads averaged */
/* Depths excluded from the comparison, m. Top: Janssen's stresses are
 * cross-section means; the wall stress needs a depth of about half the
 * width to spread across the section (Saint-Venant), so the wall pressure
 * is compared only from W/2 down, the vertical stress (a cross-section
 * force, exact at any depth) from two cells down. Bottom: the rough floor
 * holds the fill and stiffens the wall corner, which Janssen ignores. */
static const double TOP_BAND_VERTICAL = 0.1; /* m, 2 cells */
static const double TOP_BAND_WALL = 0.5;     /* m, W/2 */
static const double BOTTOM_BAND = 0.25;      /* m, a quarter width */
static const double WALL_WINDOW = 0.25;      /* m, wall-pressure averages */

enum { MAX_NODE_ROWS = 1024 };

/* Grid and damping of one run (the sensitivity study varies them). */
typedef struct silo_config {
  double cell_size;         /* m */
  int points_per_cell_axis; /* n: n x n points per cell */
  double damping;           /* local damping coefficient, - */
} silo_config;

/* Time integrals over the averaging window, divided by its length at the
 * end: the mean loads of the settled silo. */
typedef struct silo_loads {
  double wall_pressure[MAX_NODE_ROWS]; /* Pa, mean of both side walls, by
                                          node row (height / cell size) */
  double wall_friction;                /* N, upward, both side walls */
  double floor_reaction;               /* N, upward */
  double duration;                     /* s, averaged over */
} silo_loads;

typedef struct silo {
  silo_config config;
  gm_domain *domain;
  int material;
  int side_walls[2]; /* left (x = 0), right (x = W) */
  int floor;
  silo_loads loads;
} silo;

/* Janssen's lateral stress ratio, fixed from the material (see above). */
static double janssen_k(void) {
  return POISSON_RATIO / (1.0 - POISSON_RATIO);
}

/* Janssen's vertical stress at depth z (m), Pa, planar silo A/U = W/2. */
static double janssen_vertical_stress(double depth) {
  double decay = 2.0 * WALL_FRICTION * janssen_k() / SILO_WIDTH; /* 1/m */
  return DENSITY * GRAVITY / decay * (1.0 - exp(-decay * depth));
}

static int add_wall(gm_domain *domain, const double point[2],
                    const double normal[2], double friction) {
  gm_wall_def wall = gm_wall_def_default();
  for (int k = 0; k < 2; k++) {
    wall.point[k] = point[k];
    wall.normal[k] = normal[k];
  }
  wall.friction_static = wall.friction_kinetic = friction;
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &id));
  return id;
}

/* An empty silo: frictional side walls and a rough floor as planar walls
 * (they report their loads; box faces do not), two cells of grid below the
 * floor and one metre above the fill. */
static silo create_silo(const silo_config *config) {
  silo result;
  memset(&result, 0, sizeof result);
  result.config = *config;
  gm_domain_def def = gm_domain_def_default();
  def.scheme = GM_SCHEME_MUSL;
  def.cell_size = config->cell_size;
  def.origin[1] = -2.0 * config->cell_size;
  def.extent[0] = SILO_WIDTH;
  def.extent[1] = FILL_HEIGHT + 1.0 + 2.0 * config->cell_size;
  def.gravity[1] = -GRAVITY;
  def.damping = config->damping;
  result.domain = test_create_domain(&def);
  const double left[2] = {0.0, 0.0}, right[2] = {SILO_WIDTH, 0.0};
  const double into_x[2] = {1.0, 0.0}, out_x[2] = {-1.0, 0.0};
  const double up[2] = {0.0, 1.0};
  result.side_walls[0] = add_wall(result.domain, left, into_x, WALL_FRICTION);
  result.side_walls[1] = add_wall(result.domain, right, out_x, WALL_FRICTION);
  result.floor = add_wall(result.domain, left, up, FLOOR_FRICTION);
  gm_drucker_prager_def granular = gm_drucker_prager_def_default();
  granular.youngs_modulus = YOUNGS_MODULUS;
  granular.poisson_ratio = POISSON_RATIO;
  granular.density = DENSITY;
  granular.friction_angle = FRICTION_ANGLE * PI / 180.0;
  TEST_ASSERT_OK(
      result.domain,
      gm_domain_add_drucker_prager(result.domain, &granular, &result.material));
  return result;
}

/* Height of the free surface, m: the top point plus half its spacing. */
static double free_surface(const silo *s) {
  size_t count = gm_domain_point_count(s->domain);
  if (count == 0)
    return 0.0;
  const double *height = NULL;
  TEST_ASSERT_OK(s->domain, gm_domain_view_field(s->domain, GM_FIELD_POSITION,
                                                 1, &height));
  double top = height[0];
  for (size_t i = 1; i < count; i++)
    top = fmax(top, height[i]);
  return top + 0.5 * s->config.cell_size / s->config.points_per_cell_axis;
}

/* One layer, a cell thick, at rest on the current free surface: no drop,
 * so no impact (a layer released from above hits at sqrt(2 g gap)). */
static void place_layer(silo *s) {
  int per_cell = s->config.points_per_cell_axis;
  double spacing = s->config.cell_size / per_cell; /* m */
  size_t columns = (size_t)lround(SILO_WIDTH / spacing);
  size_t count = columns * (size_t)per_cell;
  double base = free_surface(s); /* m */
  double *position = malloc(2 * count * sizeof *position);
  double *volume = malloc(count * sizeof *volume);
  ck_assert(position && volume);
  for (size_t i = 0; i < count; i++) {
    position[2 * i] = ((double)(i % columns) + 0.5) * spacing;
    position[2 * i + 1] = base + ((double)(i / columns) + 0.5) * spacing;
    volume[i] = spacing * spacing; /* m^2 per unit thickness */
  }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = s->material;
  points.position = position;
  points.volume = volume;
  TEST_ASSERT_OK(s->domain, gm_domain_add_points(s->domain, &points, NULL));
  free(position);
  free(volume);
}

/* Adds this step's wall loads, weighted by dt (s), to the averages. */
static void record_loads(silo *s, double dt) {
  static gm_wall_traction profile[MAX_NODE_ROWS];
  for (int side = 0; side < 2; side++) {
    size_t count = 0;
    TEST_ASSERT_OK(s->domain, gm_domain_get_wall_tractions(
                                  s->domain, s->side_walls[side], profile,
                                  MAX_NODE_ROWS, &count));
    for (size_t i = 0; i < count; i++) {
      /* Positions run along (n_y, -n_x) from y = 0: down the left wall,
       * up the right one. */
      double height = side == 0 ? -profile[i].position : profile[i].position;
      long row = lround(height / s->config.cell_size);
      if (row >= 0 && row < MAX_NODE_ROWS)
        s->loads.wall_pressure[row] += 0.5 * profile[i].normal * dt;
    }
    gm_wall_force force = gm_wall_force_default();
    TEST_ASSERT_OK(s->domain, gm_domain_get_wall_force(
                                  s->domain, s->side_walls[side], &force));
    s->loads.wall_friction += force.impulse[1];
  }
  gm_wall_force floor = gm_wall_force_default();
  TEST_ASSERT_OK(s->domain,
                 gm_domain_get_wall_force(s->domain, s->floor, &floor));
  s->loads.floor_reaction += floor.impulse[1];
  s->loads.duration += dt;
}

/* Fills the silo layer by layer, settles it and averages the wall loads
 * over the last AVERAGING_TIME. */
static void fill_and_settle(silo *s) {
  int layers = (int)lround(FILL_HEIGHT / s->config.cell_size);
  double end = layers * LAYER_PERIOD + SETTLE_TIME; /* s */
  double time = 0.0, next_layer = 0.0;              /* s */
  int placed = 0;
  while (time < end) {
    if (placed < layers && time >= next_layer) {
      place_layer(s);
      placed++;
      next_layer += LAYER_PERIOD;
    }
    double dt = 0.0; /* s */
    TEST_ASSERT_OK(s->domain, gm_domain_stable_dt(s->domain, &dt));
    TEST_ASSERT_OK(s->domain, gm_domain_step(s->domain, dt));
    time += dt;
    if (time > end - AVERAGING_TIME)
      record_loads(s, dt);
  }
  s->loads.wall_friction /= s->loads.duration;
  s->loads.floor_reaction /= s->loads.duration;
  for (int row = 0; row < MAX_NODE_ROWS; row++)
    s->loads.wall_pressure[row] /= s->loads.duration;
}

/* Vertical stress (Pa, compression positive) of every cell row from the
 * floor, as the force the row transmits over the width; returns the number
 * of rows. */
static int vertical_stress_by_row(const silo *s, double *stress) {
  size_t count = gm_domain_point_count(s->domain);
  const double *height = NULL, *sigma_yy = NULL, *volume = NULL;
  TEST_ASSERT_OK(s->domain, gm_domain_view_field(s->domain, GM_FIELD_POSITION,
                                                 1, &height));
  TEST_ASSERT_OK(s->domain, gm_domain_view_field(s->domain, GM_FIELD_STRESS,
                                                 GM_YY, &sigma_yy));
  TEST_ASSERT_OK(s->domain,
                 gm_domain_view_field(s->domain, GM_FIELD_VOLUME, 0, &volume));
  double h = s->config.cell_size;
  int rows = 0;
  for (int row = 0; row < MAX_NODE_ROWS; row++)
    stress[row] = 0.0;
  for (size_t i = 0; i < count; i++) {
    int row = (int)floor(height[i] / h);
    ck_assert(row >= 0 && row < MAX_NODE_ROWS);
    stress[row] -= volume[i] * sigma_yy[i] / (h * SILO_WIDTH);
    rows = row + 1 > rows ? row + 1 : rows;
  }
  return rows;
}

/* Mean wall pressure (Pa) over the nodes within WALL_WINDOW/2 of height y. */
static double wall_pressure_at(const silo *s, double height) {
  double h = s->config.cell_size, sum = 0.0;
  int nodes = 0;
  for (int row = 0; row < MAX_NODE_ROWS; row++) {
    if (fabs(row * h - height) > 0.5 * WALL_WINDOW + 1e-9)
      continue;
    sum += s->loads.wall_pressure[row];
    nodes++;
  }
  ck_assert_int_gt(nodes, 0);
  return sum / nodes;
}

/* The settled silo, shared by the tests (built once, in the fixture). */
static silo settled;

static void settle_default_silo(void) {
  const silo_config config = {0.05, 2, 0.05};
  settled = create_silo(&config);
  fill_and_settle(&settled);
}

static void destroy_default_silo(void) {
  gm_domain_destroy(settled.domain);
}

/* Tolerance 10% (the issue's): Janssen assumes a uniform vertical stress,
 * a constant K and fully mobilised friction; the simulated friction reaches
 * about 0.9 mu_w, and using the initial density with deformed depths costs
 * about 1% (the fill is compressed by ~2% at the bottom). */
START_TEST(test_vertical_stress_follows_janssen) {
  double stress[MAX_NODE_ROWS];
  int rows = vertical_stress_by_row(&settled, stress);
  double surface = free_surface(&settled), h = settled.config.cell_size;
  int compared = 0;
  for (int row = 0; row < rows; row++) {
    double depth = surface - (row + 0.5) * h; /* m, at the row centre */
    if (depth < TOP_BAND_VERTICAL)
      continue;
    double expected = janssen_vertical_stress(depth);
    ck_assert_msg(fabs(stress[row] / expected - 1.0) <= 0.10,
                  "depth %.3f m: sigma_v = %.0f Pa, Janssen %.0f Pa (ratio "
                  "%.3f)",
                  depth, stress[row], expected, stress[row] / expected);
    compared++;
  }
  ck_assert_int_ge(compared, 50); /* the whole column, not a few rows */
}
END_TEST

/* Same 10% on K sigma_v, averaged over WALL_WINDOW (5 nodes) of both walls:
 * single nodes carry the +-damping share of their load that the local
 * damping adds or removes each step. With the wall contact of libgranmpm
 * 0.1 this fails (ratios 1.15-1.26): a wall node stays held when the
 * material moves away from the wall, so vibration ratchets the lateral
 * stress up; with a contact that waits for the gap to close, measured
 * ratios are 0.97-1.09. */
START_TEST(test_wall_pressure_follows_janssen) {
  double surface = free_surface(&settled);
  int compared = 0;
  for (double depth = TOP_BAND_WALL;
       depth <= surface - BOTTOM_BAND - 0.5 * WALL_WINDOW; depth += 0.25) {
    double pressure = wall_pressure_at(&settled, surface - depth);
    double expected = janssen_k() * janssen_vertical_stress(depth);
    ck_assert_msg(fabs(pressure / expected - 1.0) <= 0.10,
                  "depth %.3f m: wall pressure %.0f Pa, K Janssen %.0f Pa "
                  "(ratio %.3f, K = %.3f)",
                  depth, pressure, expected, pressure / expected, janssen_k());
    compared++;
  }
  ck_assert_int_ge(compared, 8);
}
END_TEST

/* At rest the floor and the wall friction carry the whole weight (the
 * loads are time averages, so the fill's small residual vibration cancels
 * out). The local damping force is the one load the library does not
 * report; it vanishes only once nothing moves, and while the fill still
 * creeps down the walls it carries a share that grows with the damping
 * coefficient: measured 0.5% at 0.05 (this test), 2% at 0.1, 7% at 0.3.
 * 2% is four times the share expected here. */
START_TEST(test_walls_and_floor_carry_the_weight) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(settled.domain,
                 gm_domain_get_summary(settled.domain, &summary));
  double weight = summary.mass * GRAVITY; /* N per m of thickness */
  double carried = settled.loads.floor_reaction + settled.loads.wall_friction;
  ck_assert_msg(fabs(carried / weight - 1.0) <= 0.02,
                "floor %.0f N + wall friction %.0f N = %.0f N, weight %.0f N",
                settled.loads.floor_reaction, settled.loads.wall_friction,
                carried, weight);
  /* And the balance is not the trivial one of a floor carrying everything
   * (a hydrostatic fill): the walls take a real share, Janssen's being the
   * weight less the floor load W sigma_v at the bottom. */
  double janssen_friction =
      weight - SILO_WIDTH * janssen_vertical_stress(free_surface(&settled));
  ck_assert_msg(settled.loads.wall_friction > 0.5 * janssen_friction,
                "wall friction %.0f N, Janssen %.0f N",
                settled.loads.wall_friction, janssen_friction);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("janssen");
  TCase *silo_case = tcase_create("silo_at_rest");
  tcase_add_unchecked_fixture(silo_case, settle_default_silo,
                              destroy_default_silo);
  tcase_set_timeout(silo_case, 120);
  tcase_add_test(silo_case, test_vertical_stress_follows_janssen);
  tcase_add_test(silo_case, test_wall_pressure_follows_janssen);
  tcase_add_test(silo_case, test_walls_and_floor_carry_the_weight);
  suite_add_tcase(suite, silo_case);
  return test_run_suite(suite) ? 1 : 0;
}
