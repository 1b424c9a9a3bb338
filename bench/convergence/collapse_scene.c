/*
 * collapse_scene.c - the planar column collapse shared by the convergence
 * probes (see collapse_scene.h).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "collapse_scene.h"

#include "collapse_laws.h"
#include "collapse_material.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

double collapse_scene_height(const collapse_scene *scene) {
  return scene->aspect * scene->length;
}

double collapse_scene_tau(const collapse_scene *scene) {
  return sqrt(collapse_scene_height(scene) / COLLAPSE_GRAVITY);
}

double collapse_scene_law_runout(double aspect) {
  return lube2005_runout(aspect);
}

double collapse_scene_law_height(double aspect) {
  return lube2005_final_height(aspect);
}

gm_domain_def collapse_scene_domain_def(const collapse_scene *scene) {
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = scene->cell;
  def.shape = scene->shape;
  def.family = scene->family;
  def.worker_count = scene->workers;
  if (scene->cfl > 0.0)
    def.cfl = scene->cfl;
  /* examples/column_collapse size_scene: room for twice Lube et al.'s
   * (2005) run-out beyond the column */
  double height = collapse_scene_height(scene);
  double law = collapse_scene_law_runout(scene->aspect);
  def.extent[0] = scene->length * (2.0 + 2.0 * law);
  def.extent[1] = 1.25 * height + 4.0 * scene->cell;
  def.gravity[1] = -COLLAPSE_GRAVITY;
  if (strcmp(scene->floor, "face") == 0)
    def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  else if (strcmp(scene->floor, "slip") == 0)
    def.walls[GM_FACE_YMIN] = GM_WALL_SLIP;
  return def;
}

gm_status collapse_scene_set_granular(gm_domain *domain,
                                      const collapse_scene *scene,
                                      int material) {
  if (scene->family == GM_FAMILY_PLAIN)
    return GM_OK;
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = COLLAPSE_CRITICAL_RATIO * COLLAPSE_DENSITY;
  return gm_domain_set_granular(domain, material, &granular);
}

static gm_status add_wall(gm_domain *domain, double normal_x, double normal_y,
                          double friction, int *wall_id) {
  gm_wall_def wall = gm_wall_def_default();
  wall.normal[0] = normal_x;
  wall.normal[1] = normal_y;
  wall.friction_static = wall.friction_kinetic = friction;
  return gm_domain_add_wall(domain, &wall, wall_id);
}

gm_status collapse_scene_add_walls(gm_domain *domain,
                                   const collapse_scene *scene,
                                   int *floor_wall) {
  *floor_wall = -1;
  if (strcmp(scene->floor, "wall") == 0) {
    gm_status status = add_wall(domain, 0.0, 1.0, scene->floor_mu, floor_wall);
    if (status != GM_OK)
      return status;
  }
  int back_wall = -1;
  return add_wall(domain, 1.0, 0.0, 0.0, &back_wall);
}

gm_status collapse_scene_fill(gm_domain *domain, const collapse_scene *scene,
                              int material) {
  gm_fill_def fill = gm_fill_def_default();
  fill.points_per_cell_axis = scene->ppc;
  fill.material = material;
  fill.upper[0] = scene->length;
  fill.upper[1] = collapse_scene_height(scene);
  return gm_domain_fill_box(domain, &fill, NULL, NULL);
}

size_t collapse_scene_columns(const collapse_scene *scene) {
  gm_domain_def def = collapse_scene_domain_def(scene);
  return (size_t)ceil(def.extent[0] / scene->cell) + 2;
}

double collapse_scene_connected_limit(const collapse_scene *scene,
                                      const double *positions, size_t count,
                                      unsigned char *occupied) {
  size_t columns = collapse_scene_columns(scene);
  double cell = scene->cell;
  memset(occupied, 0, columns);
  for (size_t i = 0; i < count; i++) {
    double column = floor(positions[2 * i] / cell);
    if (column >= 0.0 && column < (double)columns)
      occupied[(size_t)column] = 1;
  }
  size_t first_empty = 0;
  while (first_empty < columns && occupied[first_empty])
    first_empty++;
  return (double)first_empty * cell;
}

double collapse_scene_front(const collapse_scene *scene,
                            const double *positions, size_t count,
                            unsigned char *occupied) {
  double half = 0.5 * scene->cell / scene->ppc;
  double limit =
      collapse_scene_connected_limit(scene, positions, count, occupied);
  double front = 0.0;
  for (size_t i = 0; i < count; i++)
    if (positions[2 * i] < limit)
      front = fmax(front, positions[2 * i] + half);
  return front;
}

/* The cone matched to Mohr-Coulomb's flowing friction in plane strain:
 * examples/collapse_material.h (docs/convergence.md sec. 10). */
double collapse_scene_dp_friction(double friction) {
  return collapse_matched_cone_friction(friction);
}

int collapse_scene_fail(const gm_domain *domain, const char *what,
                        gm_status status) {
  fprintf(stderr, "%s: %s (%s)\n", what, gm_strerror(status),
          domain ? gm_domain_last_error(domain) : gm_last_create_error());
  return 1;
}
