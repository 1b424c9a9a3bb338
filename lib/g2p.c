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

/* Every array a pass touches, in restrict-qualified locals (see p2g.c). */
typedef struct gather_view {
  const double *position[2];   /* m, committed */
  const double *velocity[2];   /* m/s, committed */
  const double *deformation[GM_F_STORED];
  const double *grid_velocity[2];     /* m/s */
  const double *grid_acceleration[2]; /* m/s^2 */
  const uint32_t *point_block;
  const uint32_t *neighbour;
  const double *mass;           /* kg */
  const double *initial_volume;
  const int32_t *material;
  double *next_position[2];
  double *next_velocity[2];
  double *next_deformation[GM_F_STORED];
  double *next_volume;
  double origin[2];
  double inv_cell;
  double cells[2];         /* cells per axis, as doubles */
  int shift;
  int dim;
  bool axisymmetric;
} gather_view;

typedef struct g2p_context {
  gm_domain *domain;
  const gm_g2p_pass *pass;
  gather_view view;
} g2p_context;

/* Nodal values seen by one point: interpolated acceleration and velocity,
 * and the velocity gradient (L_xx, L_xy, L_yx, L_yy, L_zz). */
typedef struct point_gather {
  double acceleration[2]; /* m/s^2 */
  double velocity[2];     /* m/s */
  double gradient[5];     /* 1/s */
} point_gather;

static inline void gather_2d(const gather_view *v, size_t p,
                             point_gather *out) {
  double x = v->position[0][p], y = v->position[1][p];
  double wx[2], dx[2], wy[2], dy[2];
  int64_t cx = gm_shape_linear_axis(x, v->origin[0], v->inv_cell, wx, dx);
  int64_t cy = gm_shape_linear_axis(y, v->origin[1], v->inv_cell, wy, dy);
  const uint32_t *links =
      v->neighbour + (size_t)v->point_block[p] * GM_BLOCK_NEIGHBOURS;
  int64_t mask = ((int64_t)1 << v->shift) - 1;
  size_t node[4];
  gm_cell_nodes_2d(links, v->shift, cx & mask, cy & mask, node);
  const double *restrict gvx = v->grid_velocity[0];
  const double *restrict gvy = v->grid_velocity[1];
  const double *restrict gax = v->grid_acceleration[0];
  const double *restrict gay = v->grid_acceleration[1];
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
  if (v->axisymmetric)
    sum.gradient[4] = sum.velocity[0] / x;
  *out = sum;
}

static inline void gather_1d(const gather_view *v, size_t p,
                             point_gather *out) {
  double w[2], d[2];
  int64_t edge = (int64_t)1 << v->shift, mask = edge - 1;
  int64_t local =
      gm_shape_linear_axis(v->position[0][p], v->origin[0], v->inv_cell, w,
                           d) &
      mask;
  const uint32_t *links =
      v->neighbour + (size_t)v->point_block[p] * GM_BLOCK_NEIGHBOURS;
  int64_t next = local + 1;
  size_t node[2] = {(size_t)links[0] * GM_BLOCK_NODES + (size_t)local,
                    (size_t)links[next >> v->shift] * GM_BLOCK_NODES +
                        (size_t)(next & mask)};
  point_gather sum = {{0, 0}, {0, 0}, {0, 0, 0, 0, 0}};
  for (int a = 0; a < 2; a++) {
    double velocity = v->grid_velocity[0][node[a]];
    sum.acceleration[0] += w[a] * v->grid_acceleration[0][node[a]];
    sum.velocity[0] += w[a] * velocity;
    sum.gradient[0] += velocity * d[a];
  }
  *out = sum;
}

/* Moves point p; false (with a worker error) if it leaves the grid. */
static inline bool move_point(gm_domain *domain, const gather_view *v,
                              gm_worker_scratch *scratch, size_t p,
                              const point_gather *g, double dt) {
  double moved[2] = {0.0, 0.0};
  bool inside = true;
  for (int k = 0; k < v->dim; k++) {
    moved[k] = v->position[k][p] + dt * g->velocity[k];
    v->next_position[k][p] = moved[k];
    /* Same arithmetic as gm_block_key_of and the shape functions. */
    double scaled = (moved[k] - v->origin[k]) * v->inv_cell;
    inside = inside && scaled >= 0.0 && scaled < v->cells[k];
  }
  if (inside)
    return true;
  bool finite = isfinite(moved[0]) && isfinite(moved[1]);
  gm_worker_error(scratch, finite ? GM_ERR_OUT_OF_GRID : GM_ERR_NOT_FINITE, p,
                  "step: point id %lld %s (x = %g, y = %g m at t = %g s); "
                  "the step was not taken",
                  (long long)domain->points.id[p],
                  finite ? "would leave the grid box"
                         : "got a non-finite position",
                  moved[0], moved[1], domain->time + dt);
  return false;
}

/* F <- (I + L dt) F and V = det F V0; false if det F <= 0. */
static inline bool deform_point(gm_domain *domain, const gather_view *v,
                                gm_worker_scratch *scratch, size_t p,
                                const double gradient[5], double dt) {
  double f_xx = v->deformation[F_XX][p], f_xy = v->deformation[F_XY][p];
  double f_yx = v->deformation[F_YX][p], f_yy = v->deformation[F_YY][p];
  double i_xx = 1.0 + gradient[0] * dt, i_xy = gradient[1] * dt;
  double i_yx = gradient[2] * dt, i_yy = 1.0 + gradient[3] * dt;
  double next_xx = i_xx * f_xx + i_xy * f_yx;
  double next_xy = i_xx * f_xy + i_xy * f_yy;
  double next_yx = i_yx * f_xx + i_yy * f_yx;
  double next_yy = i_yx * f_xy + i_yy * f_yy;
  /* The hoop stretch is stored in axisymmetry only (1 otherwise). */
  double next_zz =
      v->axisymmetric ? (1.0 + gradient[4] * dt) * v->deformation[F_ZZ][p]
                      : 1.0;
  v->next_deformation[F_XX][p] = next_xx;
  v->next_deformation[F_XY][p] = next_xy;
  v->next_deformation[F_YX][p] = next_yx;
  v->next_deformation[F_YY][p] = next_yy;
  if (v->axisymmetric)
    v->next_deformation[F_ZZ][p] = next_zz;
  double jacobian = (next_xx * next_yy - next_xy * next_yx) * next_zz;
  v->next_volume[p] = jacobian * v->initial_volume[p];
  if (jacobian > 0.0 && jacobian < INFINITY)
    return true;
  gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                  "step: point id %lld has det F = %g (inverted or "
                  "non-finite deformation at t = %g s); reduce dt",
                  (long long)domain->points.id[p], jacobian,
                  domain->time + dt);
  return false;
}

/* Largest c_p + |v_p| of the chunk's new state (stable_dt.c's formula). */
static void chunk_signal_speed(gm_domain *domain, const gather_view *v,
                               gm_worker_scratch *scratch, size_t first,
                               size_t count) {
  const gm_material *materials = domain->materials;
  double fastest = scratch->max_signal_speed;
  for (size_t p = first; p < first + count; p++) {
    double speed_squared = 0.0;
    for (int k = 0; k < v->dim; k++)
      speed_squared += v->next_velocity[k][p] * v->next_velocity[k][p];
    double modulus = materials[v->material[p]].p_wave_modulus;
    double speed = sqrt(modulus * v->next_volume[p] / v->mass[p]) +
                   sqrt(speed_squared);
    if (speed > fastest)
      fastest = speed;
    if (speed < INFINITY)
      continue;
    gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                    "step: point id %lld got a non-finite velocity or "
                    "density at t = %g s; the step was not taken",
                    (long long)domain->points.id[p],
                    domain->time + domain->current_dt);
  }
  scratch->max_signal_speed = fastest;
}

static void g2p_chunks(void *context, size_t begin, size_t end, int worker) {
  g2p_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gm_g2p_pass *pass = ctx->pass;
  const gather_view *v = &ctx->view;
  gm_worker_scratch *scratch = &domain->scratch[worker];
  size_t point_count = domain->points.count;
  double dt = pass->dt;
  double gradients[GM_BATCH_SIZE][5];
  for (size_t chunk = begin; chunk < end; chunk++) {
    size_t first = chunk * GM_BATCH_SIZE;
    size_t count = point_count - first < GM_BATCH_SIZE ? point_count - first
                                                       : GM_BATCH_SIZE;
    for (size_t j = 0; j < count; j++) {
      size_t p = first + j;
      point_gather g;
      if (v->dim == 1)
        gather_1d(v, p, &g);
      else
        gather_2d(v, p, &g);
      if (pass->flip_velocity)
        for (int k = 0; k < v->dim; k++)
          v->next_velocity[k][p] = v->velocity[k][p] + dt * g.acceleration[k];
      if (pass->move_points)
        move_point(domain, v, scratch, p, &g, dt);
      if (pass->deform) {
        for (int k = 0; k < 5; k++)
          gradients[j][k] = g.gradient[k];
        deform_point(domain, v, scratch, p, g.gradient, dt);
      }
    }
    if (pass->deform)
      gm_stress_update_chunk(domain, scratch, first, count, dt,
                             (const double(*)[5])gradients);
    if (pass->move_points)
      chunk_signal_speed(domain, v, scratch, first, count);
  }
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
    view->grid_velocity[k] = grid->velocity[c];
    view->grid_acceleration[k] = grid->force[c];
    view->origin[k] = domain->def.origin[c];
    view->cells[k] = (double)domain->cells[k];
  }
  for (int k = 0; k < GM_F_STORED; k++) {
    view->deformation[k] = from->deformation[k];
    view->next_deformation[k] = to->deformation[k];
  }
  view->point_block = points->point_block;
  view->neighbour = grid->neighbour;
  view->mass = points->mass;
  view->initial_volume = points->initial_volume;
  view->material = points->material;
  view->next_volume = to->volume;
  view->inv_cell = domain->inv_cell;
  view->shift = grid->shift;
  view->dim = domain->dim;
  view->axisymmetric = domain->axisymmetric;
}

void gm_g2p(gm_domain *domain, const gm_g2p_pass *pass) {
  g2p_context ctx;
  ctx.domain = domain;
  ctx.pass = pass;
  make_view(domain, &ctx.view);
  size_t chunks = (domain->points.count + GM_BATCH_SIZE - 1) / GM_BATCH_SIZE;
  gm_parallel_for(&domain->pool, chunks, g2p_chunks, &ctx);
}
