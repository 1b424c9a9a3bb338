/*
 * core.h - the core of the library: the domain behind the opaque handle and
 * what every folder shares. It holds the data layout of the domain (the
 * structs it embeds: SoA point storage, materials, walls, sources, the
 * per-worker scratch, the granular work arrays), the basic constants, the
 * allocator, error recording, the block grid (block_grid.h), the worker
 * pool (threads.h) and the API checks (api_check.h). What each folder
 * does is declared in that folder's own header (docs/architecture.md).
 * Private to the library.
 */
#ifndef GM_CORE_H
#define GM_CORE_H

#include "core/api_check.h"
#include "core/block_grid.h"
#include "core/threads.h"
#include "granmpm.h"
#include "shapes/shapes.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define GM_ERROR_MESSAGE_SIZE 512
/* Kernels are written once with constant flags and specialised by forced
 * inlining into one copy per pass kind. */
#if defined(__GNUC__)
#define GM_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define GM_ALWAYS_INLINE inline
#endif
#define GM_PI                  3.14159265358979323846
#define GM_MAX_STATE           64
#define GM_MAX_MATERIALS       256
#define GM_MAX_PARAMETER_BYTES 256
#define GM_MAX_WALLS           64
#define GM_MAX_SOURCES         64
#define GM_REMOVED_POINT       UINT32_MAX
/* Points handed to a material callback at once: large enough to amortise
 * the call, small enough that the batch buffers stay in L1/L2. */
#define GM_BATCH_SIZE 128
/* Stored stress components in 1D and 2D: xx, yy, zz (hoop), xy. 3D adds
 * yz and zx (slots GM_YZ, GM_ZX: the slots are the Voigt order). */
#define GM_STRESS_STORED 4
#define GM_STRESS_SLOTS  6
/* Stored deformation gradient components: xx, xy, yx, yy, zz (hoop). 3D
 * adds xz, yz, zx, zy after them (F_XZ..F_ZY; all nine stored). */
#define GM_F_STORED 5
#define GM_F_SLOTS  9
enum {
  F_XX = 0,
  F_XY = 1,
  F_YX = 2,
  F_YY = 3,
  F_ZZ = 4,
  F_XZ = 5,
  F_YZ = 6,
  F_ZX = 7,
  F_ZY = 8
};
/* Stored components of APIC's affine matrix B_p (GM_TRANSFER_APIC): xx,
 * xy, yx, yy (row-major, dim x dim of them: 1 in 1D, 4 in 2D). */
#define GM_AFFINE_STORED 4

/* --------------------------------------------------------------- memory */
void *gm_alloc(size_t size);
void *gm_calloc(size_t count, size_t size);
void gm_free(void *pointer);
/* Grows *array (element size elem) from old_count to new_count elements,
 * keeping contents; returns false (array untouched) when out of memory. */
bool gm_grow(void **array, size_t elem, size_t old_count, size_t new_count);

/* ------------------------------------------------------- force reports */
/* What a wall or rigid material reports (force_report.c): the last
 * successful gm_domain_step() call and running totals. */
typedef struct gm_force_report {
  double impulse[3];        /* N s, of the last successful call (z: 3D) */
  double force[3];          /* N, impulse / duration */
  double duration;          /* s, that call's dt */
  double total_impulse[3];  /* N s, since the wall or material was added */
  double total_duration;    /* s */
  double smoothed_force[3]; /* N, first-order low-pass of the force */
} gm_force_report;

/* ------------------------------------------------------------ materials */
typedef struct gm_material {
  char name[64];
  gm_material_update_fn *update;
  void *user;
  size_t state_count;
  double initial_state[GM_MAX_STATE];
  double p_wave_modulus; /* Pa, K + 4G/3 bound for the stable dt */
  double density;        /* kg/m^3, default for new points */
  /* Parameters of a built-in material, owned by the domain; `user` points
   * here (re-aimed whenever the material array moves). */
  _Alignas(max_align_t) unsigned char parameters[GM_MAX_PARAMETER_BYTES];
  bool builtin;
  /* Rigid material (rigid.c): prescribed velocity, and the force the
   * deformable material exerted on it (impulse of the call in progress,
   * force of the last successful call). */
  bool rigid;
  double rigid_velocity[2]; /* m/s */
  double rigid_impulse[2];  /* N s, of the call in progress */
  gm_force_report rigid_report;
  /* Granular material (gm_domain_set_granular). */
  bool granular;
  double critical_density; /* kg/m^3, rho_cr */
  double tolerance;        /* kg/m^3, TOL */
  gm_density_control density_control;
} gm_material;

/* ---------------------------------------------------------------- points */
/* Fields a step rewrites are double-buffered: the step reads buffer `cur`
 * and writes buffer `cur ^ 1`; success swaps, failure discards. That makes a
 * step transactional without copying the domain. */
/* Only the components a geometry needs are allocated (dim components of
 * vectors; F_ZZ only in axisymmetry, where the hoop stretch evolves);
 * the others stay NULL. */
typedef struct gm_point_buffers {
  double *position[3];             /* m */
  double *velocity[3];             /* m/s */
  double *stress[GM_STRESS_SLOTS]; /* Pa, xx yy zz xy (yz zx: 3D) */
  double *deformation[GM_F_SLOTS]; /* F components, see F_XX.. */
  /* CPDI only (NULL otherwise): the domain map D, F_XX..F_YY slots. The
   * domain's half edges are r1 = D (l_x/2, 0), r2 = D (0, l_y/2) with l
   * the initial edges (domain_size). D takes the same increments as F
   * (and the same density control), so D = F bitwise until the domain of
   * an over-distorted point is reset (cpdi_reset.c). */
  double *domain_map[4];
  double *volume; /* current volume (units: gm_points_def) */
  double *state;  /* state[i*stride+k]: one pool for all
                     materials, stride = max state_count */
  /* Granular family only (NULL otherwise): gm_point_state and parallel
   * grid label of the step that produced this buffer, as the small
   * integers they are (5 bytes per point instead of two doubles' 16;
   * GM_FIELD_STATE, GM_FIELD_COMPONENT and the checkpoint convert them to
   * doubles, exactly). A label is below the point count < INT_MAX
   * (points.c). */
  uint8_t *granular_state;
  int32_t *component;
  /* GM_TRANSFER_APIC only (NULL otherwise): B_p, m^2/s, row-major dim x
   * dim (transfer.h), written by the velocity pass of G2P. */
  double *affine[GM_AFFINE_STORED];
} gm_point_buffers;

typedef struct gm_points {
  size_t count;
  size_t capacity;
  gm_point_buffers buffer[2];
  int cur; /* index of the committed buffer */
  /* Single-buffered fields (a step never changes them). */
  double *mass;              /* kg */
  double *initial_volume;    /* at creation */
  double *domain_size[3];    /* m, initial particle domain edges */
  double *external_force[3]; /* N, host-supplied, persistent; allocated on
                                first use (NULL = no external force) */
  int64_t *id;               /* stable id */
  int32_t *material;         /* material index */
  /* id -> index for ids 0..next_id-1; GM_REMOVED_POINT once a sink has
   * removed the point (ids are never reused). */
  uint32_t *index_of_id;
  size_t id_capacity;
  /* Block of each point: of the committed positions at binning, of the
   * moved ones after the move pass (right for the next step if it
   * commits). keys_valid: block_key matches the committed positions. */
  int64_t *block_key;
  bool keys_valid;
  int64_t next_id;
  size_t state_stride; /* doubles of state per point */
  /* Scratch sized with the points (no allocation inside a step). */
  uint32_t *point_block; /* block index of each point this step */
  uint32_t *order;       /* point indices grouped by block */
} gm_points;

/* ------------------------------------------------------------------ walls */
typedef struct gm_wall {
  double point[3];         /* m, on the plane (z: 3D, else 0) */
  double normal[3];        /* unit, into the material (z: 3D, else 0) */
  double friction_static;  /* mu_s */
  double friction_kinetic; /* mu_k */
} gm_wall;

/* ------------------------------------------------------ sources and sinks */
typedef struct gm_source {
  int material;
  size_t count;         /* points per injection */
  double *position;     /* m, count * dim, owned */
  double velocity[2];   /* m/s */
  double point_size;    /* m */
  double density;       /* kg/m^3 */
  double next_time;     /* s, next injection; INFINITY when done */
  double period;        /* s, 0 = once */
  int injections_left;  /* -1 = no limit */
  double injected_mass; /* kg */
  uint64_t injected_points;
} gm_source;

typedef struct gm_sink {
  double lower[2], upper[2]; /* m */
  double removed_mass;       /* kg */
  uint64_t removed_points;
} gm_sink;

/* ------------------------------------------------------------- per worker */
typedef struct gm_worker_scratch {
  double strain_increment[6][GM_BATCH_SIZE]; /* yz, zx stay zero */
  double stress[6][GM_BATCH_SIZE];           /* yz, zx rows used */
  double density[GM_BATCH_SIZE];
  uint32_t batch_index[GM_BATCH_SIZE];
  uint32_t identity_rows[GM_BATCH_SIZE]; /* 0, 1, 2, ... */
  double *state_columns[GM_MAX_STATE];
  double *state_storage;       /* GM_MAX_STATE * GM_BATCH_SIZE doubles */
  struct chunk_gather *gather; /* G2P results of the chunk (g2p.c) */
  /* Sub-batch of one material when a chunk mixes materials. */
  double sub_strain_increment[6][GM_BATCH_SIZE];
  double sub_stress[6][GM_BATCH_SIZE];
  double sub_density[GM_BATCH_SIZE];
  int64_t sub_point_id[GM_BATCH_SIZE];
  /* First error met by this worker in the current phase (lowest point
   * index wins, so the message does not depend on the partition). */
  gm_status error_status;
  size_t error_index;
  char error_message[GM_ERROR_MESSAGE_SIZE];
  int callback_result; /* material return code that caused the error */
  bool error_inverted; /* the recorded error is an inverted F (finite
                          det F <= 0): a smaller dt may avoid it */
  double max_wave_speed_squared;  /* m^2/s^2, max c_p^2 of the new state */
  double max_point_speed_squared; /* m^2/s^2, max |v_p|^2 of the new state */
  double density_control_seconds; /* this step, this worker */
  char pad[64];
} gm_worker_scratch;

/* Declared in granular/interaction.h; the work arrays only point to it. */
typedef struct gm_interaction_domain gm_interaction_domain;

/* ----------------------------------------------------- granular scratch */
/* Per-step work arrays of the granular family (components.c), sized with
 * the points and the blocks outside the step's hot path. */
typedef struct gm_granular_work {
  size_t capacity; /* points */
  /* Node box of each point's support. 32 bits suffice: a domain has at
   * most 1e9 cells per axis (domain.c), so node indices stay below
   * 1e9 + 2 ghost layers + 1 < INT32_MAX; half the bytes of int64_t
   * (16 B per point). */
  int32_t *support_low[2];
  /* Highest node, stored only for the variants whose span varies (GIMP,
   * CPDI); NULL for linear MPM and the B-splines, whose support always
   * spans support_reach + 1 nodes per axis (8 B per point fewer). */
  int32_t *support_high[2];
  int32_t support_reach; /* nodes past the lowest: 1 linear, 2 or 3 B-spline;
                            0 with support_high stored */
  gm_interaction_domain *interaction; /* per point; CPDI only (NULL
                                         otherwise) */
  /* The same for the rectangle variants, SoA for the pair search: centre
   * (the committed positions, not owned) and half edges (m; not CPDI:
   * NULL there); and whether the point's material is granular. */
  const double *box_centre[2];
  double *box_half[2];
  uint8_t *granular;
  uint32_t *parent; /* union-find */
  uint32_t *set_size;
  /* Component of each point: not owned, the component array of the next
   * point buffer, where the step commits it (components.c). */
  int32_t *label;
  uint32_t *component_size; /* points per component */
  /* Node layer of each component; before the layers, the labelling's
   * scratch (union_find.h), with layer_stamp. */
  int32_t *component_layer;
  int32_t *layer_stamp; /* greedy colouring: last component per layer */
  uint32_t *cell_order; /* points by block, then local cell */
  uint32_t *cell_start; /* per block, GM_BLOCK_NODES + 1 offsets */
  size_t cell_capacity; /* blocks cell_start holds */
  uint64_t *conflict;   /* candidate point pairs of the search, then the
                           pairs of components sharing a node */
  size_t conflict_count, conflict_capacity;
  /* CSR of the conflicts per component (components + 1 offsets); 8 bytes
   * per point, so that between steps it also holds the kept forest's
   * edges while gm_granular_remap_forest sorts them. */
  uint32_t *adjacency_start;
  int32_t *adjacency;
  size_t adjacency_capacity;
  /* Spanning forest of the last search (edges p << 32 | q by point index):
   * valid while the committed points keep their indices (no reordering,
   * addition or removal), it lets the next step re-check N - C pairs
   * instead of searching all of them (components.c). */
  uint64_t *forest;
  size_t forest_count;
  bool forest_valid;
  uint8_t *visit;    /* points to search from when the forest is reused */
  bool cells_sorted; /* cell_order/cell_start hold this step's buckets */
  /* box_half depends only on per-point constants for linear MPM and uGIMP
   * (the initial domain scaled to V_cr): kept while the points keep their
   * indices, and recomputed after any addition, removal or reordering. */
  bool boxes_valid;
  /* Of the step in progress, committed with it. */
  gm_granular_summary summary;
} gm_granular_work;

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
  bool wall_profile_valid; /* grid contact records are of a committed step */
  int rigid_count;         /* rigid materials; 0 = no rigid machinery runs */
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

/* Records the message read by gm_last_create_error() (this thread). */
gm_status gm_set_create_error(gm_status status, const char *format, ...)
    __attribute__((format(printf, 2, 3)));
/* GM_ERR_UNSUPPORTED with a message naming `what` when the domain is 3D
 * and `what` is not done in 3D yet (docs/3d.md); GM_OK otherwise. */
gm_status gm_refuse_in_3d(gm_domain *domain, const char *what);
/* Records an error message on the domain and returns status. */
gm_status gm_set_error(gm_domain *domain, gm_status status, const char *format,
                       ...) __attribute__((format(printf, 3, 4)));
/* The same into a per-worker scratch (keeps the lowest point index). */
void gm_worker_error(gm_worker_scratch *scratch, gm_status status, size_t index,
                     const char *format, ...)
    __attribute__((format(printf, 4, 5)));
/* Moves the lowest-index worker error into the domain; GM_OK if none. */
gm_status gm_collect_worker_errors(gm_domain *domain);
void gm_clear_worker_errors(gm_domain *domain);

/* Block key of a position (block_grid.c); false if outside the grid. */
bool gm_block_key_of(const gm_domain *domain, const double *position_xyz,
                     int64_t *key);
/* The block grid of the step from the points' block keys (block_grid.c). */
gm_status gm_grid_build(gm_domain *domain);
/* Grid update modes: momentum -> velocity only; momentum and force ->
 * updated velocity and acceleration. */
enum { GM_GRID_VELOCITY_ONLY = 0, GM_GRID_FULL = 1 };

/* Stable dt (stable_dt.c). */
/* max c_p + max |v_p| (m/s) of the committed state, recomputed. */
void gm_recompute_signal_speed(gm_domain *domain);

#endif
