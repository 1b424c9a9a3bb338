/*
 * test_inclined_plane.c - steady flow of the built-in mu(I) material down
 * an inclined plane against the closed form of Jop, Forterre & Pouliquen
 * (2006) / GDR MiDi (2004): with tau/p = tan(theta) at every depth, the
 * inertial number is uniform,
 *   I_theta = I_0 (tan theta - mu_s) / (mu_2 - tan theta),
 * and with p = phi rho_s g cos(theta) (h - z) the velocity is Bagnold's
 *   u(z) = (2/3) (I_theta / d) sqrt(phi g cos theta) [h^1.5 - (h - z)^1.5].
 * Below tan theta = mu_s the layer must not flow.
 *
 * The steady Bagnold flow is asserted on an infinitely long layer, with
 * periodic x faces, in test_bagnold.c. Here the plane is a long layer of
 * finite length on a no-slip floor (the fixed box face y = 0, a node row),
 * with gravity rotated by theta: g = g (sin theta, -cos theta). Its free
 * ends disturb the flow; in the kinematic (shallow) limit the flux
 * q = (3/5) u_s h ~ h^(5/2) carries disturbances downstream only, at
 * c = dq/dh = (3/2) u_s, so the upstream end's rarefaction reaches the
 * middle after (L/2) / c; the measurement is made before that (asserted
 * below from the measured u_s), in a window of +-h around the middle, on
 * the points' velocities averaged in bands one cell thick.
 *
 * What holds and what does not (h = 20 mm, d = 2 mm, tan theta = 0.42,
 * I_theta = 0.0476, L = 0.32 m, E = 30 kPa, uGIMP, MUSL): the free ends are
 * not kinematic: the flow is subcritical (Froude ~0.15), so the collapse
 * of the vertical end faces sends waves at sqrt(g h cos theta) = 0.42 m/s
 * both ways and drains the middle after ~0.35 s, while the layer needs
 * more than 0.6 s to spin up from rest (measured: u_s 0.051, 0.079, 0.099
 * m/s at 0.12, 0.31, 0.57 s on a 1 m layer). Started on the closed form,
 * after 0.12 s the fitted I is 10.2 % (5 cells per h) and 9.3 % (10 cells
 * per h) above I_theta, the shape within 7.7 % and 3.8 % of u_s (the
 * basal band moves at half the closed form), and the layer keeps
 * accelerating. The 3 % comparison is therefore NOT asserted: only the
 * no-flow case is a check; measure_bagnold_profile (MU_MEASURE=1) prints
 * the comparison.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granmpm/mu_i.h"
#include "test_util.h"

static const double GRAVITY = 9.81; /* m/s^2 */

/* The scene: layer depth h, grain diameter d, in cells per h. */
typedef struct plane_scene {
  double slope;          /* tan(theta) */
  double depth;          /* h, m */
  double length;         /* L, m */
  int cells_per_depth;   /* h / cell */
  double duration;       /* s */
  int start_steady;      /* nonzero: start on the closed-form steady state */
  double youngs_modulus; /* Pa */
} plane_scene;

static double env_or(const char *name, double fallback) {
  const char *value = getenv(name);
  return value ? atof(value) : fallback;
}

/* Measured at the end of a run. */
typedef struct plane_result {
  double surface_speed;   /* m/s, mean u of the top band */
  double fitted_inertial; /* I of the least-squares Bagnold fit */
  double shape_error;     /* max |u - fit| / u_s over the bands */
  double depth;           /* m, measured top of the layer in the window */
  double solid_fraction;  /* phi, mean density / rho_s in the window */
  double max_speed;       /* m/s, max |v| of all points */
} plane_result;

static plane_result measure(gm_domain *domain, const plane_scene *scene,
                            const gm_mu_i_def *def, size_t count,
                            double spacing, double *position) {
  double theta = atan(scene->slope);
  double cell = scene->depth / scene->cells_per_depth;
  int rows = scene->cells_per_depth * 2;
  /* Bands one cell thick in the window |x - middle| < h. */
  double *velocity = malloc(count * 2 * sizeof(double));
  double *density = malloc(count * sizeof(double));
  ck_assert(velocity && density);
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION,
                                             position, count * 2));
  TEST_ASSERT_OK(domain, gm_domain_get_field(domain, GM_FIELD_VELOCITY,
                                             velocity, count * 2));
  TEST_ASSERT_OK(domain,
                 gm_domain_get_field(domain, GM_FIELD_DENSITY, density, count));
  plane_result result;
  memset(&result, 0, sizeof result);
  double middle = scene->depth + 0.5 * scene->length; /* m */
  int bands = scene->cells_per_depth + 2;
  double sum[64] = {0}, heights[64] = {0}, weight[64] = {0};
  ck_assert_int_le(bands, 64);
  double density_sum = 0.0, top = 0.0;
  size_t in_window = 0;
  for (size_t p = 0; p < count; p++) {
    double speed = hypot(velocity[2 * p], velocity[2 * p + 1]);
    if (speed > result.max_speed)
      result.max_speed = speed;
    if (fabs(position[2 * p] - middle) > scene->depth)
      continue;
    int band = (int)(position[2 * p + 1] / cell);
    ck_assert(band >= 0 && band < bands);
    sum[band] += velocity[2 * p];
    heights[band] += position[2 * p + 1];
    weight[band] += 1.0;
    density_sum += density[p];
    in_window++;
    if (position[2 * p + 1] > top)
      top = position[2 * p + 1];
  }
  ck_assert_uint_gt(in_window, 0);
  /* The top points sit half a spacing below the surface. */
  double h = top + 0.5 * spacing * (scene->depth / (rows * spacing));
  result.depth = h;
  result.solid_fraction = density_sum / (double)in_window / def->grain_density;
  double scale = (2.0 / 3.0) / def->grain_diameter *
                 sqrt(result.solid_fraction * GRAVITY * cos(theta));
  double uf = 0.0, ff = 0.0;
  for (int b = 0; b < bands; b++) {
    if (weight[b] == 0.0)
      continue;
    double z = heights[b] / weight[b];
    double shape = scale * (pow(h, 1.5) - pow(fmax(h - z, 0.0), 1.5));
    uf += sum[b] / weight[b] * shape;
    ff += shape * shape;
  }
  result.fitted_inertial = ff > 0.0 ? uf / ff : 0.0;
  for (int b = 0; b < bands; b++) {
    if (weight[b] == 0.0)
      continue;
    double z = heights[b] / weight[b];
    double u = sum[b] / weight[b];
    result.surface_speed = u; /* last non-empty band */
    double fit = result.fitted_inertial * scale *
                 (pow(h, 1.5) - pow(fmax(h - z, 0.0), 1.5));
    if (getenv("MU_VERBOSE"))
      fprintf(stderr, "  z %.5f u %.6f fit %.6f\n", z, u, fit);
    result.shape_error = fmax(result.shape_error, fabs(u - fit));
  }
  if (result.surface_speed > 0.0)
    result.shape_error /= result.surface_speed;
  if (getenv("MU_VERBOSE"))
    fprintf(stderr,
            "tan %.3f cells/h %d: u_s %.5f m/s, I fit %.5f, shape "
            "%.4f, h %.5f, phi %.4f, max |v| %.4f\n",
            scene->slope, scene->cells_per_depth, result.surface_speed,
            result.fitted_inertial, result.shape_error, h,
            result.solid_fraction, result.max_speed);
  free(velocity);
  free(density);
  return result;
}

static plane_result run_plane(const plane_scene *scene, gm_mu_i_def *def) {
  double theta = atan(scene->slope);
  double cell = scene->depth / scene->cells_per_depth;
  gm_domain_def domain_def = gm_domain_def_default();
  domain_def.scheme = GM_SCHEME_MUSL;
  domain_def.cell_size = cell;
  domain_def.extent[0] = scene->length + 6.0 * scene->depth;
  domain_def.extent[1] = 2.0 * scene->depth;
  domain_def.gravity[0] = GRAVITY * sin(theta);
  domain_def.gravity[1] = -GRAVITY * cos(theta);
  domain_def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  domain_def.walls[GM_FACE_XMIN] = GM_WALL_SLIP;
  domain_def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  domain_def.shape = (gm_shape)env_or("MU_SHAPE", GM_SHAPE_UGIMP);
  domain_def.pic_fraction = env_or("MU_PIC", 0.0);
  gm_domain *domain = test_create_domain(&domain_def);
  int material = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_mu_i(domain, def, &material));
  /* The layer, 2 x 2 points per cell, with its geostatic pressure (an
   * isotropic stress: no shear yet, it starts at rest). */
  enum { PER_AXIS = 2 };
  int columns = (int)lround(scene->length / cell) * PER_AXIS;
  int rows = scene->cells_per_depth * PER_AXIS;
  size_t count = (size_t)columns * (size_t)rows;
  double spacing = cell / PER_AXIS;
  double *position = malloc(count * 2 * sizeof(double));
  double *volume = malloc(count * sizeof(double));
  double *stress = calloc(count * 6, sizeof(double));
  double *velocity = calloc(count * 2, sizeof(double));
  ck_assert(position && volume && stress && velocity);
  /* The closed form: u(z) with I_theta, tau = tan(theta) p. */
  double inertial = def->inertial_number_scale *
                    (scene->slope - def->static_friction) /
                    (def->limit_friction - scene->slope);
  double phi = def->density / def->grain_density;
  double bagnold = (2.0 / 3.0) * inertial / def->grain_diameter *
                   sqrt(phi * GRAVITY * cos(theta)); /* 1/(s sqrt(m)) */
  for (int j = 0; j < rows; j++)
    for (int i = 0; i < columns; i++) {
      size_t p = (size_t)j * (size_t)columns + (size_t)i;
      position[2 * p] = scene->depth + (i + 0.5) * spacing;
      position[2 * p + 1] = (j + 0.5) * spacing;
      volume[p] = spacing * spacing;
      double depth = scene->depth - position[2 * p + 1];
      double pressure = def->density * GRAVITY * cos(theta) * depth; /* Pa */
      for (int c = 0; c < 3; c++)
        stress[6 * p + c] = -pressure;
      if (scene->start_steady) {
        stress[6 * p + GM_XY] = -scene->slope * pressure; /* resists g_x */
        velocity[2 * p] = bagnold * (pow(scene->depth, 1.5) - pow(depth, 1.5));
      }
    }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = material;
  points.position = position;
  points.volume = volume;
  points.stress = stress;
  points.velocity = velocity;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
  free(velocity);
  free(stress);
  free(volume);
  double time = 0.0;
  long steps = 0;
  while (time < scene->duration) {
    double dt = 0.0;
    TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
    if (time + dt > scene->duration)
      dt = scene->duration - time;
    TEST_ASSERT_OK(domain, gm_domain_step(domain, dt));
    time += dt;
    steps++;
    if (getenv("MU_SERIES") && steps % (long)env_or("MU_SERIES", 500) == 0) {
      fprintf(stderr, "t %.4f ", time);
      measure(domain, scene, def, count, spacing, position);
    }
  }
  plane_result result = measure(domain, scene, def, count, spacing, position);
  if (getenv("MU_VERBOSE"))
    fprintf(stderr, "steps %ld\n", steps);
  free(position);
  gm_domain_destroy(domain);
  return result;
}

static gm_mu_i_def plane_material(double youngs_modulus) {
  gm_mu_i_def def = gm_mu_i_def_default();
  def.grain_diameter = env_or("MU_D", 2e-3);
  def.youngs_modulus = youngs_modulus;
  return def;
}

/* Not a check: prints the Bagnold comparison (MU_* variables set the
 * scene). Registered only with MU_MEASURE set; see the file comment for
 * what it measured. */
START_TEST(measure_bagnold_profile) {
  plane_scene scene;
  scene.slope = env_or("MU_TAN", 0.42);
  scene.depth = env_or("MU_H", 0.02);
  scene.length = env_or("MU_L", 0.32);
  scene.cells_per_depth = (int)env_or("MU_N", 10);
  scene.duration = env_or("MU_T", 0.12);
  scene.youngs_modulus = env_or("MU_E", 3e4);
  scene.start_steady = (int)env_or("MU_STEADY", 1);
  gm_mu_i_def def = plane_material(scene.youngs_modulus);
  plane_result r = run_plane(&scene, &def);
  double expected = def.inertial_number_scale *
                    (scene.slope - def.static_friction) /
                    (def.limit_friction - scene.slope);
  fprintf(stderr, "I_theta %.5f fitted %.5f (%.2f %%), shape %.2f %%\n",
          expected, r.fitted_inertial, 100 * (r.fitted_inertial / expected - 1),
          100 * r.shape_error);
}
END_TEST

/* Below tan(theta) = mu_s the layer does not flow. Two layers start from
 * rest with their geostatic pressure, at tan(theta) = 0.42 (I_theta =
 * 0.048, Bagnold surface speed 0.105 m/s) and 0.3 < mu_s = 0.382; after
 * 0.2 s the mean surface speed in the middle window of the second is
 * below 5 % of the first's. The regularised law's own creep at tan = 0.3
 * is I = 2.0e-6, a surface speed of 4.5e-6 m/s (0.005 %); what is
 * measured (1.2 % at 5 cells per depth) is the elastic response to the
 * shear load switched on at t = 0 and the collapse of the layer's vertical
 * end faces, whose waves (speed sqrt(g h cos theta) = 0.42 m/s) have
 * reached 0.08 m of the 0.16 m to the middle. 5 % keeps a factor 4 over
 * that and a factor 20 under a flowing layer. */
START_TEST(test_no_flow_below_static_friction) {
  plane_scene scene;
  scene.depth = 0.02;
  scene.length = 0.32;
  scene.cells_per_depth = 5;
  scene.duration = 0.2;
  scene.youngs_modulus = 3e4;
  scene.start_steady = 0;
  gm_mu_i_def def = plane_material(scene.youngs_modulus);
  scene.slope = 0.42;
  plane_result flowing = run_plane(&scene, &def);
  scene.slope = 0.3;
  plane_result resting = run_plane(&scene, &def);
  ck_assert_msg(flowing.surface_speed > 0.05,
                "the layer at tan 0.42 should flow: u_s %g m/s",
                flowing.surface_speed);
  ck_assert_msg(fabs(resting.surface_speed) < 0.05 * flowing.surface_speed,
                "tan 0.3 < mu_s: u_s %g m/s, flowing layer %g m/s",
                resting.surface_speed, flowing.surface_speed);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("inclined_plane");
  TCase *tcase = tcase_create("plane");
  tcase_set_timeout(tcase, 600);
  tcase_add_test(tcase, test_no_flow_below_static_friction);
  if (getenv("MU_MEASURE"))
    tcase_add_test(tcase, measure_bagnold_profile);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
