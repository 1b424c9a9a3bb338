/*
 * checkpoint.c - gm_domain_save and gm_domain_load: what a checkpoint
 * holds so that a restarted run continues bitwise like the uninterrupted
 * one, and the checks that keep a bad file from touching the domain.
 *
 * Payload (byte encoding in checkpoint_format.h):
 *   1. the setup, as named records (gm_domain_def, materials, planar walls,
 *      sources, sinks): compared on load, a mismatch names the record;
 *   2. clock and flags: time, step count, cached signal speed, steps since
 *      the last reordering, the host-edit flags;
 *   3. the points in index order: every committed double-buffered array
 *      (APIC's affine matrices included), the single-buffered ones, the id
 *      map;
 *   4. totals: sources' clocks and counts, sinks', rigid velocities, the
 *      rigid and wall force reports (last call, totals, smoothed force;
 *      their z components for walls and rigid materials of 3D domains)
 *      and the smoothing time, the granular summary.
 * Not stored, because each step rebuilds it from the above: the grid, the
 * block keys, the spare point buffer, the granular spanning forest (it
 * only saves search work; the labels are normalised by smallest id) and
 * interaction boxes, and the wall traction profile (unavailable until the
 * next step). Load marks all of them stale.
 */
#include "io/io.h"

#include "io/checkpoint_format.h"

#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* ------------------------------------------------------------ the setup */

static void describe_def(const gm_domain *domain, gm_byte_writer *out) {
  const gm_domain_def *def = &domain->def;
  size_t dim = (size_t)domain->dim;
  gm_record_integer(out, "gm_domain_def.geometry", def->geometry);
  gm_record_reals(out, "gm_domain_def.origin", def->origin, dim);
  gm_record_reals(out, "gm_domain_def.extent", def->extent, dim);
  gm_record_reals(out, "gm_domain_def.cell_size", &def->cell_size, 1);
  gm_record_reals(out, "gm_domain_def.gravity", def->gravity, dim);
  gm_record_integer(out, "gm_domain_def.scheme", def->scheme);
  for (size_t face = 0; face < 2 * dim; face++) {
    char name[48];
    snprintf(name, sizeof name, "gm_domain_def.walls[%zu]", face);
    gm_record_integer(out, name, def->walls[face]);
  }
  gm_record_reals(out, "gm_domain_def.cfl", &def->cfl, 1);
  gm_record_integer(out, "gm_domain_def.refuse_unstable_dt",
                    def->refuse_unstable_dt);
  gm_record_integer(out, "gm_domain_def.max_retries", def->max_retries);
  gm_record_reals(out, "gm_domain_def.damping", &def->damping, 1);
  gm_record_integer(out, "gm_domain_def.shape", def->shape);
  gm_record_integer(out, "gm_domain_def.family", def->family);
  gm_record_reals(out, "gm_domain_def.pic_fraction", &def->pic_fraction, 1);
  /* Written only when not the default, so that files of FLIP domains keep
   * the version-1 layout they had before APIC existed (and old files load
   * into FLIP domains); an APIC file names this record on a mismatch. */
  if (def->transfer != GM_TRANSFER_FLIP)
    gm_record_integer(out, "gm_domain_def.transfer", def->transfer);
  /* Not a field of the definition (gm_domain_set_volumetric), and written
   * only when on, so that other files keep their layout. */
  if (domain->volumetric != GM_VOLUMETRIC_POINT)
    gm_record_integer(out, "gm_domain_set_volumetric", domain->volumetric);
  /* worker_count and the task system are left out on purpose: results do
   * not depend on them, so a run may restart with other threads. */
}

/* mu(I)'s regularisation switch and exponent, as numbers rather than
 * bytes: the padding after the int is unspecified. */
static void describe_mu_i_switches(const gm_material *material,
                                   const char *name, gm_byte_writer *out) {
  gm_mu_i_def def;
  memcpy(&def, material->parameters, sizeof def);
  const double switches[2] = {def.regularise != 0, def.regularisation_exponent};
  gm_record_reals(out, name, switches, 2);
}

/* A built-in material's parameters as bytes, the span its model names
 * (materials/builtin_models.c); a user material's live behind its
 * callback's `user` pointer: only the host knows them. */
static void describe_parameters(const gm_material *material, const char *name,
                                gm_byte_writer *out) {
  const gm_builtin_model *model = gm_builtin_model_of(material->update);
  if (!model) {
    gm_record_bytes(out, name, NULL, 0);
    return;
  }
  gm_record_bytes(out, name, material->parameters + GM_BUILTIN_RECORD_BEGIN,
                  model->record_end - GM_BUILTIN_RECORD_BEGIN);
}

/* "material 2 (sand) density": names a record of material m. */
static const char *material_record(char *name, size_t size, int m,
                                   const gm_material *material,
                                   const char *what) {
  snprintf(name, size, "material %d (%s) %s", m, material->name, what);
  return name;
}

static void describe_material(const gm_domain *domain, int m,
                              gm_byte_writer *out) {
  const gm_material *material = &domain->materials[m];
  char name[160];
  size_t size = sizeof name;
  gm_record_text(out, material_record(name, size, m, material, "name"),
                 material->name);
  gm_record_integer(out, material_record(name, size, m, material, "kind"),
                    material->builtin | material->rigid << 1 |
                        material->granular << 2);
  gm_record_reals(out,
                  material_record(name, size, m, material, "initial_state"),
                  material->initial_state, material->state_count);
  gm_record_reals(out,
                  material_record(name, size, m, material, "p_wave_modulus"),
                  &material->p_wave_modulus, 1);
  gm_record_reals(out, material_record(name, size, m, material, "density"),
                  &material->density, 1);
  if (material->builtin)
    describe_parameters(
        material, material_record(name, size, m, material, "parameters"), out);
  if (material->builtin && material->update == gm_mu_i_update)
    describe_mu_i_switches(
        material, material_record(name, size, m, material, "regularisation"),
        out);
  if (material->granular) {
    const double granular[2] = {material->critical_density,
                                material->tolerance}; /* kg/m^3 */
    gm_record_reals(
        out,
        material_record(name, size, m, material, "critical_density, tolerance"),
        granular, 2);
    gm_record_integer(
        out, material_record(name, size, m, material, "density_control"),
        material->density_control);
  }
}

static void describe_source(const gm_domain *domain, int s,
                            gm_byte_writer *out) {
  const gm_source *source = &domain->sources[s];
  char name[64];
  snprintf(name, sizeof name, "source %d material, count", s);
  const double counts[2] = {source->material, (double)source->count};
  gm_record_reals(out, name, counts, 2);
  snprintf(name, sizeof name, "source %d position", s);
  gm_record_reals(out, name, source->position,
                  source->count * (size_t)domain->dim);
  snprintf(name, sizeof name, "source %d velocity, size, density, period", s);
  if (domain->dim == 3) { /* the z velocity too (no 2D file changes) */
    const double values[6] = {source->velocity[0], source->velocity[1],
                              source->velocity[2], source->point_size,
                              source->density,     source->period};
    gm_record_reals(out, name, values, 6);
    return;
  }
  const double values[5] = {source->velocity[0], source->velocity[1],
                            source->point_size, source->density,
                            source->period};
  gm_record_reals(out, name, values, 5);
}

/* Every definition a restart must rebuild, in order. */
void gm_checkpoint_describe_setup(const gm_domain *domain,
                                  gm_byte_writer *out) {
  describe_def(domain, out);
  gm_record_integer(out, "material count", domain->material_count);
  for (int m = 0; m < domain->material_count; m++)
    describe_material(domain, m, out);
  gm_record_integer(out, "planar wall count", domain->wall_count);
  for (int w = 0; w < domain->wall_count; w++) {
    const gm_wall *wall = &domain->walls[w];
    char name[64];
    snprintf(name, sizeof name, "planar wall %d point, normal, friction", w);
    if (domain->dim == 3) { /* the z components too (no 2D file changes) */
      const double values[8] = {wall->point[0],        wall->point[1],
                                wall->point[2],        wall->normal[0],
                                wall->normal[1],       wall->normal[2],
                                wall->friction_static, wall->friction_kinetic};
      gm_record_reals(out, name, values, 8);
      continue;
    }
    const double values[6] = {wall->point[0],        wall->point[1],
                              wall->normal[0],       wall->normal[1],
                              wall->friction_static, wall->friction_kinetic};
    gm_record_reals(out, name, values, 6);
  }
  gm_record_integer(out, "source count", domain->source_count);
  for (int s = 0; s < domain->source_count; s++)
    describe_source(domain, s, out);
  gm_record_integer(out, "sink count", domain->sink_count);
  for (int s = 0; s < domain->sink_count; s++) {
    const gm_sink *sink = &domain->sinks[s];
    char name[48];
    snprintf(name, sizeof name, "sink %d lower, upper", s);
    if (domain->dim == 3) { /* the z extent too (no 2D file changes) */
      const double box[6] = {sink->lower[0], sink->lower[1], sink->lower[2],
                             sink->upper[0], sink->upper[1], sink->upper[2]};
      gm_record_reals(out, name, box, 6);
      continue;
    }
    const double box[4] = {sink->lower[0], sink->lower[1], sink->upper[0],
                           sink->upper[1]};
    gm_record_reals(out, name, box, 4);
  }
}

/* --------------------------------------------------------- point arrays */

size_t gm_checkpoint_point_arrays(const gm_domain *domain, uint32_t version,
                                  gm_array_slot *slots) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *b = &points->buffer[points->cur];
  int dim = domain->dim;
  /* F_ZZ (the hoop stretch) is stored in axisymmetry only, all nine
   * components in 3D (points.c). */
  int deformation = dim == 3               ? GM_F_SLOTS
                    : domain->axisymmetric ? GM_F_STORED
                                           : F_ZZ;
  size_t n = 0, d = sizeof(double);
#define SLOT_AS(pointer, size, kind, form)                                     \
  slots[n++] = (gm_array_slot) {                                               \
    pointer, size, kind, form                                                  \
  }
#define SLOT(pointer, size, kind) SLOT_AS(pointer, size, kind, GM_FORM_RAW)
  for (int k = 0; k < dim; k++)
    SLOT(b->position[k], d, GM_CHECK_POSITION);
  for (int k = 0; k < dim; k++)
    SLOT(b->velocity[k], d, GM_CHECK_INPUT);
  /* xx yy zz xy, then yz zx in 3D (the Voigt order of the slots). */
  for (int k = 0; k < gm_stress_stored(domain); k++)
    SLOT(b->stress[k], d, GM_CHECK_FINITE);
  for (int k = 0; k < deformation; k++)
    SLOT(b->deformation[k], d,
         k == F_XX ? GM_CHECK_DEFORMATION : GM_CHECK_FINITE);
  /* CPDI: the domain map D in F's slots (since format version 2 below 3D,
   * version 3 in 3D; a version-2 3D file starts D = F, checkpoint_load.c). */
  if (b->domain_map[0] && (dim < 3 || version >= GM_CHECKPOINT_3D_MAP))
    for (int k = 0; k < gm_domain_map_stored(domain); k++)
      SLOT(b->domain_map[k], d,
           k == F_XX ? GM_CHECK_DOMAIN_MAP : GM_CHECK_FINITE);
  SLOT(b->volume, d, GM_CHECK_POSITIVE);
  SLOT(b->state, points->state_stride * d, GM_CHECK_NONE);
  if (domain->def.family == GM_FAMILY_GRANULAR) {
    /* Doubles in the file (format unchanged), small integers in memory. */
    SLOT_AS(b->granular_state, d, GM_CHECK_GRANULAR_STATE, GM_FORM_BYTE);
    SLOT_AS(b->component, d, GM_CHECK_LABEL, GM_FORM_INT32);
  }
  for (int k = 0; k < gm_affine_stored(domain); k++) /* APIC's B_p */
    SLOT(b->affine[k], d, GM_CHECK_INPUT);
  SLOT(points->mass, d, GM_CHECK_POSITIVE);
  SLOT(points->initial_volume, d, GM_CHECK_POSITIVE);
  for (int k = 0; k < dim; k++)
    SLOT(points->domain_size[k], d, GM_CHECK_POSITIVE);
  SLOT(points->id, sizeof(int64_t), GM_CHECK_ID);
  SLOT(points->material, sizeof(int32_t), GM_CHECK_MATERIAL);
#undef SLOT
#undef SLOT_AS
  return n;
}

/* ----------------------------------------------------------------- save */

static void write_points(const gm_domain *domain, gm_byte_writer *out) {
  const gm_points *points = &domain->points;
  gm_array_slot slots[GM_CHECKPOINT_MAX_ARRAYS];
  size_t slot_count =
      gm_checkpoint_point_arrays(domain, GM_CHECKPOINT_VERSION, slots);
  for (size_t k = 0; k < slot_count; k++) {
    if (slots[k].form == GM_FORM_RAW) {
      gm_writer_array(out, slots[k].data,
                      points->count * slots[k].bytes_per_point);
      continue;
    }
    /* The bytes gm_writer_array writes for the same values as doubles. */
    gm_writer_u64(out, (uint64_t)(points->count * sizeof(double)));
    for (size_t i = 0; i < points->count; i++)
      gm_writer_f64(out, slots[k].form == GM_FORM_BYTE
                             ? (double)((const uint8_t *)slots[k].data)[i]
                             : (double)((const int32_t *)slots[k].data)[i]);
  }
  bool external = points->external_force[0] != NULL;
  gm_writer_u8(out, external);
  for (int k = 0; external && k < domain->dim; k++)
    gm_writer_array(out, points->external_force[k],
                    points->count * sizeof(double));
  gm_writer_array(out, points->index_of_id,
                  (size_t)points->next_id * sizeof(uint32_t));
}

/* The x and y components, the durations, then (walls of a 3D domain,
 * `solid`) the z components: 2D files are as before. */
static void write_force_report(const gm_force_report *report, bool solid,
                               gm_byte_writer *out) {
  for (int k = 0; k < 2; k++) {
    gm_writer_f64(out, report->impulse[k]);        /* N s */
    gm_writer_f64(out, report->force[k]);          /* N */
    gm_writer_f64(out, report->total_impulse[k]);  /* N s */
    gm_writer_f64(out, report->smoothed_force[k]); /* N */
  }
  gm_writer_f64(out, report->duration);       /* s */
  gm_writer_f64(out, report->total_duration); /* s */
  if (!solid)
    return;
  gm_writer_f64(out, report->impulse[2]);        /* N s */
  gm_writer_f64(out, report->force[2]);          /* N */
  gm_writer_f64(out, report->total_impulse[2]);  /* N s */
  gm_writer_f64(out, report->smoothed_force[2]); /* N */
}

static void write_totals(const gm_domain *domain, gm_byte_writer *out) {
  for (int s = 0; s < domain->source_count; s++) {
    const gm_source *source = &domain->sources[s];
    gm_writer_f64(out, source->next_time); /* s */
    gm_writer_i64(out, source->injections_left);
    gm_writer_f64(out, source->injected_mass); /* kg */
    gm_writer_u64(out, source->injected_points);
  }
  for (int s = 0; s < domain->sink_count; s++) {
    gm_writer_f64(out, domain->sinks[s].removed_mass); /* kg */
    gm_writer_u64(out, domain->sinks[s].removed_points);
  }
  for (int m = 0; m < domain->material_count; m++) {
    const gm_material *material = &domain->materials[m];
    /* z of a rigid material in 3D only: 2D files, and 3D files without
     * rigid materials, are byte for byte those of earlier versions. */
    bool solid = domain->dim == 3 && material->rigid;
    for (int k = 0; k < (solid ? 3 : 2); k++)
      gm_writer_f64(out, material->rigid_velocity[k]); /* m/s */
    write_force_report(&material->rigid_report, solid, out);
  }
  for (int w = 0; w < domain->wall_count; w++)
    write_force_report(&domain->wall_report[w], domain->dim == 3, out);
  gm_writer_f64(out, domain->force_smoothing_time); /* s */
  const gm_granular_summary *summary = &domain->granular_summary;
  for (int k = 0; k < 3; k++)
    gm_writer_u64(out, summary->state_count[k]);
  gm_writer_u64(out, summary->component_count);
  gm_writer_u64(out, summary->layer_count);
  gm_writer_i64(out, summary->forest_reused);
  const double seconds[5] = {summary->geometry_seconds,
                             summary->pair_search_seconds,
                             summary->label_seconds, summary->layer_seconds,
                             summary->density_control_seconds};
  gm_writer_bytes(out, seconds, sizeof seconds);
}

gm_status gm_domain_save(const gm_domain *domain, const char *path) {
  if (!domain)
    return GM_ERR_NULL;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  if (!path)
    return gm_set_error(mutable_domain, GM_ERR_NULL,
                        "gm_domain_save: path is NULL");
  /* A step hook sees a committed state; a material callback does not. */
  if (domain->busy && !domain->in_hook)
    return gm_set_error(mutable_domain, GM_ERR_BUSY,
                        "gm_domain_save: called during a step");
  gm_byte_writer out;
  gm_checkpoint_begin(&out);
  gm_byte_writer setup = {0};
  gm_checkpoint_describe_setup(domain, &setup);
  gm_writer_array(&out, setup.data, setup.size);
  out.failed = out.failed || setup.failed;
  gm_writer_free(&setup);
  gm_writer_f64(&out, domain->time); /* s */
  gm_writer_u64(&out, domain->step_count);
  gm_writer_f64(&out, domain->max_signal_speed); /* m/s */
  gm_writer_i64(&out, domain->steps_since_reorder);
  gm_writer_u8(&out, domain->velocity_edited);
  gm_writer_u8(&out, domain->inputs_edited);
  gm_writer_u64(&out, domain->points.count);
  gm_writer_i64(&out, domain->points.next_id);
  write_points(domain, &out);
  write_totals(domain, &out);
  gm_checkpoint_seal(&out);
  gm_status status =
      out.failed
          ? gm_set_error(mutable_domain, GM_ERR_NO_MEMORY,
                         "gm_domain_save: out of memory encoding '%s'", path)
          : gm_checkpoint_write_file(mutable_domain, path, &out);
  gm_writer_free(&out);
  return status;
}
