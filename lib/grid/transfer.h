/*
 * transfer.h - the arrays the particle/grid transfers read and write, shared
 * by the linear kernels (p2g.c, g2p.c) and the wide-support kernels of GIMP
 * and CPDI (p2g_wide.c, g2p_wide.c). Pointers are copied into
 * restrict-qualified locals by the kernels so the compiler keeps them in
 * registers instead of reloading them after each store to the grid.
 */
#ifndef GM_TRANSFER_H
#define GM_TRANSFER_H

#include "grid/cpdi_cache.h"
#include "grid/grid.h"

#include <string.h>

/* The fused move and momentum re-map (move_remap.c, move_remap_wide.c)
 * sums the new nodal momenta (kg m/s) into spare per-node arrays: cleared
 * before the sweep, copied over the grid's momenta after it, for the
 * blocks [begin, end). */
static inline void gm_remap_sums_clear(double *const sum[2], size_t begin,
                                       size_t end) {
  size_t first = begin * GM_BLOCK_NODES;
  size_t bytes = (end - begin) * GM_BLOCK_NODES * sizeof(double);
  memset(sum[0] + first, 0, bytes);
  memset(sum[1] + first, 0, bytes);
}

static inline void gm_remap_sums_commit(gm_grid *grid, double *const sum[2],
                                        size_t begin, size_t end) {
  size_t first = begin * GM_BLOCK_NODES;
  size_t bytes = (end - begin) * GM_BLOCK_NODES * sizeof(double);
  memcpy(grid->momentum[0] + first, sum[0] + first, bytes);
  memcpy(grid->momentum[1] + first, sum[1] + first, bytes);
}

/* The arrays of a P2G pass. */
typedef struct scatter_view {
  const double *position[2];       /* m */
  const double *velocity[2];       /* m/s, source of the momentum */
  const double *mass;              /* kg */
  const double *volume;            /* of the stress buffer */
  const double *stress[4];         /* Pa, xx yy zz xy */
  const double *external_force[2]; /* N, NULL = none */
  double *grid_mass;
  double *grid_momentum[2];
  double *grid_force[2];
  const uint32_t *order;
  const uint32_t *point_start;
  const uint32_t *neighbour;
  double origin[2];  /* m, node 0 (support.h) */
  double inv_cell;   /* 1/m */
  double gravity[2]; /* m/s^2 */
  int shift;
  bool axisymmetric;
  /* Rigid points (rigid.c) take no part in the transfers. */
  bool skip_rigid;
  const int32_t *material;
  bool rigid[GM_MAX_MATERIALS];
  /* Wide supports (p2g_wide.c): the domains' shape and size. */
  const gm_shape_grid *shape_grid;
  const gm_grid *grid;
  /* Committed F_xx, F_xy, F_yx, F_yy, or for CPDI the domain map D
   * (gm_support_tensor): what deforms the domains. */
  const double *deformation[4];
  const double *domain_size[2]; /* m, initial domain edges */
  /* GM_TRANSFER_APIC: the affine matrix of the velocity buffer (xx xy yx
   * yy; 1D: xx only). The momentum a point gives node i is
   *   m_p N_ip (v_p + B_p D_p^-1 (x_i - x_p))
   * (Jiang et al. 2015, the APIC P2G), D_p = sum_i N_ip (x_i - x_p)
   * (x_i - x_p)^T from the support: the wide shapes store B_p (m^2/s);
   * linear MPM stores C_p = B_p D_p^-1 (1/s) itself (p2g.c says why). */
  bool apic;
  const double *affine[4];
  double cell; /* m, h: node n of an axis lies at origin + n h */
  /* 2D CPDI under USL's fused sweep: where the scatter keeps each point's
   * corner cells for the sweep and the deformation gather (cpdi_cache.h;
   * packed NULL: not kept). */
  gm_cpdi_cache cpdi_cache;
} scatter_view;

/* Every array a G2P pass touches (copied into restrict-qualified locals by
 * the kernels, see p2g.c). */
typedef struct gather_view {
  const double *position[2]; /* m, committed */
  const double *velocity[2]; /* m/s, committed */
  const double *deformation[GM_F_STORED];
  const double *grid_velocity[2];     /* m/s */
  const double *grid_mass;            /* kg */
  const double *grid_acceleration[2]; /* m/s^2 */
  const uint32_t *point_block;
  const uint32_t *neighbour;
  const gm_grid *grid;
  int64_t *block_key;      /* written by the move pass */
  const double *origin_xy; /* m, node 0 (not aliased in 1D) */
  const double *mass;      /* kg */
  const double *initial_volume;
  const int32_t *material;
  double *next_position[2];
  double *next_velocity[2];
  double *next_deformation[GM_F_STORED];
  double *next_volume;
  double origin[2];
  double inv_cell;
  double cells[2];     /* cells per axis, as doubles */
  double pic_fraction; /* -, gm_domain_def.pic_fraction */
  int shift;
  int dim;
  bool axisymmetric;
  /* Wide supports (g2p_wide.c). */
  const gm_shape_grid *shape_grid;
  const double *domain_size[2]; /* m, initial domain edges */
  /* What deforms the domains (gm_support_tensor), committed and next:
   * F, or for CPDI the domain map D, whose update and reset the deform
   * pass writes to next_domain_map (NULL unless CPDI). */
  const double *support_tensor[4];
  const double *next_support_tensor[4];
  const double *domain_map[4];
  double *next_domain_map[4];
  /* GM_TRANSFER_APIC: the velocity pass sets v_p = sum N_ip v_i (PIC) and
   * B_p = sum N_ip v_i (x_i - x_p)^T (Jiang et al. 2015, the APIC G2P),
   * or C_p = L in linear MPM; affine: the wide gather computes B_p (the
   * pass writes velocities). */
  bool apic;
  bool affine;
  double *next_affine[4]; /* m^2/s */
  double cell;            /* m, h */
  /* Periodic x faces (periodic.c): moved points wrap into [x0, x0 + L). */
  bool periodic_x;
  /* USL's deformation gather: the cells its scatter kept (cpdi_cache.h;
   * packed NULL: compute them). */
  gm_cpdi_cache cpdi_cache;
} gather_view;

/* What the grid tells the points of one chunk, SoA: interpolated nodal
 * acceleration and velocity, and the velocity gradient components
 * (L_xx, L_xy, L_yx, L_yy, L_zz). */
struct chunk_gather {
  double acceleration[2][GM_BATCH_SIZE]; /* m/s^2 */
  double velocity[2][GM_BATCH_SIZE];     /* m/s */
  double gradient[5][GM_BATCH_SIZE];     /* 1/s */
  double affine[4][GM_BATCH_SIZE];       /* m^2/s, B_p xx xy yx yy (APIC,
                                            wide shapes) */
};
typedef struct chunk_gather chunk_gather;

/* The support of one point in the wide kernels: axis factors for the
 * tensor-product variants, the corners for CPDI. */
typedef union wide_support {
  gm_product_support product;
  gm_cpdi_support cpdi;
} wide_support;

/* One point's F <- (I + L dt) F in plane strain (004 eq 3.23): writes the
 * in-plane components of the new F and returns its in-plane determinant.
 * Shared by the general deformation pass (g2p.c) and the elastic fast
 * path (deform_elastic.c), which must give the same bits. */
static inline double gm_deform_plane_point(double dt, double l_xx, double l_xy,
                                           double l_yx, double l_yy,
                                           double a_xx, double a_xy,
                                           double a_yx, double a_yy,
                                           double *n_xx, double *n_xy,
                                           double *n_yx, double *n_yy) {
  double i_xx = 1.0 + l_xx * dt, i_xy = l_xy * dt;
  double i_yx = l_yx * dt, i_yy = 1.0 + l_yy * dt;
  double b_xx = i_xx * a_xx + i_xy * a_yx, b_xy = i_xx * a_xy + i_xy * a_yy;
  double b_yx = i_yx * a_xx + i_yy * a_yx, b_yy = i_yx * a_xy + i_yy * a_yy;
  *n_xx = b_xx;
  *n_xy = b_xy;
  *n_yx = b_yx;
  *n_yy = b_yy;
  return b_xx * b_yy - b_xy * b_yx;
}

/* One point's stress rotated by the Jaumann rate and incremented by
 * Hooke's law in plane strain: s (Pa; xx, yy, zz, xy) under the velocity
 * gradient L (1/s) over dt (s) with Lame's constants lame and shear (Pa)
 * gives r, in the order of the general path (stress_update.c's
 * prepare_rows, then gm_elastic_update, elastic.c, or Mohr-Coulomb's
 * elastic trial, mohr_coulomb.c). Shared by the fused passes
 * deform_elastic.c and deform_mohr_coulomb.c, which must give its bits. */
static GM_ALWAYS_INLINE void
gm_plane_hooke_trial(double dt, double lame, double shear, double l_xx,
                     double l_xy, double l_yx, double l_yy, double l_zz,
                     const double s[4], double r[4]) {
  double spin = 0.5 * (l_xy - l_yx) * dt; /* W_xy dt */
  double r_xx = s[0] + 2.0 * spin * s[3];
  double r_yy = s[1] - 2.0 * spin * s[3];
  double r_xy = s[3] + spin * (s[1] - s[0]);
  double e_xx = l_xx * dt, e_yy = l_yy * dt, e_zz = l_zz * dt;
  double e_xy = 0.5 * (l_xy + l_yx) * dt;
  double volumetric = e_xx + e_yy + e_zz;
  double lame_term = lame * volumetric;
  r_xx += lame_term + 2.0 * shear * e_xx;
  r_yy += lame_term + 2.0 * shear * e_yy;
  r[2] = s[2] + (lame_term + 2.0 * shear * e_zz);
  r[0] = r_xx;
  r[1] = r_yy;
  r[3] = r_xy + 2.0 * shear * e_xy;
}

/* CPDI: the domain map takes F's increment, D <- (I + L dt) D (the
 * arithmetic of gm_deform_plane_point), for the chunk's points from the
 * gathered gradient into next_domain_map. Shared by the general
 * deformation pass (g2p.c) and the elastic one (deform_elastic.c). In
 * USF's second half D is updated in place: each point's D is read whole
 * before it is written (the pointers are not restrict). */
static inline void gm_deform_domain_map_chunk(const gather_view *v,
                                              size_t first, size_t count,
                                              const chunk_gather *g,
                                              double dt) {
  const double *d_xx = v->domain_map[F_XX] + first;
  const double *d_xy = v->domain_map[F_XY] + first;
  const double *d_yx = v->domain_map[F_YX] + first;
  const double *d_yy = v->domain_map[F_YY] + first;
  double *m_xx = v->next_domain_map[F_XX] + first;
  double *m_xy = v->next_domain_map[F_XY] + first;
  double *m_yx = v->next_domain_map[F_YX] + first;
  double *m_yy = v->next_domain_map[F_YY] + first;
  const double *l_xx = g->gradient[0], *l_xy = g->gradient[1];
  const double *l_yx = g->gradient[2], *l_yy = g->gradient[3];
  for (size_t j = 0; j < count; j++) { /* the same arithmetic as F's */
    double i_xx = 1.0 + l_xx[j] * dt, i_xy = l_xy[j] * dt;
    double i_yx = l_yx[j] * dt, i_yy = 1.0 + l_yy[j] * dt;
    double a_xx = d_xx[j], a_xy = d_xy[j], a_yx = d_yx[j], a_yy = d_yy[j];
    m_xx[j] = i_xx * a_xx + i_xy * a_yx;
    m_xy[j] = i_xx * a_xy + i_xy * a_yy;
    m_yx[j] = i_yx * a_xx + i_yy * a_yx;
    m_yy[j] = i_yx * a_xy + i_yy * a_yy;
  }
}

/* Point p's support (position, deformation: its domain's), with its lowest
 * node and its reach (the farthest node past it) per axis; false if it
 * cannot be computed (see gm_support_compute). */
static inline bool gm_wide_point_support(const gm_shape_grid *grid, int dim,
                                         const double *const position[2],
                                         const double *const deformation[4],
                                         const double *const domain_size[2],
                                         size_t p, wide_support *support,
                                         int64_t lowest[2], int64_t reach[2]) {
  reach[0] = reach[1] = 0;
  if (grid->shape != GM_SHAPE_CPDI) {
    gm_product_support *product = &support->product;
    bool found = gm_wide_product_support(grid, dim, position, deformation,
                                         domain_size, p, product);
    for (int axis = 0; axis < 2; axis++) {
      lowest[axis] = product->lowest[axis];
      reach[axis] = product->span[axis] - 1;
    }
    return found;
  }
  gm_cpdi_support *cpdi = &support->cpdi;
  bool found = gm_wide_cpdi_support(grid, dim, position, deformation,
                                    domain_size, p, cpdi);
  for (int axis = 0; axis < 2; axis++) {
    lowest[axis] = cpdi->lowest[axis];
    for (int c = 0; found && axis < dim && c < cpdi->corner_count; c++) {
      int64_t far = cpdi->cell[c][axis] + 1 - cpdi->lowest[axis];
      reach[axis] = far > reach[axis] ? far : reach[axis];
    }
  }
  return found;
}

/* Whether a support whose lowest node lies (x0, y0) nodes from a block's
 * base stays within `edge` nodes of it along each axis (two blocks: the
 * block and its +x/+y neighbours, which is all the scatter tile and the
 * gather's neighbour links reach). The binning keys every point by its
 * support, so this holds unless the keys and the supports disagree; the
 * transfers check it anyway rather than write or read outside the tile. */
static inline bool gm_wide_support_fits(int dim, int64_t x0, int64_t y0,
                                        const int64_t reach[2], int64_t edge) {
  return x0 >= 0 && y0 >= 0 && x0 + reach[0] < edge &&
         (dim < 2 || y0 + reach[1] < edge);
}

/* Scatters one block of points with a GIMP or CPDI support (p2g_wide.c). */
/* A support that does not fit the block's tile fails the step
 * (GM_ERR_OUT_OF_GRID on scratch) instead of writing outside it. */
void gm_scatter_block_wide(const scatter_view *view, const gm_p2g_pass *pass,
                           uint32_t block, const gm_domain *domain,
                           gm_worker_scratch *scratch);
/* The cell-mean volumetric rate (volumetric_mean.c): each point's tr L
 * (1/s, with the hoop rate in axisymmetry) and cell from a chunk's gather;
 * the cells' sums over all points (gm_volumetric_sum, grid.h, after every
 * chunk is stored); and each point's L shifted to its cell's mean trace. */
void gm_volumetric_store_chunk(const gm_domain *domain, const gather_view *v,
                               size_t first, size_t count,
                               const chunk_gather *g);
void gm_volumetric_apply_chunk(const gm_domain *domain, const gather_view *v,
                               size_t first, size_t count, chunk_gather *g);

/* Gathers one chunk of points with a GIMP or CPDI support (g2p_wide.c). */
/* The same check as the scatter: a support outside the block's
 * neighbours fails the step instead of reading outside them. flip, deform:
 * the pass's (g2p.c); a short 2D support leaves out the sums the pass does
 * not read (the acceleration without flip, the velocity gradient without
 * deform: out's arrays then hold zeros). */
void gm_gather_chunk_wide(const gather_view *view, size_t first, size_t count,
                          chunk_gather *out, const gm_domain *domain,
                          gm_worker_scratch *scratch, bool flip, bool deform);
/* Reports every point of the chunk whose new det F = V / V0 is not
 * positive and finite (g2p.c); a finite inversion marks the failure
 * recoverable by a smaller dt. */
void gm_report_inverted_chunk(gm_domain *domain, const gather_view *v,
                              gm_worker_scratch *scratch, size_t first,
                              size_t count, double dt);
/* The fused deformation passes of deform_elastic.c and
 * deform_mohr_coulomb.c. gm_plane_chunk_material: the chunk's one material
 * when it may take one (plane strain, committed F and stress, a single
 * material), else -1; the elastic pass is for gm_elastic_update, the
 * Mohr-Coulomb one for a material gm_mohr_coulomb_chunk_fits accepts. Each
 * pass returns false (the inverted points reported) when some det F is not
 * positive. CPDI's domain map takes its increment there too; its reset
 * stays the caller's. */
int gm_plane_chunk_material(const gm_domain *domain, const gather_view *v,
                            const gm_g2p_pass *pass, size_t first,
                            size_t count);
bool gm_deform_elastic_chunk(gm_domain *domain, const gather_view *v,
                             gm_worker_scratch *scratch, size_t first,
                             size_t count, const chunk_gather *g, double dt);
bool gm_mohr_coulomb_chunk_fits(const gm_domain *domain, int material);
bool gm_deform_mohr_coulomb_chunk(gm_domain *domain, const gather_view *v,
                                  gm_worker_scratch *scratch, size_t first,
                                  size_t count, const chunk_gather *g,
                                  double dt);
/* Block keys of the chunk's moved and deformed points (next buffer) from
 * their supports; a support leaving the grid fails the step. */
void gm_wide_keys_chunk(gm_domain *domain, const gather_view *view,
                        gm_worker_scratch *scratch, size_t first, size_t count);

/* The linear weights and gradients of a 2D point at (x, y) (m), the grid
 * indices of its cell's 4 nodes (n = a + 2 b at (cell + a, cell + b)) from
 * the links of the point's block, and the cell's node (0, 0) inside that
 * block (local). 2D blocks are always 8 x 8 nodes (domain.c): a constant
 * shift lets the lookup fold its masks and multiplies. */
static GM_ALWAYS_INLINE void
gm_linear_cell_2d(double x, double y, double origin_x, double origin_y,
                  double inv_cell, const uint32_t *links, double wx[2],
                  double dx[2], double wy[2], double dy[2], size_t node[4],
                  int64_t local[2]) {
  const int shift = GM_BLOCK_SHIFT_2D;
  const int64_t mask = ((int64_t)1 << shift) - 1;
  int64_t cx = gm_shape_linear_axis_inside(x, origin_x, inv_cell, wx, dx);
  int64_t cy = gm_shape_linear_axis_inside(y, origin_y, inv_cell, wy, dy);
  int64_t local_x = cx & mask, local_y = cy & mask;
  local[0] = local_x;
  local[1] = local_y;
  if (local_x < mask && local_y < mask) {
    /* The cell inside its block (49 of 64 cells): its nodes are the
     * block's own, at fixed offsets, without the neighbour links. */
    node[0] = (size_t)links[0] * GM_BLOCK_NODES +
              (size_t)(local_x + GM_BLOCK_EDGE_2D * local_y);
    node[1] = node[0] + 1;
    node[2] = node[0] + GM_BLOCK_EDGE_2D;
    node[3] = node[0] + GM_BLOCK_EDGE_2D + 1;
  } else {
    gm_cell_nodes_2d(links, shift, local_x, local_y, node);
  }
}

/* What USL's move of linear 2D points reads besides the point itself:
 * the updated nodal velocities v_i^L and accelerations a_i, and the
 * constants of the FLIP update, the move and the block keys. */
typedef struct linear_move_2d {
  const double *grid_velocity[2];     /* m/s */
  const double *grid_acceleration[2]; /* m/s^2 */
  double origin[2];                   /* m, node 0 */
  double inv_cell;                    /* 1/m */
  double cells[2];                    /* scaled upper bounds of x' */
  double dt;                          /* s */
  double pic, flip;                   /* -, pic_fraction and 1 - it */
  int shift;                          /* the grid's block shift */
  int64_t blocks_x;                   /* blocks along x */
} linear_move_2d;

/* One point of the flip-and-move pass (g2p.c gather_chunk_2d_kind,
 * flip_chunk, move_chunk, with the same expressions in the same order, so
 * every bit is theirs): from its weights on its cell's nodes, its committed
 * position x (m) and velocity v (m/s), the FLIP (or blended) velocity
 * v' = v + dt sum N a_i (004 eq 3.17) and the moved x' = x + dt sum N
 * v_i^L into out (v'x, v'y, x'x, x'y), and the block key of x' (the
 * arithmetic of gm_block_key_inside from the scaled coordinates the bounds
 * test already has; 0 for a point outside, never a cast of an
 * out-of-range double). Returns whether x' is inside the grid box. blend
 * (pic > 0) is a constant at each call. */
static GM_ALWAYS_INLINE bool
gm_linear_move_point_2d(const linear_move_2d *m, const double weight[4],
                        const size_t node[4], double x, double y, double vx,
                        double vy, const bool blend, double out[4],
                        int64_t *key) {
  const double *restrict gvx = m->grid_velocity[0];
  const double *restrict gvy = m->grid_velocity[1];
  const double *restrict gax = m->grid_acceleration[0];
  const double *restrict gay = m->grid_acceleration[1];
  double dt = m->dt;
  double ax = 0, ay = 0, nvx = 0, nvy = 0;
  for (int n = 0; n < 4; n++) {
    ax += weight[n] * gax[node[n]];
    ay += weight[n] * gay[node[n]];
    nvx += weight[n] * gvx[node[n]];
    nvy += weight[n] * gvy[node[n]];
  }
  if (blend) { /* flip_chunk */
    out[0] = m->flip * (vx + dt * ax) + m->pic * nvx;
    out[1] = m->flip * (vy + dt * ay) + m->pic * nvy;
  } else {
    out[0] = vx + dt * ax;
    out[1] = vy + dt * ay;
  }
  double moved_x = x + dt * nvx, moved_y = y + dt * nvy; /* m */
  out[2] = moved_x;
  out[3] = moved_y;
  double scaled_x = (moved_x - m->origin[0]) * m->inv_cell; /* move_chunk */
  double scaled_y = (moved_y - m->origin[1]) * m->inv_cell;
  bool inside = (scaled_x >= GM_GHOST_LAYERS) & (scaled_x < m->cells[0]) &
                (scaled_y >= GM_GHOST_LAYERS) & (scaled_y < m->cells[1]);
  scaled_x = inside ? scaled_x : 0.0;
  scaled_y = inside ? scaled_y : 0.0;
  *key = ((int64_t)scaled_y >> m->shift) * m->blocks_x +
         ((int64_t)scaled_x >> m->shift);
  return inside;
}

/* The linear_move_2d of the domain's current grid update, over dt. */
void gm_linear_move_2d_init(const gm_domain *domain, double dt,
                            linear_move_2d *m);
/* Names the point p (index) if its moved position in the next buffer is
 * outside the grid box or not finite (g2p.c); the step then fails. */
void gm_report_moved_point(gm_domain *domain, gm_worker_scratch *scratch,
                           size_t p, double dt);

#endif
