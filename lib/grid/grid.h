/*
 * grid.h - the grid folder: the step's kernels over the block grid:
 * binning and reordering (bins.c), particle-to-grid (p2g.c, p2g_wide.c),
 * the grid update (grid_update.c), the B-spline faces (bspline_faces.c),
 * grid-to-particle (g2p.c, g2p_wide.c) and the stress update
 * (stress_update.c). The kernels call down into boundaries/ (node
 * conditions), granular/ (density control) and points/ (CPDI reset). The
 * block grid's layout is core/block_grid.h; transfer.h is this folder's
 * own. Private to the library.
 */
#ifndef GM_GRID_H
#define GM_GRID_H

#include "boundaries/boundaries.h"
#include "granular/granular.h"
#include "points/points.h"

#include <math.h>

gm_status gm_bin_points(gm_domain *domain); /* bins.c */
void gm_reorder_points(gm_domain *domain);  /* bins.c */
/* Grows the work arrays of GM_VOLUMETRIC_CELL_MEAN to the grid's blocks
 * and the points' capacity (volumetric_mean.c); a no-op when it is off. */
gm_status gm_volumetric_reserve(gm_domain *domain);
/* The cells' sums of V_p tr L_p and V_p over their points, once every
 * chunk of a deformation pass is stored (volumetric_mean.c; 2D and 3D). */
void gm_volumetric_sum(gm_domain *domain);
/* The cell-mean volumetric rate in 3D (g2p_3d.c; the 2D functions are in
 * grid/transfer.h), on a chunk's nine components of L (1/s, row-major):
 * tr L = L_xx + L_yy + L_zz stored with the point's cell, then each
 * normal component shifted by a third of (mean - tr L). */
void gm_volumetric_store_chunk_3d(const gm_domain *domain, size_t first,
                                  size_t count,
                                  const double (*gradient)[GM_BATCH_SIZE]);
void gm_volumetric_apply_chunk_3d(const gm_domain *domain, size_t first,
                                  size_t count,
                                  double (*gradient)[GM_BATCH_SIZE]);
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
/* gm_p2g and gm_grid_update leave the image and ghost nodes as they computed
 * them: the folds, mirrors and copies below are stages of their own after
 * them (step.c), as is the walls' friction shared along each wall after a
 * GM_GRID_FULL update (gm_walls_share_friction). */
/* The 3D kernels (linear, uGIMP, cpGIMP; docs/3d.md), which gm_p2g, gm_g2p and
 * gm_grid_update call for GM_GEOMETRY_3D: p2g_3d.c, g2p_3d.c,
 * grid_update_3d.c. */
void gm_p2g_3d(gm_domain *domain, const gm_p2g_pass *pass);
void gm_grid_update_3d(gm_domain *domain, double dt, int mode);
/* B-splines on the box faces by images (bspline_faces.c; no-ops for the
 * other shapes): after a scatter, each ghost node's sums go to its mirror
 * node; after a grid update, each ghost node takes its mirror's velocity
 * (and acceleration in GM_GRID_FULL mode), reflected. */
void gm_bspline_fold_ghosts(gm_domain *domain, const gm_p2g_pass *pass);
void gm_bspline_mirror_ghosts(gm_domain *domain, int mode);
/* Periodic x faces (periodic.c; no-ops otherwise): after a scatter, the
 * sums of each image node go to its owner a box length away; after a grid
 * update, each image takes its owner's velocity (and acceleration in
 * GM_GRID_FULL mode) and mass; after the wall gaps are measured, each
 * owner takes the smaller gap of itself and its image. */
void gm_periodic_fold_images(gm_domain *domain, const gm_p2g_pass *pass);
void gm_periodic_copy_images(gm_domain *domain, int mode);
void gm_periodic_fold_gaps(gm_domain *domain);
/* A moved x (m) outside the box of periodic x faces, brought back by whole
 * periods into [x0, x0 + L) (periodic.c); x inside, or not finite, comes
 * back as it is. */
double gm_periodic_wrap_x(const gm_domain *domain, double x);

/* What a G2P pass does (g2p.c). */
typedef struct gm_g2p_pass {
  bool flip_velocity; /* v_p += dt * sum N a_i  */
  bool move_points;   /* x_p += dt * sum N v_i (nodal velocity) */
  bool deform;        /* L from nodal velocity: F, V, stress */
  bool finish;        /* the last pass of the step: block keys of wide
                         supports (they need the final F) and the
                         signal-speed bound of the new state */
  double dt;
  bool in_place;  /* deform from the next buffer's F, D and stress (the
                     second half of USF's and MUSL's split update,
                     step.c) rather than from the committed ones */
  double move_dt; /* s, the move's interval where it is not dt (MUSL's
                     move over the step with the second half of the
                     stress update, step.c); 0: dt */
} gm_g2p_pass;
void gm_g2p(gm_domain *domain, const gm_g2p_pass *pass);
size_t gm_chunk_gather_size(void); /* bytes of a worker's G2P chunk buffer */
/* USL's flip-and-move pass and its momentum re-map in one sweep over the
 * points (move_remap.c): whether the domain may take it (plane, linear,
 * USL, no APIC, rigid or periodic faces, and no more grid nodes than
 * point slots; any family: the granular node layers are blocks of the
 * grid like any other, reached through the block's links), and the
 * sweep, which leaves the points and the grid's momenta as gm_g2p then
 * gm_p2g would, bit for bit. */
bool gm_move_remap_fits(const gm_domain *domain);
void gm_move_remap(gm_domain *domain, double dt);
/* The same sweep for uGIMP, cpGIMP and CPDI in plane strain and axisymmetry
 * (move_remap_wide.c), under the same conditions. */
bool gm_move_remap_wide_fits(const gm_domain *domain);
void gm_move_remap_wide(gm_domain *domain, double dt);
/* Whether USL's scatter keeps the 2D CPDI supports' cells for the sweep
 * and the deformation gather (cpdi_cache.h: CPDI and the sweep above),
 * and where (the block key array). */
bool gm_cpdi_cache_fits(const gm_domain *domain);
struct gm_cpdi_cache;
void gm_cpdi_cache_arrays(gm_domain *domain, struct gm_cpdi_cache *out);
void gm_g2p_3d(gm_domain *domain, const gm_g2p_pass *pass);
size_t gm_chunk_gather_3d_size(void); /* the same for g2p_3d.c */

/* Stress update for one chunk of points (stress_update.c). */
/* Jaumann rotation, material call and stress write-back for points
 * [first, first+count) given their velocity gradients (1/s, L_xx L_xy L_yx
 * L_yy L_zz); reads the committed buffer (or, in_place, the next one),
 * writes the next one. */
void gm_stress_update_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count, double dt,
                            const double *const velocity_gradient[5],
                            bool in_place);
/* The same in 3D (GM_GEOMETRY_3D), from the nine components of L (1/s,
 * row-major xx xy xz yx yy yz zx zy zz): the full Jaumann spin
 * (materials/jaumann.c) and six stress components. */
void gm_stress_update_chunk_3d(gm_domain *domain, gm_worker_scratch *scratch,
                               size_t first, size_t count, double dt,
                               const double *const velocity_gradient[9],
                               bool in_place);
/* Names every point of [first, first+count) whose new stress (next buffer)
 * is not finite (stress_update.c). */
void gm_check_stress_chunk(gm_domain *domain, gm_worker_scratch *scratch,
                           size_t first, size_t count, double dt);

/* Newton's law for one velocity component of one node, in place: the
 * momentum (kg m/s) becomes the new velocity (m/s) and the force (N) the
 * acceleration (m/s^2); Cundall's local damping (0..1, -) takes a share of
 * the force's size against the motion. Returns the velocity before the
 * update (m/s). The grid updates of every dimension share it, so they round
 * alike. */
static inline double gm_node_accelerate(double *momentum, double *force,
                                        double inverse_mass, double damping,
                                        double dt) {
  double old_velocity = *momentum * inverse_mass;
  double f = *force;
  if (damping > 0.0 && old_velocity != 0.0) /* against the motion */
    f -= damping * fabs(f) * (old_velocity > 0.0 ? 1.0 : -1.0);
  double acceleration = f * inverse_mass;
  *force = acceleration;
  *momentum = old_velocity + acceleration * dt;
  return old_velocity;
}

#endif
