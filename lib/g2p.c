/*
 * g2p.c - grid-to-particle transfer and kinematics. One pass can update
 * particle velocities with the nodal accelerations (FLIP, 004 eq 3.17),
 * move points with the nodal velocities, and compute the velocity gradient
 * L = sum v_i (x) grad N_i (plus the hoop rate sum N_i v_ix / x in
 * axisymmetry), from which F <- (I + L dt) F, V = det F V0 (004 eq 3.23)
 * and the stress update follow. Points are processed in chunks of
 * GM_BATCH_SIZE, the unit of a material call.
 */
#include "internal.h"
#include "shape_linear.h"

#include <math.h>

typedef struct g2p_context {
  gm_domain *domain;
  const gm_g2p_pass *pass;
} g2p_context;

/* Nodal values seen by one point: interpolated acceleration and velocity,
 * and the velocity gradient (L_xx, L_xy, L_yx, L_yy, L_zz). */
typedef struct point_gather {
  double acceleration[2]; /* m/s^2 */
  double velocity[2];     /* m/s */
  double gradient[5];     /* 1/s */
} point_gather;

static void gather_2d(const gm_domain *domain, size_t p, point_gather *out) {
  const gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  const gm_point_buffers *current = &points->buffer[points->cur];
  double x = current->position[0][p], y = current->position[1][p];
  double wx[2], dx[2], wy[2], dy[2];
  int64_t cx = gm_shape_linear_axis(x, domain->def.origin[0], domain->inv_cell,
                                    wx, dx);
  int64_t cy = gm_shape_linear_axis(y, domain->def.origin[1], domain->inv_cell,
                                    wy, dy);
  const uint32_t *links =
      grid->neighbour + (size_t)points->point_block[p] * GM_BLOCK_NEIGHBOURS;
  int64_t mask = ((int64_t)1 << grid->shift) - 1;
  size_t node[4];
  gm_cell_nodes_2d(links, grid->shift, cx & mask, cy & mask, node);
  const double *restrict gvx = grid->velocity[0], *restrict gvy = grid->velocity[1];
  const double *restrict gax = grid->force[0], *restrict gay = grid->force[1];
  double weight[4] = {wx[0] * wy[0], wx[1] * wy[0], wx[0] * wy[1],
                      wx[1] * wy[1]};
  double grad_x[4] = {dx[0] * wy[0], dx[1] * wy[0], dx[0] * wy[1],
                      dx[1] * wy[1]};
  double grad_y[4] = {wx[0] * dy[0], wx[1] * dy[0], wx[0] * dy[1],
                      wx[1] * dy[1]};
  point_gather sum = {{0, 0}, {0, 0}, {0, 0, 0, 0, 0}};
  for (int n = 0; n < 4; n++) {
    double vx = gvx[node[n]], vy = gvy[node[n]];
    sum.acceleration[0] += weight[n] * gax[node[n]];
    sum.acceleration[1] += weight[n] * gay[node[n]];
    sum.velocity[0] += weight[n] * vx;
    sum.velocity[1] += weight[n] * vy;
    sum.gradient[0] += vx * grad_x[n];
    sum.gradient[1] += vx * grad_y[n];
    sum.gradient[2] += vy * grad_x[n];
    sum.gradient[3] += vy * grad_y[n];
  }
  /* Hoop strain rate v_r / r (002 sec 3, last row of B). */
  if (domain->axisymmetric)
    sum.gradient[4] = sum.velocity[0] / x;
  *out = sum;
}

static void gather_1d(const gm_domain *domain, size_t p, point_gather *out) {
  const gm_grid *grid = &domain->grid;
  const gm_points *points = &domain->points;
  double weight[2], gradient[2];
  int64_t cell = gm_shape_linear_axis(
      points->buffer[points->cur].position[0][p], domain->def.origin[0],
      domain->inv_cell, weight, gradient);
  const uint32_t *links =
      grid->neighbour + (size_t)points->point_block[p] * GM_BLOCK_NEIGHBOURS;
  int shift = grid->shift;
  int64_t local = cell & (((int64_t)1 << shift) - 1);
  point_gather sum = {{0, 0}, {0, 0}, {0, 0, 0, 0, 0}};
  for (int a = 0; a < 2; a++) {
    int64_t local_node = local + a;
    size_t node = (size_t)links[local_node >> shift] * GM_BLOCK_NODES +
                  (size_t)(local_node & (((int64_t)1 << shift) - 1));
    double v = grid->velocity[0][node];
    sum.acceleration[0] += weight[a] * grid->force[0][node];
    sum.velocity[0] += weight[a] * v;
    sum.gradient[0] += v * gradient[a];
  }
  *out = sum;
}

/* Moves point p; false (with a worker error) if it leaves the grid. */
static bool move_point(gm_domain *domain, gm_worker_scratch *scratch,
                       size_t p, const point_gather *g, double dt) {
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  double moved[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < domain->dim; k++) {
    moved[k] = from->position[k][p] + dt * g->velocity[k];
    to->position[k][p] = moved[k];
  }
  if (gm_block_key_of(domain, moved, &to->block_key[p]))
    return true;
  bool finite = isfinite(moved[0]) && isfinite(moved[1]);
  gm_worker_error(scratch, finite ? GM_ERR_OUT_OF_GRID : GM_ERR_NOT_FINITE, p,
                  "step: point id %lld %s (x = %g, y = %g m at t = %g s); "
                  "the step was not taken",
                  (long long)points->id[p],
                  finite ? "would leave the grid box" : "got a non-finite position",
                  moved[0], moved[1], domain->time + dt);
  return false;
}

/* F <- (I + L dt) F and V = det F V0; false if det F <= 0. */
static bool deform_point(gm_domain *domain, gm_worker_scratch *scratch,
                         size_t p, const double gradient[5], double dt) {
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  double increment[4] = {1.0 + gradient[0] * dt, gradient[1] * dt,
                         gradient[2] * dt, 1.0 + gradient[3] * dt};
  double f_xx = from->deformation[F_XX][p], f_xy = from->deformation[F_XY][p];
  double f_yx = from->deformation[F_YX][p], f_yy = from->deformation[F_YY][p];
  double next_xx = increment[0] * f_xx + increment[1] * f_yx;
  double next_xy = increment[0] * f_xy + increment[1] * f_yy;
  double next_yx = increment[2] * f_xx + increment[3] * f_yx;
  double next_yy = increment[2] * f_xy + increment[3] * f_yy;
  double next_zz = (1.0 + gradient[4] * dt) * from->deformation[F_ZZ][p];
  to->deformation[F_XX][p] = next_xx;
  to->deformation[F_XY][p] = next_xy;
  to->deformation[F_YX][p] = next_yx;
  to->deformation[F_YY][p] = next_yy;
  to->deformation[F_ZZ][p] = next_zz;
  double jacobian = (next_xx * next_yy - next_xy * next_yx) * next_zz;
  to->volume[p] = jacobian * points->initial_volume[p];
  if (jacobian > 0.0 && isfinite(jacobian))
    return true;
  gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                  "step: point id %lld has det F = %g (inverted or "
                  "non-finite deformation at t = %g s); reduce dt",
                  (long long)points->id[p], jacobian, domain->time + dt);
  return false;
}

static void finish_signal_speed(gm_domain *domain, gm_worker_scratch *scratch,
                                size_t first, size_t count) {
  for (size_t p = first; p < first + count; p++) {
    double speed = gm_point_signal_speed(domain, domain->points.cur ^ 1, p);
    if (!isfinite(speed)) {
      gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                      "step: point id %lld got a non-finite velocity or "
                      "density at t = %g s; the step was not taken",
                      (long long)domain->points.id[p],
                      domain->time + domain->current_dt);
      continue;
    }
    if (speed > scratch->max_signal_speed)
      scratch->max_signal_speed = speed;
  }
}

static void g2p_chunks(void *context, size_t begin, size_t end, int worker) {
  g2p_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gm_g2p_pass *pass = ctx->pass;
  gm_worker_scratch *scratch = &domain->scratch[worker];
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  double dt = pass->dt;
  double gradients[GM_BATCH_SIZE][5];
  for (size_t chunk = begin; chunk < end; chunk++) {
    size_t first = chunk * GM_BATCH_SIZE;
    size_t count = points->count - first < GM_BATCH_SIZE ? points->count - first
                                                         : GM_BATCH_SIZE;
    for (size_t j = 0; j < count; j++) {
      size_t p = first + j;
      point_gather g;
      if (domain->dim == 1)
        gather_1d(domain, p, &g);
      else
        gather_2d(domain, p, &g);
      if (pass->flip_velocity)
        for (int k = 0; k < domain->dim; k++)
          to->velocity[k][p] = from->velocity[k][p] + dt * g.acceleration[k];
      if (pass->move_points)
        move_point(domain, scratch, p, &g, dt);
      if (pass->deform) {
        for (int k = 0; k < 5; k++)
          gradients[j][k] = g.gradient[k];
        deform_point(domain, scratch, p, g.gradient, dt);
      }
    }
    if (pass->deform)
      gm_stress_update_chunk(domain, scratch, first, count, dt,
                             (const double(*)[5])gradients);
    if (pass->move_points)
      finish_signal_speed(domain, scratch, first, count);
  }
}

void gm_g2p(gm_domain *domain, const gm_g2p_pass *pass) {
  g2p_context ctx = {domain, pass};
  size_t chunks = (domain->points.count + GM_BATCH_SIZE - 1) / GM_BATCH_SIZE;
  gm_parallel_for(&domain->pool, chunks, g2p_chunks, &ctx);
}
