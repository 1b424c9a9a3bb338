/*
 * g2p.c - grid-to-particle transfer and kinematics. One pass can update
 * particle velocities with the nodal accelerations (FLIP, 004 eq 3.17),
 * move points with the nodal velocities, and compute the velocity gradient
 * L = sum v_i (x) grad N_i (plus the hoop rate sum N_i v_ix / x in
 * axisymmetry), from which F <- (I + L dt) F, V = det F V0 (004 eq 3.23)
 * and the stress update follow; with CPDI the domain map D takes the same
 * increment and may then be reset (cpdi_reset.c). Points are processed in
 * chunks of GM_BATCH_SIZE, the unit of a material call.
 */
#include "grid/grid.h"

#include "boundaries/boundaries.h"

#include "grid/apic_linear.h"
#include "grid/transfer.h"

#include <math.h>
#include <string.h>

typedef struct g2p_context {
  gm_domain *domain;
  const gm_g2p_pass *pass;
  gather_view view;
  linear_move_2d move; /* gather_move_chunk_2d */
  bool cell_mean;      /* a deformation pass with GM_VOLUMETRIC_CELL_MEAN */
} g2p_context;

/* What a pass needs from the gather decides what it computes:
 * acceleration only for the FLIP update, the velocity gradient (and the
 * nodal masses of its empty-node correction) only for the deformation or
 * APIC's C_p. A quantity is summed alone, so leaving the others out
 * changes no bit of it; the move pass then reads 4 nodal fields instead
 * of 5, the deform pass 3, and neither keeps the unused sums in registers
 * (profile of libblock at 1e5 points: the general gather spilled them to
 * the stack). with_acceleration and with_gradient are constants in each
 * specialisation below. */
static GM_ALWAYS_INLINE void gather_chunk_2d_kind(const gather_view *v,
                                                  size_t first, size_t count,
                                                  chunk_gather *out,
                                                  const bool with_acceleration,
                                                  const bool with_gradient) {
  const double *restrict px = v->position[0] + first;
  const double *restrict py = v->position[1] + first;
  const uint32_t *restrict point_block = v->point_block + first;
  const uint32_t *restrict neighbour = v->neighbour;
  const double *restrict gvx = v->grid_velocity[0];
  const double *restrict gvy = v->grid_velocity[1];
  const double *restrict gax = v->grid_acceleration[0];
  const double *restrict gay = v->grid_acceleration[1];
  const double *restrict gm = v->grid_mass;
  double origin_x = v->origin[0], origin_y = v->origin[1];
  double inv_cell = v->inv_cell;
  bool axisymmetric = v->axisymmetric;
  for (size_t j = 0; j < count; j++) {
    double wx[2], dx[2], wy[2], dy[2];
    size_t node[4];
    int64_t local[2];
    gm_linear_cell_2d(px[j], py[j], origin_x, origin_y, inv_cell,
                      neighbour + (size_t)point_block[j] * GM_BLOCK_NEIGHBOURS,
                      wx, dx, wy, dy, node, local);
    double weight[4] = {wx[0] * wy[0], wx[1] * wy[0], wx[0] * wy[1],
                        wx[1] * wy[1]};
    /* The gradients of node n = a + 2 b are dN/dx = dx[a] wy[b] and dN/dy
     * = wx[a] dy[b] with dx = dy = (-1/h, 1/h): +-grad_row[b] and
     * +-grad_column[a], negative for a = 0 (x) or b = 0 (y). A product with
     * a negated factor is the negated product, and s + (-t) is s - t, both
     * exactly in IEEE arithmetic: summing the magnitudes with the sign
     * in the operation gives every bit of sum += nodal * gradient, with 4
     * products for the gradients instead of 8 and no negations. */
    double grad_row[2] = {dx[1] * wy[0], dx[1] * wy[1]};    /* 1/m */
    double grad_column[2] = {wx[0] * dy[1], wx[1] * dy[1]}; /* 1/m */
    double ax = 0, ay = 0, vx = 0, vy = 0, lxx = 0, lxy = 0, lyx = 0, lyy = 0;
    for (int n = 0; n < 4; n++) {
      int a = n & 1, b = n >> 1;
      double nvx = gvx[node[n]], nvy = gvy[node[n]];
      if (with_acceleration) {
        ax += weight[n] * gax[node[n]];
        ay += weight[n] * gay[node[n]];
      }
      vx += weight[n] * nvx;
      vy += weight[n] * nvy;
      if (with_gradient) {
        double along_x = grad_row[b], along_y = grad_column[a];
        if (a) { /* dN/dx > 0 */
          lxx += nvx * along_x;
          lyx += nvy * along_x;
        } else {
          lxx -= nvx * along_x;
          lyx -= nvy * along_x;
        }
        if (b) { /* dN/dy > 0 */
          lxy += nvx * along_y;
          lyy += nvy * along_y;
        } else {
          lxy -= nvx * along_y;
          lyy -= nvy * along_y;
        }
      }
    }
    if (with_acceleration) {
      out->acceleration[0][j] = ax;
      out->acceleration[1][j] = ay;
    }
    out->velocity[0][j] = vx;
    out->velocity[1][j] = vy;
    if (!with_gradient)
      continue;
    /* A point exactly on a cell edge has zero weight, hence possibly no
     * mass, on the nodes across it; their velocity is undefined (stored as
     * 0) yet their gradient is not zero. Give them the point's own
     * interpolated velocity, which removes the spurious gradient. The
     * correction is summed only when a node is empty (rarely): otherwise
     * it adds v * (+0.0), which leaves every sum as it is (a sum started
     * at +0.0 is never -0.0 when rounding to nearest, and a non-finite v
     * already made the gradient non-finite), so skipping it changes no
     * bit. */
    bool any_empty = (gm[node[0]] == 0.0) | (gm[node[1]] == 0.0) |
                     (gm[node[2]] == 0.0) | (gm[node[3]] == 0.0);
    if (any_empty) {
      double grad_x[4] = {dx[0] * wy[0], dx[1] * wy[0], dx[0] * wy[1],
                          dx[1] * wy[1]};
      double grad_y[4] = {wx[0] * dy[0], wx[1] * dy[0], wx[0] * dy[1],
                          wx[1] * dy[1]};
      double empty_x = 0, empty_y = 0; /* gradient sum of massless nodes */
      for (int n = 0; n < 4; n++) {
        double empty = gm[node[n]] == 0.0 ? 1.0 : 0.0;
        empty_x += empty * grad_x[n];
        empty_y += empty * grad_y[n];
      }
      lxx += vx * empty_x;
      lxy += vx * empty_y;
      lyx += vy * empty_x;
      lyy += vy * empty_y;
    }
    out->gradient[0][j] = lxx;
    out->gradient[1][j] = lxy;
    out->gradient[2][j] = lyx;
    out->gradient[3][j] = lyy;
    /* Hoop strain rate v_r / r (002 sec 3, last row of B). */
    out->gradient[4][j] = axisymmetric ? vx / px[j] : 0.0;
  }
}

/* The pass kinds of the three schemes (step.c): FLIP velocities and moves
 * (acceleration and velocity), deformation (velocity and gradient), and
 * APIC's velocity pass (velocity and C_p = L, no acceleration). */
static void gather_chunk_2d(const gather_view *v, size_t first, size_t count,
                            chunk_gather *out, bool flip, bool deform) {
  bool gradient = deform || (flip && v->apic);
  bool acceleration = flip && !v->apic;
  if (acceleration && gradient)
    gather_chunk_2d_kind(v, first, count, out, true, true);
  else if (acceleration)
    gather_chunk_2d_kind(v, first, count, out, true, false);
  else if (gradient)
    gather_chunk_2d_kind(v, first, count, out, false, true);
  else /* a move alone (not a pass of any scheme): velocity only */
    gather_chunk_2d_kind(v, first, count, out, false, false);
}

/* The first pass of USL and USF (flip and move, no deformation) for
 * linear 2D points without APIC and periodic faces: the gather, the FLIP
 * update (flip_chunk), the move (move_chunk) and the block keys of the
 * moved points in one loop over the chunk (gm_linear_move_point_2d, every
 * bit theirs); what those loops stored to the chunk buffer and read back
 * stays in registers. Returns false if a moved point left the grid or is
 * not finite: the caller names it (report_outside_moves) and the step
 * fails. blend (pic_fraction > 0) is a constant in each specialisation
 * below. USL's move usually takes move_remap.c, which also sums the
 * re-mapped momenta; this serves USF and the scenes it does not fit. */
static GM_ALWAYS_INLINE bool
gather_move_chunk_2d_kind(const gather_view *v, const linear_move_2d *shared,
                          size_t first, size_t count, const bool blend) {
  /* A local copy: its fields stay in registers across the stores. */
  const linear_move_2d local_move = *shared, *m = &local_move;
  const double *restrict px = v->position[0] + first;
  const double *restrict py = v->position[1] + first;
  const double *restrict pvx = v->velocity[0] + first;
  const double *restrict pvy = v->velocity[1] + first;
  const uint32_t *restrict point_block = v->point_block + first;
  const uint32_t *restrict neighbour = v->neighbour;
  double *restrict next_x = v->next_position[0] + first;
  double *restrict next_y = v->next_position[1] + first;
  double *restrict next_vx = v->next_velocity[0] + first;
  double *restrict next_vy = v->next_velocity[1] + first;
  int64_t *restrict key = v->block_key + first;
  double origin_x = m->origin[0], origin_y = m->origin[1];
  double inv_cell = m->inv_cell;
  bool inside = true;
  for (size_t j = 0; j < count; j++) {
    double wx[2], dx[2], wy[2], dy[2], moved[4];
    size_t node[4];
    int64_t local[2];
    gm_linear_cell_2d(px[j], py[j], origin_x, origin_y, inv_cell,
                      neighbour + (size_t)point_block[j] * GM_BLOCK_NEIGHBOURS,
                      wx, dx, wy, dy, node, local);
    double weight[4] = {wx[0] * wy[0], wx[1] * wy[0], wx[0] * wy[1],
                        wx[1] * wy[1]};
    inside &= gm_linear_move_point_2d(m, weight, node, px[j], py[j], pvx[j],
                                      pvy[j], blend, moved, &key[j]);
    next_vx[j] = moved[0];
    next_vy[j] = moved[1];
    next_x[j] = moved[2];
    next_y[j] = moved[3];
  }
  return inside;
}

/* Whether a flip-and-move pass may take gather_move_chunk_2d_kind. */
static bool fused_move_fits(const gather_view *v) {
  return v->dim == 2 && v->shape_grid->shape == GM_SHAPE_LINEAR && !v->apic &&
         !v->periodic_x;
}

static bool gather_move_chunk_2d(const gather_view *v, const linear_move_2d *m,
                                 size_t first, size_t count) {
  if (m->pic == 0.0) /* FLIP: flip_chunk's own branch */
    return gather_move_chunk_2d_kind(v, m, first, count, false);
  return gather_move_chunk_2d_kind(v, m, first, count, true);
}

void gm_linear_move_2d_init(const gm_domain *domain, double dt,
                            linear_move_2d *m) {
  const gm_grid *grid = &domain->grid;
  for (int k = 0; k < 2; k++) {              /* as make_view */
    m->grid_velocity[k] = grid->momentum[k]; /* velocity by now */
    m->grid_acceleration[k] = grid->force[k];
    m->origin[k] = domain->shape_grid.origin[k];
    m->cells[k] = (double)(domain->cells[k] + GM_GHOST_LAYERS);
  }
  m->inv_cell = domain->inv_cell;
  m->dt = dt;
  m->pic = domain->def.pic_fraction;
  m->flip = 1.0 - m->pic;
  m->shift = grid->shift;
  m->blocks_x = grid->blocks_per_axis[0];
}

static void gather_chunk_1d(const gather_view *v, size_t first, size_t count,
                            chunk_gather *out) {
  int64_t edge = (int64_t)1 << v->shift, mask = edge - 1;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    double w[2], d[2];
    int64_t local = gm_shape_linear_axis(v->position[0][p], v->origin[0],
                                         v->inv_cell, w, d) &
                    mask;
    const uint32_t *links =
        v->neighbour + (size_t)v->point_block[p] * GM_BLOCK_NEIGHBOURS;
    int64_t next = local + 1;
    size_t node[2] = {(size_t)links[0] * GM_BLOCK_NODES + (size_t)local,
                      (size_t)links[next >> v->shift] * GM_BLOCK_NODES +
                          (size_t)(next & mask)};
    double acceleration = 0.0, velocity = 0.0, gradient = 0.0, empty = 0.0;
    for (int a = 0; a < 2; a++) {
      double nodal = v->grid_velocity[0][node[a]];
      acceleration += w[a] * v->grid_acceleration[0][node[a]];
      velocity += w[a] * nodal;
      gradient += nodal * d[a];
      empty += v->grid_mass[node[a]] == 0.0 ? d[a] : 0.0;
    }
    gradient += velocity * empty; /* see gather_chunk_2d */
    out->acceleration[0][j] = acceleration;
    out->velocity[0][j] = velocity;
    out->gradient[0][j] = gradient;
    for (int k = 1; k < 5; k++)
      out->gradient[k][j] = 0.0;
  }
}

/* Linear APIC: the part of C_p = sum v_i (x) grad N_i that the
 * acceleration of a node of too little mass made this step is taken out,
 * C_p -= dt sum_i (1 - theta_i) a_i (x) grad N_i (apic_linear.h says why
 * and how much), at the positions of the gather. A point none of whose
 * nodes is light keeps every bit of C_p. */
static void light_nodes_chunk(const gm_domain *domain, const gather_view *v,
                              size_t first, size_t count, double dt) {
  const double *gm = v->grid_mass;
  int dim = v->dim;
  int64_t mask = ((int64_t)1 << v->shift) - 1;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    double x = v->position[0][p], y = v->position[dim > 1 ? 1 : 0][p];
    double critical = gm_apic_light_node_mass(domain, p, x, dt); /* kg */
    double wx[2], dx[2], wy[2] = {1.0, 0.0}, dy[2] = {0.0, 0.0};
    size_t node[4];
    const uint32_t *links =
        v->neighbour + (size_t)v->point_block[p] * GM_BLOCK_NEIGHBOURS;
    if (dim == 1) {
      int64_t local =
          gm_shape_linear_axis(x, v->origin[0], v->inv_cell, wx, dx) & mask;
      int64_t next = local + 1;
      node[0] = (size_t)links[0] * GM_BLOCK_NODES + (size_t)local;
      node[1] = (size_t)links[next >> v->shift] * GM_BLOCK_NODES +
                (size_t)(next & mask);
    } else {
      int64_t local[2];
      gm_linear_cell_2d(x, y, v->origin[0], v->origin[1], v->inv_cell, links,
                        wx, dx, wy, dy, node, local);
    }
    int nodes = dim == 1 ? 2 : 4;
    bool light = false;
    for (int n = 0; n < nodes; n++)
      light |= gm[node[n]] < critical;
    if (!light)
      continue;
    double change[4] = {0, 0, 0, 0}; /* 1/s, xx xy yx yy */
    for (int n = 0; n < nodes; n++) {
      double deficit = gm_apic_light_node_deficit(gm[node[n]], critical);
      int a = n & 1, b = n >> 1;
      double grad[2] = {dx[a] * wy[b], wx[a] * dy[b]}; /* 1/m */
      for (int i = 0; i < dim; i++) {
        double part = dt * deficit * v->grid_acceleration[i][node[n]];
        for (int k = 0; k < dim; k++)
          change[dim * i + k] += part * grad[k];
      }
    }
    for (int c = 0; c < dim * dim; c++)
      v->next_affine[c][p] -= change[c];
  }
}

/* Particle velocities, FLIP: v_p += dt * sum N_i a_i (004 eq 3.17),
 * blended with PIC, v_p = sum N_i v_i, by gm_domain_def.pic_fraction. The
 * nodal velocities here are already the updated ones (grid_update.c).
 * APIC (Jiang et al. 2015), gathered at the positions of the step's
 * start: v_p = sum N_i v_i, and the affine matrix: B_p = sum N_i v_i
 * (x_i - x_p)^T for the wide shapes (g2p_wide.c), C_p = sum v_i (x) grad
 * N_i, the velocity gradient L already gathered, for linear MPM (p2g.c
 * says why linear MPM keeps C_p rather than B_p). */
static void flip_chunk(const gm_domain *domain, const gather_view *v,
                       size_t first, size_t count, const chunk_gather *g,
                       double dt) {
  if (v->apic) {
    for (int k = 0; k < v->dim; k++)
      memcpy(v->next_velocity[k] + first, g->velocity[k],
             count * sizeof(double));
    bool linear = v->shape_grid->shape == GM_SHAPE_LINEAR;
    for (int k = 0; k < v->dim * v->dim; k++) /* L: xx xy yx yy, as B */
      memcpy(v->next_affine[k] + first, linear ? g->gradient[k] : g->affine[k],
             count * sizeof(double));
    if (linear)
      light_nodes_chunk(domain, v, first, count, dt);
    return;
  }
  double pic = v->pic_fraction, flip = 1.0 - pic; /* - */
  for (int k = 0; k < v->dim; k++) {
    const double *restrict velocity = v->velocity[k] + first;
    const double *restrict acceleration = g->acceleration[k];
    const double *restrict grid_velocity = g->velocity[k];
    double *restrict next = v->next_velocity[k] + first;
    if (pic == 0.0) { /* FLIP: bitwise as before the blend existed */
      for (size_t j = 0; j < count; j++)
        next[j] = velocity[j] + dt * acceleration[j];
      continue;
    }
    for (size_t j = 0; j < count; j++)
      next[j] =
          flip * (velocity[j] + dt * acceleration[j]) + pic * grid_velocity[j];
  }
}

static void report_outside_moves(gm_domain *domain, gm_worker_scratch *scratch,
                                 size_t first, size_t count, double dt);

/* x_p += dt * sum N_i v_i; a point leaving the grid fails the step, or
 * across periodic x faces comes back through the other one. */
static void move_chunk(gm_domain *domain, const gather_view *v,
                       gm_worker_scratch *scratch, size_t first, size_t count,
                       const chunk_gather *g, double dt) {
  bool inside = true;
  for (int k = 0; k < v->dim; k++) {
    const double *restrict position = v->position[k] + first;
    const double *restrict velocity = g->velocity[k];
    double *restrict next = v->next_position[k] + first;
    /* Same arithmetic as gm_block_key_of and the shape functions. */
    double origin = v->origin[k], inv_cell = v->inv_cell, cells = v->cells[k];
    bool axis_inside = true;
    bool wrap = k == 0 && v->periodic_x;
    if (!wrap) { /* the same arithmetic, no test per point but the bounds */
      for (size_t j = 0; j < count; j++) {
        double moved = position[j] + dt * velocity[j];
        next[j] = moved;
        double scaled = (moved - origin) * inv_cell;
        axis_inside &= (scaled >= GM_GHOST_LAYERS) & (scaled < cells);
      }
    } else {
      for (size_t j = 0; j < count; j++) {
        next[j] = gm_periodic_wrap_x(domain, position[j] + dt * velocity[j]);
        double scaled = (next[j] - origin) * inv_cell;
        axis_inside &= scaled >= GM_GHOST_LAYERS && scaled < cells;
      }
    }
    inside = inside && axis_inside;
  }
  bool wide = v->shape_grid->shape != GM_SHAPE_LINEAR; /* keys: later */
  if (inside && wide)
    return;     /* every point inside: nothing to report (was: each point
                   tested again through gm_report_moved_point) */
  if (inside) { /* keys of the moved points, for the next step */
    const double *x = v->next_position[0] + first;
    const double *y = v->next_position[v->dim > 1 ? 1 : 0] + first;
    int64_t *restrict key = v->block_key + first;
    for (size_t j = 0; j < count; j++)
      key[j] =
          gm_block_key_inside(v->grid, x[j], y[j], v->origin_xy, v->inv_cell);
    return;
  }
  report_outside_moves(domain, scratch, first, count, dt);
}

/* Names the moved points of a chunk (next buffer) outside the grid box or
 * not finite; the step then fails. */
static void report_outside_moves(gm_domain *domain, gm_worker_scratch *scratch,
                                 size_t first, size_t count, double dt) {
  for (size_t p = first; p < first + count; p++)
    gm_report_moved_point(domain, scratch, p, dt);
}

void gm_report_moved_point(gm_domain *domain, gm_worker_scratch *scratch,
                           size_t p, double dt) {
  if (gm_rigid_move_is_provisional(domain, p))
    return; /* RIGID_POINTS sets and tests its position (rigid.c) */
  const gm_point_buffers *next = &domain->points.buffer[domain->points.cur ^ 1];
  double moved[2] = {next->position[0][p],
                     domain->dim > 1 ? next->position[1][p] : 0.0};
  int64_t key;
  if (gm_block_key_of(domain, moved, &key))
    return;
  bool finite = isfinite(moved[0]) && isfinite(moved[1]);
  gm_worker_error(scratch, finite ? GM_ERR_OUT_OF_GRID : GM_ERR_NOT_FINITE, p,
                  "step: point id %lld %s (x = %g, y = %g m at t = %g s); "
                  "the step was not taken",
                  (long long)domain->points.id[p],
                  finite ? "would leave the grid box"
                         : "got a non-finite position",
                  moved[0], moved[1], domain->time + dt);
}

/* F <- (I + L dt) F and V = det F V0 (004 eq 3.23); det F <= 0 fails the
 * step (returns false). In USF's second half (step.c) F and D are updated
 * in place: each is read whole before it is written, and the F and D
 * pointers are not restrict. */
static bool deform_chunk(gm_domain *domain, const gather_view *v,
                         gm_worker_scratch *scratch, size_t first, size_t count,
                         const chunk_gather *g, double dt) {
  const double *f_xx = v->deformation[F_XX] + first;
  const double *f_xy = v->deformation[F_XY] + first;
  const double *f_yx = v->deformation[F_YX] + first;
  const double *f_yy = v->deformation[F_YY] + first;
  double *n_xx = v->next_deformation[F_XX] + first;
  double *n_xy = v->next_deformation[F_XY] + first;
  double *n_yx = v->next_deformation[F_YX] + first;
  double *n_yy = v->next_deformation[F_YY] + first;
  const double *restrict initial_volume = v->initial_volume + first;
  double *restrict volume = v->next_volume + first;
  const double *restrict l_xx = g->gradient[0], *restrict l_xy = g->gradient[1];
  const double *restrict l_yx = g->gradient[2], *restrict l_yy = g->gradient[3];
  bool positive = true;
  for (size_t j = 0; j < count; j++) {
    double jacobian = gm_deform_plane_point(
        dt, l_xx[j], l_xy[j], l_yx[j], l_yy[j], f_xx[j], f_xy[j], f_yx[j],
        f_yy[j], &n_xx[j], &n_xy[j], &n_yx[j], &n_yy[j]);
    volume[j] = jacobian * initial_volume[j];
    positive &= jacobian > 0.0 && jacobian < INFINITY;
  }
  if (v->next_domain_map[0]) /* CPDI: the domain map takes F's increment */
    gm_deform_domain_map_chunk(v, first, count, g, dt);
  if (v->axisymmetric) { /* the hoop stretch multiplies det F */
    const double *f_zz = v->deformation[F_ZZ] + first;
    double *n_zz = v->next_deformation[F_ZZ] + first;
    const double *restrict l_zz = g->gradient[4];
    for (size_t j = 0; j < count; j++) {
      n_zz[j] = (1.0 + l_zz[j] * dt) * f_zz[j];
      volume[j] *= n_zz[j];
      positive &= n_zz[j] > 0.0;
    }
  }
  if (positive)
    return true;
  gm_report_inverted_chunk(domain, v, scratch, first, count, dt);
  return false;
}

void gm_report_inverted_chunk(gm_domain *domain, const gather_view *v,
                              gm_worker_scratch *scratch, size_t first,
                              size_t count, double dt) {
  const double *initial_volume = v->initial_volume + first;
  const double *volume = v->next_volume + first;
  for (size_t j = 0; j < count; j++) {
    double jacobian = volume[j] / initial_volume[j];
    if (jacobian > 0.0 && jacobian < INFINITY)
      continue;
    gm_worker_error(scratch, GM_ERR_NOT_FINITE, first + j,
                    "step: point id %lld has det F = %g (inverted or "
                    "non-finite deformation at t = %g s); reduce dt",
                    (long long)domain->points.id[first + j], jacobian,
                    domain->time + dt);
    /* A finite inversion is a step too large for the motion (an impact):
     * the step is retried with a smaller dt (step.c). */
    if (scratch->error_index == first + j && isfinite(jacobian))
      scratch->error_inverted = true;
  }
}

/* Signal-speed bound of the chunk's new state: the largest c_p^2 and the
 * largest |v_p|^2 (stable_dt.c combines them; no square root per point). */
static void chunk_signal_speed(gm_domain *domain, const gather_view *v,
                               gm_worker_scratch *scratch, size_t first,
                               size_t count) {
  const gm_material *materials = domain->materials;
  const double *restrict vx = v->next_velocity[0];
  const double *restrict vy = v->next_velocity[1];
  const double *restrict volume = v->next_volume, *restrict mass = v->mass;
  const int32_t *restrict material = v->material;
  double wave = scratch->max_wave_speed_squared;
  double flow = scratch->max_point_speed_squared;
  double screen = 0.0; /* NaN if any value is not finite */
  bool planar = v->dim > 1;
  for (size_t p = first; p < first + count; p++) {
    double speed_squared = vx[p] * vx[p] + (planar ? vy[p] * vy[p] : 0.0);
    /* c^2 = M / rho = M V / m */
    double wave_squared =
        materials[material[p]].p_wave_modulus * volume[p] / mass[p];
    screen += (speed_squared + wave_squared) * 0.0;
    flow = speed_squared > flow ? speed_squared : flow;
    wave = wave_squared > wave ? wave_squared : wave;
  }
  scratch->max_wave_speed_squared = wave;
  scratch->max_point_speed_squared = flow;
  if (screen == 0.0)
    return;
  for (size_t p = first; p < first + count; p++) {
    if (isfinite(vx[p]) && (!planar || isfinite(vy[p])))
      continue;
    gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                    "step: point id %lld got a non-finite velocity at t = "
                    "%g s; the step was not taken",
                    (long long)domain->points.id[p],
                    domain->time + domain->current_dt);
  }
}

/* The chunks of one pass; flip, move and deform are constants in each
 * specialisation below. */
static GM_ALWAYS_INLINE void g2p_chunks_kind(void *context, size_t begin,
                                             size_t end, int worker,
                                             const bool flip, const bool move,
                                             const bool deform) {
  g2p_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gather_view *v = &ctx->view;
  gm_worker_scratch *scratch = &domain->scratch[worker];
  size_t point_count = domain->points.count;
  double dt = ctx->pass->dt;
  double move_dt = ctx->pass->move_dt > 0.0 ? ctx->pass->move_dt : dt; /* s */
  chunk_gather *g = scratch->gather;
  for (size_t chunk = begin; chunk < end; chunk++) {
    size_t first = chunk * GM_BATCH_SIZE;
    size_t count = point_count - first < GM_BATCH_SIZE ? point_count - first
                                                       : GM_BATCH_SIZE;
    bool wide = v->shape_grid->shape != GM_SHAPE_LINEAR;
    if (flip && move && !deform && fused_move_fits(v)) {
      if (!gather_move_chunk_2d(v, &ctx->move, first, count))
        report_outside_moves(domain, scratch, first, count, dt);
    } else {
      if (wide)
        gm_gather_chunk_wide(v, first, count, g, domain, scratch, flip, deform);
      else if (v->dim == 1)
        gather_chunk_1d(v, first, count, g);
      else
        gather_chunk_2d(v, first, count, g, flip, deform);
      if (deform && ctx->cell_mean) /* L's trace to its cell's mean */
        gm_volumetric_apply_chunk(domain, v, first, count, g);
      if (flip)
        flip_chunk(domain, v, first, count, g, dt);
      if (move)
        move_chunk(domain, v, scratch, first, count, g, move_dt);
    }
    /* A chunk with an inverted point skips its material call: the step
     * fails anyway, and materials never see a non-positive density. */
    bool deformed = true;
    int plane_material =
        deform ? gm_plane_chunk_material(domain, v, ctx->pass, first, count)
               : -1;
    bool elastic =
        plane_material >= 0 &&
        domain->materials[plane_material].update == gm_elastic_update;
    bool mohr_coulomb = plane_material >= 0 && !elastic &&
                        gm_mohr_coulomb_chunk_fits(domain, plane_material);
    if (elastic || mohr_coulomb) {
      /* Elastic or Mohr-Coulomb plane points: F, V, Jaumann and the
       * material's law in fused loops (deform_elastic.c,
       * deform_mohr_coulomb.c), bitwise the arithmetic of the general
       * path. */
      deformed = elastic ? gm_deform_elastic_chunk(domain, v, scratch, first,
                                                   count, g, dt)
                         : gm_deform_mohr_coulomb_chunk(domain, v, scratch,
                                                        first, count, g, dt);
      if (deformed && domain->def.family != GM_FAMILY_PLAIN) {
        double start = gm_monotonic_seconds();
        gm_density_control_chunk(domain, first, count);
        scratch->density_control_seconds += gm_monotonic_seconds() - start;
      }
      if (deformed && v->next_domain_map[0]) /* as below */
        gm_cpdi_reset_chunk(domain, first, count);
    } else if (deform &&
               deform_chunk(domain, v, scratch, first, count, g, dt)) {
      const double *gradient[5] = {g->gradient[0], g->gradient[1],
                                   g->gradient[2], g->gradient[3],
                                   g->gradient[4]};
      gm_stress_update_chunk(domain, scratch, first, count, dt, gradient,
                             ctx->pass->in_place);
      if (domain->def.family != GM_FAMILY_PLAIN) {
        double start = gm_monotonic_seconds();
        gm_density_control_chunk(domain, first, count);
        scratch->density_control_seconds += gm_monotonic_seconds() - start;
      }
      if (v->next_domain_map[0]) /* once D is final but for the reset */
        gm_cpdi_reset_chunk(domain, first, count);
    } else if (deform) {
      deformed = false;
    }
    /* A wide support depends on F (cpGIMP) or D (CPDI) too: keys once
     * they are final. */
    bool finish = ctx->pass->finish; /* the new state is complete */
    if (finish && wide && deformed)
      gm_wide_keys_chunk(domain, v, scratch, first, count);
    if (finish)
      chunk_signal_speed(domain, v, scratch, first, count);
  }
}

static void g2p_flip_only(void *c, size_t b, size_t e, int w) {
  g2p_chunks_kind(c, b, e, w, true, false, false); /* MUSL, second */
}
static void g2p_move_deform(void *c, size_t b, size_t e, int w) {
  g2p_chunks_kind(c, b, e, w, false, true, true); /* MUSL, third */
}
/* USL's second pass; USF's first and third; MUSL's first */
static void g2p_deform_only(void *c, size_t b, size_t e, int w) {
  g2p_chunks_kind(c, b, e, w, false, false, true);
}
static void g2p_flip_move(void *c, size_t b, size_t e, int w) {
  g2p_chunks_kind(c, b, e, w, true, true, false); /* USL first, USF second */
}

/* The first sweep of a deformation pass with GM_VOLUMETRIC_CELL_MEAN: each
 * point's tr L and cell (volumetric_mean.c), from the gather the pass
 * itself then repeats (the same function on the same inputs: the same
 * bits). */
static void g2p_volumetric_rates(void *context, size_t begin, size_t end,
                                 int worker) {
  g2p_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gather_view *v = &ctx->view;
  gm_worker_scratch *scratch = &domain->scratch[worker];
  size_t point_count = domain->points.count;
  chunk_gather *g = scratch->gather;
  bool wide = v->shape_grid->shape != GM_SHAPE_LINEAR;
  for (size_t chunk = begin; chunk < end; chunk++) {
    size_t first = chunk * GM_BATCH_SIZE;
    size_t count = point_count - first < GM_BATCH_SIZE ? point_count - first
                                                       : GM_BATCH_SIZE;
    if (wide)
      gm_gather_chunk_wide(v, first, count, g, domain, scratch, false, true);
    else
      gather_chunk_2d(v, first, count, g, false, true);
    gm_volumetric_store_chunk(domain, v, first, count, g);
  }
}

/* The passes of the three schemes (step.c): USL flip+move then deform,
 * MUSL deform (dt/2) then flip then move+deform (dt/2), USF deform (dt/2)
 * then flip+move then deform (dt/2). */
static gm_parallel_fn *pass_kernel(const gm_g2p_pass *pass) {
  if (pass->flip_velocity && pass->move_points)
    return g2p_flip_move;
  if (pass->flip_velocity)
    return g2p_flip_only;
  if (pass->move_points)
    return g2p_move_deform;
  return g2p_deform_only;
}

static void make_view(gm_domain *domain, gather_view *view) {
  gm_points *points = &domain->points;
  gm_grid *grid = &domain->grid;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  for (int k = 0; k < 2; k++) {
    int c = k < domain->dim ? k : 0; /* 1D: the y slots alias x, unused */
    view->position[k] = from->position[c];
    view->velocity[k] = from->velocity[c];
    view->next_position[k] = to->position[c];
    view->next_velocity[k] = to->velocity[c];
    view->grid_velocity[k] = grid->momentum[c]; /* velocity by now */
    view->grid_mass = grid->mass;
    view->grid_acceleration[k] = grid->force[c];
    view->origin[k] = domain->shape_grid.origin[c]; /* node 0 */
    view->cells[k] = (double)(domain->cells[c] + GM_GHOST_LAYERS);
    view->domain_size[k] = points->domain_size[c];
  }
  for (int k = 0; k < GM_F_STORED; k++) {
    view->deformation[k] = from->deformation[k];
    view->next_deformation[k] = to->deformation[k];
  }
  /* The support of wide shapes stays the committed one (the step's shape
   * functions); only F, D and the stress (stress_update.c) may come from
   * the next buffer (gm_g2p). */
  gm_support_tensor(domain, from, view->support_tensor);
  gm_support_tensor(domain, to, view->next_support_tensor);
  for (int k = 0; k < 4; k++) { /* NULL unless CPDI */
    view->domain_map[k] = from->domain_map[k];
    view->next_domain_map[k] = to->domain_map[k];
  }
  view->point_block = points->point_block;
  view->grid = grid;
  view->periodic_x = gm_periodic_x(domain);
  view->block_key = points->block_key;
  view->origin_xy = domain->shape_grid.origin;
  view->shape_grid = &domain->shape_grid;
  view->neighbour = grid->neighbour;
  view->mass = points->mass;
  view->initial_volume = points->initial_volume;
  view->material = points->material;
  view->next_volume = to->volume;
  view->inv_cell = domain->inv_cell;
  view->pic_fraction = domain->def.pic_fraction;
  view->shift = grid->shift;
  view->dim = domain->dim;
  view->axisymmetric = domain->axisymmetric;
  view->apic = domain->def.transfer == GM_TRANSFER_APIC;
  view->affine = false; /* set by gm_g2p for a velocity pass */
  view->cell = domain->def.cell_size;
  for (int k = 0; k < 4; k++) /* 1D: only B_xx */
    view->next_affine[k] =
        view->apic ? to->affine[k < gm_affine_stored(domain) ? k : 0] : NULL;
}

/* One buffer per worker serves the 2D and the 3D gathers. */
size_t gm_chunk_gather_size(void) {
  size_t plane = sizeof(chunk_gather), solid = gm_chunk_gather_3d_size();
  return plane > solid ? plane : solid;
}

void gm_g2p(gm_domain *domain, const gm_g2p_pass *pass) {
  if (domain->dim == 3) {
    gm_g2p_3d(domain, pass);
    return;
  }
  g2p_context ctx;
  ctx.domain = domain;
  ctx.pass = pass;
  make_view(domain, &ctx.view);
  gm_linear_move_2d_init(domain, pass->dt, &ctx.move);
  ctx.view.affine = ctx.view.apic && pass->flip_velocity;
  /* USL's deformation gather (after the sweep, which gm_cpdi_cache_fits
   * implies) reads the CPDI cells its scatter kept (cpdi_cache.h). */
  memset(&ctx.view.cpdi_cache, 0, sizeof ctx.view.cpdi_cache);
  if (pass->deform && !pass->flip_velocity && !pass->move_points &&
      !pass->in_place && gm_cpdi_cache_fits(domain))
    gm_cpdi_cache_arrays(domain, &ctx.view.cpdi_cache);
  if (pass->in_place) {
    for (int k = 0; k < GM_F_STORED; k++)
      ctx.view.deformation[k] = ctx.view.next_deformation[k];
    for (int k = 0; k < 4; k++)
      ctx.view.domain_map[k] = ctx.view.next_domain_map[k];
  }
  size_t chunks = (domain->points.count + GM_BATCH_SIZE - 1) / GM_BATCH_SIZE;
  /* 2D here (3D: g2p_3d.c); gm_domain_set_volumetric refuses 1D. */
  ctx.cell_mean = pass->deform && domain->dim == 2 &&
                  domain->volumetric == GM_VOLUMETRIC_CELL_MEAN;
  if (ctx.cell_mean) {
    gm_parallel_for(&domain->pool, chunks, g2p_volumetric_rates, &ctx);
    gm_volumetric_sum(domain);
  }
  gm_parallel_for(&domain->pool, chunks, pass_kernel(pass), &ctx);
}
