/*
 * g2p_3d.c - grid-to-particle transfer and kinematics in 3D with linear
 * shape functions (the 8 nodes of the point's cell), a GIMP box (uGIMP,
 * cpGIMP: up to 5 nodes per axis) or a B-spline (3 or 4 nodes per axis;
 * support_3d.h). One pass can update
 * particle velocities with the nodal accelerations (FLIP, 004 eq 3.17,
 * blended with PIC by gm_domain_def.pic_fraction), move points with the
 * nodal velocities, and compute the velocity gradient L = sum v_i (x)
 * grad N_i (nine components), from which F <- (I + L dt) F, V = det F V0
 * (004 eq 3.23) and the stress update (stress_update.c, the full Jaumann
 * spin) follow. Points are processed in chunks of GM_BATCH_SIZE in index
 * order, each chunk by one worker: nothing is summed across points, so
 * the results do not depend on the worker count. CPDI's domain map D
 * takes F's increments and is reset once too distorted (cpdi_reset.c).
 * A linear point is keyed by its cell when it moves; a GIMP or CPDI point
 * by its support's lowest node once the step's last pass has its final
 * position and F or D (cpGIMP's box follows F, CPDI's D), as in 2D
 * (g2p_wide.c).
 *
 * GM_TRANSFER_APIC (Jiang et al. 2015): the velocity pass sets v_p to the
 * PIC velocity sum N_ip v_i and the affine matrix to B_p = sum N_ip v_i
 * (x_i - x_p)^T for the GIMP boxes, or to C_p = L = sum v_i (x) grad
 * N_ip (the same matrix, B_p D_p^-1, at the positions of the gather) for
 * linear MPM, which keeps C_p (p2g_3d.c, and p2g.c for why).
 */
#include "grid/grid.h"

#include "boundaries/boundaries.h"

#include "grid/apic_3d.h"
#include "grid/apic_linear.h"

#include <math.h>
#include <string.h>

/* Row-major indices of L_ij = dv_i/dx_j (materials/jaumann.c's order). */
enum { L_XX, L_XY, L_XZ, L_YX, L_YY, L_YZ, L_ZX, L_ZY, L_ZZ };

/* What the grid tells the points of one chunk, SoA. */
typedef struct chunk_gather_3d {
  double acceleration[3][GM_BATCH_SIZE]; /* m/s^2 */
  double velocity[3][GM_BATCH_SIZE];     /* m/s */
  double gradient[9][GM_BATCH_SIZE];     /* 1/s, L row-major */
  double affine[9][GM_BATCH_SIZE]; /* m^2/s, APIC's B_p (GIMP), row-major */
} chunk_gather_3d;

size_t gm_chunk_gather_3d_size(void) {
  return sizeof(chunk_gather_3d);
}

typedef struct g2p_3d_context {
  gm_domain *domain;
  const gm_g2p_pass *pass;
  bool left_block[256]; /* per worker (domain.c: at most 256): a point
                           keyed this pass left the block it was binned in */
  bool cell_mean;       /* a deformation pass with GM_VOLUMETRIC_CELL_MEAN */
} g2p_3d_context;

/* The sum of grad N_i (1/m) over the massless nodes of a support, node
 * by node in the order of the gather (the same products, so the same
 * bits as summing it there). */
static void empty_gradient_3d(const gm_grid *grid, const uint32_t *links,
                              const int64_t local[3],
                              double (*w)[GM_SUPPORT_3D_MAX_SPAN],
                              double (*d)[GM_SUPPORT_3D_MAX_SPAN], int span_x,
                              int span_y, int span_z, double empty[3]) {
  for (int c = 0; c < span_z; c++)
    for (int b = 0; b < span_y; b++)
      for (int a = 0; a < span_x; a++) {
        size_t node =
            gm_block_node_3d(links, local[0] + a, local[1] + b, local[2] + c);
        if (grid->mass[node] != 0.0)
          continue;
        empty[0] += d[0][a] * w[1][b] * w[2][c];
        empty[1] += w[0][a] * d[1][b] * w[2][c];
        empty[2] += w[0][a] * w[1][b] * d[2][c];
      }
}

/* Interpolates a, v and L at the chunk's committed positions (and, for
 * GIMP, the committed F: the support the scatter used); the acceleration
 * only for a FLIP pass, L only for a deformation pass or APIC's C_p in
 * linear MPM, B_p only for APIC's velocity pass with GIMP (constants in
 * each specialisation below, as is wide; each sum is taken alone, so
 * leaving one out changes no bit of the others). */
static GM_ALWAYS_INLINE void
gather_chunk_3d_kind(const gm_domain *domain, gm_worker_scratch *scratch,
                     size_t first, size_t count, chunk_gather_3d *out,
                     const bool with_acceleration, const bool with_gradient,
                     const bool with_affine, const bool wide, const bool cpdi) {
  const gm_points *points = &domain->points;
  const gm_grid *grid = &domain->grid;
  const gm_point_buffers *current = &points->buffer[points->cur];
  const double *origin = domain->shape_grid.origin; /* m, node 0 */
  double inv_cell = domain->inv_cell;               /* 1/m */
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    uint32_t block = points->point_block[p];
    const uint32_t *links =
        grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
    gm_box_support_3d support; /* weights and gradients (1/m) per axis */
    gm_cpdi_support_3d dense;  /* CPDI: per node (support_cpdi_3d.h) */
    int64_t local[3];
    bool found = true;
    if (cpdi) {
      double x[3] = {current->position[0][p], current->position[1][p],
                     current->position[2][p]}; /* m */
      double half[3], f[9];                    /* m; D row-major */
      const double *const *deformation = gm_support_slots_3d(domain, current);
      gm_box_half_edges_3d(GM_SHAPE_CPDI,
                           (const double *const *)points->domain_size,
                           deformation, p, half);
      gm_deformation_rows_3d(deformation, p, f);
      found =
          gm_cpdi_support_compute_3d(&domain->shape_grid, x, f, half, &dense);
      int64_t base[3];
      gm_block_coordinates_3d(grid, grid->block_key[block], base);
      for (int axis = 0; found && axis < 3; axis++) {
        local[axis] = dense.lowest[axis] - (base[axis] << GM_BLOCK_SHIFT_3D);
        found = local[axis] >= 0 &&
                local[axis] + dense.span[axis] <= 2 * GM_BLOCK_EDGE_3D;
      }
      for (int axis = 0; axis < 3; axis++) { /* APIC's offsets use them */
        support.span[axis] = dense.span[axis];
        support.lowest[axis] = dense.lowest[axis];
      }
    } else if (wide) {
      double x[3] = {current->position[0][p], current->position[1][p],
                     current->position[2][p]}; /* m */
      double half[3];                          /* m */
      gm_box_half_edges_3d(
          domain->shape_grid.shape, (const double *const *)points->domain_size,
          (const double *const *)current->deformation, p, half);
      found = gm_box_support_compute_3d(&domain->shape_grid, x, half, &support);
      int64_t base[3];
      gm_block_coordinates_3d(grid, grid->block_key[block], base);
      for (int axis = 0; found && axis < 3; axis++) {
        local[axis] = support.lowest[axis] - (base[axis] << GM_BLOCK_SHIFT_3D);
        found = local[axis] >= 0 &&
                local[axis] + support.span[axis] <= 2 * GM_BLOCK_EDGE_3D;
      }
    } else {
      for (int axis = 0; axis < 3; axis++)
        local[axis] = gm_shape_linear_axis(
                          current->position[axis][p], origin[axis], inv_cell,
                          support.weight[axis], support.gradient[axis]) &
                      mask;
    }
    double a[3] = {0, 0, 0}, v[3] = {0, 0, 0}, l[9] = {0};
    double affine[9] = {0};                   /* m^2/s, B_p */
    double offset[3][GM_SUPPORT_3D_MAX_SPAN]; /* m, x_i - x_p per axis */
    double empty[3] = {0, 0, 0}; /* gradient sum of massless nodes, 1/m */
    bool any_empty = false;
    if (!found) { /* gathers nothing: the step fails */
      gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                      "step: the support of point id %lld cannot be "
                      "computed or does not fit the block it was binned "
                      "in; the step was not taken",
                      (long long)points->id[p]);
      support.span[0] = support.span[1] = support.span[2] = 0;
    }
    double(*w)[GM_SUPPORT_3D_MAX_SPAN] = support.weight;
    double(*d)[GM_SUPPORT_3D_MAX_SPAN] = support.gradient;
    int span_x = wide ? support.span[0] : 2,
        span_y = wide ? support.span[1] : 2,
        span_z = wide ? support.span[2] : 2;
    size_t entry = 0; /* CPDI: (c span_y + b) span_x + a */
    for (int axis = 0; with_affine && axis < 3; axis++)
      gm_apic_axis_offsets_3d(origin[axis], domain->def.cell_size,
                              support.lowest[axis], support.span[axis],
                              current->position[axis][p], offset[axis]);
    for (int c = 0; c < span_z; c++) {
      for (int b = 0; b < span_y; b++) {
        for (int a_x = 0; a_x < span_x; a_x++, entry++) {
          int64_t nx = local[0] + a_x, ny = local[1] + b, nz = local[2] + c;
          size_t node = gm_block_node_3d(links, nx, ny, nz);
          double weight = 0.0, grad[3]; /* -, 1/m */
          if (cpdi) {
            weight = dense.weight[entry];
            for (int k = 0; k < 3; k++)
              grad[k] = dense.gradient[k][entry];
          } else {
            weight = w[0][a_x] * w[1][b] * w[2][c];
            grad[0] = d[0][a_x] * w[1][b] * w[2][c];
            grad[1] = w[0][a_x] * d[1][b] * w[2][c];
            grad[2] = w[0][a_x] * w[1][b] * d[2][c];
          }
          any_empty |= with_gradient && grid->mass[node] == 0.0;
          /* CPDI has no axis factors for empty_gradient_3d: its massless
           * nodes' gradient sum is taken here, node by node. */
          if (cpdi && with_gradient && grid->mass[node] == 0.0)
            for (int k = 0; k < 3; k++)
              empty[k] += grad[k];
          for (int i = 0; i < 3; i++) {
            double nodal = grid->momentum[i][node]; /* velocity by now */
            if (with_acceleration)
              a[i] += weight * grid->force[i][node]; /* acceleration */
            v[i] += weight * nodal;
            if (with_affine) { /* B_p = sum N_ip v_i (x_i - x_p)^T */
              double o[3] = {offset[0][a_x], offset[1][b], offset[2][c]};
              for (int k = 0; k < 3; k++)
                affine[3 * i + k] += weight * nodal * o[k];
            }
            if (!with_gradient)
              continue;
            for (int k = 0; k < 3; k++)
              l[3 * i + k] += nodal * grad[k];
          }
        }
      }
    }
    /* Massless nodes are rare (a point on a cell face, a box edge on a
     * node plane): their gradient sum is taken in a second loop over the
     * support only when one was seen, not node by node for every point. */
    if (with_gradient && any_empty && !cpdi)
      empty_gradient_3d(grid, links, local, w, d, span_x, span_y, span_z,
                        empty);
    /* As in 2D (g2p.c): a massless node (a point exactly on a cell face,
     * or a GIMP box edge on a node plane) takes the point's own
     * interpolated velocity, which removes the spurious gradient of its
     * stored zero. */
    for (int i = 0; i < 3; i++) {
      if (with_acceleration)
        out->acceleration[i][j] = a[i];
      out->velocity[i][j] = v[i];
      for (int k = 0; with_gradient && k < 3; k++)
        out->gradient[3 * i + k][j] =
            any_empty ? l[3 * i + k] + v[i] * empty[k] : l[3 * i + k];
      for (int k = 0; with_affine && k < 3; k++)
        out->affine[3 * i + k][j] = affine[3 * i + k];
    }
  }
}

/* What a pass needs (as in 2D, g2p.c): FLIP's velocity pass the
 * acceleration, a deformation pass L, APIC's velocity pass no
 * acceleration but C_p = L (linear) or B_p (GIMP). */
static GM_ALWAYS_INLINE void
gather_chunk_3d_shape(const gm_domain *domain, gm_worker_scratch *scratch,
                      size_t first, size_t count, chunk_gather_3d *out,
                      bool flip, bool deform, const bool wide,
                      const bool cpdi) {
  bool apic = domain->def.transfer == GM_TRANSFER_APIC;
  bool acceleration = flip && !apic;
  bool gradient = deform || (flip && apic && !wide);
  bool affine = flip && apic && wide;
  if (acceleration && gradient)
    gather_chunk_3d_kind(domain, scratch, first, count, out, true, true, false,
                         wide, cpdi);
  else if (acceleration)
    gather_chunk_3d_kind(domain, scratch, first, count, out, true, false, false,
                         wide, cpdi);
  else if (gradient && affine) /* not a pass of any scheme */
    gather_chunk_3d_kind(domain, scratch, first, count, out, false, true, true,
                         wide, cpdi);
  else if (gradient)
    gather_chunk_3d_kind(domain, scratch, first, count, out, false, true, false,
                         wide, cpdi);
  else if (affine)
    gather_chunk_3d_kind(domain, scratch, first, count, out, false, false, true,
                         wide, cpdi);
  else
    gather_chunk_3d_kind(domain, scratch, first, count, out, false, false,
                         false, wide, cpdi);
}

static void gather_chunk_3d(const gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count, chunk_gather_3d *out,
                            bool flip, bool deform) {
  gm_shape shape = domain->shape_grid.shape;
  if (shape == GM_SHAPE_LINEAR)
    gather_chunk_3d_shape(domain, scratch, first, count, out, flip, deform,
                          false, false);
  else if (shape == GM_SHAPE_CPDI)
    gather_chunk_3d_shape(domain, scratch, first, count, out, flip, deform,
                          true, true);
  else /* uGIMP, cpGIMP, B-splines */
    gather_chunk_3d_shape(domain, scratch, first, count, out, flip, deform,
                          true, false);
}

/* uGIMP and cpGIMP APIC: the same share as linear MPM's (apic_linear.h),
 * taken out of B_p = sum_i N_ip v_i (x_i - x_p)^T, for a box whose D_p
 * has shrunk towards the tent's (cpGIMP where a diagonal component of F
 * nears zero): B_p -= dt sum_i (1 - theta_i) N_ip a_i (x_i - x_p)^T with
 * theta_i = min(1, m_i / (r_i m_crit)), r_i = N_ip o_i^T D_p^-1 o_i the
 * node's leverage in the point's fit (about 1 for the tent's far node, so
 * that node's velocity is kept whole; small for the tail of a wide box,
 * whose velocity the fit mostly forgets). Only a box with some D_kk below
 * (c_p dt)^2 / 4 takes part, where the tent's own D_p turns unstable (the
 * one-node model of apic_linear.h without the share: f (1 - f) h^2 <
 * (c dt)^2 / 4): uGIMP's D_kk is at least h^2 / 8 with 2 points per cell
 * per axis (h^2 / 12 with 3, h^2 / 16 with 4), above it at any cfl up to
 * 0.7 (0.57, 0.5), and cpGIMP's too until its box has shrunk well below
 * its initial edge, so the boxes of test_apic.c keep their angular
 * momentum to round-off (measured: the same 2.9e-14). With (c dt)^2 / 2
 * the cpGIMP ball of test_apic.c (E = 1e5 Pa, F_xx down to 0.7) took part
 * and lost 1.3e-5 of it. Measured on the ball at E = 1e4 Pa: USL inverted
 * a point at step 83 (F_xx through zero) and now runs 400 steps, MUSL and
 * USF ran and run. 2D boxes need nothing: the 2D disc at E = 1e4 Pa runs
 * 400 steps with cpGIMP in every scheme as it did. */
static void light_nodes_box_3d(gm_domain *domain, size_t first, size_t count,
                               double dt) {
  gm_points *points = &domain->points;
  const gm_grid *grid = &domain->grid;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const double *origin = domain->shape_grid.origin; /* m, node 0 */
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    double modulus =
        domain->materials[points->material[p]].p_wave_modulus; /* Pa */
    double wave_squared = modulus * from->volume[p] / points->mass[p];
    double small = 0.25 * wave_squared * dt * dt; /* m^2 */
    uint32_t block = points->point_block[p];
    const uint32_t *links =
        grid->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
    double x[3] = {from->position[0][p], from->position[1][p],
                   from->position[2][p]}; /* m */
    double half[3];                       /* m */
    gm_box_half_edges_3d(domain->shape_grid.shape,
                         (const double *const *)points->domain_size,
                         (const double *const *)from->deformation, p, half);
    gm_box_support_3d support;
    if (!gm_box_support_compute_3d(&domain->shape_grid, x, half, &support))
      continue; /* the gather has failed the step */
    double offset[3][GM_SUPPORT_3D_MAX_SPAN]; /* m */
    double inertia[3] = {0, 0, 0};            /* m^2, D_kk */
    bool shrunk = false;
    for (int axis = 0; axis < 3; axis++) {
      gm_apic_axis_offsets_3d(origin[axis], domain->def.cell_size,
                              support.lowest[axis], support.span[axis], x[axis],
                              offset[axis]);
      for (int a = 0; a < support.span[axis]; a++)
        inertia[axis] +=
            support.weight[axis][a] * offset[axis][a] * offset[axis][a];
      shrunk |= inertia[axis] < small;
    }
    if (!shrunk || !(inertia[0] > 0 && inertia[1] > 0 && inertia[2] > 0))
      continue;
    int64_t base[3], local[3];
    gm_block_coordinates_3d(grid, grid->block_key[block], base);
    for (int axis = 0; axis < 3; axis++)
      local[axis] = support.lowest[axis] - (base[axis] << GM_BLOCK_SHIFT_3D);
    double critical = gm_apic_light_node_mass(domain, p, 0.0, dt); /* kg */
    double change[9] = {0};                                        /* m^2/s */
    for (int c = 0; c < support.span[2]; c++)
      for (int b = 0; b < support.span[1]; b++)
        for (int a = 0; a < support.span[0]; a++) {
          size_t node =
              gm_block_node_3d(links, local[0] + a, local[1] + b, local[2] + c);
          double weight = support.weight[0][a] * support.weight[1][b] *
                          support.weight[2][c];
          double o[3] = {offset[0][a], offset[1][b], offset[2][c]}; /* m */
          double leverage =
              weight * (o[0] * o[0] / inertia[0] + o[1] * o[1] / inertia[1] +
                        o[2] * o[2] / inertia[2]);
          double deficit =
              gm_apic_light_node_deficit(grid->mass[node], leverage * critical);
          for (int i = 0; i < 3; i++) {
            double part = dt * deficit * weight * grid->force[i][node];
            for (int k = 0; k < 3; k++)
              change[3 * i + k] += part * o[k];
          }
        }
    for (int k = 0; k < 9; k++)
      to->affine[k][p] -= change[k];
  }
}

/* Linear APIC: C_p -= dt sum_i (1 - theta_i) a_i (x) grad N_ip over the
 * nodes of too little mass (apic_linear.h; the 2D form in g2p.c), at the
 * positions of the gather. A point none of whose 8 nodes is light keeps
 * every bit of C_p. */
static void light_nodes_chunk_3d(gm_domain *domain, size_t first, size_t count,
                                 double dt) {
  gm_points *points = &domain->points;
  const gm_grid *grid = &domain->grid;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const double *origin = domain->shape_grid.origin; /* m, node 0 */
  const int64_t mask = GM_BLOCK_EDGE_3D - 1;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    double critical = gm_apic_light_node_mass(domain, p, 0.0, dt); /* kg */
    const uint32_t *links =
        grid->neighbour + (size_t)points->point_block[p] * GM_BLOCK_NEIGHBOURS;
    double w[3][2], d[3][2];
    int64_t local[3];
    for (int axis = 0; axis < 3; axis++)
      local[axis] = gm_shape_linear_axis(from->position[axis][p], origin[axis],
                                         domain->inv_cell, w[axis], d[axis]) &
                    mask;
    size_t node[8];
    bool light = false;
    for (int n = 0; n < 8; n++) {
      node[n] =
          gm_block_node_3d(links, local[0] + (n & 1), local[1] + ((n >> 1) & 1),
                           local[2] + (n >> 2));
      light |= grid->mass[node[n]] < critical;
    }
    if (!light)
      continue;
    double change[9] = {0}; /* 1/s, row-major */
    for (int n = 0; n < 8; n++) {
      int a = n & 1, b = (n >> 1) & 1, c = n >> 2;
      double deficit =
          gm_apic_light_node_deficit(grid->mass[node[n]], critical);
      double grad[3] = {d[0][a] * w[1][b] * w[2][c],
                        w[0][a] * d[1][b] * w[2][c],
                        w[0][a] * w[1][b] * d[2][c]}; /* 1/m */
      for (int i = 0; i < 3; i++) {
        double part = dt * deficit * grid->force[i][node[n]]; /* m/s */
        for (int k = 0; k < 3; k++)
          change[3 * i + k] += part * grad[k];
      }
    }
    for (int k = 0; k < 9; k++)
      to->affine[k][p] -= change[k];
  }
}

/* v_p += dt sum N a_i (FLIP), blended with PIC sum N v_i; with APIC the
 * PIC velocity and the affine matrix (C_p = L for linear MPM, B_p for
 * GIMP). */
static void flip_chunk_3d(gm_domain *domain, size_t first, size_t count,
                          const chunk_gather_3d *g, double dt) {
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  if (domain->def.transfer == GM_TRANSFER_APIC) {
    bool linear = domain->shape_grid.shape == GM_SHAPE_LINEAR;
    for (int k = 0; k < 3; k++)
      memcpy(to->velocity[k] + first, g->velocity[k], count * sizeof(double));
    for (int k = 0; k < 9; k++) /* L and B: both row-major */
      memcpy(to->affine[k] + first, linear ? g->gradient[k] : g->affine[k],
             count * sizeof(double));
    if (linear)
      light_nodes_chunk_3d(domain, first, count, dt);
    else if (domain->shape_grid.shape != GM_SHAPE_CPDI)
      light_nodes_box_3d(domain, first, count, dt);
    return;
  }
  double pic = domain->def.pic_fraction, flip = 1.0 - pic; /* - */
  for (int k = 0; k < 3; k++)
    for (size_t j = 0; j < count; j++) {
      double flipped =
          from->velocity[k][first + j] + dt * g->acceleration[k][j];
      to->velocity[k][first + j] =
          pic == 0.0 ? flipped : flip * flipped + pic * g->velocity[k][j];
    }
}

/* x_p += dt sum N v_i; a point leaving the grid fails the step, or across
 * periodic x faces comes back through the other one (periodic.c). Keys of
 * the moved points for the next step's binning (linear MPM; a GIMP box
 * is keyed by keys_chunk_3d once F is final). */
static void move_chunk_3d(gm_domain *domain, gm_worker_scratch *scratch,
                          size_t first, size_t count, const chunk_gather_3d *g,
                          double dt, bool *left_block) {
  gm_points *points = &domain->points;
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const double *origin = domain->shape_grid.origin;
  bool periodic = gm_periodic_x(domain);
  const int64_t *binned = domain->grid.block_key; /* keys of this binning */
  bool left = false;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    bool inside = true;
    double moved[3];
    for (int k = 0; k < 3; k++) {
      moved[k] = from->position[k][p] + dt * g->velocity[k][j];
      if (k == 0 && periodic)
        moved[0] = gm_periodic_wrap_x(domain, moved[0]);
      to->position[k][p] = moved[k];
      /* The same arithmetic as gm_block_key_of. */
      double scaled = (moved[k] - origin[k]) * domain->inv_cell;
      inside = inside && scaled >= GM_GHOST_LAYERS &&
               scaled < (double)(domain->cells[k] + GM_GHOST_LAYERS);
    }
    if (inside && domain->shape_grid.shape != GM_SHAPE_LINEAR)
      continue;
    if (!inside && gm_rigid_move_is_provisional(domain, p))
      continue; /* RIGID_POINTS sets and tests its position (rigid.c) */
    if (inside) {
      points->block_key[p] =
          gm_block_key_inside_3d(&domain->grid, moved[0], moved[1], moved[2],
                                 origin, domain->inv_cell);
      left |= points->block_key[p] != binned[points->point_block[p]];
      continue;
    }
    bool finite =
        isfinite(moved[0]) && isfinite(moved[1]) && isfinite(moved[2]);
    gm_worker_error(scratch, finite ? GM_ERR_OUT_OF_GRID : GM_ERR_NOT_FINITE, p,
                    "step: point id %lld %s (x = %g, y = %g, z = %g m at t = "
                    "%g s); the step was not taken",
                    (long long)points->id[p],
                    finite ? "would leave the grid box"
                           : "got a non-finite position",
                    moved[0], moved[1], moved[2], domain->time + dt);
  }
  *left_block |= left;
}

/* CPDI: the domain map takes F's increment, D <- (I + L dt) D, with
 * deform_chunk_3d's arithmetic (so D = F bitwise until a reset,
 * cpdi_reset.c), read whole before it is written (in place: USF). */
static void deform_domain_map_chunk_3d(const gm_point_buffers *from,
                                       gm_point_buffers *to, size_t first,
                                       size_t count, const chunk_gather_3d *g,
                                       double dt) {
  static const int slot[9] = {F_XX, F_XY, F_XZ, F_YX, F_YY,
                              F_YZ, F_ZX, F_ZY, F_ZZ};
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    double d[9], increment[9];
    for (int c = 0; c < 9; c++) {
      d[c] = from->domain_map[slot[c]][p];
      increment[c] = g->gradient[c][j] * dt + (c % 4 == 0 ? 1.0 : 0.0);
    }
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        to->domain_map[slot[3 * r + c]][p] = increment[3 * r] * d[c] +
                                             increment[3 * r + 1] * d[3 + c] +
                                             increment[3 * r + 2] * d[6 + c];
  }
}

/* F <- (I + L dt) F with nine components and V = det F V0 (004 eq 3.23);
 * false (the points named) when some det F is not positive and finite.
 * In place (USF's second half), F is read whole before it is written.
 * CPDI's domain map D takes the same increment. */
static bool deform_chunk_3d(gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count,
                            const chunk_gather_3d *g, double dt,
                            bool in_place) {
  gm_points *points = &domain->points;
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const gm_point_buffers *from = in_place ? to : &points->buffer[points->cur];
  /* Slot of F_ij, row-major (core.h's F_XX..F_ZY). */
  static const int slot[9] = {F_XX, F_XY, F_XZ, F_YX, F_YY,
                              F_YZ, F_ZX, F_ZY, F_ZZ};
  bool positive = true;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    double f[9], increment[9], next[9];
    for (int c = 0; c < 9; c++) {
      f[c] = from->deformation[slot[c]][p];
      increment[c] = g->gradient[c][j] * dt + (c % 4 == 0 ? 1.0 : 0.0);
    }
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        next[3 * r + c] = increment[3 * r] * f[c] +
                          increment[3 * r + 1] * f[3 + c] +
                          increment[3 * r + 2] * f[6 + c];
    double jacobian = next[0] * (next[4] * next[8] - next[5] * next[7]) -
                      next[1] * (next[3] * next[8] - next[5] * next[6]) +
                      next[2] * (next[3] * next[7] - next[4] * next[6]);
    for (int c = 0; c < 9; c++)
      to->deformation[slot[c]][p] = next[c];
    to->volume[p] = jacobian * points->initial_volume[p];
    positive &= jacobian > 0.0 && jacobian < INFINITY;
  }
  if (to->domain_map[0])
    deform_domain_map_chunk_3d(from, to, first, count, g, dt);
  if (positive)
    return true;
  for (size_t p = first; p < first + count; p++) {
    double jacobian = to->volume[p] / points->initial_volume[p];
    if (jacobian > 0.0 && jacobian < INFINITY)
      continue;
    gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                    "step: point id %lld has det F = %g (inverted or "
                    "non-finite deformation at t = %g s); reduce dt",
                    (long long)points->id[p], jacobian, domain->time + dt);
    if (scratch->error_index == p && isfinite(jacobian))
      scratch->error_inverted = true; /* retried with a smaller dt */
  }
  return false;
}

/* Keys of the chunk's GIMP points in the new state (next buffer: moved
 * positions, final F): the block of their support's lowest node, so the
 * next scatter reaches only that block and its upper neighbours. A box
 * that leaves the grid's nodes or grows past GM_SUPPORT_3D_MAX_SPAN nodes
 * (cpGIMP stretched) fails the step. */
static void keys_chunk_3d(gm_domain *domain, gm_worker_scratch *scratch,
                          size_t first, size_t count, bool *left_block) {
  gm_points *points = &domain->points;
  const gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  const int64_t *binned = domain->grid.block_key; /* keys of this binning */
  bool left = false;
  for (size_t p = first; p < first + count; p++) {
    double x[3] = {to->position[0][p], to->position[1][p],
                   to->position[2][p]}; /* m */
    double half[3];                     /* m */
    gm_box_half_edges_3d(domain->shape_grid.shape,
                         (const double *const *)points->domain_size,
                         gm_support_slots_3d(domain, to), p, half);
    int64_t lowest[3];
    if (gm_wide_lowest_3d(&domain->shape_grid,
                          (const double *const *)to->position,
                          (const double *const *)points->domain_size,
                          gm_support_slots_3d(domain, to), p, lowest)) {
      points->block_key[p] = gm_block_key_of_node_3d(&domain->grid, lowest[0],
                                                     lowest[1], lowest[2]);
      left |= points->block_key[p] != binned[points->point_block[p]];
      continue;
    }
    if (gm_rigid_move_is_provisional(domain, p))
      continue; /* RIGID_POINTS sets its position and key (rigid.c) */
    gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                    "step: the domain of point id %lld (half edges %g, %g, "
                    "%g m at x = %g, y = %g, z = %g m, t = %g s) would reach "
                    "past the ghost cell layer around the grid box or span "
                    "more than %d cells along an axis; the step was not "
                    "taken",
                    (long long)points->id[p], half[0], half[1], half[2], x[0],
                    x[1], x[2], domain->time + domain->current_dt,
                    GM_SUPPORT_3D_MAX_SPAN - 1);
  }
  *left_block |= left;
}

/* Largest c_p^2 and |v_p|^2 of the chunk's new state (stable_dt.c). */
static void signal_speed_3d(gm_domain *domain, gm_worker_scratch *scratch,
                            size_t first, size_t count) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  double wave = scratch->max_wave_speed_squared;  /* m^2/s^2 */
  double flow = scratch->max_point_speed_squared; /* m^2/s^2 */
  for (size_t p = first; p < first + count; p++) {
    double speed_squared = 0.0;
    for (int k = 0; k < 3; k++)
      speed_squared += to->velocity[k][p] * to->velocity[k][p];
    /* c^2 = M / rho = M V / m */
    double wave_squared =
        domain->materials[points->material[p]].p_wave_modulus * to->volume[p] /
        points->mass[p];
    if (!isfinite(speed_squared))
      gm_worker_error(scratch, GM_ERR_NOT_FINITE, p,
                      "step: point id %lld got a non-finite velocity at t = "
                      "%g s; the step was not taken",
                      (long long)points->id[p],
                      domain->time + domain->current_dt);
    flow = speed_squared > flow ? speed_squared : flow;
    wave = wave_squared > wave ? wave_squared : wave;
  }
  scratch->max_wave_speed_squared = wave;
  scratch->max_point_speed_squared = flow;
}

static void g2p_chunks_3d(void *context, size_t begin, size_t end, int worker) {
  g2p_3d_context *ctx = context;
  gm_domain *domain = ctx->domain;
  const gm_g2p_pass *pass = ctx->pass;
  gm_worker_scratch *scratch = &domain->scratch[worker];
  chunk_gather_3d *g = (chunk_gather_3d *)(void *)scratch->gather;
  size_t point_count = domain->points.count;
  for (size_t chunk = begin; chunk < end; chunk++) {
    size_t first = chunk * GM_BATCH_SIZE;
    size_t count = point_count - first < GM_BATCH_SIZE ? point_count - first
                                                       : GM_BATCH_SIZE;
    gather_chunk_3d(domain, scratch, first, count, g, pass->flip_velocity,
                    pass->deform);
    if (pass->deform && ctx->cell_mean) /* L's trace to its cell's mean */
      gm_volumetric_apply_chunk_3d(domain, first, count, g->gradient);
    if (pass->flip_velocity)
      flip_chunk_3d(domain, first, count, g, pass->dt);
    if (pass->move_points)
      move_chunk_3d(domain, scratch, first, count, g,
                    pass->move_dt > 0.0 ? pass->move_dt : pass->dt,
                    &ctx->left_block[worker]);
    /* A chunk with an inverted point skips its material call: the step
     * fails anyway. */
    bool deformed = true;
    if (pass->deform && deform_chunk_3d(domain, scratch, first, count, g,
                                        pass->dt, pass->in_place)) {
      const double *gradient[9];
      for (int c = 0; c < 9; c++)
        gradient[c] = g->gradient[c];
      gm_stress_update_chunk_3d(domain, scratch, first, count, pass->dt,
                                gradient, pass->in_place);
      /* The stress_free and granular rules (000 eqs 13-15, 18) on the
       * updated state, before the keys read the final F (cpGIMP), as in
       * 2D (g2p.c). */
      if (domain->def.family != GM_FAMILY_PLAIN) {
        double start = gm_monotonic_seconds();
        gm_density_control_chunk(domain, first, count);
        scratch->density_control_seconds += gm_monotonic_seconds() - start;
      }
      /* CPDI: once D is final but for the reset, before the keys read it
       * (as in 2D, g2p.c). */
      if (domain->points.buffer[domain->points.cur ^ 1].domain_map[0])
        gm_cpdi_reset_chunk(domain, first, count);
    } else if (pass->deform) {
      deformed = false;
    }
    /* GIMP keys need the final F (cpGIMP); an inverted F fails anyway. */
    if (pass->finish && deformed && domain->shape_grid.shape != GM_SHAPE_LINEAR)
      keys_chunk_3d(domain, scratch, first, count, &ctx->left_block[worker]);
    if (pass->finish)
      signal_speed_3d(domain, scratch, first, count);
  }
}

/* Whether the points keyed by this pass all stayed in the blocks they
 * were binned in, so that the next binning may keep the grid, order and
 * point blocks (bins.c; as the fused 2D sweep, move_remap.c). Only in
 * the plain family without periodic faces: the granular layers key their
 * points to other blocks (step.c, prepare_granular), and periodic images
 * are left to the full binning, as in 2D. */
static void note_blocks_kept(gm_domain *domain, const gm_g2p_pass *pass,
                             const g2p_3d_context *ctx) {
  bool linear = domain->shape_grid.shape == GM_SHAPE_LINEAR;
  bool keyed = linear ? pass->move_points : pass->finish;
  if (!keyed)
    return;
  bool kept = domain->def.family == GM_FAMILY_PLAIN && !gm_periodic_x(domain);
  for (int w = 0; w < domain->worker_count; w++)
    kept = kept && !ctx->left_block[w];
  domain->points.blocks_kept = kept; /* read by the next binning */
}

/* The first sweep of a deformation pass with GM_VOLUMETRIC_CELL_MEAN:
 * each point's tr L and cell (volumetric_mean.c), from the gather the
 * pass itself then repeats (the same function on the same inputs, and L
 * summed alone whatever else a pass gathers: the same bits). */
static void g2p_volumetric_rates_3d(void *context, size_t begin, size_t end,
                                    int worker) {
  g2p_3d_context *ctx = context;
  gm_domain *domain = ctx->domain;
  gm_worker_scratch *scratch = &domain->scratch[worker];
  chunk_gather_3d *g = (chunk_gather_3d *)(void *)scratch->gather;
  size_t point_count = domain->points.count;
  for (size_t chunk = begin; chunk < end; chunk++) {
    size_t first = chunk * GM_BATCH_SIZE;
    size_t count = point_count - first < GM_BATCH_SIZE ? point_count - first
                                                       : GM_BATCH_SIZE;
    gather_chunk_3d(domain, scratch, first, count, g, false, true);
    gm_volumetric_store_chunk_3d(domain, first, count,
                                 (const double(*)[GM_BATCH_SIZE])g->gradient);
  }
}

void gm_g2p_3d(gm_domain *domain, const gm_g2p_pass *pass) {
  g2p_3d_context ctx;
  ctx.domain = domain;
  ctx.pass = pass;
  for (int w = 0; w < domain->worker_count; w++)
    ctx.left_block[w] = false;
  size_t chunks = (domain->points.count + GM_BATCH_SIZE - 1) / GM_BATCH_SIZE;
  ctx.cell_mean = pass->deform && domain->volumetric == GM_VOLUMETRIC_CELL_MEAN;
  if (ctx.cell_mean) {
    gm_parallel_for(&domain->pool, chunks, g2p_volumetric_rates_3d, &ctx);
    gm_volumetric_sum(domain);
  }
  gm_parallel_for(&domain->pool, chunks, g2p_chunks_3d, &ctx);
  note_blocks_kept(domain, pass, &ctx);
}
