/*
 * g2p_wide.c - grid-to-particle gather for the shape functions whose
 * support is wider than one cell (uGIMP, cpGIMP, CPDI; support.h): the
 * interpolated acceleration and velocity and the velocity gradient
 * L = sum v_i (x) grad S_i, as in g2p.c, plus the block keys of the moved
 * points, which depend on the whole support and so on F as well.
 */
#include "grid/grid.h"

#include "grid/transfer.h"

#include <math.h>

void gm_gather_chunk_wide(const gather_view *v, size_t first, size_t count,
                          chunk_gather *out, const gm_domain *domain,
                          gm_worker_scratch *scratch) {
  int dim = v->dim;
  const double *const *deformation = v->support_tensor;
  gm_support support;
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    bool found = gm_wide_support(v->shape_grid, dim, v->position, deformation,
                                 v->domain_size, p, &support);
    uint32_t block = v->point_block[p];
    const uint32_t *links = v->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
    int64_t base[2];
    gm_block_base(v->grid, v->grid->block_key[block], base);
    int64_t x0 = support.lowest[0] - base[0];
    int64_t y0 = dim > 1 ? support.lowest[1] - base[1] : 0;
    /* Two blocks per axis: the block and its neighbour links. */
    int64_t edge = dim == 1 ? 2 * GM_BLOCK_NODES : 2 << v->shift;
    if (!found || !gm_support_within(&support, dim, x0, y0, edge)) {
      gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                      "step: the support of point id %lld cannot be "
                      "computed or does not fit the block it was binned in "
                      "(a degenerate domain, e.g. an edge far below a cell); "
                      "the step was not taken",
                      (long long)domain->points.id[p]);
      support.count = 0; /* gathers nothing: the step fails anyway */
    }
    double acceleration[2] = {0.0, 0.0}, velocity[2] = {0.0, 0.0};
    double gradient[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; /* L_ab = dv_a/dx_b */
    double empty[2] = {0.0, 0.0}; /* gradient sum of massless nodes */
    /* APIC's B_p = sum N_ip v_i (x_i - x_p)^T: node i of an entry lies at
     * origin + (lowest + offset) h, node_x/node_y being x_i - x_p of the
     * support's lowest node (m). */
    double affine[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; /* m^2/s */
    double node_x = 0.0, node_y = 0.0;
    if (v->affine) {
      node_x = v->origin[0] + (double)support.lowest[0] * v->cell -
               v->position[0][p];
      node_y = dim > 1 ? v->origin[1] + (double)support.lowest[1] * v->cell -
                             v->position[1][p]
                       : 0.0;
    }
    for (int e = 0; e < support.count; e++) {
      size_t node = gm_block_node(links, v->shift, x0 + support.offset[0][e],
                                  y0 + support.offset[1][e]);
      double weight = support.weight[e];
      double is_empty = v->grid_mass[node] == 0.0 ? 1.0 : 0.0;
      for (int b = 0; b < dim; b++)
        empty[b] += is_empty * support.gradient[b][e];
      double offset[2] = {node_x + (double)support.offset[0][e] * v->cell,
                          node_y + (double)support.offset[1][e] * v->cell};
      for (int a = 0; a < dim; a++) {
        double nodal = v->grid_velocity[a][node];
        acceleration[a] += weight * v->grid_acceleration[a][node];
        velocity[a] += weight * nodal;
        for (int b = 0; b < dim; b++)
          gradient[a][b] += nodal * support.gradient[b][e];
        if (v->affine)
          for (int b = 0; b < dim; b++)
            affine[a][b] += weight * nodal * offset[b];
      }
    }
    /* Massless nodes: the point's own velocity (see gather_chunk_2d). */
    for (int a = 0; a < dim; a++)
      for (int b = 0; b < dim; b++)
        gradient[a][b] += velocity[a] * empty[b];
    for (int a = 0; a < 2; a++) {
      out->acceleration[a][j] = a < dim ? acceleration[a] : 0.0;
      out->velocity[a][j] = a < dim ? velocity[a] : 0.0;
    }
    out->gradient[0][j] = gradient[0][0];
    out->gradient[1][j] = gradient[0][1];
    out->gradient[2][j] = gradient[1][0];
    out->gradient[3][j] = gradient[1][1];
    /* Hoop strain rate v_r / r (002 sec 3). */
    out->gradient[4][j] =
        v->axisymmetric ? velocity[0] / v->position[0][p] : 0.0;
    out->affine[0][j] = affine[0][0];
    out->affine[1][j] = affine[0][1];
    out->affine[2][j] = affine[1][0];
    out->affine[3][j] = affine[1][1];
  }
}

void gm_wide_keys_chunk(gm_domain *domain, const gather_view *v,
                        gm_worker_scratch *scratch, size_t first,
                        size_t count) {
  int dim = v->dim;
  const double *const position[2] = {v->next_position[0], v->next_position[1]};
  const double *const *deformation = v->next_support_tensor;
  for (size_t p = first; p < first + count; p++) {
    int64_t lowest[2], highest[2];
    if (gm_wide_support_bounds(v->shape_grid, dim, position, deformation,
                               v->domain_size, p, lowest, highest)) {
      v->block_key[p] = gm_block_key_of_node(v->grid, lowest[0], lowest[1]);
      continue;
    }
    gm_point_domain point; /* the failure path only: for the message */
    gm_load_point_domain(dim, position, deformation, v->domain_size, p, &point);
    double corners[4][2];
    gm_point_domain_corners(v->shape_grid->shape, dim, &point, corners);
    gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                    "step: the domain of point id %lld would reach past the "
                    "ghost cell layer around the grid box or span more than "
                    "%d cells (corners (%g, %g) to (%g, %g) m at t = %g s); "
                    "the step was not taken",
                    (long long)domain->points.id[p], GM_SUPPORT_MAX_SPAN - 1,
                    corners[0][0], corners[0][1], corners[2][0], corners[2][1],
                    domain->time + domain->current_dt);
  }
}
