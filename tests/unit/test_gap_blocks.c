/*
 * test_gap_blocks.c - the gap records of the walls and box faces
 * (grid->wall_gap, boundaries/wall_gaps.c) are stored only for the blocks
 * a measured point may write them in (gm_walls_map_gaps), not for every
 * block of the grid; a node of any other block reads the sentinel's
 * infinite records, as it read its own never-lowered ones before. And the
 * binning's counters shrink to fewer chunks where the blocks outnumber
 * the points (grid/bins.c, bin_chunks). Both were most of the granular
 * cloud's bytes outside its node layers (docs/performance.md, "Gap
 * records per block").
 *
 * Scene: three lone points at rest, no gravity, a fixed floor (the box
 * face y = 0, the one measured plane): A half a cell above the floor, B
 * and C 2 m up, far beyond the gaps' reach (8 cells in 2D, 4 in 3D). The
 * records exist for A's ring of blocks and the blocks it links only (5 of
 * 11 blocks in 2D, 8 of 24 in 3D); the old layout held block_capacity * 64
 * records (960 in 2D, 1792 in 3D), above the bound of block_count * 64 asserted
 * here (704, 1536): the capacity assertion fails on the old code. The gap of
 * A's floor nodes is A's distance to the floor less its half height.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include "boundaries/boundaries.h"
#include "core/domain.h"

#include <check.h>
#include <math.h>

static const double cell = 0.1; /* m */

/* Positions (m) of A, B, C: cell centres, A in the cells just above the
 * floor, B and C 2 m and more up. */
static const double at[3][3] = {
    {0.55, 0.05, 0.55}, {1.55, 2.05, 1.05}, {2.55, 2.55, 2.55}};

static gm_domain *build(int dim, int workers) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = dim == 3 ? GM_GEOMETRY_3D : GM_GEOMETRY_PLANE_STRAIN;
  def.cell_size = cell;
  def.worker_count = workers;
  for (int k = 0; k < 3; k++) {
    def.extent[k] = 3.0; /* m: 30 cells per axis */
    def.gravity[k] = 0.0;
  }
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e6, 0.3, 1500.0);
  double position[9], volume[3];
  for (int p = 0; p < 3; p++) {
    for (int k = 0; k < dim; k++)
      position[p * dim + k] = at[p][k];
    volume[p] = dim == 3 ? cell * cell * cell / 8 : cell * cell / 4;
  }
  test_add_points(domain, material, 3, position, NULL, volume);
  return domain;
}

/* Grid field index of the node (x, y, z) (node coordinates from the ghost
 * node below the box); its block must exist. */
static size_t node_index(const gm_grid *grid, int dim, const int64_t n[3]) {
  int64_t edge = (int64_t)1 << grid->shift, mask = edge - 1;
  int64_t key = dim == 3 ? gm_block_key_of_node_3d(grid, n[0], n[1], n[2])
                         : gm_block_key_of_node(grid, n[0], n[1]);
  uint32_t block = gm_grid_find(grid, key);
  ck_assert_uint_ne(block, GM_NO_BLOCK);
  size_t local = (size_t)((n[0] & mask) + edge * (n[1] & mask) +
                          (dim == 3 ? edge * edge * (n[2] & mask) : 0));
  return (size_t)block * GM_BLOCK_NODES + local;
}

static void check_records(int dim, size_t blocks, size_t with_records) {
  gm_domain *domain = build(dim, 1);
  TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
  const gm_grid *grid = &domain->grid;
  ck_assert_uint_eq(grid->block_count, blocks);
  ck_assert_int_eq(gm_gap_plane_count(domain), 1); /* the floor only */
  /* Records for the blocks a point within the reach may lie in (those of
   * block row y 0 and 1: their point centres start less than 8 cells, in
   * 3D 4, above the floor) and the upper neighbours they link, whose
   * nodes their points' supports reach; then the sentinel. */
  ck_assert_uint_le(grid->block_count, 32); /* has_records */
  bool has_records[32] = {false};
  for (size_t b = 0; b < grid->block_count; b++) {
    int64_t block[3] = {0, 0, 0};
    if (dim == 3)
      gm_block_coordinates_3d(grid, grid->block_key[b], block);
    else
      gm_block_coordinates(grid, grid->block_key[b], block);
    if (block[1] > 1)
      continue;
    for (int slot = 0; slot < (dim == 3 ? 8 : 4); slot++) {
      int64_t n[3] = {(block[0] + (slot & 1)) << grid->shift,
                      (block[1] + ((slot >> 1) & 1)) << grid->shift,
                      (block[2] + (slot >> 2)) << grid->shift};
      int64_t key = dim == 3 ? gm_block_key_of_node_3d(grid, n[0], n[1], n[2])
                             : gm_block_key_of_node(grid, n[0], n[1]);
      uint32_t linked = gm_grid_find(grid, key);
      if (linked != GM_NO_BLOCK)
        has_records[linked] = true;
    }
  }
  size_t count = 0;
  for (size_t b = 0; b < grid->block_count; b++) {
    ck_assert_int_eq(grid->gap_slot[b] != GM_NO_BLOCK, has_records[b]);
    count += has_records[b];
  }
  ck_assert_uint_eq(count, with_records);
  ck_assert_uint_eq(grid->gap_sentinel, with_records * GM_BLOCK_NODES);
  ck_assert_uint_lt(grid->wall_gap_capacity, blocks * GM_BLOCK_NODES);
  /* A's floor nodes: the face node row (GM_GHOST_LAYERS) under its cell.
   * Its box is the initial one moved with its centre (wall_gaps.c), half
   * its edge below the centre: one rounding of the subtraction apart. */
  double size[3], position[3];
  size_t a = 0;
  TEST_ASSERT_OK(domain, gm_domain_point_index(domain, 0, &a));
  double all[9];
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_DOMAIN_SIZE, all,
                                             (size_t)(3 * dim)));
  for (int k = 0; k < dim; k++)
    size[k] = all[a * (size_t)dim + (size_t)k];
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION, all,
                                             (size_t)(3 * dim)));
  for (int k = 0; k < dim; k++)
    position[k] = all[a * (size_t)dim + (size_t)k];
  double expected = position[1] - 0.5 * size[1]; /* m */
  int64_t lowest[3] = {6, GM_GHOST_LAYERS, 6};   /* x = 0.55 m: node 6 */
  size_t node = node_index(grid, dim, lowest);
  double gap = grid->wall_gap[gm_gap_node(grid, node)]; /* 1 plane */
  ck_assert_double_eq_tol(gap, expected, 1e-15);
  /* C's lowest node (2.55 m: node 26 on every axis): the sentinel; B's
   * (x 1.55 m, y 2.05 m: nodes 16, 21, z 1.05 m: 11), in a block linked
   * from A's ring, its own record: both infinite (never lowered). */
  int64_t far[2][3] = {{26, 26, 26}, {16, 21, 11}};
  node = node_index(grid, dim, far[0]);
  ck_assert_uint_eq(gm_gap_node(grid, node), grid->gap_sentinel);
  ck_assert(isinf(grid->wall_gap[gm_gap_node(grid, node)]));
  node = node_index(grid, dim, far[1]);
  ck_assert(isinf(grid->wall_gap[gm_gap_node(grid, node)]));
  /* 3 points in 11 or 24 blocks: 2 chunks (bin_chunks' least), 2 counters
   * per block and 4 blocks' worth of 32 spare (150 and 176 counters), not
   * 32 per block of capacity (480 and 896 before). */
  ck_assert_uint_eq(grid->chunks, 2);
  ck_assert_uint_lt(grid->chunk_capacity, GM_BIN_CHUNKS * blocks);
  gm_domain_destroy(domain);
}

START_TEST(test_records_2d) {
  /* A's ring: its block (0, 0) and (1, 0), (0, 1), (1, 1); B's (2, 2) and
   * C's (3, 3) rings share (3, 3): 4 + 4 + 3 = 11 blocks. Records: A's
   * ring and B's block (2, 2), the +x+y neighbour of (1, 1). */
  check_records(2, 11, 5);
}
END_TEST

START_TEST(test_records_3d) {
  /* Each point's block and its 7 upper neighbours (plain family: full
   * rings), none shared: 24 blocks, A's 8 with records. */
  check_records(3, 24, 8);
}
END_TEST

/* The same bits on 1 and 2 workers after 30 steps, A settling on the
 * floor under a push toward it. */
START_TEST(test_workers_2d) {
  double x[2][6];
  for (int w = 0; w < 2; w++) {
    gm_domain *domain = build(2, w + 1);
    double *velocity = NULL;
    TEST_ASSERT_OK(
        domain, gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity));
    velocity[1] = -0.5; /* m/s, A toward the floor */
    for (int step = 0; step < 30; step++)
      TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    TEST_ASSERT_OK(domain,
                   gm_domain_get_field(domain, GM_FIELD_POSITION, x[w], 6));
    gm_domain_destroy(domain);
  }
  ck_assert_mem_eq(x[0], x[1], sizeof x[0]);
  ck_assert_double_ge(x[0][1], 0.0); /* A stays above the floor */
}
END_TEST

static Suite *gap_blocks_suite(void) {
  Suite *suite = suite_create("gap_blocks");
  TCase *tcase = tcase_create("gap records");
  tcase_add_test(tcase, test_records_2d);
  tcase_add_test(tcase, test_records_3d);
  tcase_add_test(tcase, test_workers_2d);
  suite_add_tcase(suite, tcase);
  return suite;
}

int main(void) {
  return test_run_suite(gap_blocks_suite());
}
