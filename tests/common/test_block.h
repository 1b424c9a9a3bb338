/*
 * test_block.h - the rectangular elastic block the wall and friction tests
 * put on a floor or an inclined plane (test_friction, test_wall_offsets,
 * test_face_gaps): 2 x 2 points per cell, laid out in the plane's frame and
 * optionally carrying the geostatic stress of its weight. Uses only the
 * public API.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_TEST_BLOCK_H
#define GM_TEST_BLOCK_H

#include <math.h>
#include <stdlib.h>

#include "test_util.h"

/* Where the block goes and what it carries. The points lie at s along
 * `tangent` (m, from `offset` to offset + width) and n along `normal`
 * (into the block, 0 to height) from `origin`. With weight_stress (Pa/m,
 * rho g cos(theta)) > 0 each point starts with the stress of the weight of
 * the material above it, normal to the plane: sigma = s_nn n n^T, s_nn =
 * -weight_stress (height - n), sigma_zz = poisson s_nn (plane strain), free
 * ends. A block starting unstressed bounces on its floor, and friction
 * follows the normal force, bounces included. */
typedef struct test_block {
  double origin[2];     /* m, on the plane */
  double tangent[2];    /* unit, along the plane */
  double normal[2];     /* unit, into the block */
  double offset;        /* m, start of the block along the tangent */
  double width, height; /* m */
  double cell;          /* m, the grid's cell: 2 x 2 points per cell */
  double weight_stress; /* Pa/m, rho g cos(theta); 0: unstressed */
  double poisson;       /* -, for sigma_zz */
} test_block;

/* A block on a horizontal floor at height y (m), from x to x + width. */
static inline test_block test_block_on_floor(double x, double y, double width,
                                             double height, double cell) {
  test_block block = {{x, y}, {1.0, 0.0}, {0.0, 1.0}, 0.0, width,
                      height, cell,       0.0,        0.0};
  return block;
}

static inline void test_add_block(gm_domain *domain, int material,
                                  const test_block *block) {
  enum { PER_AXIS = 2 };
  int columns = (int)lround(block->width / block->cell) * PER_AXIS;
  int rows = (int)lround(block->height / block->cell) * PER_AXIS;
  size_t count = (size_t)(columns * rows);
  double spacing = block->cell / PER_AXIS; /* m */
  double *position = malloc(count * 2 * sizeof(double));
  double *volume = malloc(count * sizeof(double));
  double *stress = calloc(count * 6, sizeof(double));
  ck_assert(position && volume && stress);
  for (int j = 0; j < rows; j++) {
    for (int i = 0; i < columns; i++) {
      size_t p = (size_t)(j * columns + i);
      double s = block->offset + (i + 0.5) * spacing; /* m */
      double n = (j + 0.5) * spacing;                 /* m */
      for (int k = 0; k < 2; k++)
        position[2 * p + k] =
            block->origin[k] + s * block->tangent[k] + n * block->normal[k];
      volume[p] = spacing * spacing;
      double sigma_nn = -block->weight_stress * (block->height - n); /* Pa */
      stress[6 * p + GM_XX] = sigma_nn * block->normal[0] * block->normal[0];
      stress[6 * p + GM_YY] = sigma_nn * block->normal[1] * block->normal[1];
      stress[6 * p + GM_XY] = sigma_nn * block->normal[0] * block->normal[1];
      stress[6 * p + GM_ZZ] = block->poisson * sigma_nn;
    }
  }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.volume = volume;
  points.stress = stress;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  free(position);
  free(volume);
  free(stress);
}

#endif
