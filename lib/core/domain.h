/*
 * domain.h - the domain behind the opaque handle (struct gm_domain): its
 * data layout and the core services every folder above core/ works with.
 * The domain embeds the state of each concern by value, each in its own
 * header: the points (domain_points.h), the material records
 * (domain_materials.h), walls, sources and sinks (domain_boundaries.h),
 * the per-worker scratch (domain_workers.h), the granular work arrays
 * (domain_granular.h), the block grid (block_grid.h), the worker pool
 * (threads.h) and the shape grid (shapes/shapes.h); and it brings the
 * API checks (api_check.h). A file that reads or writes the domain's fields
 * includes this header (through its folder header); a file that does not
 * needs only core/core.h. Private to the library.
 */
#ifndef GM_DOMAIN_H
#define GM_DOMAIN_H

#include "core/api_check.h"
#include "core/block_grid.h"
#include "core/core.h"
#include "core/domain_boundaries.h"
#include "core/domain_granular.h"
#include "core/domain_materials.h"
#include "core/domain_points.h"
#include "core/domain_workers.h"
#include "core/threads.h"
#include "shapes/shapes.h"

#include <stdbool.h>
#include <stdint.h>

/* ----------------------------------------------------------------- domain */
struct gm_domain {
  gm_domain_def def;
  int dim; /* 1, 2 or 3 */
  bool axisymmetric;
  double inv_cell;  /* 1/m */
  int64_t cells[3]; /* cells per axis */
  /* Shape functions and node numbering: node 0 sits at shape_grid.origin,
   * one ghost layer below the box (support.h). */
  gm_shape_grid shape_grid;
  gm_grid grid;
  gm_points points;
  gm_material *materials;
  int material_count;
  gm_pool pool;
  gm_worker_scratch *scratch; /* one per worker */
  int worker_count;
  double time;       /* s */
  double current_dt; /* s, dt of the step being taken */
  uint64_t step_count;
  double max_signal_speed; /* m/s, max c_p + max |v_p|, committed state */
  gm_wall walls[GM_MAX_WALLS];
  int wall_count;
  gm_force_report wall_report[GM_MAX_WALLS]; /* last successful call, run */
  double wall_impulse[GM_MAX_WALLS][3];      /* N s, of the call in progress */
  double force_smoothing_time;               /* s, tau of the smoothed forces */
  bool wall_profile_valid;  /* grid contact records are of a committed step */
  int rigid_count;          /* rigid materials; 0 = no rigid machinery runs */
  gm_volumetric volumetric; /* gm_domain_set_volumetric; the arrays of
                               GM_VOLUMETRIC_CELL_MEAN are the grid's
                               (block_grid.h) */
  gm_source sources[GM_MAX_SOURCES];
  int source_count;
  gm_sink sinks[GM_MAX_SOURCES];
  int sink_count;
  gm_step_hook_fn *hook;
  void *hook_user;
  bool busy;            /* inside a step: state-changing calls refused */
  bool velocity_edited; /* host wrote velocities: signal speed is stale */
  bool inputs_edited;   /* host may have written velocities or external
                           forces: screen them at the next step */
  bool in_hook;         /* inside the step hook: edits allowed */
  int steps_since_reorder;
  gm_point_buffers snapshot; /* committed state saved before dt-halving */
  int retry_depth;           /* nesting of dt-halving retries in a step */
  size_t snapshot_capacity;
  gm_granular_work granular;            /* granular family only */
  gm_granular_summary granular_summary; /* of the last committed step */
  char last_error[GM_ERROR_MESSAGE_SIZE];
};

/* Are the x faces periodic (GM_WALL_PERIODIC; gm_domain_create checks that
 * both are)? Nodes x = 1..cells[0] (node numbering of support.h) then own
 * the columns; node i outside that range is the image of node i -+
 * cells[0] (lib/grid/periodic.c). */
static inline bool gm_periodic_x(const gm_domain *domain) {
  return domain->def.walls[GM_FACE_XMIN] == GM_WALL_PERIODIC;
}

/* Grid update modes: momentum -> velocity only; momentum and force ->
 * updated velocity and acceleration. */
enum { GM_GRID_VELOCITY_ONLY = 0, GM_GRID_FULL = 1 };

/* Stable dt (stable_dt.c). */
/* max c_p + max |v_p| (m/s) of the committed state, recomputed. */
void gm_recompute_signal_speed(gm_domain *domain);

#endif
