/*
 * fuzz/fuzz_api.c - libFuzzer harness: API call sequences with hostile
 * arguments. The input is a program: a domain definition with fields
 * overwritten by raw values (enums out of range, NaN sizes, negative
 * cells), then a sequence of calls (materials, points, fills, walls,
 * sources, steps, field access, removal) whose arguments come from the
 * input too. Besides the sanitizers' findings (any crash, overflow, leak
 * or undefined behaviour), it aborts where the library breaks a promise
 * of granmpm(3): a failed call must leave a message, and a failed step
 * must leave the domain as it was (time, step count, points).
 *
 * Bounded so that one input runs in milliseconds: at most 64 calls, 32
 * steps, and fills estimated above 20 000 points are skipped (a hostile
 * but valid box could ask for billions, which is the host's memory, not
 * a defect).
 *
 * Build and run: `make fuzz` (docs: fuzz/README.md).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>
#include <granmpm/mohr_coulomb.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"

enum { MAX_CALLS = 64, MAX_STEPS = 32, MAX_POINTS = 64 };
static const double MAX_FILL_POINTS = 20000.0;

/* Aborts with the reason: libFuzzer records the input. */
static void broken(const char *promise, const gm_domain *domain) {
  fprintf(stderr, "broken promise: %s (%s)\n", promise,
          domain ? gm_domain_last_error(domain) : gm_last_create_error());
  abort();
}

static void expect_message(gm_status status, const gm_domain *domain) {
  if (status == GM_OK)
    return;
  const char *message = gm_domain_last_error(domain);
  if (!message || !message[0])
    broken("a failed call leaves a message", domain);
  if (!gm_strerror(status))
    broken("every status has a name", domain);
}

static void read_def(fuzz_input *in, gm_domain_def *def) {
  /* A sane start, then up to eight hostile fields. */
  def->extent[0] = def->extent[1] = 1.0;
  def->cell_size = 0.1;
  def->gravity[1] = -9.81;
  int edits = fuzz_u8(in) % 9;
  for (int e = 0; e < edits; e++) {
    switch (fuzz_u8(in) % 14) {
    case 0:
      def->geometry = (gm_geometry)fuzz_u32(in);
      break;
    case 1:
      def->extent[fuzz_u8(in) % 3] = fuzz_double(in);
      break;
    case 2:
      def->origin[fuzz_u8(in) % 3] = fuzz_double(in);
      break;
    case 3:
      def->cell_size = fuzz_double(in);
      break;
    case 4:
      def->gravity[fuzz_u8(in) % 3] = fuzz_double(in);
      break;
    case 5:
      def->scheme = (gm_update_scheme)fuzz_u32(in);
      break;
    case 6:
      def->walls[fuzz_u8(in) % 6] = (gm_wall_type)fuzz_u32(in);
      break;
    case 7:
      def->cfl = fuzz_double(in);
      break;
    case 8:
      def->max_retries = (int)fuzz_u32(in);
      break;
    /* Valid worker counts stay at 1-2: threads are the pool's, and 256
     * of them per input would only slow the fuzzer down. */
    case 9:
      def->worker_count = (int)(fuzz_u8(in) % 4) - 1;
      break;
    case 10:
      def->shape = (gm_shape)fuzz_u32(in);
      break;
    case 11:
      def->family = (gm_family)fuzz_u32(in);
      break;
    case 12:
      def->pic_fraction = fuzz_double(in);
      break;
    default:
      def->damping = fuzz_double(in);
      break;
    }
  }
  /* The grid is sparse, so a huge box is legal; a fill in it is bounded
   * below. */
}

static void add_material(fuzz_input *in, gm_domain *domain) {
  int id = -1;
  gm_status status;
  if (fuzz_u8(in) & 1) {
    gm_elastic_def def = gm_elastic_def_default();
    def.youngs_modulus = fuzz_u8(in) & 1 ? fuzz_double(in) : 1e5;
    def.poisson_ratio = fuzz_u8(in) & 1 ? fuzz_double(in) : 0.3;
    def.density = fuzz_u8(in) & 1 ? fuzz_double(in) : 1000.0;
    status = gm_domain_add_elastic(domain, &def, &id);
  } else {
    gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
    def.youngs_modulus = 1e6;
    if (fuzz_u8(in) & 1)
      def.friction_angle = fuzz_double(in);
    if (fuzz_u8(in) & 1)
      def.density = fuzz_double(in);
    status = gm_domain_add_mohr_coulomb(domain, &def, &id);
  }
  expect_message(status, domain);
  if (status == GM_OK && (fuzz_u8(in) & 1)) {
    gm_granular_def granular = gm_granular_def_default();
    granular.critical_density = fuzz_double(in);
    expect_message(gm_domain_set_granular(domain, id, &granular), domain);
  }
}

static void fill_box(fuzz_input *in, gm_domain *domain, double cell) {
  gm_fill_def def = gm_fill_def_default();
  def.material = (int)(fuzz_u8(in) % 4) - 1;
  for (int k = 0; k < 2; k++) {
    def.lower[k] = fuzz_double(in);
    def.upper[k] = fuzz_double(in);
    def.velocity[k] = fuzz_u8(in) & 1 ? fuzz_double(in) : 0.0;
  }
  def.points_per_cell_axis = (int)(fuzz_u8(in) % 20) - 1;
  double n = def.points_per_cell_axis / cell;
  double estimate = fabs((def.upper[0] - def.lower[0]) * n) *
                    fabs((def.upper[1] - def.lower[1]) * n);
  if (!(estimate <= MAX_FILL_POINTS))
    return;
  expect_message(gm_domain_fill_box(domain, &def, NULL, NULL), domain);
}

static void add_points(fuzz_input *in, gm_domain *domain) {
  double position[2 * MAX_POINTS], volume[MAX_POINTS], velocity[2 * MAX_POINTS];
  size_t count = fuzz_u8(in) % (MAX_POINTS + 1);
  for (size_t i = 0; i < count; i++) {
    position[2 * i] = fuzz_double(in);
    position[2 * i + 1] = fuzz_double(in);
    volume[i] = fuzz_u8(in) & 1 ? fuzz_double(in) : 0.0025;
    velocity[2 * i] = velocity[2 * i + 1] = fuzz_double(in);
  }
  gm_points_def def = gm_points_def_default();
  def.material = (int)(fuzz_u8(in) % 4) - 1;
  def.count = count;
  def.position = position;
  def.volume = volume;
  def.velocity = fuzz_u8(in) & 1 ? velocity : NULL;
  expect_message(gm_domain_add_points(domain, &def, NULL), domain);
}

static void add_wall(fuzz_input *in, gm_domain *domain) {
  gm_wall_def def = gm_wall_def_default();
  def.point[1] = fuzz_double(in);
  def.normal[0] = fuzz_double(in);
  def.normal[1] = fuzz_double(in);
  def.friction_static = fuzz_double(in);
  def.friction_kinetic = fuzz_double(in);
  int id = -1;
  int *wall_id = fuzz_u8(in) & 1 ? &id : NULL; /* NULL must be refused */
  expect_message(gm_domain_add_wall(domain, &def, wall_id), domain);
}

/* A step that fails must leave time, step count and points as they were
 * (granmpm(3), "a failed step leaves the domain as it was"). */
static void step(fuzz_input *in, gm_domain *domain) {
  double time_before = 0.0, time_after = 0.0, dt = 0.0;
  uint64_t steps_before = 0, steps_after = 0;
  if (gm_domain_get_time(domain, &time_before, &steps_before) != GM_OK)
    broken("get_time on a live domain", domain);
  size_t points_before = gm_domain_point_count(domain);
  if (fuzz_u8(in) & 1) {
    gm_status status = gm_domain_stable_dt(domain, &dt);
    expect_message(status, domain);
  } else {
    dt = fuzz_double(in);
  }
  gm_status status = gm_domain_step(domain, dt);
  expect_message(status, domain);
  if (gm_domain_get_time(domain, &time_after, &steps_after) != GM_OK)
    broken("get_time on a live domain", domain);
  if (status != GM_OK &&
      (memcmp(&time_after, &time_before, sizeof time_after) != 0 ||
       steps_after != steps_before ||
       gm_domain_point_count(domain) != points_before))
    broken("a failed step leaves the domain as it was", domain);
}

/* gm_domain_set_field with the values just read, one of them replaced by
 * a hostile double: a refused call must leave the field as it was. */
static void write_field(fuzz_input *in, gm_domain *domain, gm_field field,
                        double *values, size_t length) {
  double *before = malloc(length * sizeof *before);
  if (!before)
    return;
  memcpy(before, values, length * sizeof *before);
  values[fuzz_u32(in) % length] = fuzz_double(in);
  gm_status status = gm_domain_set_field(domain, field, values, length);
  expect_message(status, domain);
  if (status != GM_OK &&
      gm_domain_get_field(domain, field, values, length) == GM_OK &&
      memcmp(values, before, length * sizeof *before) != 0)
    broken("a refused gm_domain_set_field leaves the field as it was", domain);
  free(before);
}

static void read_fields(fuzz_input *in, gm_domain *domain) {
  gm_field field = (gm_field)(fuzz_u8(in) % 18);
  size_t components = 0, count = gm_domain_point_count(domain);
  gm_status status = gm_domain_field_components(domain, field, &components);
  expect_message(status, domain);
  size_t length = components * count;
  /* A short buffer half the time: the call must refuse it. */
  if (fuzz_u8(in) & 1 && length > 0)
    length -= 1;
  double *out = malloc((length ? length : 1) * sizeof *out);
  if (!out)
    return;
  status = gm_domain_get_field(domain, field, out, length);
  expect_message(status, domain);
  if (status == GM_OK && length > 0)
    write_field(in, domain, field, out, length);
  free(out);
  const double *view = NULL;
  status = gm_domain_view_field(domain, field, fuzz_u8(in) % 10, &view);
  expect_message(status, domain);
  double *edit = NULL;
  status = gm_domain_edit_field(domain, field, fuzz_u8(in) % 4, &edit);
  expect_message(status, domain);
  if (status == GM_OK && count > 0)
    edit[fuzz_u32(in) % count] = fuzz_double(in);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  fuzz_input in = {data, size, 0};
  gm_domain_def def = gm_domain_def_default();
  read_def(&in, &def);
  gm_domain *domain = NULL;
  gm_status status = gm_domain_create(&def, &domain);
  if (status != GM_OK) {
    if (domain)
      broken("a failed create returns no domain", NULL);
    const char *message = gm_last_create_error();
    if (!message || !message[0])
      broken("a failed create leaves a message", NULL);
    return 0;
  }
  int steps = 0;
  for (int call = 0; call < MAX_CALLS && !fuzz_done(&in); call++) {
    switch (fuzz_u8(&in) % 7) {
    case 0:
      add_material(&in, domain);
      break;
    case 1:
      fill_box(&in, domain, def.cell_size);
      break;
    case 2:
      add_points(&in, domain);
      break;
    case 3:
      add_wall(&in, domain);
      break;
    case 4:
      if (steps++ < MAX_STEPS)
        step(&in, domain);
      break;
    case 5:
      read_fields(&in, domain);
      break;
    default: {
      gm_summary summary = gm_summary_default();
      expect_message(gm_domain_get_summary(domain, &summary), domain);
      break;
    }
    }
  }
  gm_domain_destroy(domain);
  return 0;
}
