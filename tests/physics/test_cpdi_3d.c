/*
 * test_cpdi_3d.c - CPDI in 3D (GM_GEOMETRY_3D with GM_SHAPE_CPDI,
 * lib/shapes/support_cpdi_3d.c, docs/3d.md "CPDI in 3D"):
 *  - the weights of random sheared and rotated parallelepipeds (white box):
 *    a partition of unity, zero-sum gradients, exact reproduction of
 *    linear fields (sum S_i x_i = x_p, sum x_i (x) grad S_i = I), and,
 *    for a box inside one cell along every axis, where the corner
 *    interpolation of the trilinear tent is exact, uGIMP's weights;
 *  - the fixed-free elastic bar of test_3d.c: period 4L/c within 1 %;
 *  - a block spinning about an oblique axis and sheared (every F component
 *    moves), no gravity, open faces: no NaN, mass bitwise, total momentum
 *    conserved to round-off (the gradients sum to zero, so the internal
 *    forces cancel on the grid);
 *  - that block bitwise the same with 1 and 2 workers, after a checkpoint
 *    restart, and allocating nothing in a step after warm-up;
 *  - the granular family: two points whose domains of interaction are
 *    turned (face to face, vertex to vertex, edge to edge) join one
 *    component at the closed-form step of their contact (the 15-axis
 *    separating-axis test); the disconnection tests of
 *    test_granular_3d.c run CPDI too;
 *  - periodic x faces: a block crossing the seam 6 times keeps its
 *    velocity and its positions to round-off, bitwise on 1 and 2 workers;
 *  - rigid points: a rigid block moves as prescribed, and a plate's
 *    impulse balances the momentum of the block that hits it, which
 *    rebounds as in plane strain;
 *  - what stays unsupported is refused by name: APIC and planar walls
 *    with CPDI in 3D, and a domain too thin to weigh its nodes.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "core/domain.h" /* white box: the rotated F of the granular case */
#include "shapes/shapes.h"

#include "test_counting_allocator.h"
#include "test_random.h"
#include "test_restart.h"
#include "test_util.h"

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------- the weights */
static const double grid_origin[3] = {-1.7, 0.3, 2.2}; /* m, node 0 */
static const double cell = 0.37;                       /* m */
static const int64_t last_node[3] = {14, 11, 12};

static gm_shape_grid make_grid(gm_shape shape) {
  gm_shape_grid grid;
  memset(&grid, 0, sizeof grid);
  grid.shape = shape;
  grid.dim = 3;
  grid.inv_cell = 1.0 / cell;
  for (int k = 0; k < 3; k++) {
    grid.origin[k] = grid_origin[k];
    grid.last_node[k] = last_node[k];
  }
  return grid;
}

/* A random F = R (I + S): R a rotation by up to pi about a random axis, S
 * a random shear and stretch with entries up to `amount`, det F > 0. */
static void random_deformation(double amount, double f[9]) {
  double axis[3], norm = 0.0;
  for (int k = 0; k < 3; k++) {
    axis[k] = lcg_between(-1.0, 1.0);
    norm += axis[k] * axis[k];
  }
  norm = sqrt(norm);
  for (int k = 0; k < 3; k++)
    axis[k] /= norm;
  double angle = lcg_between(-PI, PI), c = cos(angle), s = sin(angle);
  double r[9]; /* Rodrigues */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      r[3 * i + j] = (i == j ? c : 0.0) + (1.0 - c) * axis[i] * axis[j];
  r[1] -= s * axis[2];
  r[2] += s * axis[1];
  r[3] += s * axis[2];
  r[5] -= s * axis[0];
  r[6] -= s * axis[1];
  r[7] += s * axis[0];
  double u[9];
  for (int k = 0; k < 9; k++)
    u[k] = (k % 4 == 0 ? 1.0 : 0.0) + lcg_between(-amount, amount);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      f[3 * i + j] =
          r[3 * i] * u[j] + r[3 * i + 1] * u[3 + j] + r[3 * i + 2] * u[6 + j];
}

static double det3(const double f[9]) {
  return f[0] * (f[4] * f[8] - f[5] * f[7]) -
         f[1] * (f[3] * f[8] - f[5] * f[6]) +
         f[2] * (f[3] * f[7] - f[4] * f[6]);
}

/* Coordinate (m) of node n along axis k. */
static double node_at(int k, int64_t n) {
  return grid_origin[k] + (double)n * cell;
}

START_TEST(test_weights_sheared_parallelepipeds) {
  lcg_state = 20261128;
  gm_shape_grid grid = make_grid(GM_SHAPE_CPDI);
  double worst_unity = 0.0, worst_sum_gradient = 0.0, worst_position = 0.0,
         worst_identity = 0.0;
  int computed = 0;
  for (int sample = 0; sample < 3000; sample++) {
    double f[9], half[3], x[3];
    random_deformation(0.4, f);
    if (!(det3(f) > 0.05))
      continue;
    for (int k = 0; k < 3; k++) {
      half[k] = lcg_between(0.05, 0.5) * cell;
      x[k] = lcg_between(node_at(k, 3), node_at(k, last_node[k] - 3));
    }
    gm_cpdi_support_3d support;
    if (!gm_cpdi_support_compute_3d(&grid, x, f, half, &support))
      continue; /* spans more than 5 nodes: refused, counted below */
    computed++;
    int64_t lowest[3];
    ck_assert(gm_cpdi_support_lowest_3d(&grid, x, f, half, lowest));
    double unity = 0.0, position[3] = {0, 0, 0}, gradient_sum[3] = {0, 0, 0};
    double identity[9] = {0};
    size_t entry = 0;
    for (int c = 0; c < support.span[2]; c++)
      for (int b = 0; b < support.span[1]; b++)
        for (int a = 0; a < support.span[0]; a++, entry++) {
          double xi[3] = {node_at(0, support.lowest[0] + a),
                          node_at(1, support.lowest[1] + b),
                          node_at(2, support.lowest[2] + c)}; /* m */
          double w = support.weight[entry];
          ck_assert(w >= 0.0 && w <= 1.0);
          unity += w;
          for (int i = 0; i < 3; i++) {
            position[i] += w * xi[i];
            gradient_sum[i] += support.gradient[i][entry];
            for (int j = 0; j < 3; j++)
              identity[3 * i + j] += xi[i] * support.gradient[j][entry];
          }
        }
    for (int k = 0; k < 3; k++)
      ck_assert_int_eq(lowest[k], support.lowest[k]);
    worst_unity = fmax(worst_unity, fabs(unity - 1.0));
    for (int i = 0; i < 3; i++) {
      worst_position = fmax(worst_position, fabs(position[i] - x[i]) / cell);
      worst_sum_gradient =
          fmax(worst_sum_gradient, fabs(gradient_sum[i]) * cell);
      for (int j = 0; j < 3; j++)
        worst_identity = fmax(worst_identity,
                              fabs(identity[3 * i + j] - (i == j ? 1.0 : 0.0)));
    }
  }
  printf("CPDI 3D weights, %d sheared parallelepipeds: unity %.2g, "
         "position %.2g h, gradient sum %.2g / h, sum x (x) grad - I %.2g\n",
         computed, worst_unity, worst_position, worst_sum_gradient,
         worst_identity);
  /* Most samples fit 5 nodes per axis (edges up to 1 cell, stretched by
   * up to 1.4 and rotated); all four identities are exact in arithmetic:
   * round-off of sums of up to 125 terms of order 1 (1e-13, as the GIMP
   * and B-spline tests in test_support_3d.c), the identity's terms of
   * order x_i / h ~ 15 (1e-12). */
  ck_assert_int_gt(computed, 2000);
  ck_assert_double_le(worst_unity, 1e-13);
  ck_assert_double_le(worst_position, 1e-13);
  ck_assert_double_le(worst_sum_gradient, 1e-12);
  ck_assert_double_le(worst_identity, 1e-12);
}
END_TEST

/* A box (F = I) inside one cell along every axis: the tent is trilinear
 * there, so its corner interpolation is exact and CPDI's average is
 * uGIMP's exact average (004 eq 3.27), node by node. */
START_TEST(test_weights_inside_one_cell_are_ugimp) {
  lcg_state = 7;
  gm_shape_grid cpdi_grid = make_grid(GM_SHAPE_CPDI);
  gm_shape_grid gimp_grid = make_grid(GM_SHAPE_UGIMP);
  static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double worst = 0.0; /* weights, and gradients times h */
  for (int sample = 0; sample < 1000; sample++) {
    double x[3], half[3];
    for (int k = 0; k < 3; k++) {
      int64_t node = 3 + (int64_t)(lcg_uniform() * 6);
      half[k] = lcg_between(0.01, 0.45) * cell;
      x[k] = node_at(k, node) + half[k] +
             lcg_uniform() * (cell - 2.0 * half[k]) * 0.999;
    }
    gm_cpdi_support_3d cpdi;
    gm_box_support_3d box;
    ck_assert(gm_cpdi_support_compute_3d(&cpdi_grid, x, identity, half, &cpdi));
    ck_assert(gm_box_support_compute_3d(&gimp_grid, x, half, &box));
    /* Both supports list the cell's nodes first (lowest equal); uGIMP may
     * list a third node of weight 0 (support_3d.h), CPDI two per axis. */
    size_t entry = 0;
    for (int c = 0; c < cpdi.span[2]; c++)
      for (int b = 0; b < cpdi.span[1]; b++)
        for (int a = 0; a < cpdi.span[0]; a++, entry++) {
          for (int k = 0; k < 3; k++)
            ck_assert_int_eq(cpdi.lowest[k], box.lowest[k]);
          double w = box.weight[0][a] * box.weight[1][b] * box.weight[2][c];
          double g[3] = {
              box.gradient[0][a] * box.weight[1][b] * box.weight[2][c],
              box.weight[0][a] * box.gradient[1][b] * box.weight[2][c],
              box.weight[0][a] * box.weight[1][b] * box.gradient[2][c]};
          worst = fmax(worst, fabs(cpdi.weight[entry] - w));
          for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(cpdi.gradient[k][entry] - g[k]) * cell);
        }
  }
  printf("CPDI 3D inside one cell against uGIMP: %.2g\n", worst);
  /* Round-off of the two evaluations (weights of order 1, gradients of
   * order 1 / h). A wrong corner gradient (a sign, a missing cross
   * product) is off by order 1. */
  ck_assert_double_le(worst, 1e-13);
}
END_TEST

START_TEST(test_bounds_refused) {
  gm_shape_grid grid = make_grid(GM_SHAPE_CPDI);
  static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double half[3] = {0.25 * cell, 0.25 * cell, 0.25 * cell};
  int64_t lowest[3];
  gm_cpdi_support_3d support;
  /* Inside. */
  double x[3] = {node_at(0, 5) + 0.5 * cell, node_at(1, 5), node_at(2, 5)};
  ck_assert(gm_cpdi_support_compute_3d(&grid, x, identity, half, &support));
  /* A corner below node 0. */
  double low[3] = {node_at(0, 0) + 0.1 * cell, x[1], x[2]};
  ck_assert(!gm_cpdi_support_lowest_3d(&grid, low, identity, half, lowest));
  /* A NaN centre. */
  double nan_x[3] = {x[0], NAN, x[2]};
  ck_assert(!gm_cpdi_support_lowest_3d(&grid, nan_x, identity, half, lowest));
  /* Stretched along x to 4.5 cells: 6 node planes. */
  double stretched[9] = {9, 0, 0, 0, 1, 0, 0, 0, 1};
  ck_assert(!gm_cpdi_support_lowest_3d(&grid, x, stretched, half, lowest));
  /* An F of determinant 0 (flattened): no corner gradients. */
  double flat[9] = {1, 0, 0, 0, 1, 0, 0, 0, 0};
  ck_assert(!gm_cpdi_support_compute_3d(&grid, x, flat, half, &support));
}
END_TEST

/* ------------------------------------------------------------ the bar */
static const double BAR_LENGTH = 25.0;  /* m, along x */
static const double BAR_SIDE = 2.0;     /* m, the y and z extents */
static const double BAR_YOUNGS = 100.0; /* Pa */
static const double BAR_POISSON = 0.3;  /* - */
static const double BAR_DENSITY = 1.0;  /* kg/m^3 */
static const double BAR_V0 = 0.1;       /* m/s */
static const double BAR_CELL = 1.0;     /* m */

/* The bar of test_3d.c: x = 0 FIXED, SLIP y and z faces, the first mode
 * v_x = v0 sin(pi x / (2L)). */
static gm_domain *bar_3d(gm_update_scheme scheme) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  def.scheme = scheme;
  def.cell_size = BAR_CELL;
  def.extent[0] = 30.0;
  def.extent[1] = def.extent[2] = BAR_SIDE;
  def.walls[GM_FACE_XMIN] = GM_WALL_FIXED;
  for (int face = GM_FACE_YMIN; face <= GM_FACE_ZMAX; face++)
    def.walls[face] = GM_WALL_SLIP;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, BAR_YOUNGS, BAR_POISSON, BAR_DENSITY);
  const double lower[3] = {0.0, 0.0, 0.0};
  const double upper[3] = {BAR_LENGTH, BAR_SIDE, BAR_SIDE};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  size_t count = gm_domain_point_count(domain);
  const double *x = NULL;
  double *v = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &v));
  for (size_t i = 0; i < count; ++i)
    v[i] = BAR_V0 * sin(PI * x[i] / (2.0 * BAR_LENGTH));
  return domain;
}

static double centre_of_mass_velocity(const gm_domain *domain) {
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  return summary.momentum[0] / summary.mass; /* m/s */
}

/* Times of the sign changes of samples[k] (taken at k dt). */
static int zero_crossings(const double *samples, int sample_count, double dt,
                          double *times, int max_times) {
  int found = 0;
  for (int k = 0; k + 1 < sample_count && found < max_times; ++k) {
    double a = samples[k], b = samples[k + 1];
    if ((a > 0 && b <= 0) || (a < 0 && b >= 0))
      times[found++] = dt * (k + a / (a - b));
  }
  return found;
}

/* _i: scheme. */
START_TEST(test_bar_period_cpdi_3d) {
  gm_update_scheme scheme = (gm_update_scheme)_i;
  double modulus = BAR_YOUNGS * (1 - BAR_POISSON) /
                   ((1 + BAR_POISSON) * (1 - 2 * BAR_POISSON)); /* Pa */
  double wave_speed = sqrt(modulus / BAR_DENSITY);              /* m/s */
  double period = 4.0 * BAR_LENGTH / wave_speed;                /* s */
  double dt = 0.2 * BAR_CELL / wave_speed;                      /* s */
  int steps = (int)ceil(2.3 * period / dt);
  gm_domain *domain = bar_3d(scheme);
  double *v_cm = malloc((size_t)(steps + 1) * sizeof *v_cm);
  ck_assert_ptr_nonnull(v_cm);
  v_cm[0] = centre_of_mass_velocity(domain);
  for (int k = 1; k <= steps; ++k) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    v_cm[k] = centre_of_mass_velocity(domain);
  }
  /* Period from the zero crossings at T/4 ... 9T/4 of v_cm, as in
   * test_3d.c. Expected: the lumped-mass dispersion, +0.06 % for uGIMP
   * and cpGIMP on this bar; 1 % fails a wrong modulus (E for M is 16 %),
   * a free end (period halved) or a wrong corner gradient (the stiffness
   * scales with it). */
  double crossing[5];
  ck_assert_int_eq(zero_crossings(v_cm, steps + 1, dt, crossing, 5), 5);
  double measured = (crossing[4] - crossing[0]) / 2.0;
  printf("3D bar CPDI %s: period %.6g s, 4L/c = %.6g s (%+.4f %%)\n",
         test_scheme_name(scheme), measured, period,
         100.0 * (measured / period - 1.0));
  ck_assert_msg(fabs(measured - period) <= 0.01 * period,
                "CPDI %s: period %.6g s, expected 4L/c = %.6g s",
                test_scheme_name(scheme), measured, period);
  free(v_cm);
  gm_domain_destroy(domain);
}
END_TEST

/* -------------------------------------------- the sheared, spun block */
static const double BLOCK_CELL = 0.1;    /* m */
static const double BLOCK_CENTRE = 0.6;  /* m, every axis; box 1.2 m */
static const double BLOCK_HALF = 0.2;    /* m, half edge */
static const double BLOCK_OMEGA = 3.0;   /* rad/s about (1, 2, 3)/sqrt 14 */
static const double BLOCK_SHEAR = 1.5;   /* 1/s, dv_x/dy and dv_z/dx */
static const double BLOCK_YOUNGS = 2e4;  /* Pa */
static const double BLOCK_DENSITY = 1e3; /* kg/m^3 */

/* A cube with v = omega x r + shear + a drift, open faces, no gravity: the
 * domains rotate and shear at once (every F component moves). */
static gm_domain *block(gm_update_scheme scheme, int workers) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = BLOCK_CELL;
  for (int k = 0; k < 3; k++) {
    def.extent[k] = 2.0 * BLOCK_CENTRE;
    def.gravity[k] = 0.0;
  }
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, BLOCK_YOUNGS, 0.3, BLOCK_DENSITY);
  double lower[3], upper[3];
  for (int k = 0; k < 3; k++) {
    lower[k] = BLOCK_CENTRE - BLOCK_HALF;
    upper[k] = BLOCK_CENTRE + BLOCK_HALF;
  }
  test_fill_box(domain, material, lower, upper, 2, NULL);
  size_t count = gm_domain_point_count(domain);
  const double *x[3];
  double *v[3];
  for (int k = 0; k < 3; k++) {
    TEST_ASSERT_OK(domain,
                   gm_domain_view_field(domain, GM_FIELD_POSITION, k, &x[k]));
    TEST_ASSERT_OK(domain,
                   gm_domain_edit_field(domain, GM_FIELD_VELOCITY, k, &v[k]));
  }
  double axis[3] = {1.0 / sqrt(14.0), 2.0 / sqrt(14.0), 3.0 / sqrt(14.0)};
  for (size_t i = 0; i < count; i++) {
    double r[3] = {x[0][i] - BLOCK_CENTRE, x[1][i] - BLOCK_CENTRE,
                   x[2][i] - BLOCK_CENTRE};
    v[0][i] = BLOCK_OMEGA * (axis[1] * r[2] - axis[2] * r[1]) +
              BLOCK_SHEAR * r[1] + 0.05;
    v[1][i] = BLOCK_OMEGA * (axis[2] * r[0] - axis[0] * r[2]) - 0.03;
    v[2][i] = BLOCK_OMEGA * (axis[0] * r[1] - axis[1] * r[0]) +
              BLOCK_SHEAR * r[0] + 0.02;
  }
  return domain;
}

static void run(gm_domain *domain, int steps) {
  for (int k = 0; k < steps; k++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
}

/* _i: scheme. */
START_TEST(test_block_momentum_cpdi_3d) {
  gm_update_scheme scheme = (gm_update_scheme)_i;
  gm_domain *domain = block(scheme, 1);
  gm_summary start = gm_summary_default(), end = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &start));
  run(domain, 150);
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &end));
  size_t count = gm_domain_point_count(domain);
  double *f = malloc(9 * count * sizeof *f);
  double *stress = malloc(6 * count * sizeof *stress);
  ck_assert_ptr_nonnull(f);
  ck_assert_ptr_nonnull(stress);
  TEST_ASSERT_OK(
      domain,
      gm_domain_get_field(domain, GM_FIELD_DEFORMATION_GRADIENT, f, 9 * count));
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_STRESS, stress, 6 * count));
  double smallest_off[9]; /* largest |F_ij - delta_ij| per component */
  for (int k = 0; k < 9; k++)
    smallest_off[k] = 0.0;
  bool finite = true;
  for (size_t p = 0; p < count; p++) {
    for (int k = 0; k < 9; k++) {
      finite = finite && isfinite(f[9 * p + k]);
      smallest_off[k] =
          fmax(smallest_off[k], fabs(f[9 * p + k] - (k % 4 == 0 ? 1.0 : 0.0)));
    }
    for (int k = 0; k < 6; k++)
      finite = finite && isfinite(stress[6 * p + k]);
  }
  ck_assert(finite);
  /* The block really was rotated and sheared: every F component moved by
   * at least 0.05 somewhere (the spin alone turns it by 0.45 rad). */
  for (int k = 0; k < 9; k++)
    ck_assert_msg(smallest_off[k] > 0.05, "F component %d moved only %g", k,
                  smallest_off[k]);
  ck_assert(start.mass == end.mass); /* bitwise: masses are per point */
  /* No external force: the grid's internal forces sum to -sum_p V sigma
   * sum_i grad S_i = 0 (zero-sum gradients), so FLIP keeps the total
   * momentum to round-off of the sums (|p| ~ M 0.5 m/s, 150 steps). */
  double scale = 0.0, drift = 0.0; /* kg m/s */
  for (int k = 0; k < 3; k++) {
    scale = fmax(scale, fabs(start.momentum[k]));
    drift = fmax(drift, fabs(end.momentum[k] - start.momentum[k]));
  }
  double spin_scale = start.mass * BLOCK_OMEGA * BLOCK_HALF; /* kg m/s */
  printf("CPDI 3D block %s: momentum drift %.3g of M omega a, F off I up to "
         "%.3g\n",
         test_scheme_name(scheme), drift / spin_scale, smallest_off[1]);
  ck_assert_msg(drift <= 1e-12 * spin_scale, "%s: momentum drift %g (scale %g)",
                test_scheme_name(scheme), drift, scale);
  free(f);
  free(stress);
  gm_domain_destroy(domain);
}
END_TEST

/* _i: scheme. Every field the API shows, bitwise (test_restart.h). */
START_TEST(test_workers_bitwise_cpdi_3d) {
  gm_update_scheme scheme = (gm_update_scheme)_i;
  test_snapshot result[2];
  for (int workers = 1; workers <= 2; workers++) {
    gm_domain *domain = block(scheme, workers);
    run(domain, 80);
    result[workers - 1] = test_snapshot_take(domain, NULL, NULL);
    gm_domain_destroy(domain);
  }
  test_snapshot_assert_same(&result[0], &result[1], "1 against 2 workers");
  test_snapshot_free(&result[0]);
  test_snapshot_free(&result[1]);
}
END_TEST

static gm_domain *build_block(int workers, void *context) {
  return block(*(const gm_update_scheme *)context, workers);
}

/* _i: scheme; saved on 1 worker at step 40, continued on 1 (_i < 3) or 2
 * for 40 steps; the restarted domain runs 3 steps first (stale caches). */
START_TEST(test_restart_bitwise_cpdi_3d) {
  gm_update_scheme scheme = (gm_update_scheme)(_i % 3);
  test_restart_run restart = {.what = "CPDI block",
                              .build = build_block,
                              .context = &scheme,
                              .workers_before = 1,
                              .workers_after = _i < 3 ? 1 : 2,
                              .steps_before = 40,
                              .steps_after = 40,
                              .stale_steps = 3,
                              .dt = 0.0};
  test_restart_check(&restart);
}
END_TEST

/* _i: scheme (_i % 3), workers (_i / 3 + 1). The bar keeps its points
 * within their blocks' reach, so after warm-up the grid keeps its blocks
 * and every work array its size. */
START_TEST(test_no_allocation_cpdi_3d) {
  test_install_counting_allocator();
  gm_update_scheme scheme = (gm_update_scheme)(_i % 3);
  gm_domain *domain = block(scheme, _i / 3 + 1);
  run(domain, 5);
  long before = atomic_load(&test_allocations);
  run(domain, 20);
  long after = atomic_load(&test_allocations);
  gm_domain_destroy(domain);
  ck_assert_int_eq(gm_set_allocator(NULL), GM_OK);
  ck_assert_msg(after == before, "%s, %d workers: %ld allocations in 20 steps",
                test_scheme_name(scheme), _i / 3 + 1, after - before);
}
END_TEST

/* ------------------------------------------------- periodic x faces */
/* The periodic block of test_periodic.c: 8 cells long (the period, x faces
 * GM_WALL_PERIODIC, origin off 0), 2 x 2 cells across, 2 points per cell
 * per axis, open y and z faces, no gravity, E = 1e4 Pa, moving at
 * (1.3, 0.02, -0.01) m/s through 6 crossings of the 0.8 m seam. A CPDI
 * support reaches the image nodes past the seam, which periodic.c folds
 * onto their owners; a uniform velocity stays uniform only if every node
 * sum has all its points (the other shapes: 1.1e-14 m/s, 6e-14 m). */
static gm_domain *periodic_block(gm_update_scheme scheme, int workers) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  def.scheme = scheme;
  def.worker_count = workers;
  def.cell_size = 0.1;
  def.origin[0] = -0.3;
  def.origin[2] = 0.2;
  def.extent[0] = 0.8;
  def.extent[1] = def.extent[2] = 0.6;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_PERIODIC;
  for (int k = 0; k < 3; k++)
    def.gravity[k] = 0.0;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e4, 0.3, 1000.0);
  const double lower[3] = {-0.3, 0.2, 0.4}, upper[3] = {0.5, 0.4, 0.6};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  return domain;
}

/* _i: USL, MUSL, USF. */
START_TEST(test_periodic_translation_cpdi_3d) {
  gm_update_scheme scheme = (gm_update_scheme)_i;
  gm_domain *domain = periodic_block(scheme, 1);
  size_t count = gm_domain_point_count(domain);
  ck_assert_uint_eq(count, 8 * 2 * 2 * 8);
  const double speed[3] = {1.3, 0.02, -0.01}; /* m/s */
  const double period = 0.8, x0 = -0.3;       /* m */
  double *start = malloc(3 * count * sizeof(double));
  double *position = malloc(3 * count * sizeof(double));
  double *velocity = malloc(3 * count * sizeof(double));
  ck_assert(start && position && velocity);
  test_get_field_by_id(domain, GM_FIELD_POSITION, 0, start); /* ids 0.. */
  for (int k = 0; k < 3; k++) {
    double *v = NULL;
    TEST_ASSERT_OK(domain,
                   gm_domain_edit_field(domain, GM_FIELD_VELOCITY, k, &v));
    for (size_t p = 0; p < count; p++)
      v[p] = speed[k];
  }
  double time = 0.0, end = 6.0 * period / speed[0]; /* s */
  while (time < end) {
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    dt = time + dt > end ? end - time : dt;
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    time += dt;
  }
  test_get_field_by_id(domain, GM_FIELD_POSITION, 0, position);
  test_get_field_by_id(domain, GM_FIELD_VELOCITY, 0, velocity);
  double worst_velocity = 0.0, worst_position = 0.0; /* m/s, m */
  for (size_t p = 0; p < count; p++)                 /* by id */
    for (int k = 0; k < 3; k++) {
      worst_velocity =
          fmax(worst_velocity, fabs(velocity[3 * p + k] - speed[k]));
      double expected = start[3 * p + k] + speed[k] * time;
      if (k == 0) /* wrapped into [x0, x0 + period) */
        expected = x0 + fmod(expected - x0, period);
      double off = fabs(position[3 * p + k] - expected);
      if (k == 0) /* a point on the seam may sit at either end */
        off = fmin(off, period - off);
      worst_position = fmax(worst_position, off);
    }
  printf("CPDI 3D periodic %s: |v - v0| %.3g m/s, position %.3g m\n",
         test_scheme_name(scheme), worst_velocity, worst_position);
  /* As for the other shapes (test_periodic.c): round-off, 1e-11 m/s and
   * 1e-9 m allowed; a missing image fold drifts the momentum by 3e-5. */
  ck_assert_double_le(worst_velocity, 1e-11);
  ck_assert_double_le(worst_position, 1e-9);
  free(start);
  free(position);
  free(velocity);
  gm_domain_destroy(domain);
}
END_TEST

/* The periodic block under a sheared, wavy velocity, 100 steps: the same
 * bits with 1 and 2 workers. */
START_TEST(test_periodic_workers_cpdi_3d) {
  test_snapshot result[2];
  for (int workers = 1; workers <= 2; workers++) {
    gm_domain *domain = periodic_block(GM_SCHEME_MUSL, workers);
    size_t count = gm_domain_point_count(domain);
    const double *x[3];
    double *v[3];
    for (int k = 0; k < 3; k++) {
      TEST_ASSERT_OK(domain,
                     gm_domain_view_field(domain, GM_FIELD_POSITION, k, &x[k]));
      TEST_ASSERT_OK(domain,
                     gm_domain_edit_field(domain, GM_FIELD_VELOCITY, k, &v[k]));
    }
    for (size_t p = 0; p < count; p++) {
      v[0][p] = 0.8 + 0.3 * sin(2.0 * PI * x[0][p] / 0.8) + 0.5 * x[1][p];
      v[1][p] = 0.1 * cos(2.0 * PI * x[0][p] / 0.8);
      v[2][p] = 0.2 * (x[1][p] - 0.3);
    }
    run(domain, 100);
    result[workers - 1] = test_snapshot_take(domain, NULL, NULL);
    gm_domain_destroy(domain);
  }
  test_snapshot_assert_same(&result[0], &result[1],
                            "periodic, 1 against 2 workers");
  test_snapshot_free(&result[0]);
  test_snapshot_free(&result[1]);
}
END_TEST

/* ------------------------------------------------------ rigid points */
/* The scenes of test_rigid.c's 3D cases (0.05 m cells, a 2 x 1 x 1 m box,
 * open faces): rigid points mark the nodes of their CPDI support with a
 * nonzero weight, and those take the prescribed velocity. */
static int add_plate(gm_domain *domain, const double velocity[3]) {
  gm_rigid_def rigid = gm_rigid_def_default();
  for (int k = 0; k < 3; k++)
    rigid.velocity[k] = velocity[k];
  int plate = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_rigid(domain, &rigid, &plate));
  return plate;
}

static gm_domain *rigid_domain(gm_update_scheme scheme, int dim) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = dim == 3 ? GM_GEOMETRY_3D : GM_GEOMETRY_PLANE_STRAIN;
  def.shape = GM_SHAPE_CPDI;
  def.scheme = scheme;
  def.cell_size = 0.05;
  def.extent[0] = 2.0;
  def.extent[1] = def.extent[2] = 1.0;
  return test_create_domain(&def);
}

/* A rigid block moving at (0.5, -0.25, 0.3) m/s alone (MUSL): every point
 * at x0 + v t to 1e-12 m after 100 steps, its velocity exactly v, its
 * stress zero. A reached node left unmarked would carry 0 (or gravity's
 * velocity) and slow the point by its weight. */
START_TEST(test_rigid_motion_cpdi_3d) {
  gm_domain *domain = rigid_domain(GM_SCHEME_MUSL, 3);
  const double velocity[3] = {0.5, -0.25, 0.3}; /* m/s */
  int plate = add_plate(domain, velocity);
  const double lower[3] = {0.4, 0.4, 0.4}, upper[3] = {0.6, 0.6, 0.6};
  size_t count = test_fill_box(domain, plate, lower, upper, 2, NULL);
  double *start = malloc(3 * count * sizeof *start);
  double *now = malloc(6 * count * sizeof *now);
  ck_assert(start && now);
  test_get_field_by_id(domain, GM_FIELD_POSITION, 0, start);
  const double dt = 1e-3; /* s */
  for (int step = 0; step < 100; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
  test_get_field_by_id(domain, GM_FIELD_POSITION, 0, now);
  for (size_t i = 0; i < 3 * count; i++)
    ck_assert_msg(fabs(now[i] - (start[i] + velocity[i % 3] * 100 * dt)) <
                      1e-12,
                  "point %zu axis %zu at %.17g", i / 3, i % 3, now[i]);
  test_get_field_by_id(domain, GM_FIELD_VELOCITY, 0, now);
  for (size_t i = 0; i < 3 * count; i++)
    ck_assert(now[i] == velocity[i % 3]);
  test_get_field_by_id(domain, GM_FIELD_STRESS, 0, now);
  for (size_t i = 0; i < 6 * count; i++)
    ck_assert(now[i] == 0.0);
  free(start);
  free(now);
  gm_domain_destroy(domain);
}
END_TEST

/* The block of test_rigid.c (E = 1e6 Pa, nu = 0, 0.4 x 0.2 x 0.2 m)
 * thrown at (1, 0.2, -0.1) m/s ((1, 0.2) in plane strain) into a resting
 * rigid plate, 0.5 s, USL: the plate's total impulse and the block's
 * momentum (kg m/s; per m of thickness in the plane). */
typedef struct impact {
  double start[3], end[3], impulse[3];
} impact;

static impact run_impact(int dim) {
  gm_domain *domain = rigid_domain(GM_SCHEME_USL, dim);
  const double rest[3] = {0.0, 0.0, 0.0};
  int plate = add_plate(domain, rest);
  const double plate_lower[3] = {1.2, 0.3, 0.3};
  const double plate_upper[3] = {1.3, 0.7, 0.7};
  test_fill_box(domain, plate, plate_lower, plate_upper, 2, NULL);
  int block = test_add_elastic(domain, 1e6, 0.0, 1000.0);
  gm_fill_def fill = gm_fill_def_default();
  fill.material = block;
  const double block_lower[3] = {0.7, 0.4, 0.4};
  const double block_upper[3] = {1.1, 0.6, 0.6};
  memcpy(fill.lower, block_lower, sizeof fill.lower);
  memcpy(fill.upper, block_upper, sizeof fill.upper);
  fill.velocity[0] = 1.0;
  fill.velocity[1] = 0.2;
  fill.velocity[2] = dim == 3 ? -0.1 : 0.0;
  TEST_ASSERT_OK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  impact result = {{0}, {0}, {0}};
  gm_summary summary = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  memcpy(result.start, summary.momentum, sizeof result.start);
  for (int step = 0; step < 2500; step++) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 2e-4));
    gm_rigid_load load = gm_rigid_load_default();
    TEST_ASSERT_OK(domain, gm_domain_get_rigid_load(domain, plate, &load));
    for (int k = 0; k < 3; k++)
      result.impulse[k] += load.impulse[k];
  }
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &summary));
  memcpy(result.end, summary.momentum, sizeof result.end);
  gm_domain_destroy(domain);
  return result;
}

/* The plate's impulse is minus the block's momentum change, per
 * component, to 1e-9 of the momentum (the same nodal sums: round-off over
 * 2500 steps). With nu = 0 the 3D block must rebound as the plane one
 * does (the z sliding changes the no-slip contact a little): 0.05 of the
 * momentum fails a 3D support marked differently from the 2D one (a
 * rebound of 0 or 1). */
START_TEST(test_rigid_impact_cpdi_3d) {
  impact solid = run_impact(3);
  impact plane = run_impact(2);
  double scale =
      sqrt(solid.start[0] * solid.start[0] + solid.start[1] * solid.start[1] +
           solid.start[2] * solid.start[2]); /* kg m/s */
  for (int k = 0; k < 3; k++)
    ck_assert_msg(fabs(solid.impulse[k] + solid.end[k] - solid.start[k]) <
                      1e-9 * scale,
                  "axis %d: impulse %.12g, momentum change %.12g", k,
                  solid.impulse[k], solid.end[k] - solid.start[k]);
  double rebound[2] = {-solid.end[0] / solid.start[0],
                       -plane.end[0] / plane.start[0]}; /* - */
  printf("3D rigid impact CPDI USL: rebound %.4f of the x momentum (plane "
         "strain %.4f)\n",
         rebound[0], rebound[1]);
  ck_assert_msg(fabs(rebound[0] - rebound[1]) < 0.05,
                "rebound %g, plane strain %g", rebound[0], rebound[1]);
}
END_TEST

/* ------------------------------------- granular: rotated domains meet */
/* Two single granular points (rho = 1500 kg/m^3, rho_cr = 1200 kg/m^3,
 * initial cube of edge L = 0.05 m, cell 0.1 m, no gravity) approach each
 * other along x at 0.5 m/s each from 0.2 m apart. Their domains of
 * interaction are their CPDI parallelepipeds scaled to V_cr: cubes of edge
 * l_i = L (rho / rho_cr)^(1/3), turned as F turns them. The host has no
 * call that sets F, so this white-box test writes a rotation R into the
 * committed F before the first step (L = 0 for a lone point in uniform
 * motion keeps it): case 0 keeps F = I, whose cubes meet face to face at
 * a centre distance l_i; case 1 turns both by 45 degrees about z, which
 * meet vertex to vertex at sqrt(2) l_i (a face normal separates them until
 * then); case 2 turns A about z and B about y, whose edges (A's along z,
 * B's along y) meet at sqrt(2) l_i, where only the cross product of the
 * two edges (x) separates them: the six face normals alone stop
 * separating at 0.1031 m (step 97 instead of 124), the axis-aligned box
 * test of the other shapes at l_i (step 147). The points merge into one
 * component at the first step that starts with the distance below the
 * contact distance. */
static const int ROTATION_SLOT[9] = {0, 1, 5, 2, 3, 6, 7, 8, 4}; /* core.h */

static void set_rotation(gm_domain *domain, size_t p, char axis) {
  double c = sqrt(0.5), r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (axis == 'z') {
    r[0] = c, r[1] = -c, r[3] = c, r[4] = c;
  } else if (axis == 'y') {
    r[0] = c, r[2] = c, r[6] = -c, r[8] = c;
  }
  gm_point_buffers *buffer = &domain->points.buffer[domain->points.cur];
  for (int k = 0; k < 9; k++) { /* F and the domain map D that CPDI reads */
    buffer->deformation[ROTATION_SLOT[k]][p] = r[k];
    buffer->domain_map[ROTATION_SLOT[k]][p] = r[k];
  }
}

START_TEST(test_granular_rotated_domains_meet) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  def.family = GM_FAMILY_GRANULAR;
  def.cell_size = 0.1;
  def.extent[0] = 1.0;
  def.extent[1] = def.extent[2] = 0.4;
  for (int k = 0; k < 3; k++)
    def.gravity[k] = 0.0;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e5, 0.3, 1500.0);
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = 1200.0;
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &granular));
  const double edge = 0.05, start = 0.2, speed = 0.5, dt = 1e-3; /* SI */
  double position[6] = {0.3, 0.2, 0.2, 0.3 + start, 0.2, 0.2};   /* m */
  double velocity[6] = {speed, 0, 0, -speed, 0, 0};              /* m/s */
  double volume[2] = {edge * edge * edge, edge * edge * edge};   /* m^3 */
  double size[6] = {edge, edge, edge, edge, edge, edge};         /* m */
  gm_points_def points = gm_points_def_default();
  points.material = material;
  points.count = 2;
  points.position = position;
  points.velocity = velocity;
  points.volume = volume;
  points.domain_size = size;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  static const char axes[3][2] = {{0, 0}, {'z', 'z'}, {'z', 'y'}};
  set_rotation(domain, 0, axes[_i][0]);
  set_rotation(domain, 1, axes[_i][1]);
  double interaction = edge * cbrt(1500.0 / 1200.0);                /* m, l_i */
  double contact = _i == 0 ? interaction : sqrt(2.0) * interaction; /* m */
  int expected = (int)floor((start - contact) / (2.0 * speed * dt)) + 1;
  int merge_step = -1;
  for (int step = 0; step < expected + 5 && merge_step < 0; step++) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    gm_granular_summary summary = gm_granular_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
    if (summary.component_count == 1)
      merge_step = step;
  }
  printf("CPDI 3D granular, rotation case %d: merge at step %d (closed form "
         "%d)\n",
         _i, merge_step, expected);
  /* Within one step: the positions are x0 + v t to round-off and
   * (start - contact) / (2 v dt) is 0.14 and 0.83 from an integer. */
  ck_assert_msg(merge_step >= expected - 1 && merge_step <= expected + 1,
                "case %d: merged at step %d, closed form %d", _i, merge_step,
                expected);
  gm_domain_destroy(domain);
}
END_TEST

/* -------------------------------------------------------------- misuse */
static gm_status create_cpdi_3d(gm_family family, gm_transfer transfer,
                                bool periodic) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  def.family = family;
  def.transfer = transfer;
  if (periodic)
    def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_PERIODIC;
  gm_domain *domain = NULL;
  gm_status status = gm_domain_create(&def, &domain);
  ck_assert((status == GM_OK) == (domain != NULL));
  gm_domain_destroy(domain);
  return status;
}

START_TEST(test_unsupported_refused_cpdi_3d) {
  /* Every family is accepted. */
  ck_assert_int_eq(create_cpdi_3d(GM_FAMILY_PLAIN, GM_TRANSFER_FLIP, false),
                   GM_OK);
  ck_assert_int_eq(
      create_cpdi_3d(GM_FAMILY_STRESS_FREE, GM_TRANSFER_FLIP, false), GM_OK);
  ck_assert_int_eq(create_cpdi_3d(GM_FAMILY_GRANULAR, GM_TRANSFER_FLIP, false),
                   GM_OK);
  /* APIC too since 2026-11-28 (test_apic.c). */
  ck_assert_int_eq(create_cpdi_3d(GM_FAMILY_PLAIN, GM_TRANSFER_APIC, false),
                   GM_OK);
  ck_assert_int_eq(create_cpdi_3d(GM_FAMILY_PLAIN, GM_TRANSFER_FLIP, true),
                   GM_OK);
  /* Planar walls are accepted since 2026-11-28 (test_walls_3d.c,
   * test_wall_watertight.c). */
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_3D;
  def.shape = GM_SHAPE_CPDI;
  gm_domain *domain = test_create_domain(&def);
  gm_wall_def wall = gm_wall_def_default();
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_wall(domain, &wall, &id));
  ck_assert_int_eq(id, 0);
  /* A domain far too thin to weigh its nodes (its corner gradients divide
   * by its volume), and one spanning more than 5 node planes. */
  int material = test_add_elastic(domain, 1e5, 0.3, 1000.0);
  double position[3] = {0.5, 0.5, 0.5}, volume = 1e-3; /* m, m^3 */
  double thin[3] = {1e-170, 1e-170, 1e-170};           /* m: volume 1e-510, 0 */
  gm_points_def points = gm_points_def_default();
  points.material = material;
  points.count = 1;
  points.position = position;
  points.volume = &volume;
  points.domain_size = thin;
  ck_assert_int_ne(gm_domain_add_points(domain, &points, NULL), GM_OK);
  ck_assert_ptr_nonnull(strstr(gm_domain_last_error(domain), "point 0"));
  double long_domain[3] = {0.45, 0.1, 0.1}; /* cell 0.1 m: 6 planes */
  points.domain_size = long_domain;
  ck_assert_int_eq(gm_domain_add_points(domain, &points, NULL),
                   GM_ERR_OUT_OF_GRID);
  ck_assert_uint_eq(gm_domain_point_count(domain), 0);
  gm_domain_destroy(domain);
}
END_TEST

static Suite *cpdi_3d_suite(void) {
  Suite *suite = suite_create("cpdi_3d");
  TCase *weights = tcase_create("weights");
  tcase_add_test(weights, test_weights_sheared_parallelepipeds);
  tcase_add_test(weights, test_weights_inside_one_cell_are_ugimp);
  tcase_add_test(weights, test_bounds_refused);
  suite_add_tcase(suite, weights);
  TCase *laws = tcase_create("laws");
  tcase_set_timeout(laws, 300);
  tcase_add_loop_test(laws, test_block_momentum_cpdi_3d, 0, 3);
  tcase_add_loop_test(laws, test_workers_bitwise_cpdi_3d, 0, 3);
  tcase_add_loop_test(laws, test_restart_bitwise_cpdi_3d, 0, 6);
  tcase_add_loop_test(laws, test_no_allocation_cpdi_3d, 0, 6);
  tcase_add_loop_test(laws, test_periodic_translation_cpdi_3d, 0, 3);
  tcase_add_test(laws, test_periodic_workers_cpdi_3d);
  tcase_add_test(laws, test_rigid_motion_cpdi_3d);
  tcase_add_loop_test(laws, test_granular_rotated_domains_meet, 0, 3);
  tcase_add_test(laws, test_unsupported_refused_cpdi_3d);
  suite_add_tcase(suite, laws);
  /* The bar's period and the rigid impact (tests/README.md, "Slow cases":
   * the momentum, workers, restart, allocation and rigid-motion cases above
   * keep the 3D CPDI paths under the sanitizers). */
  TCase *slow = tcase_create("period and impact");
  tcase_set_timeout(slow, 300);
  tcase_set_tags(slow, "slow");
  tcase_add_loop_test(slow, test_bar_period_cpdi_3d, 0, 3);
  tcase_add_test(slow, test_rigid_impact_cpdi_3d);
  suite_add_tcase(suite, slow);
  return suite;
}

int main(void) {
  return test_run_suite(cpdi_3d_suite());
}
