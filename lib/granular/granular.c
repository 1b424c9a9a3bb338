/*
 * granular.c - the public side of the granular method (000 sec 3):
 * marking materials granular, the per-step summary, and the sizing of the
 * work arrays that components.c uses inside the step.
 */
#include "granular/granular.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* In the granular family no point of a granular material may be looser
 * than rho_cr - TOL (V_cr = m / rho_cr is the largest volume a point may
 * have, 000 sec 3.3; see gm_check_placement_density in points.c). Marking a
 * material granular, or raising its rho_cr, must not leave an existing
 * point (at its current volume) or a source of it below that: O(N). The
 * slack of a few ulps is the rounding of m / V, as in points.c. */
static gm_status check_existing_density(gm_domain *domain, int material,
                                        const gm_granular_def *def) {
  if (domain->def.family != GM_FAMILY_GRANULAR)
    return GM_OK;
  double lowest = def->critical_density - def->tolerance; /* kg/m^3 */
  const gm_points *points = &domain->points;
  const double *volume = points->buffer[points->cur].volume; /* current */
  double slack = 4.0 * DBL_EPSILON * def->critical_density;  /* kg/m^3 */
  for (size_t p = 0; p < points->count; p++) {
    double density = points->mass[p] / volume[p]; /* kg/m^3 */
    if (points->material[p] == material && density < lowest - slack)
      return gm_set_error(
          domain, GM_ERR_INVALID_ARGUMENT,
          "gm_domain_set_granular: point id %lld of material %d has density "
          "%.12g kg/m^3, below critical_density %.12g kg/m^3 (- tolerance "
          "%g): in the granular family V_cr = m/rho_cr is the largest "
          "volume a point may have (000 sec 3.3); critical_density must be "
          "<= %.12g kg/m^3 (its density + tolerance)",
          (long long)points->id[p], material, density, def->critical_density,
          def->tolerance, density + def->tolerance);
  }
  for (int s = 0; s < domain->source_count; s++) {
    const gm_source *source = &domain->sources[s];
    bool injects = source->injections_left != 0; /* 0: finished */
    if (injects && source->material == material &&
        source->density < lowest - slack)
      return gm_set_error(
          domain, GM_ERR_INVALID_ARGUMENT,
          "gm_domain_set_granular: source %d of material %d injects at "
          "%.12g kg/m^3, below critical_density %.12g kg/m^3 (- tolerance "
          "%g): in the granular family V_cr = m/rho_cr is the largest "
          "volume a point may have (000 sec 3.3); critical_density must be "
          "<= %.12g kg/m^3 (its density + tolerance)",
          s, material, source->density, def->critical_density, def->tolerance,
          source->density + def->tolerance);
  }
  return GM_OK;
}

gm_status gm_domain_set_granular(gm_domain *domain, int material,
                                 const gm_granular_def *def) {
  gm_granular_def full;
  gm_status status =
      gm_api_take_def(domain, "gm_domain_set_granular", GM_LAYOUT_GRANULAR_DEF,
                      def, &full, NULL, NULL);
  if (status != GM_OK)
    return status;
  def = &full;
  if (material < 0 || material >= domain->material_count)
    return gm_set_error(domain, GM_ERR_UNKNOWN_MATERIAL,
                        "gm_domain_set_granular: material %d does not exist "
                        "(%d materials)",
                        material, domain->material_count);
  gm_material *target = &domain->materials[material];
  if (target->rigid)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_set_granular: material %d is rigid",
                        material);
  status = gm_check_positive(domain, "gm_granular_def", "critical_density",
                             def->critical_density, "kg/m^3", false);
  if (status == GM_OK)
    status = gm_check_positive(domain, "gm_granular_def", "tolerance",
                               def->tolerance, "kg/m^3", true);
  if (status != GM_OK)
    return status;
  if (def->density_control != GM_DENSITY_CONTROL_RETURN &&
      def->density_control != GM_DENSITY_CONTROL_SCALE)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_granular_def.density_control %d is not a "
                        "gm_density_control value",
                        (int)def->density_control);
  if ((status = check_existing_density(domain, material, def)) != GM_OK)
    return status;
  domain->granular.boxes_valid = false; /* domains of interaction change */
  target->granular = true;
  target->critical_density = def->critical_density;
  target->tolerance = def->tolerance;
  target->density_control = def->density_control;
  return GM_OK;
}

gm_status gm_domain_get_granular_summary(const gm_domain *domain,
                                         gm_granular_summary *summary) {
  gm_status status =
      gm_api_check_result(domain, "gm_domain_get_granular_summary",
                          GM_LAYOUT_GRANULAR_SUMMARY, summary, "summary");
  if (status != GM_OK)
    return status;
  gm_granular_summary result = domain->granular_summary;
  result.struct_size = sizeof result;
  memset(result.state_count, 0, sizeof result.state_count);
  const gm_points *points = &domain->points;
  const uint8_t *state = points->buffer[points->cur].granular_state;
  for (size_t p = 0; p < points->count; p++) {
    int value = state ? state[p] : GM_STATE_QUASI_STATIC;
    if (value >= 0 && value < 3)
      result.state_count[value]++;
  }
  gm_api_give_result(GM_LAYOUT_GRANULAR_SUMMARY, summary, &result);
  return GM_OK;
}

#define GROW_WORK(field, elem)                                                 \
  do {                                                                         \
    if (!gm_grow((void **)&(field), (elem), old_capacity, capacity))           \
      return gm_set_error(domain, GM_ERR_NO_MEMORY,                            \
                          "granular: out of memory for %zu points", capacity); \
  } while (0)

gm_status gm_granular_reserve(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  size_t capacity = domain->points.capacity;
  size_t old_capacity = work->capacity;
  if (capacity > old_capacity) {
    /* The highest node only where the span varies (domain_granular.h). */
    work->support_reach = gm_fixed_support_reach(domain->shape_grid.shape);
    int axes = domain->dim == 3 ? 3 : 2; /* as before 3D below it */
    for (int k = 0; k < axes; k++) {
      GROW_WORK(work->support_low[k], sizeof(int32_t));
      if (work->support_reach == 0)
        GROW_WORK(work->support_high[k], sizeof(int32_t));
    }
    /* The pair test reads the parallelograms of CPDI (48 bytes per point)
     * or the boxes of the rectangle variants (16), never both
     * (pair_rules.h): only the one the domain's shape uses is allocated. */
    if (domain->shape_grid.shape == GM_SHAPE_CPDI && domain->dim == 3) {
      GROW_WORK(work->interaction3, sizeof(gm_interaction_domain3));
    } else if (domain->shape_grid.shape == GM_SHAPE_CPDI) {
      GROW_WORK(work->interaction, sizeof(gm_interaction_domain));
    } else {
      for (int k = 0; k < axes; k++)
        GROW_WORK(work->box_half[k], sizeof(double));
    }
    GROW_WORK(work->granular, sizeof(uint8_t));
    GROW_WORK(work->visit, sizeof(uint8_t));
    GROW_WORK(work->forest, sizeof(uint64_t));
    GROW_WORK(work->parent, sizeof(uint32_t));
    GROW_WORK(work->set_size, sizeof(uint32_t));
    GROW_WORK(work->component_size, sizeof(uint32_t));
    GROW_WORK(work->component_layer, sizeof(int32_t));
    GROW_WORK(work->layer_stamp, sizeof(int32_t));
    GROW_WORK(work->cell_order, sizeof(uint32_t));
    /* components + 1 <= capacity + 1 offsets, and the forest's edges
     * between steps (domain_granular.h): 8 bytes per point. */
    GROW_WORK(work->adjacency_start, sizeof(uint64_t));
    work->capacity = capacity;
  }
  /* The cell buckets of the pair search cover the blocks of the plain
   * binning, the one the search runs on (called after it), not the node
   * layers the step may add after the search: those can be several times
   * as many (one full copy of the blocks per layer). Grown like the grid's
   * blocks: the count and 4 at first, then by an eighth and 4, so a resting
   * scene allocates only at its first step. */
  size_t blocks = domain->grid.block_count;
  if (blocks > work->cell_capacity) {
    size_t row = GM_BLOCK_NODES + 1;
    size_t room = blocks + 4 + (work->cell_capacity ? blocks / 8 : 0);
    if (!gm_grow((void **)&work->cell_start, row * sizeof(uint32_t),
                 work->cell_capacity, room))
      return gm_set_error(domain, GM_ERR_NO_MEMORY,
                          "granular: out of memory for %zu blocks", room);
    work->cell_capacity = room;
  }
  return GM_OK;
}

void gm_granular_free(gm_domain *domain) {
  gm_granular_work *work = &domain->granular;
  for (int k = 0; k < 3; k++) {
    gm_free(work->support_low[k]);
    gm_free(work->support_high[k]);
  }
  gm_free(work->interaction);
  gm_free(work->interaction3);
  for (int k = 0; k < 3; k++)
    gm_free(work->box_half[k]);
  gm_free(work->granular);
  gm_free(work->visit);
  gm_free(work->forest);
  gm_free(work->parent);
  gm_free(work->set_size);
  gm_free(work->component_size);
  gm_free(work->component_layer);
  gm_free(work->layer_stamp);
  gm_free(work->cell_order);
  gm_free(work->cell_start);
  gm_free(work->conflict);
  gm_free(work->adjacency_start);
  gm_free(work->adjacency);
  memset(work, 0, sizeof *work);
}
