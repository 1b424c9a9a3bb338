/*
 * sources.c - filling and discharge: sources inject points of a material
 * at fixed positions, once or periodically (000 sec 4.3, 001 sec 5.1.2);
 * sinks remove the points that enter a box (an orifice) and count the
 * discharged mass, so a flow rate can be read at any time.
 *
 * An injection is part of the step it starts: it is undone (the points
 * truncated away, the sources' clocks restored) when the step fails.
 * Removal happens after the step has committed and cannot fail.
 */
#include "boundaries/boundaries.h"

#include <math.h>
#include <string.h>

static bool inside_grid(const gm_domain *domain, const double *position) {
  int64_t key;
  return gm_block_key_of(domain, position, &key);
}

static gm_status validate_source(gm_domain *domain, const gm_source_def *def) {
  if (domain->source_count >= GM_MAX_SOURCES)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_source: at most %d sources",
                        GM_MAX_SOURCES);
  if (def->material < 0 || def->material >= domain->material_count)
    return gm_set_error(domain, GM_ERR_UNKNOWN_MATERIAL,
                        "gm_source_def.material %d is unknown (%d materials)",
                        def->material, domain->material_count);
  if (def->count == 0 || def->count > 1000000)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_source_def.count is %zu, must be in 1..1000000",
                        def->count);
  if (!def->position)
    return gm_set_error(domain, GM_ERR_NULL, "gm_source_def.position is NULL");
  const char *name = "gm_source_def";
  gm_status status =
      gm_check_positive(domain, name, "point_size", def->point_size, "m", 0);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "density", def->density, "kg/m^3",
                               true);
  if (status == GM_OK)
    status = gm_check_positive(domain, name, "period", def->period, "s", true);
  if (status == GM_OK)
    /* Its density is fixed now: refused here, not at its first injection
     * inside a step (as gm_domain_add_points refuses points). */
    status = gm_check_placement_density(
        domain, def->material,
        def->density > 0.0 ? def->density
                           : domain->materials[def->material].density,
        "gm_domain_add_source: the source (gm_source_def.density, 0 = the "
        "material's)");
  if (status != GM_OK)
    return status;
  if (!isfinite(def->start_time) || def->max_injections < 0)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_source_def: start_time must be finite and "
                        "max_injections >= 0");
  for (int k = 0; k < domain->dim; k++)
    if (!isfinite(def->velocity[k]))
      return gm_set_error(domain, GM_ERR_NOT_FINITE,
                          "gm_source_def.velocity[%d] is not finite", k);
  for (size_t i = 0; i < def->count; i++) {
    const double *position = def->position + i * (size_t)domain->dim;
    if (!inside_grid(domain, position) ||
        (domain->axisymmetric && !(position[0] > 0.0)))
      return gm_set_error(domain, GM_ERR_OUT_OF_GRID,
                          "gm_source_def: point %zu (%g, %g, %g) is outside "
                          "the grid%s",
                          i, position[0], domain->dim > 1 ? position[1] : 0.0,
                          domain->dim > 2 ? position[2] : 0.0,
                          domain->axisymmetric ? " or at radius <= 0" : "");
  }
  return GM_OK;
}

gm_status gm_domain_add_source(gm_domain *domain, const gm_source_def *def,
                               int *source_id) {
  gm_source_def full;
  gm_status status =
      gm_api_take_def(domain, "gm_domain_add_source", GM_LAYOUT_SOURCE_DEF, def,
                      &full, source_id, "source_id");
  if (status != GM_OK)
    return status;
  def = &full;
  status = validate_source(domain, def);
  if (status != GM_OK)
    return status;
  size_t values = def->count * (size_t)domain->dim;
  double *position = gm_alloc(values * sizeof(double));
  if (!position)
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "gm_domain_add_source: out of memory");
  memcpy(position, def->position, values * sizeof(double));
  gm_source *source = &domain->sources[domain->source_count];
  memset(source, 0, sizeof *source);
  source->material = def->material;
  source->count = def->count;
  source->position = position;
  for (int k = 0; k < domain->dim; k++)
    source->velocity[k] = def->velocity[k];
  source->point_size = def->point_size;
  source->density = def->density > 0.0
                        ? def->density
                        : domain->materials[def->material].density;
  source->next_time = def->start_time;
  source->period = def->period;
  source->injections_left = def->max_injections ? def->max_injections
                            : def->period > 0.0 ? -1
                                                : 1;
  *source_id = domain->source_count++;
  return GM_OK;
}

gm_status gm_domain_add_sink(gm_domain *domain, const gm_sink_def *def,
                             int *sink_id) {
  gm_sink_def full;
  gm_status status =
      gm_api_take_def(domain, "gm_domain_add_sink", GM_LAYOUT_SINK_DEF, def,
                      &full, sink_id, "sink_id");
  if (status != GM_OK)
    return status;
  def = &full;
  if (domain->sink_count >= GM_MAX_SOURCES)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_add_sink: at most %d sinks", GM_MAX_SOURCES);
  gm_sink *sink = &domain->sinks[domain->sink_count];
  memset(sink, 0, sizeof *sink);
  for (int k = 0; k < domain->dim; k++) {
    if (!isfinite(def->lower[k]) || !isfinite(def->upper[k]) ||
        !(def->upper[k] > def->lower[k]))
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_sink_def: lower[%d] = %g and upper[%d] = %g "
                          "must be finite with upper > lower",
                          k, def->lower[k], k, def->upper[k]);
    sink->lower[k] = def->lower[k];
    sink->upper[k] = def->upper[k];
  }
  for (int k = domain->dim; k < 3; k++) { /* axes the domain lacks */
    sink->lower[k] = -INFINITY;
    sink->upper[k] = INFINITY;
  }
  *sink_id = domain->sink_count++;
  return GM_OK;
}

static gm_status get_totals(const gm_domain *domain, gm_flow_totals *totals,
                            int id, int count, const char *what, double mass,
                            uint64_t points) {
  gm_status status = gm_api_check_result(domain, what, GM_LAYOUT_FLOW_TOTALS,
                                         totals, "totals");
  if (status != GM_OK)
    return status;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  if (id < 0 || id >= count)
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "%s: id %d is unknown (%d defined)", what, id, count);
  gm_flow_totals result = gm_flow_totals_default();
  result.mass = mass;
  result.points = points;
  gm_api_give_result(GM_LAYOUT_FLOW_TOTALS, totals, &result);
  return GM_OK;
}

gm_status gm_domain_get_source_totals(const gm_domain *domain, int source_id,
                                      gm_flow_totals *totals) {
  if (!domain)
    return GM_ERR_NULL;
  bool known = source_id >= 0 && source_id < domain->source_count;
  const gm_source *source = known ? &domain->sources[source_id] : NULL;
  return get_totals(domain, totals, source_id, domain->source_count,
                    "gm_domain_get_source_totals",
                    known ? source->injected_mass : 0.0,
                    known ? source->injected_points : 0);
}

gm_status gm_domain_get_sink_totals(const gm_domain *domain, int sink_id,
                                    gm_flow_totals *totals) {
  if (!domain)
    return GM_ERR_NULL;
  bool known = sink_id >= 0 && sink_id < domain->sink_count;
  const gm_sink *sink = known ? &domain->sinks[sink_id] : NULL;
  return get_totals(
      domain, totals, sink_id, domain->sink_count, "gm_domain_get_sink_totals",
      known ? sink->removed_mass : 0.0, known ? sink->removed_points : 0);
}

/* One injection of a source through the (all-or-nothing) point insertion. */
static gm_status inject(gm_domain *domain, gm_source *source) {
  int dim = domain->dim;
  size_t count = source->count;
  double *block = gm_alloc(count * (size_t)(3 * dim + 1) * sizeof(double));
  if (!block)
    return gm_set_error(domain, GM_ERR_NO_MEMORY, "source: out of memory");
  double *velocity = block, *edges = block + count * (size_t)dim;
  double *volume = edges + count * (size_t)dim;
  double *mass = volume + count;
  double injected = 0.0;
  for (size_t i = 0; i < count; i++) {
    double measure = 1.0; /* length, area, or ring volume */
    for (int k = 0; k < dim; k++) {
      velocity[i * dim + k] = source->velocity[k];
      edges[i * dim + k] = source->point_size;
      measure *= source->point_size;
    }
    if (domain->axisymmetric)
      measure *= 2.0 * GM_PI * source->position[i * dim];
    volume[i] = measure;
    mass[i] = source->density * measure;
    injected += mass[i];
  }
  gm_points_def points = gm_points_def_default();
  points.count = count;
  points.material = source->material;
  points.position = source->position;
  points.velocity = velocity;
  points.volume = volume;
  points.mass = mass;
  points.domain_size = edges;
  gm_status status = gm_points_append(domain, &points, NULL);
  gm_free(block);
  if (status != GM_OK)
    return status;
  source->injected_mass += injected;
  source->injected_points += count;
  return GM_OK;
}

gm_status gm_sources_inject(gm_domain *domain, gm_injection_undo *undo) {
  undo->count = domain->points.count;
  undo->next_id = domain->points.next_id;
  memcpy(undo->sources, domain->sources,
         (size_t)domain->source_count * sizeof(gm_source));
  for (int s = 0; s < domain->source_count; s++) {
    gm_source *source = &domain->sources[s];
    if (source->injections_left == 0 || source->next_time > domain->time)
      continue;
    /* At most one injection per source and step, at the same positions:
     * periods missed (a step longer than the period, or a source added
     * late) are skipped, not stacked on top of each other. */
    gm_status status = inject(domain, source);
    if (status != GM_OK) {
      gm_sources_undo(domain, undo);
      return status;
    }
    if (source->injections_left > 0)
      source->injections_left--;
    double next = INFINITY;
    if (source->period > 0.0) {
      double missed =
          floor((domain->time - source->next_time) / source->period);
      next = source->next_time + (missed + 1.0) * source->period;
      if (!(next > domain->time)) /* a period below the clock's resolution */
        next = INFINITY;
    }
    source->next_time = next;
  }
  return GM_OK;
}

void gm_sources_undo(gm_domain *domain, const gm_injection_undo *undo) {
  if (domain->points.count != undo->count ||
      domain->points.next_id != undo->next_id)
    gm_points_truncate(domain, undo->count, undo->next_id);
  memcpy(domain->sources, undo->sources,
         (size_t)domain->source_count * sizeof(gm_source));
}

void gm_sinks_remove(gm_domain *domain) {
  if (domain->sink_count == 0)
    return;
  gm_points *points = &domain->points;
  const gm_point_buffers *buffer = &points->buffer[points->cur];
  int dim = domain->dim;
  /* point_block is free after a committed step: it holds the flags. The
   * next binning must then rebuild it, even where no point is removed
   * (a kept binning, bins.c, would read the flags as blocks). */
  uint32_t *flags = points->point_block;
  points->blocks_kept = false;
  bool any = false;
  for (size_t i = 0; i < points->count; i++) {
    /* A missing axis reads 0, inside the sink's infinite extent there. */
    double x[3] = {buffer->position[0][i],
                   dim > 1 ? buffer->position[1][i] : 0.0,
                   dim > 2 ? buffer->position[2][i] : 0.0};
    flags[i] = 0;
    for (int s = 0; s < domain->sink_count; s++) {
      gm_sink *sink = &domain->sinks[s];
      if (x[0] < sink->lower[0] || x[0] >= sink->upper[0] ||
          x[1] < sink->lower[1] || x[1] >= sink->upper[1] ||
          x[2] < sink->lower[2] || x[2] >= sink->upper[2])
        continue;
      flags[i] = 1;
      sink->removed_mass += points->mass[i];
      sink->removed_points++;
      any = true;
      break;
    }
  }
  if (any)
    gm_points_remove(domain, flags);
}

void gm_sources_free(gm_domain *domain) {
  for (int s = 0; s < domain->source_count; s++)
    gm_free(domain->sources[s].position);
}
