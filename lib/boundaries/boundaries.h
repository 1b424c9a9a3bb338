/*
 * boundaries.h - the boundaries folder: planar walls (walls.c) and their
 * gaps to the material (wall_gaps.c), rigid material points (rigid.c),
 * sources and sinks (sources.c), and what walls and rigid materials report
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
 * (N s) with the obstacle; tau (s) is the smoothing time. */
void gm_force_report_commit(gm_force_report *report, const double impulse[2],
                            double dt, double tau);

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

#endif
