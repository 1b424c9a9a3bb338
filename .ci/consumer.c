/*
 * consumer.c - a stand-alone program built by .ci/run OUTSIDE the source
 * tree against the INSTALLED library, with nothing but
 * `pkg-config --cflags --libs granmpm`. It proves that the installed header,
 * library and granmpm.pc are usable together, and that a short simulation
 * gives answers known without running one.
 *
 * Scene: a 0.5 m x 0.5 m block of elastic material (plane strain, per unit
 * thickness) falls freely in the middle of a 1 m x 1 m grid, far from every
 * face, for 10 steps of 1 ms.
 *
 * Exit status 0 when every check holds, 1 otherwise (each failure printed).
 */
#include <granmpm.h>

#include <stdio.h>
#include <string.h>

/* Numbers chosen to be exact in binary floating point, so the expected
 * values below are exact too. */
#define CELL_SIZE            0.125   /* m */
#define POINTS_PER_CELL_AXIS 2       /* lattice spacing 0.0625 m */
#define BLOCK_LOWER          0.25    /* m, both axes */
#define BLOCK_UPPER          0.75    /* m, both axes */
#define DENSITY              1000.0  /* kg/m^3 */
#define GRAVITY_Y            (-9.75) /* m/s^2, exact in binary */
#define STEP_DT              1e-3    /* s, below the stable bound (~1.7e-3 s) */
#define STEP_COUNT           10

static int failures;

static void check(int condition, const char *what) {
  if (!condition) {
    fprintf(stderr, "consumer: FAILED: %s\n", what);
    failures++;
  }
}

static double absolute(double x) {
  return x < 0 ? -x : x;
}

/* Prints the failing call with the domain's message and counts it. */
static int status_ok(gm_status status, const gm_domain *domain,
                     const char *call) {
  if (status == GM_OK)
    return 1;
  fprintf(stderr, "consumer: FAILED: %s: %s (%s)\n", call, gm_strerror(status),
          domain ? gm_domain_last_error(domain) : gm_last_create_error());
  failures++;
  return 0;
}

static gm_domain *create_domain(void) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_PLANE_STRAIN;
  def.extent[0] = def.extent[1] = 1.0; /* m */
  def.cell_size = CELL_SIZE;
  def.gravity[1] = GRAVITY_Y;
  gm_domain *domain = NULL;
  if (!status_ok(gm_domain_create(&def, &domain), NULL, "gm_domain_create"))
    return NULL;
  check(domain != NULL, "gm_domain_create returned a domain");
  return domain;
}

static int fill_block(gm_domain *domain) {
  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.density = DENSITY;
  int material = -1;
  if (!status_ok(gm_domain_add_elastic(domain, &elastic, &material), domain,
                 "gm_domain_add_elastic"))
    return 0;
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.lower[0] = fill.lower[1] = BLOCK_LOWER;
  fill.upper[0] = fill.upper[1] = BLOCK_UPPER;
  fill.points_per_cell_axis = POINTS_PER_CELL_AXIS;
  int64_t first_id = -1;
  size_t count = 0;
  if (!status_ok(gm_domain_fill_box(domain, &fill, &first_id, &count), domain,
                 "gm_domain_fill_box"))
    return 0;
  /* 4 cells per axis, 2 points per cell axis: 8 x 8 points. */
  check(count == 64, "fill_box created 64 points");
  check(gm_domain_point_count(domain) == 64, "point count is 64");
  return 1;
}

static int get_summary(const gm_domain *domain, gm_summary *summary) {
  *summary = gm_summary_default();
  return status_ok(gm_domain_get_summary(domain, summary), domain,
                   "gm_domain_get_summary");
}

static void run_and_check(gm_domain *domain) {
  gm_summary before, after;
  if (!get_summary(domain, &before))
    return;
  /* 0.25 m^2 of area (per unit thickness) at 1000 kg/m^3 = 250 kg/m. Every
   * point mass (3.90625 kg) and their sum are exact in binary; 1e-12
   * relative only allows a library computing volumes in another order. */
  check(absolute(before.mass - 250.0) <= 1e-12 * 250.0, "initial mass 250");
  for (int step = 0; step < STEP_COUNT; step++)
    if (!status_ok(gm_domain_step(domain, STEP_DT), domain, "gm_domain_step"))
      return;
  if (!get_summary(domain, &after))
    return;
  /* MPM never changes a point's mass and the summary sums in an
   * index-independent order, so the total is bitwise unchanged. */
  check(after.mass == before.mass, "mass conserved exactly");
  /* Far from every wall the only external force is gravity, and the
   * internal forces cancel (shape-function gradients sum to zero), so the
   * momentum is M g t. 1e-9 relative covers rounding over 10 steps. */
  double expected_momentum = before.mass * GRAVITY_Y * STEP_DT * STEP_COUNT;
  check(absolute(after.momentum[1] - expected_momentum) <=
            1e-9 * absolute(expected_momentum),
        "vertical momentum equals M g t");
  double time = 0;
  uint64_t steps = 0;
  if (status_ok(gm_domain_get_time(domain, &time, &steps), domain,
                "gm_domain_get_time")) {
    check(steps == STEP_COUNT, "step count is 10");
    /* time is a sum of 10 rounded dt values: 1e-12 relative. */
    check(absolute(time - STEP_DT * STEP_COUNT) <= 1e-12 * STEP_DT * STEP_COUNT,
          "simulated time is 10 ms");
  }
}

int main(void) {
  check(strcmp(gm_version(), GM_VERSION_STRING) == 0,
        "gm_version() == GM_VERSION_STRING (header and library match)");
  check(gm_version_number() == GM_VERSION_NUMBER,
        "gm_version_number() == GM_VERSION_NUMBER");
  gm_domain *domain = create_domain();
  if (domain && fill_block(domain))
    run_and_check(domain);
  gm_domain_destroy(domain);
  if (failures) {
    fprintf(stderr, "consumer: %d check(s) failed\n", failures);
    return 1;
  }
  printf("consumer: libgranmpm %s: all checks passed\n", gm_version());
  return 0;
}
