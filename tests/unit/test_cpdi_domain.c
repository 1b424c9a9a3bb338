/*
 * test_cpdi_domain.c - the current particle domains of CPDI and cpGIMP
 * through the public API (GM_FIELD_DOMAIN_CORNERS):
 *  - under a large simple shear of a CPDI block the domain of every point is
 *    its initial square carried by its F (corners x_p +- F r1 +- F r2, area
 *    det F times the initial area), in plane strain and in axisymmetry, and
 *    the domains' total area is the block's volume;
 *  - a point whose domain would reach past the ghost cell layer around the
 *    box fails the step with GM_ERR_OUT_OF_GRID naming the point, and the
 *    step rolls back bitwise; gm_domain_add_points refuses such a domain.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_restart.h"
#include "test_util.h"

#include <check.h>
#include <ctype.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A field of every point, in point-index order (caller frees). */
static double *get_field(const gm_domain *domain, gm_field field,
                         size_t *components) {
  TEST_ASSERT_OK(domain, gm_domain_field_components(domain, field, components));
  size_t length = gm_domain_point_count(domain) * *components;
  double *values = malloc((length + 1) * sizeof *values);
  ck_assert_ptr_nonnull(values);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, field, values, length));
  return values;
}

/* ------------------------------------------------ the sheared CPDI block */

/* Box 2 m x 0.8 m (cells 0.05 m) with a fixed bottom; a soft elastic
 * block 1.2 m x 0.4 m on it, 2 x 2 points per cell. The block is wide so
 * that its free sides, where the shear stress must vanish, disturb the
 * simple shear of the middle only near them. */
static gm_domain *create_block(gm_geometry geometry) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = geometry;
  def.shape = GM_SHAPE_CPDI;
  def.extent[0] = 2.0;  /* m */
  def.extent[1] = 0.8;  /* m */
  def.cell_size = 0.05; /* m */
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  gm_domain *domain = test_create_domain(&def);
  /* E = 1 kPa, rho = 1000 kg/m^3: shear wave speed ~0.6 m/s, so the
   * block shears by 0.5 in a fraction of a second. */
  int material = test_add_elastic(domain, 1e3, 0.3, 1000.0);
  const double lower[3] = {0.2, 0.0, 0.0}, upper[3] = {1.4, 0.4, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  return domain;
}

/* Initial simple shear v_x = shear_rate * y (m/s, y from the bottom). */
static void set_simple_shear(gm_domain *domain, double shear_rate) {
  const double *y = NULL;
  double *velocity_x = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 1, &y));
  TEST_ASSERT_OK(
      domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity_x));
  for (size_t i = 0; i < gm_domain_point_count(domain); i++)
    velocity_x[i] = shear_rate * y[i];
}

/* Mean F_xy over the points: the block's shear strain dx/dY. */
static double mean_shear(const gm_domain *domain) {
  size_t components = 0;
  double *f = get_field(domain, GM_FIELD_DEFORMATION_GRADIENT, &components);
  size_t count = gm_domain_point_count(domain);
  double sum = 0.0;
  for (size_t i = 0; i < count; i++)
    sum += f[i * components + 1]; /* row-major: F_xy */
  free(f);
  return sum / (double)count;
}

/* Steps at the stable dt until the mean shear exceeds `target`. */
static void shear_until(gm_domain *domain, double target) {
  set_simple_shear(domain, 2.0); /* 1/s */
  int steps = 0;
  while (mean_shear(domain) <= target) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    ck_assert_msg(++steps < 2000, "mean shear only %g after %d steps",
                  mean_shear(domain), steps);
  }
}

/* Shoelace area (m^2) of the polygon of 4 corners (x, y interleaved),
 * relative to the first corner so the products stay small. */
static double polygon_area(const double corner[8]) {
  double area = 0.0;
  for (int c = 1; c + 1 < 4; c++) {
    double ax = corner[2 * c] - corner[0], ay = corner[2 * c + 1] - corner[1];
    double bx = corner[2 * c + 2] - corner[0];
    double by = corner[2 * c + 3] - corner[1];
    area += 0.5 * (ax * by - ay * bx);
  }
  return area;
}

/* What this checks: that the reported domain of every point is its
 * initial square convected by the point's own F, i.e. corners
 * x_p +- F (l_x, 0) +- F (0, l_y) counter-clockwise from the lower left,
 * hence area det F_(2x2) l_x l_y * 4, and (plane strain) that these areas
 * add up to the volume, V = det F V0 with V0 the initial domain's area.
 * What it does not check: that F itself is right (it comes from the grid
 * velocity gradient), that the CPDI weights are computed from these
 * corners (test_shape_variants does that, white box), or that neighbouring
 * domains still tile the block without gaps or overlaps (CPDI1 does not
 * guarantee that). Tolerances: corners are sums of ~1 m positions and
 * ~0.05 m edge vectors, exact to a few ulps of 1 m (1e-15 m) against
 * edges of 0.025 m and more: 1e-12 relative leaves a wide margin, while a
 * domain not following F would be off by the order of the strain, 0.5. */
static void check_domains_follow_f(const gm_domain *domain, bool plane) {
  size_t count = gm_domain_point_count(domain), nc, nf, np, ns, nv;
  double *corners = get_field(domain, GM_FIELD_DOMAIN_CORNERS, &nc);
  double *f = get_field(domain, GM_FIELD_DEFORMATION_GRADIENT, &nf);
  double *position = get_field(domain, GM_FIELD_POSITION, &np);
  double *size = get_field(domain, GM_FIELD_DOMAIN_SIZE, &ns);
  double *volume = get_field(domain, GM_FIELD_VOLUME, &nv);
  ck_assert_uint_eq(nc, 8);
  static const double sign1[4] = {-1.0, 1.0, 1.0, -1.0};
  static const double sign2[4] = {-1.0, -1.0, 1.0, 1.0};
  double area_sum = 0.0, volume_sum = 0.0; /* m^2 per unit thickness */
  for (size_t i = 0; i < count; i++) {
    const double *fi = f + i * nf, *corner = corners + i * nc;
    double half_x = 0.5 * size[i * ns], half_y = 0.5 * size[i * ns + 1];
    for (int c = 0; c < 4; c++) {
      for (size_t k = 0; k < 2; k++) { /* row k of F times half edges */
        double expected = position[i * np + k] + sign1[c] * fi[3 * k] * half_x +
                          sign2[c] * fi[3 * k + 1] * half_y;
        REQUIRE(fabs(corner[2 * c + k] - expected) <= 1e-12 * half_x,
                "point %zu corner %d axis %zu at %.17g m, x_p + F r gives "
                "%.17g m",
                i, c, k, corner[2 * c + k], expected);
      }
    }
    double jacobian = fi[0] * fi[4] - fi[1] * fi[3]; /* det of F in x, y */
    double expected_area = jacobian * 4.0 * half_x * half_y;
    double area = polygon_area(corner);
    REQUIRE(fabs(area - expected_area) <= 1e-12 * expected_area,
            "point %zu: domain area %.17g m^2, det F x initial area %.17g", i,
            area, expected_area);
    area_sum += area;
    volume_sum += volume[i];
  }
  /* V0 is the initial domain's area up to the rounding of the square root
   * that made the domain size from it (one ulp), so sum V = sum det F V0
   * matches the summed areas to ~1e-15 relative. In axisymmetry the volume
   * is the ring 2 pi r A and carries the hoop stretch too: not compared. */
  if (plane)
    ck_assert_msg(fabs(area_sum - volume_sum) <= 1e-12 * volume_sum,
                  "summed domain area %.17g m^2, summed volume %.17g", area_sum,
                  volume_sum);
  free(corners);
  free(f);
  free(position);
  free(size);
  free(volume);
}

START_TEST(test_sheared_block_domain_area) {
  gm_domain *domain = create_block(GM_GEOMETRY_PLANE_STRAIN);
  shear_until(domain, 0.5);
  check_domains_follow_f(domain, true);
  gm_domain_destroy(domain);
}
END_TEST

/* Axisymmetric: x is the radius, y the axis; the same shear in the r-z
 * plane also changes radii, so the hoop stretch enters det F. The domain
 * lives in the r-z plane: its area is det of F's r-z block times the
 * initial area. */
START_TEST(test_sheared_block_domain_area_axisymmetric) {
  gm_domain *domain = create_block(GM_GEOMETRY_AXISYMMETRIC);
  shear_until(domain, 0.5);
  check_domains_follow_f(domain, false);
  gm_domain_destroy(domain);
}
END_TEST

/* ------------------------------------------------ a domain leaving the grid */

/* The domain as `before` (test_restart.h: every field, the ids, the time
 * and step count, the granular counts; memcmp: -0.0 differs from 0.0, NaN
 * equals itself). */
static void check_state_unchanged(const gm_domain *domain,
                                  const test_snapshot *before) {
  test_snapshot after = test_snapshot_take(domain, NULL, NULL);
  test_snapshot_assert_same(before, &after, "changed by the failed step");
  test_snapshot_free(&after);
}

/* Does text contain the integer as a whole number (not inside 13 or 0.3)? */
static bool names_integer(const char *text, long long value) {
  char token[32];
  int length = snprintf(token, sizeof token, "%lld", value);
  for (const char *at = strstr(text, token); at; at = strstr(at + 1, token)) {
    bool starts = at == text || (!isdigit((unsigned char)at[-1]) &&
                                 at[-1] != '.' && at[-1] != '-');
    bool ends = !isdigit((unsigned char)at[length]) && at[length] != '.' &&
                at[length] != 'e';
    if (starts && ends)
      return true;
  }
  return false;
}

/* Box 1 m x 1 m with open walls, cells 0.1 m. Point id 0 rests in a
 * corner; point id 1 carries a 0.3 m square domain (1.5 cells each side
 * of it) and moves at `velocity` (m/s) from near the centre. The two share no
 * node, and a lone point moving uniformly keeps F = I (every node it
 * reaches gets its velocity, so the velocity gradient vanishes). */
static gm_domain *create_mover(gm_shape shape, const double velocity[2]) {
  gm_domain_def def = gm_domain_def_default();
  def.shape = shape;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e3, 0.3, 1000.0);
  /* The mover is 3 mm off centre so that no step ends with its domain
   * exactly on the ghost layer's edge, where rounding would decide. */
  const double position[4] = {0.15, 0.15, 0.503, 0.497};        /* m */
  const double speed[4] = {0.0, 0.0, velocity[0], velocity[1]}; /* m/s */
  const double volume[2] = {0.0025, 0.09};                      /* m^2 */
  const double domain_size[4] = {0.05, 0.05, 0.3, 0.3};         /* m */
  gm_points_def points = gm_points_def_default();
  points.count = 2;
  points.material = material;
  points.position = position;
  points.velocity = speed;
  points.volume = volume;
  points.domain_size = domain_size;
  int64_t first_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, &first_id));
  ck_assert_int_eq(first_id, 0);
  return domain;
}

/* How far (m) the mover's domain reaches past the box face it heads for
 * (axis, side 0 low / 1 high). */
static double reach_past_face(const gm_domain *domain, int axis, int side) {
  size_t index = 0, components = 0;
  TEST_ASSERT_OK(domain, gm_domain_point_index(domain, 1, &index));
  double *corners = get_field(domain, GM_FIELD_DOMAIN_CORNERS, &components);
  const double *corner = corners + index * components;
  double reach = side ? corner[4 + axis] - 1.0 : 0.0 - corner[axis];
  free(corners);
  return reach;
}

/* Steps with dt = 0.01 s (stable: ~0.02 s) until a step fails; it must be
 * GM_ERR_OUT_OF_GRID naming point 1, exactly when the domain would
 * reach past the ghost layer (one cell, 0.1 m, beyond the face), after
 * steps that took it into that layer, with the domain rolled back. */
static void check_domain_leaves(gm_shape shape, int axis, int side) {
  double velocity[2] = {0.0, 0.0};
  velocity[axis] = side ? 1.0 : -1.0; /* m/s */
  gm_domain *domain = create_mover(shape, velocity);
  const double dt = 0.01, cell = 0.1; /* s, m */
  double deepest = -1.0; /* m, furthest accepted reach past the face */
  for (int step = 0; step < 100; step++) {
    double reach = reach_past_face(domain, axis, side);
    deepest = fmax(deepest, reach);
    test_snapshot before = test_snapshot_take(domain, NULL, NULL);
    gm_status status = gm_domain_step(domain, dt);
    if (status == GM_OK) {
      test_snapshot_free(&before);
      continue;
    }
    const char *message = gm_domain_last_error(domain);
    ck_assert_msg(status == GM_ERR_OUT_OF_GRID, "%s: status %d: %s",
                  test_shape_name(shape), (int)status, message);
    ck_assert_msg(names_integer(message, 1), "message does not name id 1: %s",
                  message);
    /* The domain moves 0.01 m per step: the failing step is the one that
     * would take it past the ghost layer, and the accepted ones went well
     * into it (the 1e-9 m margins are far above the positions' rounding
     * and far below the 0.01 m of a step). */
    ck_assert_double_lt(reach, cell);
    ck_assert_double_ge(reach + dt * 1.0, cell - 1e-9);
    ck_assert_double_gt(deepest, 0.5 * cell);
    check_state_unchanged(domain, &before);
    test_snapshot_free(&before);
    gm_domain_destroy(domain);
    return;
  }
  ck_abort_msg("%s: the domain never left the grid", test_shape_name(shape));
}

START_TEST(test_domain_leaving_grid_cpdi) {
  check_domain_leaves(GM_SHAPE_CPDI, 0, 1);
  check_domain_leaves(GM_SHAPE_CPDI, 1, 0);
}
END_TEST

START_TEST(test_domain_leaving_grid_cpgimp) {
  check_domain_leaves(GM_SHAPE_CPGIMP, 0, 0);
  check_domain_leaves(GM_SHAPE_CPGIMP, 1, 1);
}
END_TEST

/* Adds four points, the last one (index 3) at the box centre with a
 * domain of `edge` m; returns the status and leaves the domain's count in
 * *added. */
static gm_status add_with_domain(gm_shape shape, double box, double edge,
                                 char *message, size_t message_size,
                                 size_t *added) {
  gm_domain_def def = gm_domain_def_default();
  def.shape = shape;
  def.extent[0] = def.extent[1] = box; /* m; cells 0.1 m */
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e3, 0.3, 1000.0);
  const double position[8] = {0.15, 0.15, 0.35,      0.15,
                              0.55, 0.15, 0.5 * box, 0.5 * box}; /* m */
  const double volume[4] = {0.0025, 0.0025, 0.0025, 0.0025};     /* m^2 */
  const double domain_size[8] = {0.05, 0.05, 0.05, 0.05,
                                 0.05, 0.05, edge, edge}; /* m */
  gm_points_def points = gm_points_def_default();
  points.count = 4;
  points.material = material;
  points.position = position;
  points.volume = volume;
  points.domain_size = domain_size;
  gm_status status = gm_domain_add_points(domain, &points, NULL);
  snprintf(message, message_size, "%s", gm_domain_last_error(domain));
  *added = gm_domain_point_count(domain);
  gm_domain_destroy(domain);
  return status;
}

/* gm_domain_add_points refuses a point whose domain reaches past the ghost
 * layer (1.7 m in a 1 m box) or touches more than 8 cells (0.95 m, 9.5
 * cells, in a 3 m box), naming its index, and adds nothing; the same
 * points with a domain that fits (0.3 m; 0.65 m, at most 8 cells) are
 * accepted, so the refusal is the domain's doing. */
START_TEST(test_add_points_domain_too_large) {
  static const gm_shape shapes[3] = {GM_SHAPE_UGIMP, GM_SHAPE_CPGIMP,
                                     GM_SHAPE_CPDI};
  static const double box[2] = {1.0, 3.0}, bad[2] = {1.7, 0.95},
                      good[2] = {0.3, 0.65}; /* m */
  char message[512];
  size_t added = 0;
  for (int s = 0; s < 3; s++) {
    const char *name = test_shape_name(shapes[s]);
    for (int c = 0; c < 2; c++) {
      gm_status status = add_with_domain(shapes[s], box[c], bad[c], message,
                                         sizeof message, &added);
      ck_assert_msg(status == GM_ERR_OUT_OF_GRID,
                    "%s, edge %g m: status %d (%s)", name, bad[c], (int)status,
                    message);
      ck_assert_msg(names_integer(message, 3),
                    "message does not name point 3: %s", message);
      ck_assert_uint_eq(added, 0);
      status = add_with_domain(shapes[s], box[c], good[c], message,
                               sizeof message, &added);
      ck_assert_msg(status == GM_OK, "%s, edge %g m refused: %s", name, good[c],
                    message);
      ck_assert_uint_eq(added, 4);
    }
  }
}
END_TEST

/* A CPDI domain far thinner than a cell (edges 1e-175 m: its area
 * underflows, and the corner gradients divide by it) used to be accepted,
 * and its support could not be computed at the step, which the scatter
 * did not check (found by fuzz/fuzz_checkpoint: a write outside the scatter
 * tile). gm_domain_add_points now refuses it, naming the point, and adds
 * nothing. */
START_TEST(test_add_points_domain_too_thin) {
  char message[512];
  size_t added = 0;
  gm_status status = add_with_domain(GM_SHAPE_CPDI, 1.0, 1e-175, message,
                                     sizeof message, &added);
  ck_assert_msg(status == GM_ERR_INVALID_ARGUMENT, "status %d (%s)",
                (int)status, message);
  ck_assert_msg(names_integer(message, 3), "message does not name point 3: %s",
                message);
  ck_assert_msg(strstr(message, "thin") != NULL, "message: %s", message);
  ck_assert_uint_eq(added, 0);
}
END_TEST

static Suite *cpdi_domain_suite(void) {
  Suite *suite = suite_create("cpdi_domain");
  TCase *shear = tcase_create("shear");
  tcase_set_timeout(shear, 120);
  tcase_add_test(shear, test_sheared_block_domain_area);
  tcase_add_test(shear, test_sheared_block_domain_area_axisymmetric);
  suite_add_tcase(suite, shear);
  TCase *grid = tcase_create("out_of_grid");
  tcase_add_test(grid, test_domain_leaving_grid_cpdi);
  tcase_add_test(grid, test_domain_leaving_grid_cpgimp);
  tcase_add_test(grid, test_add_points_domain_too_large);
  tcase_add_test(grid, test_add_points_domain_too_thin);
  suite_add_tcase(suite, grid);
  return suite;
}

int main(void) {
  return test_run_suite(cpdi_domain_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
