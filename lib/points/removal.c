/*
 * removal.c - taking points out of the domain: compaction of every
 * per-point array of the committed state (order kept, so points stay
 * sorted by block), and truncation back to an earlier count (undoing an
 * injection). Removed ids map to GM_REMOVED_POINT and are never reused,
 * so every other id still finds its point.
 */
#include "points/points.h"

#include <string.h>

/* Moves element `from` of an array of `size`-byte elements to `to`. */
static void move_element(void *array, size_t size, size_t to, size_t from) {
  if (array && to != from)
    memcpy((char *)array + to * size, (char *)array + from * size, size);
}

static void move_point(gm_domain *domain, size_t to, size_t from) {
  gm_points *points = &domain->points;
  gm_point_buffers *buffer = &points->buffer[points->cur];
  for (int k = 0; k < 3; k++) {
    move_element(buffer->position[k], sizeof(double), to, from);
    move_element(buffer->velocity[k], sizeof(double), to, from);
    move_element(points->domain_size[k], sizeof(double), to, from);
    move_element(points->external_force[k], sizeof(double), to, from);
  }
  for (int k = 0; k < GM_STRESS_SLOTS; k++) /* NULL slots: skipped */
    move_element(buffer->stress[k], sizeof(double), to, from);
  for (int k = 0; k < GM_F_SLOTS; k++)
    move_element(buffer->deformation[k], sizeof(double), to, from);
  for (int k = 0; k < GM_F_SLOTS; k++) /* CPDI: 4 slots, 9 in 3D */
    move_element(buffer->domain_map[k], sizeof(double), to, from);
  move_element(buffer->volume, sizeof(double), to, from);
  move_element(buffer->granular_state, sizeof(uint8_t), to, from);
  move_element(buffer->component, sizeof(int32_t), to, from);
  for (int k = 0; k < GM_AFFINE_STORED; k++)
    move_element(buffer->affine[k], sizeof(double), to, from);
  if (points->state_stride)
    move_element(buffer->state, points->state_stride * sizeof(double), to,
                 from);
  move_element(points->mass, sizeof(double), to, from);
  move_element(points->initial_volume, sizeof(double), to, from);
  move_element(points->id, sizeof(int64_t), to, from);
  move_element(points->material, sizeof(int32_t), to, from);
}

void gm_points_remove(gm_domain *domain, const uint32_t *flags) {
  gm_points *points = &domain->points;
  domain->granular.forest_valid = false; /* indices change */
  domain->granular.boxes_valid = false;
  size_t kept = 0;
  for (size_t i = 0; i < points->count; i++) {
    if (flags[i]) {
      points->index_of_id[points->id[i]] = GM_REMOVED_POINT;
      continue;
    }
    move_point(domain, kept, i);
    points->index_of_id[points->id[kept]] = (uint32_t)kept;
    kept++;
  }
  if (kept == points->count)
    return;
  points->count = kept;
  points->keys_valid = false;
  gm_recompute_signal_speed(domain);
}

void gm_points_truncate(gm_domain *domain, size_t count, int64_t next_id) {
  gm_points *points = &domain->points;
  domain->granular.forest_valid = false; /* may name dropped points */
  domain->granular.boxes_valid = false;
  points->count = count;
  points->next_id = next_id;
  points->keys_valid = false;
  gm_recompute_signal_speed(domain);
}
