/*
 * points.h - the points folder: SoA point storage (points.c), taking points
 * out (removal.c), gm_domain_fill_box (fill_box.c), field access
 * (fields.c) and the CPDI domain reset (cpdi_reset.c). The storage itself
 * (gm_points, gm_point_buffers) is in core/domain_points.h. Private to the
 * library.
 */
#ifndef GM_POINTS_H
#define GM_POINTS_H

#include "core/domain.h"

/* GM_ERR_INVALID_ARGUMENT if a point of granular material material_id
 * would be placed in the granular family below rho_cr - TOL (points.c says
 * why); `what` names the caller and the point or def for the message. */
gm_status gm_check_placement_density(gm_domain *domain, int material_id,
                                     double density, const char *what);

/* Point storage (points.c). */
gm_status gm_points_reserve(gm_domain *domain, size_t capacity);
/* Room in the id -> index map for `extra` more ids (grows by at least a
 * half); false, the map untouched, when out of memory. */
bool gm_points_reserve_ids(gm_points *points, size_t extra);
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
/* Stress components stored per point: 4 (xx yy zz xy) below 3D, 6 in 3D
 * (points.c). */
int gm_stress_stored(const gm_domain *domain);
/* Slots of CPDI's domain map D stored per point: F_XX..F_YY (4) below
 * 3D, all nine in 3D (points.c). */
int gm_domain_map_stored(const gm_domain *domain);
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
/* The nine slots (core.h's F_XX..F_ZY) that deform the 3D point domains
 * of a buffer set: the CPDI domain map D, or F (cpGIMP reads its
 * diagonal; uGIMP, the B-splines and linear MPM ignore it). */
static inline const double *const *
gm_support_slots_3d(const gm_domain *domain, const gm_point_buffers *buffer) {
  bool cpdi = domain->shape_grid.shape == GM_SHAPE_CPDI;
  return (const double *const *)(cpdi ? buffer->domain_map
                                      : buffer->deformation);
}
/* Point p's domain (support.h) in one buffer set (points.c). */
void gm_point_domain_at(const gm_domain *domain, const gm_point_buffers *buffer,
                        size_t p, gm_point_domain *out);

/* CPDI domain reset (cpdi_reset.c). The largest ratio of the singular
 * values of a point's domain map D before it is reset to the initial
 * domain scaled to the same area: a square domain then has an aspect of
 * at most 3 (see cpdi_reset.c and gm_domain_create(3)). */
#define GM_CPDI_MAX_DISTORTION 3.0
/* Resets map (D_xx, D_xy, D_yx, D_yy) to sqrt(det D) I when the ratio of
 * its singular values exceeds max_distortion and det D > 0; true if it
 * did. */
bool gm_cpdi_domain_reset(double map[4], double max_distortion);
/* The same in 3D: map is D row-major (D_xx, D_xy, D_xz, D_yx, ..., D_zz),
 * reset to cbrt(det D) I when sigma_max / sigma_min exceeds
 * max_distortion and det D > 0; true if it did. */
bool gm_cpdi_domain_reset_3d(double map[9], double max_distortion);
/* The resets of the next buffer's points [first, first + count): after
 * their deformation and density control (g2p.c); nothing in 1D. */
void gm_cpdi_reset_chunk(const gm_domain *domain, size_t first, size_t count);

#endif
