/* examples/minimal.c - the README's minimal program: an elastic block
 * settling under gravity on a fixed floor, plane strain, stepped 100 times
 * with the largest stable time step. make check builds and runs it.
 * SPDX-License-Identifier: BSD-2-Clause */
#include <granmpm.h>
#include <stdio.h>
#include <stdlib.h>

int main(void) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = GM_GEOMETRY_PLANE_STRAIN;
  def.extent[0] = 1.0;    /* m */
  def.extent[1] = 1.0;    /* m */
  def.cell_size = 0.05;   /* m */
  def.gravity[1] = -9.81; /* m/s^2 */
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;

  gm_domain *domain = NULL;
  gm_status status = gm_domain_create(&def, &domain);
  if (status != GM_OK) {
    fprintf(stderr, "create: %s\n", gm_last_create_error());
    return 1;
  }

  gm_elastic_def elastic = gm_elastic_def_default();
  elastic.youngs_modulus = 1e6; /* Pa */
  elastic.poisson_ratio = 0.3;
  elastic.density = 1000.0; /* kg/m^3 */
  int material = -1;
  status = gm_domain_add_elastic(domain, &elastic, &material);

  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.lower[0] = 0.3; /* m */
  fill.lower[1] = 0.0; /* m */
  fill.upper[0] = 0.7; /* m */
  fill.upper[1] = 0.4; /* m */
  fill.points_per_cell_axis = 2;
  int64_t first_id = 0;
  size_t count = 0;
  if (status == GM_OK)
    status = gm_domain_fill_box(domain, &fill, &first_id, &count);

  for (int step = 0; status == GM_OK && step < 100; step++)
    status = gm_domain_step(domain, 0.0); /* <= 0: largest stable dt */

  /* Velocities are interleaved: v[2*i] = v_x, v[2*i+1] = v_y (m/s).
   */
  size_t length = 2 * count;
  double *velocity = malloc(length * sizeof *velocity);
  if (status == GM_OK && velocity == NULL)
    status = GM_ERR_NO_MEMORY;
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_VELOCITY, velocity, length);
  if (status != GM_OK) {
    fprintf(stderr, "%s: %s\n", gm_strerror(status),
            gm_domain_last_error(domain));
    free(velocity);
    gm_domain_destroy(domain);
    return 1;
  }

  double mean_vy = 0.0; /* m/s */
  for (size_t i = 0; i < count; i++)
    mean_vy += velocity[2 * i + 1] / (double)count;
  double time = 0.0; /* s */
  uint64_t steps = 0;
  gm_domain_get_time(domain, &time, &steps);
  printf("%zu points, %llu steps, t = %g s, mean v_y = %g m/s\n", count,
         (unsigned long long)steps, time, mean_vy);
  free(velocity);
  gm_domain_destroy(domain);
  return 0;
}
