/*
 * api_check.h - the checked preamble of every public call that takes a
 * definition or result structure (add, set, get, create), and the table of
 * the structures' layouts it checks against. Private to the library.
 *
 * The layout rule (design.md: fields are only ever appended): a caller
 * compiled against an earlier header passes the struct_size of that
 * earlier layout. Such a size is accepted; the fields it does not cover
 * take their gm_X_init() defaults for a definition, and are not written
 * for a result. A size larger than the library's is accepted too (its
 * extra bytes are ignored, or left alone). Any other size is refused with
 * GM_ERR_STRUCT_SIZE and a message naming the structure and the size the
 * library expects.
 */
#ifndef GM_API_CHECK_H
#define GM_API_CHECK_H

#include "granmpm.h"

#include <stdbool.h>
#include <stddef.h>

/* Every public structure that starts with size_t struct_size. */
typedef enum gm_layout {
  GM_LAYOUT_DOMAIN_DEF,
  GM_LAYOUT_MATERIAL_DEF,
  GM_LAYOUT_ELASTIC_DEF,
  GM_LAYOUT_WALL_DEF,
  GM_LAYOUT_WALL_FORCE,
  GM_LAYOUT_RIGID_DEF,
  GM_LAYOUT_RIGID_LOAD,
  GM_LAYOUT_SOURCE_DEF,
  GM_LAYOUT_SINK_DEF,
  GM_LAYOUT_FLOW_TOTALS,
  GM_LAYOUT_GRANULAR_DEF,
  GM_LAYOUT_GRANULAR_SUMMARY,
  GM_LAYOUT_POINTS_DEF,
  GM_LAYOUT_FILL_DEF,
  GM_LAYOUT_SUMMARY,
  GM_LAYOUT_DRUCKER_PRAGER_DEF,
  GM_LAYOUT_FILLING_DEF,
  GM_LAYOUT_MOHR_COULOMB_DEF,
  GM_LAYOUT_PERZYNA_DEF,
  GM_LAYOUT_STRESS_FREE_DEF,
  GM_LAYOUT_VON_MISES_DEF,
  GM_LAYOUT_MU_I_DEF,
  GM_LAYOUT_ALLOCATOR,
  GM_LAYOUT_COUNT
} gm_layout;

/* The structure's name ("gm_wall_def") and its current size (bytes). */
const char *gm_layout_name(gm_layout layout);
size_t gm_layout_size(gm_layout layout);

/* Is size the struct_size of this layout, of an earlier one, or larger? */
bool gm_layout_known(gm_layout layout, size_t size);

/* GM_ERR_STRUCT_SIZE with the message naming the structure, the size
 * given and the size expected; set on domain, or as the create error
 * (gm_last_create_error) when domain is NULL. */
gm_status gm_layout_refuse(gm_domain *domain, gm_layout layout, size_t size);

/* full (the library's layout) = the defaults, overwritten by the part of
 * the caller's structure its struct_size covers; full's struct_size is the
 * library's. The caller's struct_size must be known. */
void gm_layout_complete(gm_layout layout, const void *caller, void *full);

/* The preamble of a call that takes a definition and changes the domain:
 * GM_ERR_NULL for a NULL domain (no message) or def, or a NULL *id_out
 * when id_name names one (NULL: the call has no required output);
 * GM_ERR_BUSY inside a step; GM_ERR_STRUCT_SIZE for an unknown size. On
 * GM_OK, full holds the completed definition (gm_layout_complete). `what`
 * names the function in messages. */
gm_status gm_api_take_def(gm_domain *domain, const char *what, gm_layout layout,
                          const void *def, void *full, const void *id_out,
                          const char *id_name);

/* The preamble of a call that fills a result structure: GM_ERR_NULL for a
 * NULL domain (no message) or out (named out_name in the message),
 * GM_ERR_STRUCT_SIZE for an unknown size. Reading calls are allowed inside
 * a step. */
gm_status gm_api_check_result(const gm_domain *domain, const char *what,
                              gm_layout layout, const void *out,
                              const char *out_name);

/* Writes the library's result `full` into the caller's checked structure:
 * as many bytes as both layouts have; the caller's struct_size becomes
 * that count (as the gm_X_init functions set it). */
void gm_api_give_result(gm_layout layout, void *out, const void *full);

#endif
