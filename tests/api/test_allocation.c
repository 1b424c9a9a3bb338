/*
 * test_allocation.c - "no allocation inside a step after warm-up": every
 * library allocation goes through the gm_set_allocator hook, so a counting
 * allocator sees them all. After a few warm-up steps (the grid and the
 * per-step work arrays reach their size), further steps of a scene whose
 * occupied region stays the same must not allocate at all, with one or two
 * workers and with each update scheme, for linear MPM and for the
 * granular family with CPDI and a planar wall, for a layer sliding
 * across periodic x faces (GM_WALL_PERIODIC), and for a 3D block
 * (GM_GEOMETRY_3D) resting on a fixed floor against a rigid plate, with
 * linear, uGIMP and cpGIMP shapes, the linear block beside an oblique
 * planar wall (also with GM_TRANSFER_APIC), the cubic B-spline block
 * beside the same wall (B-spline walls in 3D since 2026-11-29), and a 3D
 * layer sliding across periodic x faces. Also
 * checks that every
 * allocation is freed by gm_domain_destroy (the counts balance), and that
 * running out of memory in the middle of a step or of a material registration
 * fails cleanly without changing the domain.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "test_counting_allocator.h"
#include "test_util.h"

/* An elastic block resting on a fixed floor under gravity: it compresses
 * and oscillates but stays in the same cells, so after warm-up the set of
 * grid blocks, hence every work array, keeps its size. */
/* granular: the same with CPDI, the granular family (a second, small block
 * far from the first makes two parallel grids, so the conflict search
 * runs) and a planar wall against the block's left side (wall gaps).
 * periodic: a layer filling the width between periodic x faces, moving at
 * 3 m/s along x, so its points cross the seam in the measured steps. */
/* The 3D periodic layer: uGIMP, filling the period on the fixed zmin
 * face, moving at 3 m/s along x so its points cross the seam in the
 * measured steps. */
static gm_domain *sliding_layer_3d(gm_update_scheme scheme, int workers) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_UGIMP;
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = 0.05;
  def.extent[0] = 0.6;
  def.extent[1] = def.extent[2] = 0.4;
  def.gravity[2] = -9.81;
  def.walls[GM_FACE_ZMIN] = GM_WALL_FIXED;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_PERIODIC;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double lower[3] = {0.0, 0.1, 0.0};
  const double upper[3] = {0.6, 0.3, 0.2};
  size_t count = test_fill_box(domain, material, lower, upper, 2, NULL);
  double *vx = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &vx));
  for (size_t p = 0; p < count; p++)
    vx[p] = 3.0; /* m/s */
  return domain;
}

/* The 3D block: 0.4 m cube on the fixed zmin face, gravity along -z,
 * spanning blocks of several colours (4 x 4 x 4 nodes each), against a
 * rigid plate. */
static gm_domain *resting_block_3d(gm_update_scheme scheme, int workers,
                                   gm_shape shape, gm_transfer transfer) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.transfer = transfer;
  def.shape = shape;
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = 0.05;
  def.extent[0] = def.extent[1] = def.extent[2] = 1.0;
  def.gravity[2] = -9.81;
  def.walls[GM_FACE_ZMIN] = GM_WALL_FIXED;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double lower[3] = {0.3, 0.3, 0.0};
  const double upper[3] = {0.7, 0.7, 0.4};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  /* A rigid plate at rest against the block's +x side (their node planes
   * meet at x = 0.7 m): the rigid nodes' marks, constraint and impulses. */
  gm_rigid_def plate = gm_rigid_def_default();
  int plate_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_rigid(domain, &plate, &plate_id));
  const double plate_lower[3] = {0.7, 0.35, 0.05};
  const double plate_upper[3] = {0.75, 0.65, 0.35};
  test_fill_box(domain, plate_id, plate_lower, plate_upper, 2, NULL);
  /* The wall with linear MPM and the cubic B-spline (the widest support's
   * gaps); the uGIMP and cpGIMP scenes keep what they tested before. */
  if (shape != GM_SHAPE_LINEAR && shape != GM_SHAPE_BSPLINE3)
    return domain;
  /* A frictional wall of oblique normal against the block's x side, 0.01
   * to 0.09 m from it (wall gaps, contact and friction patches). */
  gm_wall_def wall = gm_wall_def_default();
  const double point[3] = {0.25, 0.5, 0.2}, normal[3] = {1.0, 0.1, 0.1};
  for (int k = 0; k < 3; k++) {
    wall.point[k] = point[k];
    wall.normal[k] = normal[k];
  }
  wall.friction_static = wall.friction_kinetic = 0.3;
  int wall_id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  return domain;
}

static gm_domain *resting_block(gm_update_scheme scheme, int workers,
                                bool granular, bool periodic) {
  gm_domain_def def = gm_domain_def_default();
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = 0.05;
  def.extent[0] = def.extent[1] = 2.0;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  if (granular) {
    def.shape = GM_SHAPE_CPDI;
    def.family = GM_FAMILY_GRANULAR;
  }
  if (periodic)
    def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_PERIODIC;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  const double lower[3] = {periodic ? 0.0 : 0.5, 0.0, 0.0};
  const double upper[3] = {periodic ? 2.0 : 1.5, 0.6, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  if (periodic) {
    double *velocity = NULL;
    TEST_ASSERT_OK(
        domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity));
    for (size_t p = 0; p < gm_domain_point_count(domain); p++)
      velocity[p] = 3.0; /* m/s: ~8 cells in the 200 measured steps */
  }
  if (granular) {
    gm_granular_def def_granular = gm_granular_def_default();
    def_granular.critical_density = 990.0; /* kg/m^3, below rho0 = 1000 */
    TEST_ASSERT_OK(domain,
                   gm_domain_set_granular(domain, material, &def_granular));
    const double small_lower[3] = {1.8, 0.0, 0.0};
    const double small_upper[3] = {1.9, 0.1, 0.0};
    test_fill_box(domain, material, small_lower, small_upper, 2, NULL);
    gm_wall_def wall = gm_wall_def_default();
    wall.point[0] = 0.5;
    wall.normal[0] = 1.0;
    wall.normal[1] = 0.0;
    int wall_id = -1;
    TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &wall_id));
  }
  return domain;
}

/* Scene numbers: 0..5 linear MPM; 6..11 granular CPDI with a planar wall;
 * 12..17 the periodic layer; 18..35 the 3D block, linear, uGIMP, cpGIMP;
 * 36..41 the linear 3D block with APIC; 42..47 the 3D periodic layer;
 * 48..53 the 3D block, cubic B-spline, with the wall; within each six,
 * USL, MUSL, USF with one worker, then with two. */
static void check_no_allocation_after_warm_up(int scene) {
  static const gm_update_scheme schemes[3] = {GM_SCHEME_USL, GM_SCHEME_MUSL,
                                              GM_SCHEME_USF};
  gm_update_scheme scheme = schemes[scene % 3];
  int workers = 1 + scene / 3 % 2;
  bool granular = scene >= 6 && scene < 12;
  bool periodic = scene >= 12 && scene < 18;
  /* GM_GEOMETRY_3D: linear, uGIMP, cpGIMP, then linear with APIC */
  bool solid = (scene >= 18 && scene < 42) || scene >= 48;
  bool apic = scene >= 36 && scene < 42;
  bool layer_3d = scene >= 42 && scene < 48; /* the 3D periodic layer */
  static const gm_shape solid_shapes[6] = {
      GM_SHAPE_LINEAR, GM_SHAPE_UGIMP, GM_SHAPE_CPGIMP,
      GM_SHAPE_LINEAR, GM_SHAPE_UGIMP, GM_SHAPE_BSPLINE3}; /* by six */
  gm_shape shape = layer_3d ? GM_SHAPE_UGIMP
                   : solid  ? solid_shapes[(scene - 18) / 6]
                            : GM_SHAPE_LINEAR;
  test_install_counting_allocator();
  gm_domain *domain =
      layer_3d ? sliding_layer_3d(scheme, workers)
      : solid  ? resting_block_3d(scheme, workers, shape,
                                 apic ? GM_TRANSFER_APIC : GM_TRANSFER_FLIP)
               : resting_block(scheme, workers, granular, periodic);
  enum { WARM_UP_STEPS = 5, MEASURED_STEPS = 200 };
  for (int step = 0; step < WARM_UP_STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, -1.0));
  long before = atomic_load(&test_allocations);
  for (int step = 0; step < MEASURED_STEPS; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, -1.0));
  long during = atomic_load(&test_allocations) - before;
  ck_assert_msg(during == 0,
                "%s, %d workers%s (%s): %ld allocations in %d steps after "
                "warm-up",
                test_scheme_name(scheme), workers,
                granular   ? ", granular CPDI with a wall"
                : periodic ? ", periodic layer"
                : layer_3d ? ", 3D periodic layer"
                : apic     ? ", 3D block, APIC"
                : solid    ? ", 3D block"
                           : "",
                test_shape_name(shape), during, MEASURED_STEPS);
  gm_domain_destroy(domain);
  ck_assert_msg(atomic_load(&test_allocations) == atomic_load(&test_releases),
                "allocations %ld != frees %ld after destroy",
                atomic_load(&test_allocations), atomic_load(&test_releases));
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
}

START_TEST(test_no_allocation_after_warm_up) {
  check_no_allocation_after_warm_up(_i);
}
END_TEST

/* The 3D scenes in USL (scene 18 + 3 j). */
START_TEST(test_no_allocation_3d_usl) {
  check_no_allocation_after_warm_up(18 + 3 * _i);
}
END_TEST

/* The 3D scenes in MUSL and USF (scenes 18 + 3 j + 1 and + 2). */
START_TEST(test_no_allocation_3d_musl_usf) {
  check_no_allocation_after_warm_up(18 + 3 * (_i / 2) + 1 + _i % 2);
}
END_TEST

/* Out of memory at every allocation of a step that must grow the grid (new
 * points in far blocks): the step either succeeds or fails with
 * GM_ERR_NO_MEMORY leaving the positions as they were, and the next step
 * works. (Regression: a half-grown grid kept a freed pointer; ASan in CI
 * reports such a use-after-free.) */
START_TEST(test_out_of_memory_while_growing_the_grid) {
  test_install_counting_allocator();
  for (long failing = 0; failing < 40; failing++) {
    gm_domain_def def = gm_domain_def_default();
    def.extent[0] = def.extent[1] = 10.0;
    def.cell_size = 0.1;
    gm_domain *domain = test_create_domain(&def);
    int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
    double position[2 * 21], volume[21];
    for (int i = 0; i < 21; i++) { /* one point, then 20 in far blocks */
      position[2 * i] = i == 0 ? 0.05 : 0.05 + 0.8 * ((i - 1) % 10);
      position[2 * i + 1] = i == 0 ? 0.05 : 5.0 + 0.8 * ((i - 1) / 10);
      volume[i] = 0.01;
    }
    gm_points_def points = gm_points_def_default();
    points.material = material;
    points.count = 1;
    points.position = position;
    points.volume = volume;
    TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-5));
    points.count = 20;
    points.position = position + 2;
    points.volume = volume + 1;
    TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
    double before[42], after[42];
    TEST_ASSERT_OK(domain,
                   gm_domain_get_field(domain, GM_FIELD_POSITION, before, 42));
    atomic_store(&test_fail_countdown, failing);
    gm_status status = gm_domain_step(domain, 1e-5);
    atomic_store(&test_fail_countdown, -1);
    ck_assert_msg(status == GM_OK || status == GM_ERR_NO_MEMORY,
                  "allocation %ld failing: step returned %d", failing,
                  (int)status);
    if (status != GM_OK) {
      TEST_ASSERT_OK(domain,
                     gm_domain_get_field(domain, GM_FIELD_POSITION, after, 42));
      ck_assert_msg(memcmp(before, after, sizeof before) == 0,
                    "allocation %ld failing: positions changed", failing);
    }
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-5));
    gm_domain_destroy(domain);
  }
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
}
END_TEST

/* A material with one state variable that it reports as its stress. */
static int state_as_stress(const gm_material_batch *batch, void *user,
                           char *message, size_t message_size) {
  (void)user;
  (void)message;
  (void)message_size;
  for (size_t i = 0; i < batch->count; i++)
    batch->stress[GM_XX][i] = batch->state[0][i];
  return 0;
}

/* Out of memory while a second material widens the state pool: the call
 * fails with GM_ERR_NO_MEMORY and the first material's state is intact.
 * (Regression: one pool was widened before the other failed.) */
START_TEST(test_out_of_memory_while_widening_state) {
  test_install_counting_allocator();
  for (long failing = 0; failing < 6; failing++) {
    gm_domain_def def = gm_domain_def_default();
    gm_domain *domain = test_create_domain(&def);
    gm_material_def material = gm_material_def_default();
    material.update = state_as_stress;
    material.state_count = 1;
    const double seven = 7.0;
    material.initial_state = &seven;
    material.p_wave_modulus = 1e6;
    material.density = 1000.0;
    int first = -1, second = -1;
    TEST_ASSERT_OK(domain, gm_domain_add_material(domain, &material, &first));
    const double lower[3] = {0.2, 0.2, 0.0}, upper[3] = {0.6, 0.6, 0.0};
    size_t count = test_fill_box(domain, first, lower, upper, 2, NULL);
    material.state_count = 2;
    material.initial_state = NULL;
    atomic_store(&test_fail_countdown, failing);
    gm_status status = gm_domain_add_material(domain, &material, &second);
    atomic_store(&test_fail_countdown, -1);
    ck_assert(status == GM_OK || status == GM_ERR_NO_MEMORY);
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-6));
    double *stress = malloc(count * 6 * sizeof(double));
    ck_assert_ptr_nonnull(stress);
    TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_STRESS, stress,
                                               count * 6));
    for (size_t i = 0; i < count; i++)
      ck_assert_msg(stress[i * 6 + GM_XX] == 7.0,
                    "allocation %ld failing: point %zu state became %g",
                    failing, i, stress[i * 6 + GM_XX]);
    free(stress);
    gm_domain_destroy(domain);
  }
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
}
END_TEST

/* Live bytes through a hook that records each block's size in front of it
 * (16 bytes, enough alignment for every library type). */
static atomic_long live_bytes;

static void *sizing_malloc(size_t size, void *user) {
  (void)user;
  unsigned char *block = malloc(size + 16);
  if (!block)
    return NULL;
  memcpy(block, &size, sizeof size);
  atomic_fetch_add(&live_bytes, (long)size);
  return block + 16;
}

static void sizing_free(void *pointer, void *user) {
  (void)user;
  if (!pointer)
    return;
  unsigned char *block = (unsigned char *)pointer - 16;
  size_t size;
  memcpy(&size, block, sizeof size);
  atomic_fetch_sub(&live_bytes, (long)size);
  free(block);
}

/* Issue 15: "<= 300 bytes per point in 2D (<= 400 with the granular
 * family), grid and scratch included". The library's memory is the sum of
 * its parts, each sized to what the scene uses (docs/performance.md, "Where
 * the bytes go"): for a plane-strain elastic block with linear shapes and
 * FLIP,
 *  - 272 B per point: two buffers of position, velocity (2 each), stress
 *    (4), F (4) and volume (208), mass, initial volume and domain size (32),
 *    id, material, id -> index, block key, block index and order (32);
 *  - per grid block: 64 nodes of 5 node fields and the floor face's gap
 *    (48 B per node) and the block's links and chunk counters (160 B),
 *    3232 B, over the occupied blocks and the ring their cells reach plus
 *    a headroom of 4 blocks;
 *  - a fixed part: the domain, one worker's scratch, the block hash (about
 *    150 kB; 256 kiB allowed).
 * The granular family (_i = 1: the same block, its material granular with
 * rho_cr 1 % below rho0, so every point interacts and one parallel grid
 * holds them) adds
 *  - 76 B per point: the granular state (1 byte) and grid label (int32) in
 *    both buffers (10), the support's lowest node (2 x int32, 8; the
 *    highest is the next node with linear shapes), the interaction
 *    box half edges (16), the granular and visit flags (2), the spanning
 *    forest (8), union-find parent and set size (8), points per component,
 *    layer per component and the colouring's stamps (12, also the
 *    labelling's scratch), the cell buckets (4), the layer CSR offsets (8,
 *    also the forest's sort buffer);
 *  - per block, the cell bucket offsets (65 x uint32, 260 B).
 * With doubles for the state and label and the union-find's 24-byte
 * smallest-id and root-order scratch (main before issue 15's granular
 * cut) it took 134 B per point: 3.8 MB over this bound.
 * 128 x 128 cells of 2 x 2 points: 65536 points; their cells' lowest nodes
 * are nodes 1..128 per axis (node 0 is the ghost layer), 17 blocks of 8,
 * and the ring makes 18 x 18 = 324 blocks. The old sizing (grid 1.5x the
 * occupied blocks, the id map grown slab by slab to 1.4x) exceeded the
 * plain bound by about 600 kB. */
START_TEST(test_memory_is_the_sum_of_its_parts) {
  bool granular = _i == 1;
  gm_allocator allocator = {sizeof(gm_allocator), sizing_malloc, sizing_free,
                            NULL};
  ck_assert_int_eq(gm_set_allocator(&allocator), GM_OK);
  atomic_store(&live_bytes, 0);
  gm_domain_def def = gm_domain_def_default();
  def.worker_count = 1;
  def.cell_size = 1.0 / 64.0; /* m */
  def.extent[0] = def.extent[1] = 2.5;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  def.family = granular ? GM_FAMILY_GRANULAR : GM_FAMILY_PLAIN;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1000.0);
  if (granular) {
    gm_granular_def def_granular = gm_granular_def_default();
    def_granular.critical_density = 990.0; /* kg/m^3, below rho0 = 1000 */
    TEST_ASSERT_OK(domain,
                   gm_domain_set_granular(domain, material, &def_granular));
  }
  const double lower[3] = {0.0, 0.0, 0.0}, upper[3] = {2.0, 2.0, 0.0};
  size_t count = test_fill_box(domain, material, lower, upper, 2, NULL);
  ck_assert_uint_eq(count, 65536);
  for (int step = 0; step < 5; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, -1.0));
  if (granular) { /* the scene the bound describes: one parallel grid */
    gm_granular_summary summary = gm_granular_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
    ck_assert_uint_eq(summary.component_count, 1);
  }
  const double blocks = 18.0 * 18.0 + 4.0;
  double per_point = granular ? 272.0 + 76.0 : 272.0;    /* B */
  double per_block = granular ? 3232.0 + 260.0 : 3232.0; /* B */
  double bound =
      per_point * (double)count + per_block * blocks + 256.0 * 1024.0; /* B */
  double live = (double)atomic_load(&live_bytes);                      /* B */
  ck_assert_msg(live <= bound,
                "%s: %.1f bytes per point live, bound %.1f (%.0f per point, "
                "the grid, the fixed part)",
                granular ? "granular" : "plain", live / (double)count,
                bound / (double)count, per_point);
  gm_domain_destroy(domain);
  ck_assert_int_eq(atomic_load(&live_bytes), 0);
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("allocation");
  TCase *tcase = tcase_create("steady_state");
  tcase_set_timeout(tcase, 60);
  /* Every 2D scene, and every 3D one in USL with one and two workers. */
  tcase_add_loop_test(tcase, test_no_allocation_after_warm_up, 0, 18);
  tcase_add_loop_test(tcase, test_no_allocation_3d_usl, 0, 12);
  tcase_add_test(tcase, test_out_of_memory_while_growing_the_grid);
  tcase_add_test(tcase, test_out_of_memory_while_widening_state);
  /* 0: plain, 1: granular family. */
  tcase_add_loop_test(tcase, test_memory_is_the_sum_of_its_parts, 0, 2);
  suite_add_tcase(suite, tcase);
  /* The 3D scenes in MUSL and USF, about 120 s of this test's 200 under
   * AddressSanitizer: tagged slow (tests/README.md), so the sanitize stage
   * keeps every 2D scheme and the 3D scenes in USL. */
  TCase *schemes_3d = tcase_create("3D schemes");
  tcase_set_tags(schemes_3d, "slow");
  tcase_set_timeout(schemes_3d, 60);
  tcase_add_loop_test(schemes_3d, test_no_allocation_3d_musl_usf, 0, 24);
  suite_add_tcase(suite, schemes_3d);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
