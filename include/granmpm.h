/*
 * granmpm.h - public API of libgranmpm, an embeddable Material Point Method
 * library for granular flows.
 *
 * Conventions (see granmpm(3)):
 *  - one opaque handle, gm_domain; no internal layout is public;
 *  - every *_def struct (and every result struct such as gm_summary)
 *    starts with `size_t struct_size`. Its defaults come from the exported
 *    gm_status gm_X_init(gm_X *out, size_t struct_size) (the gm_*_init
 *    convention: pass sizeof *out; GM_ERR_NULL, or GM_ERR_STRUCT_SIZE for a
 *    size the library does not know; struct_size is set to the bytes
 *    filled), callable from any language, and from the inline
 *    gm_X_default(), which returns the same values by calling it. Always
 *    start from one of them, then set fields;
 *  - every fallible call returns a gm_status (0 = GM_OK, negative = error);
 *    gm_domain_last_error() holds a message naming the point, material or
 *    parameter at fault;
 *  - SI units throughout; tension is positive in stresses;
 *  - the library never prints, exits or aborts on user input.
 *
 * Thread safety: calls on one domain must not overlap; distinct domains may be
 * used from distinct threads at the same time.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GRANMPM_H
#define GRANMPM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(GM_BUILDING_LIBRARY) && defined(__GNUC__)
#define GM_API __attribute__((visibility("default")))
#else
#define GM_API
#endif

/* ---------------------------------------------------------------- version */

#define GM_VERSION_MAJOR  0
#define GM_VERSION_MINOR  1
#define GM_VERSION_PATCH  0
#define GM_VERSION_STRING "0.1.0"
/** MAJOR*10000 + MINOR*100 + PATCH, comparable with gm_version_number(). */
#define GM_VERSION_NUMBER                                                      \
  (GM_VERSION_MAJOR * 10000 + GM_VERSION_MINOR * 100 + GM_VERSION_PATCH)

/** Version of the library actually linked, as "MAJOR.MINOR.PATCH". */
GM_API const char *gm_version(void);
/** Version of the library actually linked, as GM_VERSION_NUMBER. */
GM_API int gm_version_number(void);

/* ----------------------------------------------------------------- status */

/* X(name, value, description). Values are fixed forever: never renumber. */
#define GM_STATUS_LIST(X)                                                      \
  X(GM_OK, 0, "success")                                                       \
  X(GM_ERR_NULL, -1, "a required pointer argument is NULL")                    \
  X(GM_ERR_INVALID_ARGUMENT, -2, "an argument is outside its valid range")     \
  X(GM_ERR_STRUCT_SIZE, -3,                                                    \
    "struct_size is wrong: initialise definitions with gm_*_def_default()")    \
  X(GM_ERR_NO_MEMORY, -4, "out of memory")                                     \
  X(GM_ERR_OUT_OF_GRID, -5, "a material point is outside the background grid") \
  X(GM_ERR_NOT_FINITE, -6, "a non-finite value (NaN or infinity) appeared")    \
  X(GM_ERR_UNSTABLE_DT, -7, "the time step exceeds the stable bound")          \
  X(GM_ERR_CALLBACK, -8, "a user callback reported a failure")                 \
  X(GM_ERR_UNKNOWN_MATERIAL, -9, "no material with that id")                   \
  X(GM_ERR_UNKNOWN_POINT, -10, "no material point with that id")               \
  X(GM_ERR_IO, -11, "a file could not be read or written")                     \
  X(GM_ERR_BUSY, -12, "the domain is inside a step or callback")               \
  X(GM_ERR_UNSUPPORTED, -13, "not supported for this geometry or setting")

#define GM_STATUS_ENUM_ITEM_(name, value, text) name = value,
typedef enum gm_status { GM_STATUS_LIST(GM_STATUS_ENUM_ITEM_) } gm_status;
#undef GM_STATUS_ENUM_ITEM_

/** Static description of a status code; never NULL. */
GM_API const char *gm_strerror(gm_status status);

/* --------------------------------------------------------------- settings */

/** Geometry of a domain. Vectors have gm_geometry_dimension() components. */
typedef enum gm_geometry {
  GM_GEOMETRY_1D = 1,           /* uniaxial strain along x */
  GM_GEOMETRY_PLANE_STRAIN = 2, /* x, y; unit thickness in z */
  GM_GEOMETRY_AXISYMMETRIC = 3, /* x = radius r >= 0, y = axial z */
  GM_GEOMETRY_3D = 4            /* x, y, z; linear, uGIMP and cpGIMP
                                   shapes, plain family
                                   (gm_domain_create(3)) */
} gm_geometry;

/** Where in the explicit cycle the stress is updated (see 002 section 4.4). */
typedef enum gm_update_scheme {
  GM_SCHEME_USL = 0,  /* update stress last, from v + a dt */
  GM_SCHEME_MUSL = 1, /* modified USL: velocities re-mapped (Wieckowski) */
  GM_SCHEME_USF = 2   /* update stress first: half from v at the step's
                         start, half after the move (Nairn's USAVG) */
} gm_update_scheme;

/** Shape functions: how points and grid nodes exchange values (000 sec
 * 2.1). Every variant works in 1D, plane strain and axisymmetry. The GIMP
 * and CPDI domains may reach one ghost cell beyond the box faces (those
 * nodes take the face's condition); a domain reaching further, or touching
 * more than 9 nodes along an axis, fails the step with GM_ERR_OUT_OF_GRID.
 * The B-splines depend on the point's position only and reach the ghost
 * nodes next to a face, which keep them a partition of unity there. A
 * B-spline point's domain (for the granular domains of interaction and
 * the domain output) is its initial rectangle, as for uGIMP. Node counts
 * below are per point in 2D for domains up to a cell wide. */
typedef enum gm_shape {
  GM_SHAPE_LINEAR = 0,   /* original MPM: tents of the point's cell, 4 nodes */
  GM_SHAPE_UGIMP = 1,    /* GIMP, the initial rectangular domain: 9 nodes */
  GM_SHAPE_CPGIMP = 2,   /* GIMP, rectangle stretched by |F_xx|, |F_yy| */
  GM_SHAPE_CPDI = 3,     /* CPDI1: parallelogram spanned by F r1, F r2
                            (parallelepiped in 3D), reset to the initial
                            shape once too distorted (gm_domain_create(3)) */
  GM_SHAPE_BSPLINE2 = 4, /* quadratic B-splines on the nodes (Steffen et al.
                            2008): 3 nodes per axis, 9 in 2D */
  GM_SHAPE_BSPLINE3 = 5  /* cubic B-splines: 4 nodes per axis, 16 in 2D */
} gm_shape;

/** Algorithm family (000 sec 4): what happens to points of a granular
 * material (gm_domain_set_granular) below their critical density. */
typedef enum gm_family {
  GM_FAMILY_PLAIN = 0,       /* conventional MPM: nothing */
  GM_FAMILY_STRESS_FREE = 1, /* stress-free while rho < rho_cr (Dunatunga
                                and Kamrin) */
  GM_FAMILY_GRANULAR = 2     /* Granular MPM: point states, domains of
                                interaction, parallel grids and density
                                control (000 sec 3) */
} gm_family;

/** How velocities travel between points and grid (gm_domain_create(3)). */
typedef enum gm_transfer {
  GM_TRANSFER_FLIP = 0, /* FLIP, blended with PIC by pic_fraction (default) */
  GM_TRANSFER_APIC = 1  /* affine PIC (Jiang et al. 2015): each point also
                           carries an affine matrix (GM_FIELD_AFFINE);
                           linear and angular momentum survive the
                           transfers, without FLIP's noise */
} gm_transfer;

/** Boundary condition on one face of the grid box. GM_WALL_PERIODIC
 * joins the two x faces (both must have it): the nodes on x = x0 and
 * x = x0 + L are one node, a ghost node beyond one face is the image of
 * the node a box length L away, and a point leaving through one face comes
 * back through the other (gm_domain_create(3): plain and stress_free
 * families only; no planar walls or rigid materials; y faces, and z faces
 * in 3D, may not be periodic). */
typedef enum gm_wall_type {
  GM_WALL_OPEN = 0,     /* no condition: a point crossing it is an error */
  GM_WALL_FIXED = 1,    /* no-slip: both velocity components zero */
  GM_WALL_SLIP = 2,     /* frictionless: normal velocity zero */
  GM_WALL_PERIODIC = 3, /* the x faces wrap around onto each other */
  GM_WALL_SYMMETRY = 4  /* a symmetry plane: normal velocity always zero */
} gm_wall_type;
/* GM_WALL_FIXED and GM_WALL_SLIP are walls that material may leave: a
 * face node is held only while its material touches the face (a gap of at
 * most 0.01 cells), and material a fraction of a cell above the face falls
 * onto it. GM_WALL_SYMMETRY holds the normal velocity of its face nodes
 * whatever the gap, as the mirror image of the material beyond the plane
 * would: use it for the symmetry planes of a half or quarter domain
 * (gm_domain_create(3)). */

/** Faces of the grid box, indices into gm_domain_def.walls. */
enum {
  GM_FACE_XMIN = 0,
  GM_FACE_XMAX = 1,
  GM_FACE_YMIN = 2,
  GM_FACE_YMAX = 3,
  GM_FACE_ZMIN = 4,
  GM_FACE_ZMAX = 5
};

/* User task system (Box2D style), used instead of the built-in pool when
 * enqueue_task is set. The library calls enqueue_task once per parallel
 * loop; the task system must run task(start, end, worker, task_context)
 * over [0, item_count) in ranges of at least min_range items, with worker in
 * [0, worker_count). It may run it inline and return NULL. finish_task waits
 * for a non-NULL handle returned by enqueue_task. */
typedef void gm_task_fn(int start, int end, int worker, void *task_context);
typedef void *gm_enqueue_task_fn(gm_task_fn *task, int item_count,
                                 int min_range, void *task_context, void *user);
typedef void gm_finish_task_fn(void *user_task, void *user);

typedef struct gm_domain_def {
  size_t struct_size;      /* set by gm_domain_def_default() */
  gm_geometry geometry;    /* default GM_GEOMETRY_PLANE_STRAIN */
  double origin[3];        /* m, lower corner of the grid box */
  double extent[3];        /* m, size of the grid box; rounded up to cells */
  double cell_size;        /* m, edge of the square background cells */
  double gravity[3];       /* m/s^2, body acceleration; default 0 */
  gm_update_scheme scheme; /* default GM_SCHEME_USL */
  gm_wall_type walls[6];   /* per face (GM_FACE_*); default GM_WALL_OPEN */
  double cfl;              /* Courant number in (0, 1]; default 0.5 */
  int refuse_unstable_dt;  /* nonzero: dt above the bound fails; default 0 */
  int max_retries;         /* halvings of dt on a recoverable material
                              failure or an inverted F; default 4,
                              range 0..20 */
  int worker_count;        /* built-in pool threads, 1..256; default 1 */
  gm_enqueue_task_fn *enqueue_task; /* NULL: built-in pool */
  gm_finish_task_fn *finish_task;   /* required with enqueue_task */
  void *task_user;                  /* passed to the two functions above */
  double damping;      /* local non-viscous damping in [0, 1): every nodal force
                          component f loses damping * |f| against the node's
                          motion (Cundall's damping, for reaching static states;
                          it vanishes at equilibrium); default 0 = none */
  gm_shape shape;      /* shape functions; default GM_SHAPE_LINEAR */
  gm_family family;    /* default GM_FAMILY_PLAIN */
  double pic_fraction; /* a in [0, 1], -: share of PIC in the point
                          velocity update, v_p <- (1 - a) (v_p + dt sum N_i
                          a_i) + a sum N_i v_i (the FLIP-PIC blend).
                          Default 0 = FLIP (004 eq 3.17), which keeps the
                          kinetic energy of point velocity patterns the grid
                          cannot see (with more points than nodes) for
                          ever: a few percent lets a scene come to rest
                          (gm_domain_create(3)); 1 = PIC, dissipative.
                          Must be 0 with GM_TRANSFER_APIC. */
  gm_transfer transfer; /* default GM_TRANSFER_FLIP */
} gm_domain_def;

/** Defaults: the values in the field comments above, with extent 1 m
 * per axis and cell_size 0.1 m. gm_*_init convention (top of file):
 * gm_domain_def_init(&d, sizeof d) writes them, gm_domain_def_default() returns
 * them. */
GM_API gm_status gm_domain_def_init(gm_domain_def *out, size_t struct_size);

static inline gm_domain_def gm_domain_def_default(void) {
  gm_domain_def value;
  (void)gm_domain_def_init(&value, sizeof value);
  return value;
}

/** Number of vector components for a geometry (1, 2 or 3); 0 if unknown. */
GM_API int gm_geometry_dimension(gm_geometry geometry);

/* ----------------------------------------------------------------- domain */

typedef struct gm_domain gm_domain;

/** Creates a domain. On failure *out is NULL and the status says why;
 * gm_last_create_error() then holds the message. */
GM_API gm_status gm_domain_create(const gm_domain_def *def, gm_domain **out);
/** Message of the last failed gm_domain_create(), gm_series_create() or
 * gm_set_allocator() on this thread. */
GM_API const char *gm_last_create_error(void);
/** Frees the domain and everything it owns. NULL is a no-op, and so is a
 * call from inside a step hook or material callback of that domain. */
GM_API void gm_domain_destroy(gm_domain *domain);
/** Message describing the last error on this domain ("" if none). */
GM_API const char *gm_domain_last_error(const gm_domain *domain);

/* -------------------------------------------------------------- materials */

/** Stress and strain components, Voigt order. Shear strains are tensor
 * components (eps_xy), not engineering strains. In 1D and 2D the yz and zx
 * components are identically zero. Points do not store them
 * (gm_domain_view_field gives GM_ERR_UNSUPPORTED, gm_domain_get_field
 * copies zeros), but a gm_material_batch has all six rows: the yz and zx
 * rows of strain_increment and stress arrive zero, and values a material
 * writes into the stress ones are discarded. */
enum {
  GM_XX = 0,
  GM_YY = 1,
  GM_ZZ = 2, /* out of plane; the hoop component theta-theta in axisymmetry */
  GM_XY = 3,
  GM_YZ = 4,
  GM_ZX = 5
};

/** A batch of points handed to a material update, as SoA slices. The stress
 * arrives already rotated by the Jaumann spin (the library does that), so a
 * material only integrates its rate law over strain_increment. */
typedef struct gm_material_batch {
  size_t struct_size; /* sizeof as known by the library */
  size_t count;       /* points in this batch */
  int worker;         /* 0 .. worker_count-1, stable */
  int material;       /* material id */
  gm_geometry geometry;
  double dt;                         /* s */
  const double *strain_increment[6]; /* D dt per component (GM_XX..) */
  const double *density;             /* kg/m^3 at the end of the step */
  double *stress[6];    /* Pa, in: rotated sigma_t, out: t+dt; all six
                           valid (yz, zx: see GM_YZ above) */
  double *const *state; /* state[k][i], k < state_count */
  size_t state_count;
  const int64_t *point_id; /* ids, for error messages */
} gm_material_batch;

/** Material update: return 0 on success, > 0 for a recoverable failure (the
 * step is retried with dt halved), < 0 for a fatal one (the step fails with
 * GM_ERR_CALLBACK and the domain is unchanged). Runs on worker threads,
 * concurrently with other batches: it must be thread-safe and must not call
 * gm_* functions that change a domain. On failure it may write a message of
 * up to message_size bytes into message (NUL-terminated). */
typedef int gm_material_update_fn(const gm_material_batch *batch, void *user,
                                  char *message, size_t message_size);

typedef struct gm_material_def {
  size_t struct_size;
  const char *name;              /* copied; for messages and VTU */
  gm_material_update_fn *update; /* required */
  void *user;                    /* passed to update; must outlive domain */
  size_t state_count;            /* doubles of state per point, 0..64 */
  const double *initial_state;   /* state_count values; NULL = zeros */
  double p_wave_modulus;         /* Pa, upper bound of K + 4G/3 (> 0):
                                    sets the stable time step */
  double density;                /* kg/m^3, default for new points (> 0) */
} gm_material_def;

/** Defaults: name "user", every other field 0 or NULL (update,
 * p_wave_modulus and density must be set). gm_*_init convention (top of file):
 * gm_material_def_init(&d, sizeof d) writes them, gm_material_def_default()
 * returns them. */
GM_API gm_status gm_material_def_init(gm_material_def *out, size_t struct_size);

static inline gm_material_def gm_material_def_default(void) {
  gm_material_def value;
  (void)gm_material_def_init(&value, sizeof value);
  return value;
}

/** Registers a user material; *material_id receives its id (0, 1, ...). */
GM_API gm_status gm_domain_add_material(gm_domain *domain,
                                        const gm_material_def *def,
                                        int *material_id);

/** Isotropic linear elasticity (hypoelastic, with the Jaumann rate). */
typedef struct gm_elastic_def {
  size_t struct_size;
  const char *name;
  double youngs_modulus; /* Pa, > 0 */
  double poisson_ratio;  /* -1 < nu < 0.5 */
  double density;        /* kg/m^3, > 0 */
} gm_elastic_def;

/** Defaults: E = 1 MPa, nu = 0.3, density 1000 kg/m^3. gm_*_init convention
 * (top of file): gm_elastic_def_init(&d, sizeof d) writes them,
 * gm_elastic_def_default() returns them. */
GM_API gm_status gm_elastic_def_init(gm_elastic_def *out, size_t struct_size);

static inline gm_elastic_def gm_elastic_def_default(void) {
  gm_elastic_def value;
  (void)gm_elastic_def_init(&value, sizeof value);
  return value;
}

/** Registers the built-in linear elastic material (written against the same
 * gm_material_update_fn interface as user materials). */
GM_API gm_status gm_domain_add_elastic(gm_domain *domain,
                                       const gm_elastic_def *def,
                                       int *material_id);

/** The built-in elastic update itself, for users composing materials:
 * `user` must point to a gm_elastic_def. */
GM_API int gm_elastic_update(const gm_material_batch *batch, void *user,
                             char *message, size_t message_size);

/* ------------------------------------------------------------------ walls */

/** A rigid planar wall with Coulomb friction, enforced on grid nodes (any
 * normal: inclined chutes, hopper walls, or a box face made frictional).
 * Nodes on or behind the plane that carry mass and move into it faster
 * than their material's gap to the wall allows (the smallest distance
 * from the wall to the domain of a point on the node, over dt; gaps below
 * 0.003 cells count as contact) lose the excess normal velocity (the wall
 * pushes, never pulls, and material that left it can come back) and
 * their tangential velocity is reduced by at most mu times that normal
 * velocity change: they stick when that is enough (mu_static), otherwise
 * slide with mu_kinetic. Nodes further in front that carry a point centre
 * near the plane (with the shapes wider than a tent; with linear shapes
 * those less than h (|n_x| + |n_y| + |n_z|) in front of an oblique plane,
 * in 2D as in 3D) approach it at most by that centre's distance in a
 * step, so no point centre passes through a wall. With the B-splines,
 * in every geometry, a wall parallel to a slip, fixed or symmetry box
 * face (or to the axis r = 0 in axisymmetry) and less than 1.5
 * (quadratic) or 2 (cubic) cells from its plane is refused
 * (GM_ERR_UNSUPPORTED): those faces are mirrors for them, which would undo
 * its friction; leave the face GM_WALL_OPEN to put a wall on its plane.
 * See gm_walls(3). */
typedef struct gm_wall_def {
  size_t struct_size;
  double point[3];         /* m, any point of the plane */
  double normal[3];        /* pointing into the material side; normalised */
  double friction_static;  /* mu_s >= 0 */
  double friction_kinetic; /* mu_k, 0 <= mu_k <= mu_s */
} gm_wall_def;

/** Defaults: a frictionless floor through the origin (normal
 * (0, 1, 0), friction 0). gm_*_init convention (top of file):
 * gm_wall_def_init(&d, sizeof d) writes them, gm_wall_def_default() returns
 * them. */
GM_API gm_status gm_wall_def_init(gm_wall_def *out, size_t struct_size);

static inline gm_wall_def gm_wall_def_default(void) {
  gm_wall_def value;
  (void)gm_wall_def_init(&value, sizeof value);
  return value;
}

/** Adds a wall; *wall_id receives its id (0, 1, ...). At most 64 walls. */
GM_API gm_status gm_domain_add_wall(gm_domain *domain, const gm_wall_def *def,
                                    int *wall_id);

/** What a wall did to the material (N; per unit thickness in plane
 * strain, per unit area in 1D, the whole ring in axisymmetry), see
 * gm_walls(3). Contact acts on grid nodes as a velocity constraint: the
 * impulse of one step is the momentum of the nodes moving into the wall,
 * whatever the step's length, so impulse / dt spikes after a very short
 * step (a 1e-12 s step right after a gap closed: ~1e12 N). The impulses
 * are exact; `smoothed_force` is a force that cannot spike. */
typedef struct gm_wall_force {
  size_t struct_size;
  /* The last successful gm_domain_step() call, averaged over its dt: */
  double force[3];   /* N, impulse / duration */
  double normal;     /* N, force . normal */
  double tangential; /* N, |force - normal * n| */
  /* Appended (a caller compiled with the struct ending above still works:
   * only its fields are written): */
  double impulse[3];         /* N s, of the wall on the material in that call */
  double normal_impulse;     /* N s, impulse . normal (>= 0) */
  double tangential_impulse; /* N s, |impulse - normal_impulse * n| */
  double duration;           /* s, the time that call covered (its dt) */
  double total_impulse[3];   /* N s, summed over every successful call since
                                the wall was added */
  double total_duration;     /* s, the time total_impulse covers */
  double smoothed_force[3];  /* N, the force through a first-order low-pass
                                filter of time constant smoothing_time: its
                                magnitude grows by at most |impulse| /
                                smoothing_time in any one call */
  double smoothed_normal;    /* N, smoothed_force . normal */
  double smoothed_tangential; /* N, |smoothed_force - smoothed_normal * n| */
  double smoothing_time;      /* s, gm_domain_set_force_smoothing_time() */
} gm_wall_force;

/** Defaults: zeros. gm_*_init convention (top of file):
 * gm_wall_force_init(&d, sizeof d) writes them, gm_wall_force_default() returns
 * them. */
GM_API gm_status gm_wall_force_init(gm_wall_force *out, size_t struct_size);

static inline gm_wall_force gm_wall_force_default(void) {
  gm_wall_force value;
  (void)gm_wall_force_init(&value, sizeof value);
  return value;
}

GM_API gm_status gm_domain_get_wall_force(const gm_domain *domain, int wall_id,
                                          gm_wall_force *force);

/* ------------------------------------------------------ rigid obstacles */

/** Rigid material points: a retaining wall, a load-cell plate, a moving
 * tool. Points of a rigid material move with its prescribed velocity and
 * carry no stress; the grid nodes they touch take that velocity (no-slip)
 * for the deformable material, and the library reports the force the
 * material exerts on them (the impact force of 000 sec 4.4). In
 * GM_GEOMETRY_3D (linear, uGIMP and cpGIMP shapes) the nodes of a point's
 * cell or box take all three components and the force has a z component.
 * See gm_rigid(3). */
typedef struct gm_rigid_def {
  size_t struct_size;
  const char *name;   /* copied */
  double density;     /* kg/m^3, > 0: gives the points a mass (reported) */
  double velocity[3]; /* m/s, prescribed, dim components used (z: 3D);
                         change with gm_domain_set_rigid_velocity() */
} gm_rigid_def;

/** Defaults: name "rigid", density 1000 kg/m^3, at rest. gm_*_init convention
 * (top of file): gm_rigid_def_init(&d, sizeof d) writes them,
 * gm_rigid_def_default() returns them. */
GM_API gm_status gm_rigid_def_init(gm_rigid_def *out, size_t struct_size);

static inline gm_rigid_def gm_rigid_def_default(void) {
  gm_rigid_def value;
  (void)gm_rigid_def_init(&value, sizeof value);
  return value;
}

/** Registers a rigid material; add its points with gm_domain_add_points()
 * or gm_domain_fill_box() as for any material. */
GM_API gm_status gm_domain_add_rigid(gm_domain *domain, const gm_rigid_def *def,
                                     int *material_id);

/** Sets the prescribed velocity (m/s, dim components used) of a rigid
 * material from the next step on. */
GM_API gm_status gm_domain_set_rigid_velocity(gm_domain *domain,
                                              int material_id,
                                              const double velocity[3]);

/** Force (N, units as gm_domain_get_wall_force) the deformable material
 * exerted on the rigid material's points during the last successful
 * gm_domain_step() call, averaged over its dt: impulse / dt, which spikes
 * after a very short step; gm_domain_get_rigid_load() also reports the
 * impulse and a smoothed force. force[2] is the z component in
 * GM_GEOMETRY_3D and 0 otherwise (as in gm_rigid_load). */
GM_API gm_status gm_domain_get_rigid_force(const gm_domain *domain,
                                           int material_id, double force[3]);

/** The load the deformable material put on a rigid material: the fields
 * of gm_wall_force without the wall's normal/tangential split. */
typedef struct gm_rigid_load {
  size_t struct_size;
  double force[3];          /* N, impulse / duration of the last call */
  double impulse[3];        /* N s, in the last successful step call */
  double duration;          /* s, the time that call covered (its dt) */
  double total_impulse[3];  /* N s, summed over every successful call since
                               the rigid material was added */
  double total_duration;    /* s, the time total_impulse covers */
  double smoothed_force[3]; /* N, low-pass filtered force (time constant
                               smoothing_time) */
  double smoothing_time;    /* s */
} gm_rigid_load;

/** Defaults: zeros. gm_*_init convention (top of file):
 * gm_rigid_load_init(&d, sizeof d) writes them, gm_rigid_load_default()
 * returns them. */
GM_API gm_status gm_rigid_load_init(gm_rigid_load *out, size_t struct_size);

static inline gm_rigid_load gm_rigid_load_default(void) {
  gm_rigid_load value;
  (void)gm_rigid_load_init(&value, sizeof value);
  return value;
}

GM_API gm_status gm_domain_get_rigid_load(const gm_domain *domain,
                                          int material_id, gm_rigid_load *load);

/** Time constant (s, finite, > 0; default 1e-3 s) of the low-pass filter
 * behind the smoothed forces of walls and rigid materials: tau dF/dt =
 * f(t) - F, with f each step call's impulse spread evenly over its dt.
 * Takes effect from the next step; the filter state carries on. */
GM_API gm_status gm_domain_set_force_smoothing_time(gm_domain *domain,
                                                    double seconds);

/* ------------------------------------------------------ sources and sinks */

/** A source injects `count` points of a material at fixed positions, once
 * or periodically (000 sec 4.3: 3 points every 0.17 s; 001 sec 5.1.2: a
 * 12 x 12 block every 0.2 s). Injection happens at the start of the first
 * step whose start time is >= the injection time; it is part of that step
 * (undone if the step fails). See gm_sources(3). */
typedef struct gm_source_def {
  size_t struct_size;
  int material;
  size_t count;           /* points per injection, >= 1 */
  const double *position; /* m, count * dim, copied */
  double velocity[3];     /* m/s, of every injected point */
  double point_size;      /* m, edge of each point's square domain: volume
                             size (1D), size^2 (plane strain) or
                             2 pi r size^2 (axisymmetry) */
  double density;         /* kg/m^3; 0 = the material's density */
  double start_time;      /* s, first injection */
  double period;          /* s between injections; 0 = inject once */
  int max_injections;     /* 0 = no limit */
} gm_source_def;

/** Defaults: every field 0 or NULL (material, count, position and
 * point_size must be set). gm_*_init convention (top of file):
 * gm_source_def_init(&d, sizeof d) writes them, gm_source_def_default() returns
 * them. */
GM_API gm_status gm_source_def_init(gm_source_def *out, size_t struct_size);

static inline gm_source_def gm_source_def_default(void) {
  gm_source_def value;
  (void)gm_source_def_init(&value, sizeof value);
  return value;
}

/** Adds a source; *source_id (required, not NULL) receives its id. */
GM_API gm_status gm_domain_add_source(gm_domain *domain,
                                      const gm_source_def *def, int *source_id);

/** A sink removes every point whose position enters its box (an orifice)
 * at the end of a step, and accumulates the removed mass. Removed ids are
 * never reused; gm_domain_point_index() then reports them unknown. */
typedef struct gm_sink_def {
  size_t struct_size;
  double lower[3]; /* m, box corner; a point x is in when lower <= x */
  double upper[3]; /* m, opposite corner; ... and x < upper */
} gm_sink_def;

/** Defaults: an empty box at the origin (zeros). gm_*_init convention (top of
 * file): gm_sink_def_init(&d, sizeof d) writes them, gm_sink_def_default()
 * returns them. */
GM_API gm_status gm_sink_def_init(gm_sink_def *out, size_t struct_size);

static inline gm_sink_def gm_sink_def_default(void) {
  gm_sink_def value;
  (void)gm_sink_def_init(&value, sizeof value);
  return value;
}

GM_API gm_status gm_domain_add_sink(gm_domain *domain, const gm_sink_def *def,
                                    int *sink_id);

/** Mass and number of points a source injected or a sink removed so far. */
typedef struct gm_flow_totals {
  size_t struct_size;
  double mass;     /* kg (units as gm_points_def masses) */
  uint64_t points; /* count */
} gm_flow_totals;

/** Defaults: zeros. gm_*_init convention (top of file):
 * gm_flow_totals_init(&d, sizeof d) writes them, gm_flow_totals_default()
 * returns them. */
GM_API gm_status gm_flow_totals_init(gm_flow_totals *out, size_t struct_size);

static inline gm_flow_totals gm_flow_totals_default(void) {
  gm_flow_totals value;
  (void)gm_flow_totals_init(&value, sizeof value);
  return value;
}

GM_API gm_status gm_domain_get_source_totals(const gm_domain *domain,
                                             int source_id,
                                             gm_flow_totals *totals);
GM_API gm_status gm_domain_get_sink_totals(const gm_domain *domain, int sink_id,
                                           gm_flow_totals *totals);

/* --------------------------------------------------------------- granular */

/** What the granular family does to a connected point whose density fell
 * below rho_cr - TOL in a step (000 sec 3.2). */
typedef enum gm_density_control {
  GM_DENSITY_CONTROL_RETURN = 0, /* eqs 13-15: stress 0, F back to the
                                    previous step's, V = det F V0 */
  GM_DENSITY_CONTROL_SCALE = 1   /* eq 18: stress 0, F scaled by
                                    (V_cr / V)^(1/d): keeps the step's
                                    rotation and shear, not its dilation */
} gm_density_control;

typedef struct gm_granular_def {
  size_t struct_size;
  double critical_density; /* kg/m^3, rho_cr > 0: V_cr = m / rho_cr, the
                              largest volume of a point (granular family:
                              points are placed at rho >= rho_cr - TOL) */
  double tolerance;        /* kg/m^3, TOL >= 0; default 1e-6 */
  gm_density_control density_control; /* default ..._RETURN */
} gm_granular_def;

/** Defaults: critical_density 0 (must be set), tolerance 1e-6 kg/m^3,
 * GM_DENSITY_CONTROL_RETURN. gm_*_init convention (top of file):
 * gm_granular_def_init(&d, sizeof d) writes them, gm_granular_def_default()
 * returns them. */
GM_API gm_status gm_granular_def_init(gm_granular_def *out, size_t struct_size);

static inline gm_granular_def gm_granular_def_default(void) {
  gm_granular_def value;
  (void)gm_granular_def_init(&value, sizeof value);
  return value;
}

/** Makes a material granular: the stress_free and granular families act
 * on its points. Call before adding its points. Points of other materials
 * (elastic walls, rigid plates) take part in the granular method with
 * their own current domain as domain of interaction, and two such points
 * interact whenever they share a grid node, as in plain MPM.
 * In the granular family V_cr = m / rho_cr is the largest volume a point
 * may have (000 sec 3.3): gm_domain_add_points, gm_domain_fill_box and
 * gm_domain_add_source refuse points of a granular material placed below
 * rho_cr - TOL (GM_ERR_INVALID_ARGUMENT), and this call refuses a rho_cr
 * that would leave an existing point of the material, or a source of it
 * with injections left, below rho_cr - TOL (gm_granular(3)). */
GM_API gm_status gm_domain_set_granular(gm_domain *domain, int material,
                                        const gm_granular_def *def);

/** States of the granular method (GM_FIELD_STATE), decided in each step of
 * the granular family; in the other families every point reports
 * GM_STATE_QUASI_STATIC. */
typedef enum gm_point_state {
  GM_STATE_QUASI_STATIC = 0, /* connected, rho > rho_cr + TOL */
  GM_STATE_MODERATE = 1,     /* connected, rho at rho_cr: within TOL, or
                                held there by density control this step */
  GM_STATE_DISCONNECTED = 2  /* its domain of interaction met no other:
                                alone on its grid; a granular point is
                                then stress-free with F and density
                                frozen, others keep their behaviour */
} gm_point_state;

typedef struct gm_granular_summary {
  size_t struct_size;
  size_t state_count[3];  /* points per gm_point_state, last step */
  size_t component_count; /* parallel grids (connected components) */
  size_t layer_count;     /* node layers that held them (components
                             sharing no node share a layer) */
  int forest_reused;      /* 1: the previous step's spanning forest still held,
                             so only points outside the largest component
                             searched for partners */
  /* Wall time of the last step's granular phases (s), for profiling:
   * supports and domains of interaction; pair search with union-find;
   * labels; node layers and re-binning; density control (summed over
   * workers). */
  double geometry_seconds, pair_search_seconds, label_seconds, layer_seconds,
      density_control_seconds;
} gm_granular_summary;

/** Defaults: zeros. gm_*_init convention (top of file):
 * gm_granular_summary_init(&d, sizeof d) writes them,
 * gm_granular_summary_default() returns them. */
GM_API gm_status gm_granular_summary_init(gm_granular_summary *out,
                                          size_t struct_size);

static inline gm_granular_summary gm_granular_summary_default(void) {
  gm_granular_summary value;
  (void)gm_granular_summary_init(&value, sizeof value);
  return value;
}

/** Statistics of the last committed step. state_count counts
 * GM_FIELD_STATE (every point quasi-static outside the granular family and
 * before its first step); the other counts and times are zero there. */
GM_API gm_status gm_domain_get_granular_summary(const gm_domain *domain,
                                                gm_granular_summary *summary);

/* ----------------------------------------------------------------- points */

/* Per-point arrays are interleaved: position[i*dim + k], dim from
 * gm_geometry_dimension(). "Volume" is per unit area in 1D (m), per unit
 * thickness in plane strain (m^2), and the full 2*pi*r ring in axisymmetry
 * (m^3); masses (kg) follow the same convention. */
typedef struct gm_points_def {
  size_t struct_size;
  size_t count;
  int material;              /* from gm_domain_add_material/elastic */
  const double *position;    /* m, count*dim, required */
  const double *velocity;    /* m/s, count*dim; NULL = at rest */
  const double *volume;      /* count, > 0, required */
  const double *mass;        /* kg, count; NULL = density * volume */
  const double *density;     /* kg/m^3, count; NULL = material density;
                                ignored where mass is given */
  const double *domain_size; /* m, count*dim, initial particle domain
                                edge lengths (used by GIMP/CPDI and the
                                granular method); NULL = the volume in
                                1D, its square root in plane strain,
                                sqrt(V / (2 pi r)) in axisymmetry, its
                                cube root in 3D */
  const double *stress;      /* Pa, count*6 (Voigt, GM_XX..); NULL = 0 */
} gm_points_def;

/** Defaults: every field 0 or NULL (count, position and volume must
 * be set). gm_*_init convention (top of file):
 * gm_points_def_init(&d, sizeof d) writes them, gm_points_def_default() returns
 * them. */
GM_API gm_status gm_points_def_init(gm_points_def *out, size_t struct_size);

static inline gm_points_def gm_points_def_default(void) {
  gm_points_def value;
  (void)gm_points_def_init(&value, sizeof value);
  return value;
}

/** Adds points. Ids are first_id, first_id+1, ...; they never change and are
 * never reused. first_id may be NULL. All-or-nothing: on error no point is
 * added. */
GM_API gm_status gm_domain_add_points(gm_domain *domain,
                                      const gm_points_def *def,
                                      int64_t *first_id);

typedef struct gm_fill_def {
  size_t struct_size;
  int material;
  double lower[3];          /* m, box corner */
  double upper[3];          /* m, opposite corner */
  int points_per_cell_axis; /* n: n^dim points per full cell, 1..16 */
  double velocity[3];       /* m/s, initial velocity */
  double density;           /* kg/m^3; 0 = the material's density */
} gm_fill_def;

/** Defaults: points_per_cell_axis 2, every other field 0. gm_*_init convention
 * (top of file): gm_fill_def_init(&d, sizeof d) writes them,
 * gm_fill_def_default() returns them. */
GM_API gm_status gm_fill_def_init(gm_fill_def *out, size_t struct_size);

static inline gm_fill_def gm_fill_def_default(void) {
  gm_fill_def value;
  (void)gm_fill_def_init(&value, sizeof value);
  return value;
}

/** Fills the box with points on a regular lattice of spacing
 * cell_size / n, each at the centre of its sub-cell. first_id and count
 * (points added) may be NULL. */
GM_API gm_status gm_domain_fill_box(gm_domain *domain, const gm_fill_def *def,
                                    int64_t *first_id, size_t *count);

/** Number of points. */
GM_API size_t gm_domain_point_count(const gm_domain *domain);

/** Point fields. Fields are stored per point index; indices may change at
 * every step (points are kept sorted by cell), ids never change. */
typedef enum gm_field {
  GM_FIELD_POSITION = 0,             /* m, dim components */
  GM_FIELD_VELOCITY = 1,             /* m/s, dim components, writable */
  GM_FIELD_EXTERNAL_FORCE = 2,       /* N, dim components, writable; added each
                                        step until changed */
  GM_FIELD_MASS = 3,                 /* kg */
  GM_FIELD_VOLUME = 4,               /* current volume */
  GM_FIELD_INITIAL_VOLUME = 5,       /* volume at creation */
  GM_FIELD_DENSITY = 6,              /* kg/m^3, mass / volume */
  GM_FIELD_STRESS = 7,               /* Pa, 6 components GM_XX..GM_ZX */
  GM_FIELD_DEFORMATION_GRADIENT = 8, /* 9 components, row-major F_ij */
  GM_FIELD_MATERIAL = 9,             /* material id as double */
  GM_FIELD_ID = 10,                  /* point id as double (exact below 2^53) */
  GM_FIELD_DOMAIN_SIZE = 11,    /* m, dim components, initial domain size */
  GM_FIELD_DOMAIN_CORNERS = 12, /* m, current domain (copy only): 2 ends in
                                   1D; in 2D 4 corners x, y
                                   counter-clockwise from the lower left
                                   (see gm_shape); in 3D 8 corners x, y, z
                                   in VTK_HEXAHEDRON order (gm_fields(3)) */
  GM_FIELD_STATE = 13,          /* gm_point_state of the last step */
  GM_FIELD_COMPONENT = 14,      /* parallel grid of the last step: 0, 1, ...
                                   in order of each grid's smallest point
                                   id; 0 outside the granular family */
  GM_FIELD_AFFINE = 15          /* APIC's affine matrix, dim x dim
                                   row-major (xx, xy, yx, yy in 2D): B_p =
                                   sum_i N_ip v_i (x_i - x_p)^T, m^2/s, for
                                   GIMP and CPDI; C_p = sum_i v_i (x) grad
                                   N_ip, 1/s, for linear MPM (see
                                   gm_domain_create(3)); writable, to start
                                   an affine velocity field; stored with
                                   GM_TRANSFER_APIC only (zeros otherwise) */
} gm_field;

/** Number of components of a field in this domain's geometry. */
GM_API gm_status gm_domain_field_components(const gm_domain *domain,
                                            gm_field field, size_t *components);

/** Copies a field for all points, interleaved (out[i*components + k]), in
 * point-index order. out_length is the capacity of out in doubles. */
GM_API gm_status gm_domain_get_field(const gm_domain *domain, gm_field field,
                                     double *out, size_t out_length);

/** Copies the point ids in point-index order. */
GM_API gm_status gm_domain_get_ids(const gm_domain *domain, int64_t *out,
                                   size_t out_length);

/** Index of the point with that id. */
GM_API gm_status gm_domain_point_index(const gm_domain *domain, int64_t id,
                                       size_t *index);

/** Copies values into a writable field for all points, interleaved
 * (values[i*components + k]) in point-index order, as gm_domain_get_field
 * gives them: GM_FIELD_VELOCITY, GM_FIELD_EXTERNAL_FORCE and (with
 * GM_TRANSFER_APIC) GM_FIELD_AFFINE. length must be exactly point count x
 * components. Every value must be finite: a NaN or infinity is refused
 * (naming the point id and component) and nothing is written. Allowed
 * between steps and from a step hook. The stable way to set point
 * velocities; gm_domain_edit_field() is the zero-copy, provisional one. */
GM_API gm_status gm_domain_set_field(gm_domain *domain, gm_field field,
                                     const double *values, size_t length);

/* ------------------------------------------------------------------- step */

/** Where a step hook is called. */
typedef enum gm_hook_stage {
  GM_HOOK_BEFORE_STEP = 0, /* before dt is chosen and checked and before any
                              transfer; the hook may edit velocities and
                              external forces (the stable dt sees them) */
  GM_HOOK_AFTER_STEP = 1   /* after the step is committed */
} gm_hook_stage;

/** A nonzero return at GM_HOOK_BEFORE_STEP cancels the step with
 * GM_ERR_CALLBACK (edits the hook made stay). The hook may read fields and
 * use gm_domain_set_field() or gm_domain_edit_field(); other state-changing
 * calls give GM_ERR_BUSY. */
typedef int gm_step_hook_fn(gm_domain *domain, gm_hook_stage stage, void *user);

/** Installs (or with NULL removes) the step hook. */
GM_API gm_status gm_domain_set_step_hook(gm_domain *domain,
                                         gm_step_hook_fn *hook, void *user);

/** Advances by dt seconds; dt <= 0 means the largest stable dt. On error the
 * domain is exactly as before the call (except for edits made by a hook). */
GM_API gm_status gm_domain_step(gm_domain *domain, double dt);

/** Largest stable dt for the current state: cfl * h / (max c_p + max |v_p|)
 * (a safe bound of the fastest signal max(c_p + |v_p|)), with
 * c_p = sqrt(M / rho_p) the P-wave speed (004 eq 3.11-3.12). Velocities
 * edited with gm_domain_edit_field() are taken into account. */
GM_API gm_status gm_domain_stable_dt(const gm_domain *domain, double *dt);

/** Simulated time (s) and number of completed steps (a dt-halving retry
 * counts each sub-step); either pointer may be NULL, not both. */
GM_API gm_status gm_domain_get_time(const gm_domain *domain, double *time,
                                    uint64_t *step_count);

typedef struct gm_summary {
  size_t struct_size;
  double mass;              /* kg */
  double momentum[3];       /* kg m/s */
  double kinetic_energy;    /* J */
  double centre_of_mass[3]; /* m */
} gm_summary;

/** Defaults: zeros. gm_*_init convention (top of file):
 * gm_summary_init(&d, sizeof d) writes them, gm_summary_default() returns them.
 */
GM_API gm_status gm_summary_init(gm_summary *out, size_t struct_size);

static inline gm_summary gm_summary_default(void) {
  gm_summary value;
  (void)gm_summary_init(&value, sizeof value);
  return value;
}

/** Totals over all points (summed in index-independent order). */
GM_API gm_status gm_domain_get_summary(const gm_domain *domain,
                                       gm_summary *summary);

/* ----------------------------------------------------------------- output */

/** Writes all points and fields as a VTK XML unstructured grid (.vtu) with
 * raw binary appended data. */
GM_API gm_status gm_domain_write_vtu(const gm_domain *domain, const char *path);

/** A ParaView time series: a .pvd file listing one .vtu per frame. */
typedef struct gm_series gm_series;

/** Starts a series at pvd_path (e.g. "out/bar.pvd"); frames are written
 * beside it as <stem>_NNNNNN.vtu. The directory must exist. */
GM_API gm_status gm_series_create(const char *pvd_path, gm_series **out);
/** Writes the domain's current state as the next frame and rewrites the
 * .pvd so it is complete after every call. */
GM_API gm_status gm_series_write(gm_series *series, const gm_domain *domain);
/** Writes every point's current domain (GM_FIELD_DOMAIN_CORNERS) as a
 * polygon: a VTK_QUAD per point in 2D, a VTK_LINE in 1D, a VTK_HEXAHEDRON
 * in 3D, with the point's
 * fields as cell data, so ParaView draws the domains (000 Figs 12, 16). */
GM_API gm_status gm_domain_write_domains_vtu(const gm_domain *domain,
                                             const char *path);
/** Nonzero: every later gm_series_write also writes the domains beside the
 * frame (<stem>_domains_NNNNNN.vtu), listed in the .pvd as part 1 of the
 * same time step. Default 0. */
GM_API gm_status gm_series_set_domains(gm_series *series, int enabled);
/** Frees the series (files stay). NULL is a no-op. */
GM_API void gm_series_destroy(gm_series *series);

/* ------------------------------------------------------- long runs, restart */

/** Called by gm_domain_advance after every committed step with the time
 * reached (s); return nonzero to stop the run there. */
typedef int gm_progress_fn(const gm_domain *domain, double time,
                           double end_time, void *user);

/** Steps until the domain's time reaches end_time (s) exactly: steps of dt
 * (s; <= 0: the stable dt of each step), the last one shortened. progress
 * may be NULL. A progress callback that returns nonzero stops the run with
 * GM_ERR_CALLBACK (the domain keeps every step committed so far); a failed
 * step returns its status, the domain as after the last good step. */
GM_API gm_status gm_domain_advance(gm_domain *domain, double end_time,
                                   double dt, gm_progress_fn *progress,
                                   void *user);

/** Writes a checkpoint of the domain's state (points, time, step count,
 * sources, sinks, wall and rigid totals) to path: a versioned binary file
 * with a checksum, written to a temporary file that is flushed and renamed
 * over path, so a crash never leaves a broken file under path. Materials
 * (user callbacks included), walls, sources and sinks are not code the
 * file can hold: a restart builds the same setup, then loads. */
GM_API gm_status gm_domain_save(const gm_domain *domain, const char *path);

/** Restores a checkpoint into a domain built with the same gm_domain_def,
 * materials, walls, rigid bodies, sources and sinks (a fingerprint of the
 * setup is stored and checked). The run then continues bitwise identically
 * to the uninterrupted one. Truncated, corrupted or mismatched files are
 * refused (GM_ERR_IO or GM_ERR_INVALID_ARGUMENT with a message), leaving
 * the domain unchanged. */
GM_API gm_status gm_domain_load(gm_domain *domain, const char *path);

/* ------------------------------------------------------------------ hooks */

typedef struct gm_allocator {
  size_t struct_size;
  void *(*malloc_fn)(size_t size, void *user);
  void (*free_fn)(void *pointer, void *user);
  void *user;
} gm_allocator;

/** Replaces malloc/free for all later allocations (NULL restores the
 * default). Call before creating any domain; not thread-safe. */
GM_API gm_status gm_set_allocator(const gm_allocator *allocator);

/* ------------------------------------------------- built-in material models */
/* Each written against the public gm_material_update_fn interface. */
#include "granmpm/drucker_prager.h"
#include "granmpm/filling.h"
#include "granmpm/mohr_coulomb.h"
#include "granmpm/perzyna.h"
#include "granmpm/stress_free.h"
#include "granmpm/von_mises.h"

/* ============================================================ PROVISIONAL
 * Everything above this line is the stable API: from 1.0 on it changes only
 * by additions (new functions, new enum values, new fields at the end of a
 * struct that starts with struct_size), and 0.x releases already keep to
 * that. Everything below is provisional: exported and versioned like the
 * rest (the ABI check covers it), but its shape may still change in a 0.x
 * release, each change named in the release notes:
 *  - the zero-copy views gm_domain_view_field(), gm_domain_edit_field(),
 *    gm_domain_view_ids(): they promise that each component of a field is
 *    one contiguous array of doubles in point-index order, a storage layout
 *    the coming speed and 3D work may change (the copies
 *    gm_domain_get_field() and gm_domain_set_field() are stable);
 *  - the wall traction profile gm_domain_get_wall_tractions(): its entry
 *    struct has no struct_size to grow by, and its per-node force is the
 *    impulse / dt that spikes after a very short step (gm_wall_force's
 *    impulses and smoothed force are the stable readings);
 *  - the mu(I) material (granmpm/mu_i.h): its parameters may still
 *    change (its steady inclined-plane flow matches the Bagnold profile to
 *    3 % on a periodic chute, tests/physics/test_bagnold.c);
 *  - the volumetric averaging gm_domain_set_volumetric(): the averaging
 *    (over a cell, volume-weighted) may change as its measurements
 *    (docs/convergence.md section 26) go on.
 * This is zstd's static-linking-only section turned around: a program that
 * must rely on the stable part only defines GM_STABLE_ONLY before including
 * this header, and the compiler then names every provisional call it makes.
 * Without it (the default) both parts are declared, so existing programs
 * compile unchanged. See granmpm(3), STABILITY. */
#ifndef GM_STABLE_ONLY

/* ------------------------------------------------- zero-copy field access */

/** Zero-copy access to one component of a stored field (point-index order,
 * point_count values). Valid until the next call that changes the domain.
 * Components that are identically zero in this geometry, and computed
 * fields (GM_FIELD_DENSITY, GM_FIELD_MATERIAL, GM_FIELD_ID,
 * GM_FIELD_DOMAIN_CORNERS, and GM_FIELD_STATE and GM_FIELD_COMPONENT, which
 * the granular family stores as small integers, not doubles), are not
 * stored as doubles and give GM_ERR_UNSUPPORTED: copy them with
 * gm_domain_get_field. */
GM_API gm_status gm_domain_view_field(const gm_domain *domain, gm_field field,
                                      size_t component, const double **data);

/** Writable zero-copy access, for GM_FIELD_VELOCITY,
 * GM_FIELD_EXTERNAL_FORCE and (with GM_TRANSFER_APIC) GM_FIELD_AFFINE only,
 * between steps or from a step hook. Values written are validated at the
 * start of the next step. */
GM_API gm_status gm_domain_edit_field(gm_domain *domain, gm_field field,
                                      size_t component, double **data);

/** Zero-copy access to the ids (point-index order). */
GM_API gm_status gm_domain_view_ids(const gm_domain *domain,
                                    const int64_t **ids);

/* ---------------------------------------------------- wall traction profile */

/** One node's share of a wall's load: the traction profile along a wall
 * (the wall-traction plots of 001/002). */
typedef struct gm_wall_traction {
  double position;   /* m along the wall from def.point, in the direction
                        (normal_y, -normal_x) */
  double normal;     /* Pa: the node's normal force per cell length (per
                        unit thickness in plane strain; in axisymmetry the
                        force on the whole ring, N/m: divide by 2 pi r for
                        a pressure), >= 0 */
  double tangential; /* Pa: its tangential (friction) force per cell
                        length, signed along the same direction */
} gm_wall_traction;

/** The nodes the wall acted on in the last committed step, sorted by
 * position. *count receives their number; if it exceeds capacity nothing
 * is written and GM_ERR_INVALID_ARGUMENT is returned (call again with a
 * larger buffer). After a failed step the profile is unavailable
 * (GM_ERR_INVALID_ARGUMENT) until the next successful one. */
GM_API gm_status gm_domain_get_wall_tractions(const gm_domain *domain,
                                              int wall_id,
                                              gm_wall_traction *tractions,
                                              size_t capacity, size_t *count);

/* ------------------------------------------------ volumetric averaging */
/** The volumetric strain rate each point's deformation takes
 * (gm_domain_set_volumetric(), gm_domain_create(3)). With several points per
 * cell, linear MPM enforces a flow's incompressibility (an elastic solid near
 * nu = 0.5, the plastic flow of a pressure-insensitive or psi = 0 material) at
 * every point of a cell; the cell's few nodal velocities cannot meet that many
 * constraints and the flow stiffens ("volumetric locking", docs/convergence.md
 * sections 25-26). GM_VOLUMETRIC_CELL_MEAN replaces each point's
 * volumetric rate tr L (1/s; in axisymmetry with the hoop rate v_r / r)
 * by the volume-weighted mean of tr L over the points in its background
 * cell and keeps the point's deviatoric part (the B-bar idea, Hughes
 * 1980, in the cell-wise form of Coombs et al. 2018, CMAME 333:1):
 * L_p <- L_p + (mean - tr L_p) / n I, n = 2 in plane strain, 3 in
 * axisymmetry (xx, yy and the hoop rate) and 3 in GM_GEOMETRY_3D (xx, yy,
 * zz; the cell of 8 nodes). F, the volume and the stress follow that L.
 * Plane strain, axisymmetry and 3D with every shape and family (the
 * granular family averages each component over its own points); rigid
 * points take no part. 1D (nothing to lock) is refused
 * (GM_ERR_UNSUPPORTED). Off by default: results are then those of the
 * library without it, bit for bit. */
typedef enum gm_volumetric {
  GM_VOLUMETRIC_POINT = 0,    /* each point its own tr L (default) */
  GM_VOLUMETRIC_CELL_MEAN = 1 /* tr L averaged over the cell's points */
} gm_volumetric;

/** Sets how the points' volumetric strain rate is taken (above), from
 * the next step on; allowed between steps only (during a step, a step
 * hook included: GM_ERR_BUSY). A checkpoint records it when it is on and
 * loads only into a domain with the same setting. The
 * averaging costs a second velocity-gradient gather and a scatter of two
 * values per point in each deformation pass; its work arrays grow with the
 * grid, outside the passes. Bad values give GM_ERR_INVALID_ARGUMENT, 1D
 * domains GM_ERR_UNSUPPORTED (the setting is then unchanged). */
GM_API gm_status gm_domain_set_volumetric(gm_domain *domain,
                                          gm_volumetric volumetric);

/* ------------------------------------------------------------- mu(I) model */
#include "granmpm/mu_i.h"

#endif /* GM_STABLE_ONLY */

#ifdef __cplusplus
}
#endif

#endif /* GRANMPM_H */
