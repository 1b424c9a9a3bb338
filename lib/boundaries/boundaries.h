/*
 * boundaries.h - the boundaries folder: planar walls (walls.c) and their
 * gaps to the material (wall_gaps.c), rigid material points (rigid.c),
 * the box faces' centre-gap rule (face_centres.c), sources and sinks
 * (sources.c), and what walls and rigid materials report
 * (force_report.c). The conditions are applied node by node from the grid
 * update (grid/grid_update.c), which calls down into this folder. Private
 * to the library.
 */
#ifndef GM_BOUNDARIES_H
#define GM_BOUNDARIES_H

#include "materials/materials.h"
#include "points/points.h"

#define GM_DEFAULT_FORCE_SMOOTHING_TIME 1e-3 /* s */
/* Commits a successful call of length dt (s) that exchanged `impulse`
 * (N s, `components` of it: 2, or 3 for a 3D wall) with the obstacle; tau
 * (s) is the smoothing time. */
void gm_force_report_commit(gm_force_report *report, const double *impulse,
                            int components, double dt, double tau);

/* Walls (walls.c). Contact of one node with the walls: `velocity` (m/s)
 * is the node's updated velocity, changed in place; gap (one per wall, m,
 * or NULL = 0) lets it approach a wall by that much in dt, and centre_gap
 * (one per wall, m, or NULL) the same for the nodes the wall's contact
 * does not reach, from the nearest point centre; returns true if
 * a wall acted. Without `friction` only the normal approach is removed. If
 * block_force is not NULL, mass/dt times each wall's velocity change (N) is
 * added to block_force[2 w], [2 w + 1]. If record is not NULL it gets the one
 * wall that acted and its normal change and the tangential velocity before
 * friction, for gm_walls_share_friction (wall -1 when none or several acted);
 * when none acted, a node in front of exactly one wall it shares, or whose
 * friction strips it joins (the row a cell in front of a wall on a node row),
 * gets that wall with normal change 0. */
typedef struct gm_wall_pool_record {
  int wall;              /* the one wall that acted; -1: none or several */
  double normal_change;  /* m/s, its normal velocity change (> 0; 0: not
                            pushed, in front of the plane) */
  double tangent_before; /* m/s, tangential velocity before its friction,
                            along (n_y, -n_x) */
} gm_wall_pool_record;
bool gm_walls_contact(const gm_domain *domain, const double node_position[2],
                      double velocity[2], const double *gap,
                      const double *centre_gap, double dt, bool friction,
                      double *block_force, double mass_over_dt, int *first_wall,
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
/* Gives a gap slot (grid->gap_slot) to every block a measured point may
 * lower a gap record in: the blocks the measure visits and their linked
 * neighbours (with periodic x faces every block, whose images fold into
 * their owners' records, grid/periodic.c), in block order; returns the
 * nodes with records, the sentinel included (wall_gaps.c). After each
 * grid build, before the measure. */
size_t gm_walls_map_gaps(gm_domain *domain);
/* The same marking in 3D (wall_gaps_3d.c): gap_slot 0 for each block to
 * give a slot (gm_walls_map_gaps numbers them). */
void gm_walls_mark_gaps_3d(gm_domain *domain);
/* Marks block b and the blocks it links (its points' supports reach) for
 * a gap slot (wall_gaps.c). */
void gm_walls_mark_linked(gm_grid *grid, size_t b);
/* Sets the gap and centre-gap records of nodes [begin, end) (gap record
 * indices, gm_gap_node) to infinity (wall_gaps.c). */
void gm_clear_gap_records(gm_domain *domain, size_t begin, size_t end);
/* Gap records per node: the planar walls and the measured box faces. */
int gm_gap_plane_count(const gm_domain *domain);
/* Centre-gap records per node (grid->wall_centre_gap): as the gap records
 * with the shapes wider than a tent, the planar walls only with linear
 * shapes, whose faces need no centre gap (grid_update.c); in 3D the
 * planar walls only, with every shape. Linear MPM uses them on oblique
 * planes only, in 2D (walls.c) and 3D (walls_3d.c) alike
 * (gm_wall_tent_reach). */
int gm_centre_gap_plane_count(const gm_domain *domain);
/* Slot of box face f (2 axis + side) in a node's gap records; -1 when
 * the face is not measured (open, or a B-spline mirror). */
int gm_gap_face_slot(const gm_domain *domain, int face);
/* The gap record layout of a step: gm_gap_plane_count,
 * gm_centre_gap_plane_count and gm_gap_face_slot per face, taken once per
 * grid update rather than per node (each loops over the faces). */
typedef struct gm_gap_layout {
  int planes;       /* gap records per node */
  int centres;      /* centre-gap records per node */
  int face_slot[6]; /* per face (GM_FACE_*); -1: not measured */
} gm_gap_layout;
void gm_gap_layout_of(const gm_domain *domain, gm_gap_layout *out);
/* Cells (less GM_ON_ROW) in front of the wall within which a node's linear
 * tent reaches behind an oblique plane, |n_x| + |n_y| + |n_z|: linear MPM's
 * nodes beyond GM_WALL_REACH but within it get the centre-gap bound, in 2D
 * (gm_walls_contact) and 3D (gm_walls_contact_3d) alike (walls.c). */
double gm_wall_tent_reach(const gm_wall *wall);
/* Distance (cells) in front of a wall within which a node shares the wall
 * (see gm_walls_contact): one cell less GM_ON_ROW, so that the next node
 * row in front of a wall on a node row stays out. A wall placed a rounding
 * error in front of a row (the silo of tests/physics/test_silo_filling.c puts
 * its side wall 1e-9 cells in front of one, to keep that row behind it) counts
 * as on the row: with a margin of 1e-9 cells, as first written, the row in
 * front of that wall lay exactly on the reach and the rounding of its
 * distance let it act, as a second wall one cell inside the fill (the
 * poured fill then kept 0.055 J/m of kinetic energy; 1e-6 or 0.5 cells
 * both give a fill at rest). A tent reaching 1e-6 cells behind the plane
 * shares 5e-13 of its area with the wall. */
#define GM_ON_ROW     1e-6
#define GM_WALL_REACH (1.0 - GM_ON_ROW)
/* Distance (cells) in front of a wall below which a node that does not
 * share the wall may still join its friction strip (gm_walls_share_friction)
 * if it carries material touching the wall: the row a whole cell in front
 * of a wall on a node row, or the row 1-2 cells in front of a wall between
 * rows whose bottom points lie beyond the row in front of the plane. Such
 * a node never takes a normal impulse. A node two cells in front carries
 * no point whose tent-shape domain reaches the plane. */
#define GM_STRIP_REACH (2.0 - GM_ON_ROW)
/* Gaps (cells) below which a wall or a box face counts as touched: see
 * gm_walls_contact (walls.c). */
#define GM_CONTACT_TOLERANCE 3e-3
/* Gap (cells) beyond which material that touched a box face may leave it
 * (grid_update.c, constrain_faces; grid_update_3d.c). */
#define GM_FACE_RELEASE 0.01
/* Sizes the per-block wall-force partial sums for the current walls. */
gm_status gm_walls_reserve(gm_domain *domain);

/* Planar walls in 3D (walls_3d.c, wall_gaps_3d.c; linear shapes, uGIMP,
 * cpGIMP and CPDI; not the B-splines). An
 * orthonormal basis t1, t2 of the wall's plane (t2 = n x t1). */
void gm_wall_tangents_3d(const gm_wall *wall, double t1[3], double t2[3]);
/* Doubles of pooled sums wall w's friction patches need. */
size_t gm_walls_patch_doubles_3d(const gm_domain *domain, int w);
/* Does any wall reach into the 3D block with lowest node base (ix, iy,
 * iz)? */
bool gm_walls_near_block_3d(const gm_domain *domain, const int64_t base[3]);
/* gm_wall_pool_record in 3D: the tangential velocity before friction
 * along t1 and t2 (m/s). */
typedef struct gm_wall_pool_record_3d {
  int wall;
  double normal_change;     /* m/s */
  double tangent_before[2]; /* m/s */
} gm_wall_pool_record_3d;
/* gm_walls_contact in 3D: position and velocity 3-vectors, gap one per
 * wall (m), centre_gap one per wall (m) with the wide shapes, NULL with
 * linear ones, block_force 3 per wall (N). */
bool gm_walls_contact_3d(const gm_domain *domain, const double position[3],
                         double velocity[3], const double *gap,
                         const double *centre_gap, double dt, bool friction,
                         double *block_force, double mass_over_dt,
                         gm_wall_pool_record_3d *record);
/* gm_walls_share_friction in 3D: Coulomb's law on the sums of patches
 * one cell by one cell of the plane. Serial, block order. */
void gm_walls_share_friction_3d(gm_domain *domain, double dt, int mode);
/* The node gaps to every planar wall and measured box face in 3D
 * (grid->wall_gap, gm_gap_plane_count per node) and the centre gaps to
 * the walls (grid->wall_centre_gap), after the
 * mass P2G (wall_gaps_3d.c). */
void gm_walls_measure_gaps_3d(gm_domain *domain);

/* Rigid points (rigid.c). After the mass P2G (step.c's stage
 * MARK_RIGID_NODES): marks the nodes each rigid point touches with its
 * material (grid->rigid_material, 0 = none, material + 1 otherwise). */
void gm_rigid_mark_nodes(gm_domain *domain);
/* Grid update of one node touched by a rigid material: its velocity
 * becomes the prescribed one; in FULL mode the acceleration follows and
 * the node's impulse on the rigid body is stored for gm_rigid_add_impulse.
 * old_velocity: the node's velocity before the update (m/s, dim
 * components: 3 in 3D, grid_update_3d.c). */
void gm_rigid_constrain_node(gm_domain *domain, size_t node,
                             const double *old_velocity, double dt, bool full);
/* Adds the committed sub-step's impulses on each rigid material. */
void gm_rigid_add_impulse(gm_domain *domain);
/* Rigid points of the new (spare) buffer get their prescribed velocity. */
void gm_rigid_set_point_velocities(gm_domain *domain);
/* B-splines: after the FLIP update of the point velocities and before
 * the remap's scatter (USL, MUSL, USF), rigid points take their
 * prescribed velocity again. Their update gathered the free nodes of their
 * support too (the cell rule), and a rigid body's momentum on the grid is its
 * prescribed one, in the remap as in the first scatter. Other shapes:
 * nothing (their whole support is held, the update is the prescribed
 * velocity already). */
void gm_rigid_hold_remap_velocities(gm_domain *domain);
/* B-splines (rigid.c's header: the cell rule): rigid points move by the
 * prescribed velocity times dt and keep F and V, in place of what G2P
 * gathered from nodes outside their cells; their keys for the next
 * binning follow. Fails the step (GM_ERR_OUT_OF_GRID) where one would
 * leave the grid. Other shapes: nothing (their whole support is held). */
gm_status gm_rigid_move_points(gm_domain *domain, double dt);
/* Is point p's G2P move provisional (a rigid point with the B-splines,
 * whose position gm_rigid_move_points sets and tests afterwards)? G2P's
 * test of the moved point then skips it: the move it gathered from the
 * free nodes of its support, which may leave the grid box under an
 * unstable update there, is thrown away. */
bool gm_rigid_move_is_provisional(const gm_domain *domain, size_t p);
gm_status gm_rigid_reserve(gm_domain *domain);
/* Does any wall reach into the block with lower corner node (ix, iy)? */
bool gm_walls_near_block(const gm_domain *domain, int64_t base_x,
                         int64_t base_y);
/* Adds the committed sub-step's wall forces (summed per block in block
 * order) times dt to the impulse of the gm_domain_step call in progress. */
void gm_walls_add_impulse(gm_domain *domain, double dt);

/* The box faces' centre-gap rule (face_centres.c), for the shapes wider
 * than a tent: a node with mass at index (node indices, domain->dim of
 * them) in front of a measured slip or fixed face may approach it by at
 * most its nearest point centre's distance (centre_gap: the node's
 * centre-gap records), less the contact tolerance, in dt (s); velocity
 * (m/s) is changed in place. The face's own nodes are left to the grid
 * update's face rule. */
void gm_limit_face_centres(const gm_domain *domain, const gm_gap_layout *layout,
                           const double *centre_gap, const int64_t *index,
                           double dt, double *velocity);
/* Can the block with lower corner node base (edge nodes a side) hold a
 * node gm_limit_face_centres acts on? Only with the wide shapes, and only
 * within reach (nodes: a support's span) of a measured face: a point less
 * than a cell from the face reaches no farther. */
bool gm_block_near_faces(const gm_domain *domain, const int64_t *base,
                         int64_t edge, int64_t reach);

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

#endif
