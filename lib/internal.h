/*
 * internal.h - the domain behind the opaque handle: SoA point storage, the
 * sparse block grid, materials, the worker pool. Private to the library.
 */
#ifndef GM_INTERNAL_H
#define GM_INTERNAL_H

#include "api_check.h"
#include "granmpm.h"
#include "grid.h"
#include "interaction.h"
#include "support.h"
#include "threads.h"
#include "union_find.h"

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
/* Stored stress components in 1D and 2D: xx, yy, zz (hoop), xy. */
#define GM_STRESS_STORED 4
/* Stored deformation gradient components: xx, xy, yx, yy, zz (hoop). */
#define GM_F_STORED 5
enum { F_XX = 0, F_XY = 1, F_YX = 2, F_YY = 3, F_ZZ = 4 };
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
  double impulse[2];        /* N s, of the last successful call */
  double force[2];          /* N, impulse / duration */
  double duration;          /* s, that call's dt */
  double total_impulse[2];  /* N s, since the wall or material was added */
  double total_duration;    /* s */
  double smoothed_force[2]; /* N, first-order low-pass of the force */
} gm_force_report;
#define GM_DEFAULT_FORCE_SMOOTHING_TIME 1e-3 /* s */
/* Commits a successful call of length dt (s) that exchanged `impulse`
 * (N s) with the obstacle; tau (s) is the smoothing time. */
void gm_force_report_commit(gm_force_report *report, const double impulse[2],
                            double dt, double tau);

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
  double *position[3];              /* m */
  double *velocity[3];              /* m/s */
  double *stress[GM_STRESS_STORED]; /* Pa, xx yy zz xy */
  double *deformation[GM_F_STORED]; /* F components, see F_XX.. */
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
   * grid label of the step that produced this buffer. */
  double *granular_state;
  double *component;
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
  double point[2];         /* m, on the plane */
  double normal[2];        /* unit, into the material */
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

/* ----------------------------------------------------- granular scratch */
/* Per-step work arrays of the granular family (components.c), sized with
 * the points and the blocks outside the step's hot path. */
typedef struct gm_granular_work {
  size_t capacity;         /* points */
  int64_t *support_low[2]; /* node box of each point's support */
  int64_t *support_high[2];
  gm_interaction_domain *interaction; /* per point */
  /* The same for the rectangle variants, SoA for the pair search: centre
   * (the committed positions, not owned) and half edges (m); and whether
   * the point's material is granular. */
  const double *box_centre[2];
  double *box_half[2];
  uint8_t *granular;
  uint32_t *parent; /* union-find */
  uint32_t *set_size;
  int32_t *label;  /* component of each point */
  int64_t *min_id; /* union-find labelling scratch */
  gm_root_order *roots;
  uint32_t *component_size; /* points per component */
  int32_t *component_layer; /* node layer of each component */
  int32_t *layer_stamp;     /* greedy colouring: last component per layer */
  uint32_t *cell_order;     /* points by block, then local cell */
  uint32_t *cell_start;     /* per block, GM_BLOCK_NODES + 1 offsets */
  size_t cell_capacity;     /* blocks cell_start holds */
  uint64_t *conflict;       /* candidate point pairs of the search, then the
                               pairs of components sharing a node */
  size_t conflict_count, conflict_capacity;
  uint32_t *adjacency_start; /* CSR of the conflicts per component */
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
  int dim; /* 1 or 2 */
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
  double wall_impulse[GM_MAX_WALLS][2];      /* N s, of the call in progress */
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

/* Records the message read by gm_last_create_error() (this thread). */
gm_status gm_set_create_error(gm_status status, const char *format, ...)
    __attribute__((format(printf, 2, 3)));
/* Records an error message on the domain and returns status. */
gm_status gm_set_error(gm_domain *domain, gm_status status, const char *format,
                       ...) __attribute__((format(printf, 3, 4)));
/* GM_ERR_INVALID_ARGUMENT if a point of granular material material_id
 * would be placed in the granular family below rho_cr - TOL (points.c says
 * why); `what` names the caller and the point or def for the message. */
gm_status gm_check_placement_density(gm_domain *domain, int material_id,
                                     double density, const char *what);
/* The same into a per-worker scratch (keeps the lowest point index). */
void gm_worker_error(gm_worker_scratch *scratch, gm_status status, size_t index,
                     const char *format, ...)
    __attribute__((format(printf, 4, 5)));
/* Moves the lowest-index worker error into the domain; GM_OK if none. */
gm_status gm_collect_worker_errors(gm_domain *domain);
void gm_clear_worker_errors(gm_domain *domain);

/* A built-in material (written against the public callback interface):
 * its parameters are copied into the domain and passed to update as
 * `user` (materials.c). */
typedef struct gm_builtin_material {
  const char *def_name; /* the public def struct, for messages */
  const char *name;
  gm_material_update_fn *update;
  const void *parameters; /* copied, at most GM_MAX_PARAMETER_BYTES */
  size_t parameter_size;
  size_t state_count;
  const double *initial_state; /* state_count values, NULL = zeros */
  double p_wave_modulus;       /* Pa, K + 4G/3 */
  double density;              /* kg/m^3 */
} gm_builtin_material;
gm_status gm_add_builtin_material(gm_domain *domain,
                                  const gm_builtin_material *spec,
                                  int *material_id);
/* Young's modulus finite > 0 and Poisson ratio in (-1, 0.5); sets the
 * message naming def_name's fields. */
gm_status gm_check_elastic_constants(gm_domain *domain, const char *def_name,
                                     double youngs_modulus,
                                     double poisson_ratio);
/* value finite and > 0 (or >= 0 when zero_allowed); message names
 * def_name.field and the unit. */
gm_status gm_check_positive(gm_domain *domain, const char *def_name,
                            const char *field, double value, const char *unit,
                            bool zero_allowed);

/* Point storage (points.c). */
gm_status gm_points_reserve(gm_domain *domain, size_t capacity);
void gm_points_free(gm_points *points);
/* gm_domain_add_points without the busy check (sources inject mid-step). */
gm_status gm_points_append(gm_domain *domain, const gm_points_def *def,
                           int64_t *first_id);
/* Removes the points whose flag is nonzero (flags: one per point),
 * keeping the order of the others (removal.c). */
void gm_points_remove(gm_domain *domain, const uint32_t *flags);
/* Drops the points added after `count` and the ids after `next_id`. */
void gm_points_truncate(gm_domain *domain, size_t count, int64_t next_id);
/* Widens the per-point state pool to stride doubles. */
gm_status gm_points_restride_state(gm_domain *domain, size_t stride);
/* Components of APIC's B_p a domain stores: dim x dim with
 * GM_TRANSFER_APIC, none otherwise. */
static inline int gm_affine_stored(const gm_domain *domain) {
  return domain->def.transfer == GM_TRANSFER_APIC ? domain->dim * domain->dim
                                                  : 0;
}
/* Sizes one buffer set for capacity points (keeps contents). */
gm_status gm_buffers_reserve(const gm_domain *domain, gm_point_buffers *buffer,
                             size_t old_capacity, size_t capacity);
/* Allocates the external-force arrays (zeros) if not yet there. */
gm_status gm_points_need_external_force(gm_domain *domain);
void gm_buffers_free(gm_point_buffers *buffer);
/* Copies count points of every double-buffered field. */
void gm_buffers_copy(gm_point_buffers *to, const gm_point_buffers *from,
                     size_t count, size_t state_stride);
/* The tensor that deforms the point domains of a buffer set: the CPDI
 * domain map D, or F (cpGIMP reads its diagonal; uGIMP and linear MPM
 * ignore it). F_XX..F_YY slots. */
static inline void gm_support_tensor(const gm_domain *domain,
                                     const gm_point_buffers *buffer,
                                     const double *out[4]) {
  bool cpdi = domain->shape_grid.shape == GM_SHAPE_CPDI;
  for (int k = 0; k < 4; k++)
    out[k] = cpdi ? buffer->domain_map[k] : buffer->deformation[k];
}
/* Point p's domain (support.h) in one buffer set (points.c). */
void gm_point_domain_at(const gm_domain *domain, const gm_point_buffers *buffer,
                        size_t p, gm_point_domain *out);
/* Block key of a position (grid.c); false if outside the grid. */
bool gm_block_key_of(const gm_domain *domain, const double *position_xyz,
                     int64_t *key);

/* Step phases. */
gm_status gm_grid_build(gm_domain *domain); /* grid.c */
gm_status gm_bin_points(gm_domain *domain); /* bins.c */
void gm_reorder_points(gm_domain *domain);  /* bins.c */
/* What a P2G pass accumulates (p2g.c). */
typedef struct gm_p2g_pass {
  bool mass;           /* nodal mass */
  bool momentum;       /* nodal momentum */
  bool forces;         /* internal, body and host forces */
  int velocity_buffer; /* buffer whose velocities give the momentum */
  int stress_buffer;   /* buffer whose stress and volume give forces */
  bool check_inputs;   /* reject non-finite host-written inputs */
} gm_p2g_pass;
void gm_p2g(gm_domain *domain, const gm_p2g_pass *pass);
void gm_grid_update(gm_domain *domain, double dt, int mode); /* grid_update */
/* Grid update modes: momentum -> velocity only; momentum and force ->
 * updated velocity and acceleration. */
enum { GM_GRID_VELOCITY_ONLY = 0, GM_GRID_FULL = 1 };
/* B-splines on the box faces by images (bspline_faces.c; no-ops for the
 * other shapes): after a scatter, each ghost node's sums go to its mirror
 * node; after a grid update, each ghost node takes its mirror's velocity
 * (and acceleration in GM_GRID_FULL mode), reflected. */
void gm_bspline_fold_ghosts(gm_domain *domain, const gm_p2g_pass *pass);
void gm_bspline_mirror_ghosts(gm_domain *domain, int mode);

/* What a G2P pass does (g2p.c). */
typedef struct gm_g2p_pass {
  bool flip_velocity; /* v_p += dt * sum N a_i  */
  bool move_points;   /* x_p += dt * sum N v_i (nodal velocity) */
  bool deform;        /* L from nodal velocity: F, V, stress */
  bool finish;        /* the last pass of the step: block keys of wide
                         supports (they need the final F) and the
                         signal-speed bound of the new state */
  double dt;
  bool in_place; /* deform from the next buffer's F, D and stress (the
                    second half of USF's split update, step.c) rather
                    than from the committed ones */
} gm_g2p_pass;
void gm_g2p(gm_domain *domain, const gm_g2p_pass *pass);
size_t gm_chunk_gather_size(void); /* bytes of a worker's G2P chunk buffer */

/* Stress update for one chunk of points (stress_update.c). */
/* Jaumann rotation, material call and stress write-back for points
 * [first, first+count) given their velocity gradients (1/s, L_xx L_xy L_yx
 * L_yy L_zz); reads the committed buffer (or, in_place, the next one),
 * writes the next one. */
void gm_stress_update_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count, double dt,
                            const double *const velocity_gradient[5],
                            bool in_place);

/* Walls (walls.c). Contact of one node with the walls: `velocity` (m/s)
 * is the node's updated velocity, changed in place; gap (one per wall, m,
 * or NULL = 0) lets it approach a wall by that much in dt, and centre_gap
 * (one per wall, m, or NULL) the same for the nodes the wall's contact
 * does not reach, from the nearest point centre; returns true if
 * a wall acted. If block_force is not NULL, mass/dt times each wall's velocity
 * change (N) is added to block_force[2 w], [2 w + 1]. If record is not
 * NULL it gets the one wall that acted and its normal change and the
 * tangential velocity before friction, for gm_walls_share_friction
 * (wall -1 when none or several acted); when none acted, a node in front
 * of exactly one wall it shares gets that wall with normal change 0. */
typedef struct gm_wall_pool_record {
  int wall;              /* the one wall that acted; -1: none or several */
  double normal_change;  /* m/s, its normal velocity change (> 0; 0: not
                            pushed, in front of the plane) */
  double tangent_before; /* m/s, tangential velocity before its friction,
                            along (n_y, -n_x) */
} gm_wall_pool_record;
bool gm_walls_contact(const gm_domain *domain, const double node_position[2],
                      double velocity[2], const double *gap,
                      const double *centre_gap, double dt, double *block_force,
                      double mass_over_dt, int *first_wall,
                      gm_wall_pool_record *record);
/* Coulomb friction shared along each wall (walls.c): after the nodal
 * update, the per-node friction of the nodes with one wall is replaced by
 * Coulomb's law on the pooled normal impulse and tangential momentum of
 * the nodes in each one-cell strip along the wall. Serial, block order. */
void gm_walls_share_friction(gm_domain *domain, double dt, int mode);
/* The node gaps to every planar wall and to the box faces that hold
 * material (grid->wall_gap, gm_gap_plane_count per node: the walls, then
 * the faces) from the committed point domains, after the mass P2G
 * (wall_gaps.c; step.c's stage MEASURE_WALL_GAPS). */
void gm_walls_measure_gaps(gm_domain *domain);
/* Gap records per node: the planar walls and the measured box faces. */
int gm_gap_plane_count(const gm_domain *domain);
/* Slot of box face f (2 axis + side) in a node's gap records; -1 when
 * the face is not measured (open, or a B-spline mirror). */
int gm_gap_face_slot(const gm_domain *domain, int face);
/* Gaps (cells) below which a wall or a box face counts as touched: see
 * gm_walls_contact (walls.c). */
#define GM_CONTACT_TOLERANCE 3e-3
/* Sizes the per-block wall-force partial sums for the current walls. */
gm_status gm_walls_reserve(gm_domain *domain);

/* Rigid points (rigid.c). After the mass P2G (step.c's stage
 * MARK_RIGID_NODES): marks the nodes each rigid point touches with its
 * material (grid->rigid_material, 0 = none, material + 1 otherwise). */
void gm_rigid_mark_nodes(gm_domain *domain);
/* Grid update of one node touched by a rigid material: its velocity
 * becomes the prescribed one; in FULL mode the acceleration follows and
 * the node's impulse on the rigid body is stored for gm_rigid_add_impulse. */
void gm_rigid_constrain_node(gm_domain *domain, size_t node,
                             const double old_velocity[2], double dt,
                             bool full);
/* Adds the committed sub-step's impulses on each rigid material. */
void gm_rigid_add_impulse(gm_domain *domain);
/* Rigid points of the new (spare) buffer get their prescribed velocity. */
void gm_rigid_set_point_velocities(gm_domain *domain);
gm_status gm_rigid_reserve(gm_domain *domain);
/* Does any wall reach into the block with lower corner node (ix, iy)? */
bool gm_walls_near_block(const gm_domain *domain, int64_t base_x,
                         int64_t base_y);
/* Adds the committed sub-step's wall forces (summed per block in block
 * order) times dt to the impulse of the gm_domain_step call in progress. */
void gm_walls_add_impulse(gm_domain *domain, double dt);

/* Sources and sinks (sources.c). The sources' state before an injection,
 * to undo it when the step then fails. */
typedef struct gm_injection_undo {
  size_t count;    /* points before */
  int64_t next_id; /* ids before */
  gm_source sources[GM_MAX_SOURCES];
} gm_injection_undo;
/* Injects every due source (time <= domain->time); fills undo. */
gm_status gm_sources_inject(gm_domain *domain, gm_injection_undo *undo);
void gm_sources_undo(gm_domain *domain, const gm_injection_undo *undo);
/* Removes the committed points inside sinks (cannot fail). */
void gm_sinks_remove(gm_domain *domain);
void gm_sources_free(gm_domain *domain);

/* Granular family (components.c, density_control.c, granular.c). */
/* After the plain binning: domains of interaction, components by
 * union-find, node layers; re-keys and re-bins the points by layer. */
gm_status gm_granular_prepare(gm_domain *domain);
/* After the stress update of a chunk: stress-free and density-control
 * rules of the stress_free and granular families (000 eqs 13-15, 18). */
void gm_density_control_chunk(gm_domain *domain, size_t first, size_t count);
/* CPDI domain reset (cpdi_reset.c). The largest ratio of the singular
 * values of a point's domain map D before it is reset to the initial
 * domain scaled to the same area: a square domain then has an aspect of
 * at most 3 (see cpdi_reset.c and gm_domain_create(3)). */
#define GM_CPDI_MAX_DISTORTION 3.0
/* Resets map (D_xx, D_xy, D_yx, D_yy) to sqrt(det D) I when the ratio of
 * its singular values exceeds max_distortion and det D > 0; true if it
 * did. */
bool gm_cpdi_domain_reset(double map[4], double max_distortion);
/* The resets of the next buffer's points [first, first + count): after
 * their deformation and density control (g2p.c); nothing in 1D. */
void gm_cpdi_reset_chunk(const gm_domain *domain, size_t first, size_t count);
/* Pair search (pair_search.c) and layers (layers.c). */
typedef enum gm_pair_pass { GM_PASS_JOIN, GM_PASS_CONFLICTS } gm_pair_pass;
/* Every pair sharing a node: from every point with half windows (subset
 * NULL), or from the points with subset[p] != 0 with full windows. JOIN
 * unites interacting pairs and records the forest; a subset search also
 * appends the pairs of different sets that do not interact to
 * work->conflict (point indices p << 32 | q: the candidates for the
 * conflicts of the layers, kept by components.c). CONFLICTS appends the
 * pairs of components that share a node (label low << 32 | high). */
gm_status gm_pair_search(gm_domain *domain, const int max_span[2],
                         gm_pair_pass pass, const uint8_t *subset);
gm_status gm_assign_layers(gm_domain *domain, size_t components,
                           size_t *layer_count);
/* Follows a reordering (points->order: new index k holds old order[k])
 * in the kept spanning forest; scratch: count entries. */
void gm_granular_remap_forest(gm_domain *domain, uint32_t *scratch);
/* Sizes the granular work arrays for the points and blocks. */
gm_status gm_granular_reserve(gm_domain *domain);
void gm_granular_free(gm_domain *domain);

/* Stable dt (stable_dt.c). */
/* max c_p + max |v_p| (m/s) of the committed state, recomputed. */
void gm_recompute_signal_speed(gm_domain *domain);

#endif
