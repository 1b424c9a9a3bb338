/*
 * checkpoint_load.c - gm_domain_load: the file is read whole and checked
 * (header and checksum, setup, then the consistency of counts, ids,
 * materials and positions, so that even a file with a valid checksum
 * cannot make the library index out of bounds), memory is reserved, and
 * only then is the domain's state replaced. Every refusal therefore leaves
 * the domain as it was. The payload layout is in checkpoint.c.
 */
#include "io/io.h"

#include "io/checkpoint_format.h"

#include <limits.h>
#include <math.h>
#include <string.h>

/* A checkpoint's state, decoded but not yet applied: numbers by value,
 * arrays as (unaligned) pointers into the file. */
typedef struct loaded_state {
  double time; /* s */
  uint64_t step_count;
  double max_signal_speed; /* m/s */
  int64_t steps_since_reorder;
  bool velocity_edited, inputs_edited;
  size_t count; /* points */
  int64_t next_id;
  const unsigned char *array[GM_CHECKPOINT_MAX_ARRAYS];
  bool external; /* external forces were allocated */
  const unsigned char *external_force[3];
  const unsigned char *index_of_id;
  gm_source sources[GM_MAX_SOURCES];          /* clocks and totals only */
  gm_sink sinks[GM_MAX_SOURCES];              /* totals only */
  double rigid_velocity[GM_MAX_MATERIALS][3]; /* m/s (z: 3D) */
  gm_force_report rigid_report[GM_MAX_MATERIALS];
  gm_force_report wall_report[GM_MAX_WALLS];
  double force_smoothing_time; /* s */
  gm_granular_summary summary;
  uint32_t version; /* the file's format version */
} loaded_state;

/* --------------------------------------------------------------- decode */

static void read_clock(gm_byte_reader *in, loaded_state *state) {
  state->time = gm_reader_f64(in);
  state->step_count = gm_reader_u64(in);
  state->max_signal_speed = gm_reader_f64(in);
  state->steps_since_reorder = gm_reader_i64(in);
  state->velocity_edited = gm_reader_u8(in) != 0;
  state->inputs_edited = gm_reader_u8(in) != 0;
  uint64_t count = gm_reader_u64(in);
  state->next_id = gm_reader_i64(in);
  /* Each point takes at least 8 bytes and each id 4, so larger counts
   * cannot be real; this also keeps the byte counts below from
   * overflowing. */
  size_t room = in->size - in->offset;
  if (count > room / 8 || count > (uint64_t)INT_MAX - 1 ||
      state->next_id < (int64_t)count || (uint64_t)state->next_id > room / 4)
    in->failed = true;
  state->count = in->failed ? 0 : (size_t)count;
}

static void read_points(gm_byte_reader *in, const gm_domain *domain,
                        loaded_state *state) {
  gm_array_slot slots[GM_CHECKPOINT_MAX_ARRAYS];
  size_t slot_count = gm_checkpoint_point_arrays(domain, state->version, slots);
  for (size_t k = 0; k < slot_count; k++)
    state->array[k] =
        gm_reader_array(in, state->count * slots[k].bytes_per_point);
  state->external = gm_reader_u8(in) != 0;
  for (int k = 0; state->external && k < domain->dim; k++)
    state->external_force[k] =
        gm_reader_array(in, state->count * sizeof(double));
  if (in->failed)
    return;
  state->index_of_id =
      gm_reader_array(in, (size_t)state->next_id * sizeof(uint32_t));
}

/* As checkpoint.c writes it: z last, for the walls and rigid materials of
 * a 3D domain. */
static void read_force_report(gm_byte_reader *in, bool solid,
                              gm_force_report *report) {
  *report = (gm_force_report){0};
  for (int k = 0; k < 2; k++) {
    report->impulse[k] = gm_reader_f64(in);
    report->force[k] = gm_reader_f64(in);
    report->total_impulse[k] = gm_reader_f64(in);
    report->smoothed_force[k] = gm_reader_f64(in);
  }
  report->duration = gm_reader_f64(in);
  report->total_duration = gm_reader_f64(in);
  if (!solid)
    return;
  report->impulse[2] = gm_reader_f64(in);
  report->force[2] = gm_reader_f64(in);
  report->total_impulse[2] = gm_reader_f64(in);
  report->smoothed_force[2] = gm_reader_f64(in);
}

static void read_totals(gm_byte_reader *in, const gm_domain *domain,
                        loaded_state *state) {
  for (int s = 0; s < domain->source_count; s++) {
    gm_source *source = &state->sources[s];
    source->next_time = gm_reader_f64(in);
    int64_t left = gm_reader_i64(in);
    if (left < -1 || left > INT_MAX)
      in->failed = true;
    source->injections_left = (int)left;
    source->injected_mass = gm_reader_f64(in);
    source->injected_points = gm_reader_u64(in);
  }
  for (int s = 0; s < domain->sink_count; s++) {
    state->sinks[s].removed_mass = gm_reader_f64(in);
    state->sinks[s].removed_points = gm_reader_u64(in);
  }
  for (int m = 0; m < domain->material_count; m++) {
    /* As checkpoint.c writes it: z for a rigid material in 3D (its rigid
     * flag is part of the material record the setup compared). */
    bool solid = domain->dim == 3 && domain->materials[m].rigid;
    state->rigid_velocity[m][2] = 0.0;
    for (int k = 0; k < (solid ? 3 : 2); k++)
      state->rigid_velocity[m][k] = gm_reader_f64(in);
    read_force_report(in, solid, &state->rigid_report[m]);
  }
  for (int w = 0; w < domain->wall_count; w++)
    read_force_report(in, domain->dim == 3, &state->wall_report[w]);
  state->force_smoothing_time = gm_reader_f64(in);
  if (!(state->force_smoothing_time > 0.0) ||
      !isfinite(state->force_smoothing_time))
    in->failed = true;
  gm_granular_summary *summary = &state->summary;
  *summary = gm_granular_summary_default();
  for (int k = 0; k < 3; k++)
    summary->state_count[k] = (size_t)gm_reader_u64(in);
  summary->component_count = (size_t)gm_reader_u64(in);
  summary->layer_count = (size_t)gm_reader_u64(in);
  summary->forest_reused = (int)gm_reader_i64(in);
  summary->geometry_seconds = gm_reader_f64(in);
  summary->pair_search_seconds = gm_reader_f64(in);
  summary->label_seconds = gm_reader_f64(in);
  summary->layer_seconds = gm_reader_f64(in);
  summary->density_control_seconds = gm_reader_f64(in);
}

/* ------------------------------------------------------------- validate */

static double real_at(const unsigned char *bytes, size_t index) {
  double value;
  memcpy(&value, bytes + index * sizeof value, sizeof value);
  return value;
}

static bool valid_reals(const unsigned char *bytes, size_t values,
                        gm_array_check check) {
  for (size_t i = 0; i < values; i++) {
    double value = real_at(bytes, i);
    if (!isfinite(value) || (check == GM_CHECK_POSITIVE && !(value > 0.0)))
      return false;
  }
  return true;
}

/* The granular state or parallel-grid label of every point is a small
 * integer the library writes: a gm_point_state, or a label below the point
 * count (components are numbered from 0 and each holds a point). Memory
 * holds them as bytes and int32 (core/domain_points.h), so nothing else
 * converts exactly. */
static bool valid_small_integers(const unsigned char *bytes, size_t count,
                                 gm_array_check check) {
  double limit = check == GM_CHECK_GRANULAR_STATE ? GM_STATE_DISCONNECTED
                                                  : (double)count - 1.0;
  for (size_t i = 0; i < count; i++) {
    double value = real_at(bytes, i);
    if (!(value >= 0.0 && value <= limit && value == floor(value)))
      return false;
  }
  return true;
}

/* Point i's position is finite, inside the grid box, off the axis. */
static bool valid_position(const gm_domain *domain, const loaded_state *state,
                           size_t i) {
  /* The positions are the first dim arrays (gm_checkpoint_point_arrays). */
  double xyz[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < domain->dim; k++)
    xyz[k] = real_at(state->array[k], i);
  int64_t key;
  return gm_block_key_of(domain, xyz, &key) &&
         (!domain->axisymmetric || xyz[0] > 0.0);
}

/* The 2x2 tensors in slots first..first+3 (F_XX, F_XY, F_YX, F_YY), times
 * slot first+4 when with_hoop (axisymmetry's F_ZZ), have a positive
 * determinant at every point. A step never leaves an inverted F or CPDI
 * map behind (g2p.c refuses det F <= 0), so a file holding one was not
 * written by the library, and a domain loaded from it could never step. */
static bool valid_jacobians(const loaded_state *state, size_t first,
                            bool with_hoop) {
  for (size_t i = 0; i < state->count; i++) {
    double xx = real_at(state->array[first + F_XX], i);
    double xy = real_at(state->array[first + F_XY], i);
    double yx = real_at(state->array[first + F_YX], i);
    double yy = real_at(state->array[first + F_YY], i);
    double det = xx * yy - xy * yx;
    if (with_hoop)
      det *= real_at(state->array[first + F_ZZ], i);
    if (!(det > 0.0 && isfinite(det)))
      return false;
  }
  return true;
}

/* The 3x3 F of 3D in slots first..first+8 (F_XX..F_ZY, core.h) has a
 * positive determinant at every point, as g2p_3d.c leaves it. */
static bool valid_jacobians_3d(const loaded_state *state, size_t first) {
  /* Slot of F_ij, row-major. */
  static const int slot[9] = {F_XX, F_XY, F_XZ, F_YX, F_YY,
                              F_YZ, F_ZX, F_ZY, F_ZZ};
  for (size_t i = 0; i < state->count; i++) {
    double f[9];
    for (int c = 0; c < 9; c++)
      f[c] = real_at(state->array[first + (size_t)slot[c]], i);
    double det = f[0] * (f[4] * f[8] - f[5] * f[7]) -
                 f[1] * (f[3] * f[8] - f[5] * f[6]) +
                 f[2] * (f[3] * f[7] - f[4] * f[6]);
    if (!(det > 0.0 && isfinite(det)))
      return false;
  }
  return true;
}

/* Ids and the id -> index map must be each other's inverse. */
static bool valid_ids(const loaded_state *state, const unsigned char *ids) {
  uint32_t index;
  int64_t id;
  for (size_t i = 0; i < state->count; i++) {
    memcpy(&id, ids + i * sizeof id, sizeof id);
    if (id < 0 || id >= state->next_id)
      return false;
    memcpy(&index, state->index_of_id + (size_t)id * sizeof index,
           sizeof index);
    if (index != i)
      return false;
  }
  for (int64_t j = 0; j < state->next_id; j++) {
    memcpy(&index, state->index_of_id + (size_t)j * sizeof index, sizeof index);
    if (index == GM_REMOVED_POINT)
      continue;
    if (index >= state->count)
      return false;
    memcpy(&id, ids + (size_t)index * sizeof id, sizeof id);
    if (id != j)
      return false;
  }
  return true;
}

static bool valid_materials(const gm_domain *domain, const loaded_state *state,
                            const unsigned char *materials) {
  for (size_t i = 0; i < state->count; i++) {
    int32_t material;
    memcpy(&material, materials + i * sizeof material, sizeof material);
    if (material < 0 || material >= domain->material_count)
      return false;
  }
  return true;
}

/* Name of the first array that fails its check, or NULL if all pass. */
static const char *first_invalid(const gm_domain *domain,
                                 const loaded_state *state) {
  gm_array_slot slots[GM_CHECKPOINT_MAX_ARRAYS];
  size_t slot_count = gm_checkpoint_point_arrays(domain, state->version, slots);
  for (size_t k = 0; k < slot_count; k++) {
    const unsigned char *bytes = state->array[k];
    size_t values = state->count * slots[k].bytes_per_point / sizeof(double);
    switch (slots[k].check) {
    case GM_CHECK_FINITE:
    case GM_CHECK_POSITIVE:
      if (!valid_reals(bytes, values, slots[k].check))
        return "a non-finite or non-positive point value";
      break;
    case GM_CHECK_DEFORMATION:
    case GM_CHECK_DOMAIN_MAP:
      if (!valid_reals(bytes, values, GM_CHECK_FINITE))
        return "a non-finite or non-positive point value";
      /* F_ZZ follows F_YY in axisymmetry, all nine of F or D in 3D
       * (gm_checkpoint_point_arrays). */
      if (!(domain->dim == 3
                ? valid_jacobians_3d(state, k)
                : valid_jacobians(state, k,
                                  slots[k].check == GM_CHECK_DEFORMATION &&
                                      domain->axisymmetric)))
        return slots[k].check == GM_CHECK_DEFORMATION
                   ? "an inverted deformation gradient (det F <= 0)"
                   : "an inverted CPDI domain (det <= 0)";
      break;
    case GM_CHECK_INPUT: /* host-written values are screened by the step */
      if (!state->inputs_edited && !valid_reals(bytes, values, GM_CHECK_FINITE))
        return "a non-finite velocity";
      break;
    case GM_CHECK_POSITION:
      for (size_t i = 0; k == 0 && i < state->count; i++)
        if (!valid_position(domain, state, i))
          return "a point outside the grid box";
      break;
    case GM_CHECK_ID:
      if (!valid_ids(state, bytes))
        return "point ids that do not match the id map";
      break;
    case GM_CHECK_MATERIAL:
      if (!valid_materials(domain, state, bytes))
        return "an unknown material id";
      break;
    case GM_CHECK_GRANULAR_STATE:
    case GM_CHECK_LABEL:
      if (!valid_small_integers(bytes, state->count, slots[k].check))
        return slots[k].check == GM_CHECK_GRANULAR_STATE
                   ? "a granular state that is not a gm_point_state"
                   : "a parallel-grid label that is not an integer below "
                     "the point count";
      break;
    case GM_CHECK_NONE:
      break;
    }
  }
  return NULL;
}

/* --------------------------------------------------------------- apply */

/* Room for the loaded points; on failure the domain's state is as before
 * (only capacities may have grown). */
static gm_status reserve_for(gm_domain *domain, const loaded_state *state) {
  gm_points *points = &domain->points;
  if (gm_points_reserve(domain, state->count) != GM_OK)
    return GM_ERR_NO_MEMORY;
  size_t ids = (size_t)state->next_id;
  if (ids > points->id_capacity) {
    void *map = points->index_of_id;
    if (!gm_grow(&map, sizeof(uint32_t), points->id_capacity, ids))
      return GM_ERR_NO_MEMORY;
    points->index_of_id = map;
    points->id_capacity = ids;
  }
  if (!state->external || points->external_force[0])
    return GM_OK;
  if (gm_points_need_external_force(domain) == GM_OK)
    return GM_OK;
  for (int k = 0; k < 3; k++) { /* all components or none */
    gm_free(points->external_force[k]);
    points->external_force[k] = NULL;
  }
  return GM_ERR_NO_MEMORY;
}

static void copy_bytes(void *to, const unsigned char *from, size_t size) {
  if (size > 0)
    memcpy(to, from, size);
}

static void apply_points(gm_domain *domain, const loaded_state *state) {
  gm_points *points = &domain->points;
  gm_array_slot slots[GM_CHECKPOINT_MAX_ARRAYS];
  size_t slot_count = gm_checkpoint_point_arrays(domain, state->version, slots);
  for (size_t k = 0; k < slot_count; k++) {
    if (slots[k].form == GM_FORM_RAW) {
      copy_bytes(slots[k].data, state->array[k],
                 state->count * slots[k].bytes_per_point);
      continue;
    }
    /* Small integers as doubles (checked by valid_small_integers). */
    for (size_t i = 0; i < state->count; i++) {
      double value = real_at(state->array[k], i);
      if (slots[k].form == GM_FORM_BYTE)
        ((uint8_t *)slots[k].data)[i] = (uint8_t)value;
      else
        ((int32_t *)slots[k].data)[i] = (int32_t)value;
    }
  }
  for (int k = 0; k < domain->dim; k++) {
    if (state->external) {
      copy_bytes(points->external_force[k], state->external_force[k],
                 state->count * sizeof(double));
    } else { /* as in the saved run: no external-force pass at all */
      gm_free(points->external_force[k]);
      points->external_force[k] = NULL;
    }
  }
  copy_bytes(points->index_of_id, state->index_of_id,
             (size_t)state->next_id * sizeof(uint32_t));
  points->count = state->count;
  points->next_id = state->next_id;
  points->keys_valid = false; /* the next binning keys the positions */
}

static void apply_totals(gm_domain *domain, const loaded_state *state) {
  for (int s = 0; s < domain->source_count; s++) {
    gm_source *source = &domain->sources[s];
    source->next_time = state->sources[s].next_time;
    source->injections_left = state->sources[s].injections_left;
    source->injected_mass = state->sources[s].injected_mass;
    source->injected_points = state->sources[s].injected_points;
  }
  for (int s = 0; s < domain->sink_count; s++) {
    domain->sinks[s].removed_mass = state->sinks[s].removed_mass;
    domain->sinks[s].removed_points = state->sinks[s].removed_points;
  }
  for (int m = 0; m < domain->material_count; m++) {
    for (int k = 0; k < 3; k++)
      domain->materials[m].rigid_velocity[k] = state->rigid_velocity[m][k];
    domain->materials[m].rigid_report = state->rigid_report[m];
  }
  for (int w = 0; w < domain->wall_count; w++)
    domain->wall_report[w] = state->wall_report[w];
  domain->force_smoothing_time = state->force_smoothing_time;
  domain->granular_summary = state->summary;
}

/* A 3D CPDI file of a version without the domain map (format version 2):
 * its domains followed F, so D starts as F and the run continues as it
 * would have (to the first reset). */
static void start_domain_map_at_f(gm_domain *domain,
                                  const loaded_state *state) {
  gm_point_buffers *b = &domain->points.buffer[domain->points.cur];
  if (domain->dim < 3 || !b->domain_map[0] ||
      state->version >= GM_CHECKPOINT_3D_MAP)
    return;
  for (int k = 0; k < GM_F_SLOTS; k++)
    copy_bytes(b->domain_map[k], (const unsigned char *)b->deformation[k],
               state->count * sizeof(double));
}

static void apply(gm_domain *domain, const loaded_state *state) {
  apply_points(domain, state);
  start_domain_map_at_f(domain, state);
  apply_totals(domain, state);
  domain->time = state->time;
  domain->step_count = state->step_count;
  domain->max_signal_speed = state->max_signal_speed;
  domain->steps_since_reorder = (int)state->steps_since_reorder;
  domain->velocity_edited = state->velocity_edited;
  domain->inputs_edited = state->inputs_edited;
  /* Caches of the last step that the file does not hold, all tied to
   * the old points' indices: the forest only speeds up the next search,
   * the interaction boxes are recomputed, the traction profile returns
   * with the next step. */
  domain->granular.forest_valid = false;
  domain->granular.boxes_valid = false;
  domain->wall_profile_valid = false;
}

/* ------------------------------------------------------------ the call */

/* Compares the file's setup section with the domain's own description. */
static gm_status check_setup(gm_domain *domain, const char *path,
                             gm_byte_reader *in) {
  size_t size = 0;
  const unsigned char *records = gm_reader_any_array(in, &size);
  if (!records)
    return gm_set_error(domain, GM_ERR_IO,
                        "gm_domain_load: '%s' is corrupted (setup section)",
                        path);
  gm_byte_writer own = {0};
  gm_checkpoint_describe_setup(domain, &own);
  char difference[GM_ERROR_MESSAGE_SIZE / 2];
  gm_status status = GM_OK;
  if (own.failed)
    status = gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "gm_domain_load: out of memory reading '%s'", path);
  else if (!gm_records_equal(records, size, own.data, own.size, difference,
                             sizeof difference))
    status = gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_load: '%s' was saved from another setup: "
                          "%s",
                          path, difference);
  gm_writer_free(&own);
  return status;
}

/* Decodes and checks the state; GM_OK leaves it ready to apply. */
static gm_status decode(gm_domain *domain, const char *path, gm_byte_reader *in,
                        loaded_state *state) {
  read_clock(in, state);
  if (!in->failed)
    read_points(in, domain, state);
  if (!in->failed)
    read_totals(in, domain, state);
  if (in->failed || in->offset != in->size)
    return gm_set_error(domain, GM_ERR_IO,
                        "gm_domain_load: '%s' is corrupted: its contents do "
                        "not fit its setup",
                        path);
  const char *problem = first_invalid(domain, state);
  if (problem)
    return gm_set_error(domain, GM_ERR_IO,
                        "gm_domain_load: '%s' is corrupted: it holds %s", path,
                        problem);
  return GM_OK;
}

gm_status gm_domain_load(gm_domain *domain, const char *path) {
  if (!domain)
    return GM_ERR_NULL;
  if (!path)
    return gm_set_error(domain, GM_ERR_NULL, "gm_domain_load: path is NULL");
  if (domain->busy)
    return gm_set_error(domain, GM_ERR_BUSY,
                        "gm_domain_load: called during a step");
  unsigned char *file = NULL;
  gm_byte_reader in;
  uint32_t version = 0;
  gm_status status =
      gm_checkpoint_read_file(domain, path, &file, &in, &version);
  if (status != GM_OK)
    return status;
  /* About 14 kB of totals: off the stack, an embedding code's threads
   * may have small ones. */
  loaded_state *state = gm_calloc(1, sizeof *state);
  if (!state)
    status = gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "gm_domain_load: out of memory reading '%s'", path);
  if (status == GM_OK) {
    state->version = version;
    status = check_setup(domain, path, &in);
  }
  if (status == GM_OK)
    status = decode(domain, path, &in, state);
  if (status == GM_OK && reserve_for(domain, state) != GM_OK)
    status = gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "gm_domain_load: out of memory for the %zu points "
                          "of '%s'",
                          state->count, path);
  if (status == GM_OK)
    apply(domain, state);
  gm_free(state);
  gm_free(file);
  return status;
}
