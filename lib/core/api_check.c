/*
 * api_check.c - the checked preamble of the public calls that take a
 * definition or result structure, and the table of those structures'
 * layouts: the current size, the sizes of the earlier layouts still
 * accepted, and the defaults that complete them (api_check.h).
 */
#include "core/core.h"

#include "core/api_check.h"
#include "core/domain.h"

#include <string.h>

/* Earlier layouts per structure, at most this many. */
#define GM_MAX_EARLIER_LAYOUTS 5

typedef struct layout_entry {
  const char *name;
  size_t size; /* bytes, sizeof the current layout */
  /* struct_size of each earlier layout a caller may have been compiled
   * against: the offset of the first field appended since; 0 ends. */
  size_t earlier[GM_MAX_EARLIER_LAYOUTS];
  /* Writes the gm_X_init() defaults into a structure of `size` bytes. */
  void (*defaults)(void *out);
} layout_entry;

#define DEFAULTS_OF(type)                                                      \
  static void defaults_##type(void *out) {                                     \
    (void)type##_init(out, sizeof(type));                                      \
  }
DEFAULTS_OF(gm_domain_def)
DEFAULTS_OF(gm_material_def)
DEFAULTS_OF(gm_elastic_def)
DEFAULTS_OF(gm_wall_def)
DEFAULTS_OF(gm_wall_force)
DEFAULTS_OF(gm_rigid_def)
DEFAULTS_OF(gm_rigid_load)
DEFAULTS_OF(gm_source_def)
DEFAULTS_OF(gm_sink_def)
DEFAULTS_OF(gm_flow_totals)
DEFAULTS_OF(gm_granular_def)
DEFAULTS_OF(gm_granular_summary)
DEFAULTS_OF(gm_points_def)
DEFAULTS_OF(gm_fill_def)
DEFAULTS_OF(gm_summary)
DEFAULTS_OF(gm_drucker_prager_def)
DEFAULTS_OF(gm_filling_def)
DEFAULTS_OF(gm_mohr_coulomb_def)
DEFAULTS_OF(gm_perzyna_def)
DEFAULTS_OF(gm_stress_free_def)
DEFAULTS_OF(gm_von_mises_def)
DEFAULTS_OF(gm_mu_i_def)
/* gm_allocator has no gm_X_init (its callbacks have no default a caller
 * could keep): all but the size zero. It has no earlier layout, so
 * gm_layout_complete never needs these. */
static void defaults_gm_allocator(void *out) {
  gm_allocator none = {sizeof(gm_allocator), NULL, NULL, NULL};
  memcpy(out, &none, sizeof none);
}

#define LAYOUT(type, ...)                                                      \
  { #type, sizeof(type), {__VA_ARGS__ }, defaults_##type }

/* The earlier layouts are those of include/granmpm.h's history: only two
 * structures have grown. gm_domain_def gained damping, shape, family,
 * pic_fraction and transfer one at a time; gm_wall_force gained the
 * impulse fields (impulse through smoothing_time) at once.
 * gm_granular_summary changed in another way: its interaction_count was
 * replaced by forest_reused and the timings, so its earlier layout is not
 * a prefix of the current one and is not accepted. */
static const layout_entry layouts[GM_LAYOUT_COUNT] = {
    [GM_LAYOUT_DOMAIN_DEF] =
        LAYOUT(gm_domain_def, offsetof(gm_domain_def, damping),
               offsetof(gm_domain_def, shape), offsetof(gm_domain_def, family),
               offsetof(gm_domain_def, pic_fraction),
               offsetof(gm_domain_def, transfer)),
    [GM_LAYOUT_MATERIAL_DEF] = LAYOUT(gm_material_def, 0),
    [GM_LAYOUT_ELASTIC_DEF] = LAYOUT(gm_elastic_def, 0),
    [GM_LAYOUT_WALL_DEF] = LAYOUT(gm_wall_def, 0),
    [GM_LAYOUT_WALL_FORCE] =
        LAYOUT(gm_wall_force, offsetof(gm_wall_force, impulse)),
    [GM_LAYOUT_RIGID_DEF] = LAYOUT(gm_rigid_def, 0),
    [GM_LAYOUT_RIGID_LOAD] = LAYOUT(gm_rigid_load, 0),
    [GM_LAYOUT_SOURCE_DEF] = LAYOUT(gm_source_def, 0),
    [GM_LAYOUT_SINK_DEF] = LAYOUT(gm_sink_def, 0),
    [GM_LAYOUT_FLOW_TOTALS] = LAYOUT(gm_flow_totals, 0),
    [GM_LAYOUT_GRANULAR_DEF] = LAYOUT(gm_granular_def, 0),
    [GM_LAYOUT_GRANULAR_SUMMARY] = LAYOUT(gm_granular_summary, 0),
    [GM_LAYOUT_POINTS_DEF] = LAYOUT(gm_points_def, 0),
    [GM_LAYOUT_FILL_DEF] = LAYOUT(gm_fill_def, 0),
    [GM_LAYOUT_SUMMARY] = LAYOUT(gm_summary, 0),
    [GM_LAYOUT_DRUCKER_PRAGER_DEF] = LAYOUT(gm_drucker_prager_def, 0),
    [GM_LAYOUT_FILLING_DEF] = LAYOUT(gm_filling_def, 0),
    [GM_LAYOUT_MOHR_COULOMB_DEF] = LAYOUT(gm_mohr_coulomb_def, 0),
    [GM_LAYOUT_PERZYNA_DEF] = LAYOUT(gm_perzyna_def, 0),
    [GM_LAYOUT_STRESS_FREE_DEF] = LAYOUT(gm_stress_free_def, 0),
    [GM_LAYOUT_VON_MISES_DEF] = LAYOUT(gm_von_mises_def, 0),
    [GM_LAYOUT_MU_I_DEF] = LAYOUT(gm_mu_i_def, 0),
    [GM_LAYOUT_ALLOCATOR] = LAYOUT(gm_allocator, 0),
};

const char *gm_layout_name(gm_layout layout) {
  return layouts[layout].name;
}

size_t gm_layout_size(gm_layout layout) {
  return layouts[layout].size;
}

bool gm_layout_known(gm_layout layout, size_t size) {
  const layout_entry *entry = &layouts[layout];
  if (size >= entry->size)
    return true;
  for (int k = 0; k < GM_MAX_EARLIER_LAYOUTS && entry->earlier[k]; k++)
    if (size == entry->earlier[k])
      return true;
  return false;
}

gm_status gm_layout_refuse(gm_domain *domain, gm_layout layout, size_t size) {
  const layout_entry *entry = &layouts[layout];
  const char *format = "%s.struct_size is %zu, expected %zu%s: %s%s%s";
  const char *earlier =
      entry->earlier[0] ? " (or the size of an earlier layout)" : "";
  /* gm_allocator alone has no gm_X_default(): its size is set by hand. */
  bool by_hand = layout == GM_LAYOUT_ALLOCATOR;
  const char *how = by_hand ? "set it to sizeof(" : "initialise with ";
  const char *end = by_hand ? ")" : "_default()";
  if (!domain)
    return gm_set_create_error(GM_ERR_STRUCT_SIZE, format, entry->name, size,
                               entry->size, earlier, how, entry->name, end);
  return gm_set_error(domain, GM_ERR_STRUCT_SIZE, format, entry->name, size,
                      entry->size, earlier, how, entry->name, end);
}

/* struct_size, the first member of every structure of the table. */
static size_t struct_size_of(const void *structure) {
  size_t size;
  memcpy(&size, structure, sizeof size);
  return size;
}

void gm_layout_complete(gm_layout layout, const void *caller, void *full) {
  const layout_entry *entry = &layouts[layout];
  size_t size = struct_size_of(caller);
  entry->defaults(full);
  memcpy(full, caller, size < entry->size ? size : entry->size);
  memcpy(full, &entry->size, sizeof entry->size);
}

gm_status gm_api_take_def(gm_domain *domain, const char *what, gm_layout layout,
                          const void *def, void *full, const void *id_out,
                          const char *id_name) {
  if (!domain)
    return GM_ERR_NULL;
  if (!def || (id_name && !id_out))
    return gm_set_error(domain, GM_ERR_NULL, "%s: %s is NULL", what,
                        def ? id_name : "def");
  if (domain->busy)
    return gm_set_error(domain, GM_ERR_BUSY, "%s: called during a step", what);
  size_t size = struct_size_of(def);
  if (!gm_layout_known(layout, size))
    return gm_layout_refuse(domain, layout, size);
  gm_layout_complete(layout, def, full);
  return GM_OK;
}

gm_status gm_api_check_result(const gm_domain *domain, const char *what,
                              gm_layout layout, const void *out,
                              const char *out_name) {
  if (!domain)
    return GM_ERR_NULL;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  if (!out)
    return gm_set_error(mutable_domain, GM_ERR_NULL, "%s: %s is NULL", what,
                        out_name);
  size_t size = struct_size_of(out);
  if (!gm_layout_known(layout, size))
    return gm_layout_refuse(mutable_domain, layout, size);
  return GM_OK;
}

void gm_api_give_result(gm_layout layout, void *out, const void *full) {
  size_t size = struct_size_of(out);
  size_t filled = size < layouts[layout].size ? size : layouts[layout].size;
  memcpy(out, full, filled);
  memcpy(out, &filled, sizeof filled);
}
