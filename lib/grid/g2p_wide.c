/*
 * g2p_wide.c - grid-to-particle gather for the shape functions whose
 * support is wider than one cell (uGIMP, cpGIMP, CPDI; support.h): the
 * interpolated acceleration and velocity and the velocity gradient
 * L = sum v_i (x) grad S_i, as in g2p.c, plus the block keys of the moved
 * points, which depend on the whole support and so on F as well. USL's
 * deformation gather of 2D CPDI takes the corner cells its scatter kept
 * (cpdi_cache.h) and forms the fractions and corner gradients from the
 * corners.
 */
#include "grid/grid.h"

#include "boundaries/boundaries.h"

#include "grid/gather_wide.h"
#include "grid/transfer.h"

#include <math.h>

/* CPDI corner by corner (support.c): each corner interpolates the nodes
 * of its cell bilinearly, v_c = sum N_i(x_c) v_i, and the point takes
 * v_p = share sum_c v_c and L = sum_c v_c (x) g_c: the entry sums with
 * weight share N_i and gradient N_i g_c, factored per corner (equal to
 * round-off). base: the block's base node. */
static GM_ALWAYS_INLINE void
gather_cpdi(const gather_view *v, const uint32_t *links, const int64_t base[2],
            const gm_cpdi_support *support, point_gather *sum, const int dim) {
  double share = support->share;
  for (int c = 0; c < support->corner_count; c++) {
    int64_t x = support->cell[c][0] - base[0];
    int64_t y = dim > 1 ? support->cell[c][1] - base[1] : 0;
    double velocity[2] = {0.0, 0.0};     /* m/s, v_c */
    double acceleration[2] = {0.0, 0.0}; /* m/s^2 */
    double empty = 0.0; /* -, the corner's weight on massless nodes */
    for (int b = 0; b < (dim > 1 ? 2 : 1); b++)
      for (int a = 0; a < 2; a++) {
        size_t node = gm_block_node(links, v->shift, x + a, y + b);
        double value = support->axis[c][0][a] * support->axis[c][1][b];
        empty += v->grid_mass[node] == 0.0 ? value : 0.0;
        for (int k = 0; k < dim; k++) {
          velocity[k] += value * v->grid_velocity[k][node];
          acceleration[k] += value * v->grid_acceleration[k][node];
        }
      }
    const double *g = support->corner_gradient[c]; /* 1/m */
    for (int k = 0; k < dim; k++) {
      sum->velocity[k] += share * velocity[k];
      sum->acceleration[k] += share * acceleration[k];
      for (int b = 0; b < dim; b++)
        sum->gradient[k][b] += velocity[k] * g[b];
      sum->empty[k] += empty * g[k];
    }
  }
}

/* The entry table, with APIC's B_p = sum N_ip v_i (x_i - x_p)^T: node i of
 * an entry lies at origin + (lowest + offset) h, node_x/node_y being
 * x_i - x_p of the support's lowest node (m). */
static void gather_entries_affine(const gather_view *v, const uint32_t *links,
                                  int64_t x0, int64_t y0, size_t p,
                                  const gm_support *support, point_gather *sum,
                                  double affine[2][2]) {
  int dim = v->dim;
  double node_x =
      v->origin[0] + (double)support->lowest[0] * v->cell - v->position[0][p];
  double node_y = dim > 1
                      ? v->origin[1] + (double)support->lowest[1] * v->cell -
                            v->position[1][p]
                      : 0.0;
  for (int e = 0; e < support->count; e++) {
    size_t node = gm_block_node(links, v->shift, x0 + support->offset[0][e],
                                y0 + support->offset[1][e]);
    double weight = support->weight[e];
    if (dim > 1)
      gather_node(v, node, weight, support->gradient[0][e],
                  support->gradient[1][e], sum, 2);
    else
      gather_node(v, node, weight, support->gradient[0][e], 0.0, sum, 1);
    double offset[2] = {node_x + (double)support->offset[0][e] * v->cell,
                        node_y + (double)support->offset[1][e] * v->cell};
    for (int a = 0; a < dim; a++) {
      double nodal = v->grid_velocity[a][node];
      for (int b = 0; b < dim; b++)
        affine[a][b] += weight * nodal * offset[b];
    }
  }
}

/* Point p's sums into slot j of the chunk's output, with the massless
 * nodes' correction. The acceleration is stored only where the pass reads
 * it (acceleration: the FLIP update, flip_chunk) and B_p only with APIC
 * (with_affine; flip_chunk's APIC copy): the deformation pass reads the
 * gradient alone, so its 6 stores of zeros per point are left out. */
static GM_ALWAYS_INLINE void
store_point_gather(const gather_view *v, size_t p, size_t j, point_gather *sum,
                   double affine[2][2], chunk_gather *out, const int dim,
                   const bool acceleration, const bool with_affine) {
  /* Massless nodes: the point's own velocity (see gather_chunk_2d). */
  for (int a = 0; a < dim; a++)
    for (int b = 0; b < dim; b++)
      sum->gradient[a][b] += sum->velocity[a] * sum->empty[b];
  for (int a = 0; a < 2; a++) {
    if (acceleration)
      out->acceleration[a][j] = a < dim ? sum->acceleration[a] : 0.0;
    out->velocity[a][j] = a < dim ? sum->velocity[a] : 0.0;
  }
  out->gradient[0][j] = sum->gradient[0][0];
  out->gradient[1][j] = sum->gradient[0][1];
  out->gradient[2][j] = sum->gradient[1][0];
  out->gradient[3][j] = sum->gradient[1][1];
  /* Hoop strain rate v_r / r (002 sec 3). */
  out->gradient[4][j] =
      v->axisymmetric ? sum->velocity[0] / v->position[0][p] : 0.0;
  if (!with_affine)
    return;
  out->affine[0][j] = affine[0][0];
  out->affine[1][j] = affine[0][1];
  out->affine[2][j] = affine[1][0];
  out->affine[3][j] = affine[1][1];
}

static GM_ALWAYS_INLINE void
gather_chunk_kind(const gather_view *v, size_t first, size_t count,
                  chunk_gather *out, const gm_domain *domain,
                  gm_worker_scratch *scratch, const int dim,
                  const bool acceleration, const bool gradient) {
  const double *const *deformation = v->support_tensor;
  bool cpdi = v->shape_grid->shape == GM_SHAPE_CPDI;
  /* Two blocks per axis: the block and its neighbour links. */
  int64_t edge = dim == 1 ? 2 * GM_BLOCK_NODES : 2 << v->shift;
  /* uGIMP and cpGIMP in 2D try the short support first (support_short.h);
   * a longer domain, or one the checks refuse, takes the general one. */
  gm_shape shape = v->shape_grid->shape;
  bool rectangle = shape == GM_SHAPE_UGIMP || shape == GM_SHAPE_CPGIMP;
  bool try_short = dim == 2 && rectangle && !v->affine;
  /* CPDI in 2D takes its inline support (support_cpdi.h) and the gather of
   * gather_wide.h; a support it refuses takes the general path, which
   * refuses it too and records the error. */
  bool try_cpdi = dim == 2 && cpdi && !v->affine;
  /* A local copy: the stores of the sums (doubles) would otherwise reload
   * the grid's origin and spacing at every point. */
  const gm_shape_grid shape_grid = *v->shape_grid;
  wide_support support;
  /* USL: the cells its scatter kept (cpdi_cache.h). */
  bool kept_cells = try_cpdi && v->cpdi_cache.packed;
  gm_tile_values tile_values; /* CPDI: the block's tile (tile_values.h) */
  uint32_t base_block = GM_NO_BLOCK;
  int64_t base[2] = {0, 0}; /* node of base_block's lower corner */
  for (size_t j = 0; j < count; j++) {
    size_t p = first + j;
    uint32_t block = v->point_block[p];
    const uint32_t *links = v->neighbour + (size_t)block * GM_BLOCK_NEIGHBOURS;
    if (block != base_block) { /* two integer divisions: once per block,
                                  not per point (a chunk's points are
                                  mostly in one block) */
      gm_block_base(v->grid, v->grid->block_key[block], base);
      base_block = block;
      if (try_cpdi)
        gm_tile_values_start(links, &tile_values);
    }
    gm_cpdi_kept kept; /* kept_cells excludes try_short: CPDI only */
    if (kept_cells && gm_cpdi_kept_load(&v->cpdi_cache, p, &kept)) {
      /* The fractions and corner gradients from the kept cells, bitwise
       * gm_cpdi_support_2d's. Its own sums, before the others' zeros: the
       * corners' gather sets every one (the zeros cost 7 stores). */
      double corners[4][2], corner_gradient[4][2]; /* m, 1/m */
      point_gather kept_sum;
      gather_cpdi_kept_rows(v, &tile_values, &kept, acceleration, gradient);
      gm_cpdi_kept_fractions(&shape_grid, v->position, deformation,
                             v->domain_size, p, base, &kept, corners);
      (void)gm_cpdi_corner_gradients_2d(corners, corner_gradient);
      gather_cpdi_kept_2d(&tile_values, &kept, &corner_gradient[0][0],
                          &kept_sum, acceleration, gradient);
      store_point_gather(v, p, j, &kept_sum, NULL, out, 2, acceleration, false);
      continue;
    }
    point_gather sum = {
        {0.0, 0.0}, {0.0, 0.0}, {{0.0, 0.0}, {0.0, 0.0}}, {0.0, 0.0}};
    double affine[2][2] = {{0.0, 0.0}, {0.0, 0.0}}; /* m^2/s, APIC's B_p */
    gm_short_axis axis[2];
    double half[2]; /* m */
    int64_t lowest[2], reach[2];
    if (try_short) {
      gm_rectangle_half_edges(shape, 2, v->domain_size, deformation, p, half);
      if (gm_short_support_2d(&shape_grid, v->position[0][p], v->position[1][p],
                              half[0], half[1], axis)) {
        int64_t sx = axis[0].lowest - base[0], sy = axis[1].lowest - base[1];
        reach[0] = axis[0].reach;
        reach[1] = axis[1].reach;
        if (gm_wide_support_fits(2, sx, sy, reach, edge)) {
          gather_short_2d(v, links, sx, sy, axis, &sum, acceleration, gradient);
          store_point_gather(v, p, j, &sum, affine, out, 2, acceleration,
                             false); /* not taken with APIC */
          continue;
        }
      }
    }
    if (try_cpdi) {
      gm_cpdi_support *corners = &support.cpdi;
      if (gm_cpdi_point_support_2d(&shape_grid, v->position, deformation,
                                   v->domain_size, p, corners, reach)) {
        int64_t cx = corners->lowest[0] - base[0];
        int64_t cy = corners->lowest[1] - base[1];
        if (gm_wide_support_fits(2, cx, cy, reach, edge)) {
          gather_cpdi_2d(v, &tile_values, base, corners, reach, &sum,
                         acceleration, gradient);
          store_point_gather(v, p, j, &sum, affine, out, 2, acceleration,
                             false); /* not taken with APIC */
          continue;
        }
      }
    }
    bool found =
        gm_wide_point_support(v->shape_grid, dim, v->position, deformation,
                              v->domain_size, p, &support, lowest, reach);
    int64_t x0 = lowest[0] - base[0];
    int64_t y0 = dim > 1 ? lowest[1] - base[1] : 0;
    if (!found || !gm_wide_support_fits(dim, x0, y0, reach, edge)) {
      gm_worker_error(scratch, GM_ERR_OUT_OF_GRID, p,
                      "step: the support of point id %lld cannot be "
                      "computed or does not fit the block it was binned in "
                      "(a degenerate domain, e.g. an edge far below a cell); "
                      "the step was not taken",
                      (long long)domain->points.id[p]);
      /* gathers nothing: the step fails anyway */
    } else if (v->affine) {
      gm_support entries;
      if (cpdi)
        gm_cpdi_support_expand(&support.cpdi, dim, &entries);
      else
        gm_product_support_expand(&support.product, &entries);
      gather_entries_affine(v, links, x0, y0, p, &entries, &sum, affine);
    } else if (cpdi) {
      gather_cpdi(v, links, base, &support.cpdi, &sum, dim);
    } else {
      gather_product(v, links, x0, y0, &support.product, &sum, dim);
    }
    store_point_gather(v, p, j, &sum, affine, out, dim, acceleration,
                       v->affine);
  }
}

void gm_gather_chunk_wide(const gather_view *v, size_t first, size_t count,
                          chunk_gather *out, const gm_domain *domain,
                          gm_worker_scratch *scratch, bool flip, bool deform) {
  if (v->dim == 1)
    gather_chunk_kind(v, first, count, out, domain, scratch, 1, true, true);
  else if (flip && !deform) /* USL's first pass, USF's and MUSL's second */
    gather_chunk_kind(v, first, count, out, domain, scratch, 2, true, false);
  else if (!flip && deform) /* USL's second, USF's and MUSL's first and third */
    gather_chunk_kind(v, first, count, out, domain, scratch, 2, false, true);
  else
    gather_chunk_kind(v, first, count, out, domain, scratch, 2, true, true);
}

void gm_wide_keys_chunk(gm_domain *domain, const gather_view *v,
                        gm_worker_scratch *scratch, size_t first,
                        size_t count) {
  int dim = v->dim;
  const double *const position[2] = {v->next_position[0], v->next_position[1]};
  const double *const *deformation = v->next_support_tensor;
  gm_shape shape = v->shape_grid->shape;
  bool try_short =
      dim == 2 && (shape == GM_SHAPE_UGIMP || shape == GM_SHAPE_CPGIMP);
  bool try_cpdi = dim == 2 && shape == GM_SHAPE_CPDI;
  /* Local copies for CPDI's test: the key stores (int64_t) may alias the
   * grid's integers and the loop's calls (the failure path) anything, so
   * the grid's origin, spacing and last nodes and the arrays' addresses
   * were loaded again at every point. */
  const gm_shape_grid shape_grid = *v->shape_grid;
  const double *const map[4] = {deformation[0], deformation[1], deformation[2],
                                deformation[3]};
  const double *const size[2] = {v->domain_size[0], v->domain_size[1]};
  int64_t *const keys = v->block_key;
  for (size_t p = first; p < first + count; p++) {
    int64_t lowest[2], highest[2];
    if (try_cpdi) { /* support_cpdi.h: gm_support_bounds' lowest and tests */
      if (gm_cpdi_lowest_2d(&shape_grid, position[0][p], position[1][p],
                            map[0][p], map[1][p], map[2][p], map[3][p],
                            0.5 * size[0][p], 0.5 * size[1][p], lowest)) {
        keys[p] = gm_block_key_of_node(v->grid, lowest[0], lowest[1]);
        continue;
      }
    }
    if (try_short) {  /* support_short.h; else the general bounds */
      double half[2]; /* m */
      gm_rectangle_half_edges(shape, 2, v->domain_size, deformation, p, half);
      if (gm_short_lowest_2d(v->shape_grid, position[0][p], position[1][p],
                             half[0], half[1], lowest)) {
        v->block_key[p] = gm_block_key_of_node(v->grid, lowest[0], lowest[1]);
        continue;
      }
    }
    if (gm_wide_support_bounds(v->shape_grid, dim, position, deformation,
                               v->domain_size, p, lowest, highest)) {
      v->block_key[p] = gm_block_key_of_node(v->grid, lowest[0], lowest[1]);
      continue;
    }
    if (gm_rigid_move_is_provisional(domain, p))
      continue; /* RIGID_POINTS sets its position and key (rigid.c) */
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
