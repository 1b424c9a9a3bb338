/*
 * gather_wide.h - one point's gather from the nodes of a tensor-product
 * support (uGIMP, cpGIMP, the B-splines): the sums of g2p.c (acceleration,
 * velocity, velocity gradient and the massless nodes' gradient sum), node
 * by node from the support's axis factors, general (gm_product_support)
 * or short (support_short.h). Shared by the gather pass (g2p_wide.c) and
 * USL's fused move and re-map of the short GIMP supports
 * (move_remap_wide.c), which must give the same bits. Reads only the
 * view's nodal arrays and shape grid.
 */
#ifndef GM_GATHER_WIDE_H
#define GM_GATHER_WIDE_H

#include "grid/tile_values.h"
#include "grid/transfer.h"

/* The sums of one point's gather (g2p.c): acceleration and velocity,
 * L_ab = sum v_ia dN_i/dx_b, the gradient sum of massless nodes. */
typedef struct point_gather {
  double acceleration[2]; /* m/s^2 */
  double velocity[2];     /* m/s */
  double gradient[2][2];  /* 1/s */
  double empty[2];        /* 1/m */
} point_gather;

/* One node's terms. The acceleration (read by the FLIP update) and the
 * gradient with its empty-node sum (read by the deformation) are left out
 * where the pass does not read them (gather_short_2d's passes); each sum
 * is taken alone, so the ones kept have the same bits. */
static GM_ALWAYS_INLINE void
gather_node_kind(const gather_view *v, size_t node, double weight,
                 double grad_x, double grad_y, point_gather *sum, const int dim,
                 const bool acceleration, const bool gradient) {
  double grad[2] = {grad_x, grad_y};
  if (gradient) {
    double is_empty = v->grid_mass[node] == 0.0 ? 1.0 : 0.0;
    for (int b = 0; b < dim; b++)
      sum->empty[b] += is_empty * grad[b];
  }
  for (int a = 0; a < dim; a++) {
    double nodal = v->grid_velocity[a][node];
    if (acceleration)
      sum->acceleration[a] += weight * v->grid_acceleration[a][node];
    sum->velocity[a] += weight * nodal;
    if (gradient)
      for (int b = 0; b < dim; b++)
        sum->gradient[a][b] += nodal * grad[b];
  }
}

/* Every sum (the general and CPDI paths). */
static GM_ALWAYS_INLINE void gather_node(const gather_view *v, size_t node,
                                         double weight, double grad_x,
                                         double grad_y, point_gather *sum,
                                         const int dim) {
  gather_node_kind(v, node, weight, grad_x, grad_y, sum, dim, true, true);
}

/* A tensor-product support node by node, in the entry order b, a of
 * gm_product_support_expand (so the sums are bitwise those of the table). */
static GM_ALWAYS_INLINE void gather_product(const gather_view *v,
                                            const uint32_t *links, int64_t x0,
                                            int64_t y0,
                                            const gm_product_support *support,
                                            point_gather *sum, const int dim) {
  int span_x = support->span[0];
  for (int b = 0; b < support->span[1]; b++) {
    double weight_y = support->weight[1][b],
           gradient_y = support->gradient_y[b];
    for (int a = 0; a < span_x; a++)
      gather_node(v, gm_block_node(links, v->shift, x0 + a, y0 + b),
                  support->weight[0][a] * weight_y,
                  support->gradient_x[a] * weight_y,
                  support->weight_x_per_cell[a] * gradient_y, sum, dim);
  }
}

/* A short uGIMP or cpGIMP support in 2D (support_short.h), node by node in
 * the entry order b, a of gather_product, so the sums are bitwise
 * gather_product's. x0, y0: the lowest node from the block's base; where
 * the support lies inside the block (most points: x0, y0 + reach < 8), its
 * nodes sit at fixed offsets from the block's first, without the links. */
#if defined(__GNUC__)
/* gather_node_kind on pairs: acceleration and velocity (a_x, a_y), (v_x,
 * v_y), the gradient's columns (L_xx, L_yx), (L_xy, L_yy) and the empty
 * sums (e_x, e_y). */
static GM_ALWAYS_INLINE void
gather_node_pair(const gather_view *v, size_t node, double weight,
                 double grad_x, double grad_y, gm_pair *acc, gm_pair *vel,
                 gm_pair *column_x, gm_pair *column_y, gm_pair *empty,
                 const bool acceleration, const bool gradient) {
  gm_pair w = {weight, weight};
  gm_pair nodal = {v->grid_velocity[0][node], v->grid_velocity[1][node]};
  if (gradient) {
    /* The gradient where the node is massless, +0 where not, by a mask:
     * the sums of is_empty * g bit for bit. Those products are +0 or -0
     * (g < 0) at a node with mass, and a sum that starts at +0 is never
     * -0 and gains nothing from a zero of either sign; g is finite on the
     * short support (its bounds refuse NaN). */
    gm_pair mass = {v->grid_mass[node], v->grid_mass[node]};
    gm_pair zero = {0.0, 0.0}, g = {grad_x, grad_y};
    *empty += (gm_pair)((gm_pair_mask)g & (mass == zero));
  }
  if (acceleration) {
    gm_pair a = {v->grid_acceleration[0][node], v->grid_acceleration[1][node]};
    *acc += w * a;
  }
  *vel += w * nodal;
  if (gradient) {
    gm_pair gx = {grad_x, grad_x}, gy = {grad_y, grad_y};
    *column_x += nodal * gx;
    *column_y += nodal * gy;
  }
}
#endif

static GM_ALWAYS_INLINE void gather_short_nodes(
    const gather_view *v, const uint32_t *links, int64_t x0, int64_t y0,
    const gm_short_axis axis[2], const double gradient_x[3],
    const double weight_x_per_cell[3], point_gather *sum,
    const bool acceleration, const bool gradient, const bool inside) {
  const int64_t edge = GM_BLOCK_EDGE_2D;
  size_t first = (size_t)links[0] * GM_BLOCK_NODES + (size_t)(x0 + edge * y0);
#if defined(__GNUC__)
  gm_pair zero = {0.0, 0.0};
  gm_pair acc = zero, vel = zero, column_x = zero, column_y = zero,
          empty = zero;
#endif
  /* Loops of 3 with an exit past the reach: unrolled by the compiler, one
   * test for the third row and column instead of a counted loop. */
  for (int b = 0; b < 3; b++) {
    if (b > axis[1].reach)
      break;
    double weight_y = axis[1].weight[b], gradient_y = axis[1].gradient[b];
    for (int a = 0; a < 3; a++) {
      if (a > axis[0].reach)
        break;
      size_t node =
          inside ? first + (size_t)(a + edge * b)
                 : gm_block_node(links, GM_BLOCK_SHIFT_2D, x0 + a, y0 + b);
#if defined(__GNUC__)
      gather_node_pair(v, node, axis[0].weight[a] * weight_y,
                       gradient_x[a] * weight_y,
                       weight_x_per_cell[a] * gradient_y, &acc, &vel, &column_x,
                       &column_y, &empty, acceleration, gradient);
#else
      gather_node_kind(
          v, node, axis[0].weight[a] * weight_y, gradient_x[a] * weight_y,
          weight_x_per_cell[a] * gradient_y, sum, 2, acceleration, gradient);
#endif
    }
  }
#if defined(__GNUC__) /* the sums start at 0, as sum's: the same bits */
  for (int k = 0; k < 2; k++) {
    sum->acceleration[k] = acc[k];
    sum->velocity[k] = vel[k];
    sum->gradient[k][0] = column_x[k];
    sum->gradient[k][1] = column_y[k];
    sum->empty[k] = empty[k];
  }
#endif
}

static GM_ALWAYS_INLINE void
gather_short_2d(const gather_view *v, const uint32_t *links, int64_t x0,
                int64_t y0, const gm_short_axis axis[2], point_gather *sum,
                const bool acceleration, const bool gradient) {
  double inv_cell = v->shape_grid->inv_cell;  /* 1/m */
  double gradient_x[3], weight_x_per_cell[3]; /* 1/m, gm_product_support's */
  for (int a = 0; a < 3; a++) {
    gradient_x[a] = inv_cell * axis[0].gradient[a];
    weight_x_per_cell[a] = inv_cell * axis[0].weight[a];
  }
  const int64_t edge = GM_BLOCK_EDGE_2D;
  if (x0 + axis[0].reach < edge && y0 + axis[1].reach < edge)
    gather_short_nodes(v, links, x0, y0, axis, gradient_x, weight_x_per_cell,
                       sum, acceleration, gradient, true);
  else
    gather_short_nodes(v, links, x0, y0, axis, gradient_x, weight_x_per_cell,
                       sum, acceleration, gradient, false);
}

/* Might one of the four nodes of a corner's cell have no mass? Node
 * masses are sums of non-negative terms; where their product is positive
 * none is zero (a zero factor gives 0, or NaN beside an infinite or NaN
 * one), so false means no massless node; true (a zero, an underflow, a
 * NaN) sends the corner to the exact test node by node. mass: the tile's
 * masses from the cell's lower left node. */
static GM_ALWAYS_INLINE bool cpdi_corner_may_be_empty(const double *mass) {
  const int edge = GM_TILE_EDGE_2D;
  return !(mass[0] * mass[1] * (mass[edge] * mass[edge + 1]) > 0.0);
}

/* CPDI in 2D corner by corner (support_cpdi.h), the sums of g2p_wide.c's
 * gather_cpdi in its order: each corner interpolates the nodes of its cell
 * bilinearly, v_c = sum N_i(x_c) v_i, and the point takes v_p = share
 * sum_c v_c and L = sum_c v_c (x) g_c. As gather_short_2d: the
 * acceleration only where the pass reads it (the FLIP update), the
 * gradient and the empty-node sum only where it deforms (each sum taken
 * alone, so the ones kept have the same bits), and a node's x and y
 * components summed as one pair. A corner's four nodes are read from the
 * block's tile of nodal values (tile_values.h; its rows up to the
 * support's copied), wherever its cell lies. cell_node:
 * corner c's cell as the tile node x + 16 y of its lower left node (x, y
 * from the block's base node); axis: its bilinear
 * factors, axis[4 c + 2 k + a] as gm_cpdi_support's axis[c][k][a];
 * gradient_c: g_c (1/m) in 2 c + k. A corner whose four nodes all have
 * mass adds nothing to the empty-node sum (+0 four times, then +0 times
 * g_c), so its mass tests are one look at the four masses
 * (cpdi_corner_may_be_empty), and none where every node the tile copied
 * has mass (test_mass false: each term of the node-by-node test would be
 * +0, as the sum it starts from; gather_cpdi_corners_2d). */
static GM_ALWAYS_INLINE void gather_cpdi_corners_kind(
    const gm_tile_values *tile, const int cell_node[4], const double *axis,
    const double *gradient_c, double share, point_gather *sum,
    const bool acceleration, const bool gradient, const bool test_mass) {
  const int edge = GM_TILE_EDGE_2D;
#if defined(__GNUC__)
  gm_pair zero = {0.0, 0.0}, shares = {share, share};
  gm_pair acc = zero, vel = zero, column_x = zero, column_y = zero,
          empty_sum = zero;
#else /* the sums start at 0 (every one is set, so sum may come unset) */
  *sum = (point_gather){
      {0.0, 0.0}, {0.0, 0.0}, {{0.0, 0.0}, {0.0, 0.0}}, {0.0, 0.0}};
#endif
  for (int c = 0; c < 4; c++) {
    /* tile nodes (a, b) = (0, 0), (1, 0), (0, 1), (1, 1) */
    int first = cell_node[c];
    int node[4] = {first, first + 1, first + edge, first + edge + 1};
    double empty = 0.0; /* -, the corner's weight on massless nodes */
    if (test_mass && cpdi_corner_may_be_empty(&tile->mass[first]))
      for (int n = 0; n < 4; n++)
        empty += tile->mass[node[n]] == 0.0
                     ? axis[4 * c + (n & 1)] * axis[4 * c + 2 + (n >> 1)]
                     : 0.0;
#if defined(__GNUC__)
    gm_pair velocity = zero, corner_acc = zero; /* m/s, m/s^2 */
#else
    double velocity[2] = {0.0, 0.0}, corner_acc[2] = {0.0, 0.0};
#endif
    for (int n = 0; n < 4; n++) {
      int i = node[n];
      double value = axis[4 * c + (n & 1)] * axis[4 * c + 2 + (n >> 1)];
#if defined(__GNUC__)
      gm_pair w = {value, value}, nodal;
      memcpy(&nodal, tile->velocity[i], sizeof nodal);
      velocity += w * nodal;
      if (acceleration) {
        gm_pair a;
        memcpy(&a, tile->acceleration[i], sizeof a);
        corner_acc += w * a;
      }
#else
      for (int k = 0; k < 2; k++) {
        velocity[k] += value * tile->velocity[i][k];
        if (acceleration)
          corner_acc[k] += value * tile->acceleration[i][k];
      }
#endif
    }
    /* g_c (1/m), read only where the pass deforms (NULL otherwise) */
    const double *g = gradient ? gradient_c + 2 * c : NULL;
#if defined(__GNUC__)
    vel += shares * velocity;
    if (acceleration)
      acc += shares * corner_acc;
    if (gradient) {
      gm_pair gx = {g[0], g[0]}, gy = {g[1], g[1]}, e = {empty, empty},
              both = {g[0], g[1]};
      column_x += velocity * gx;
      column_y += velocity * gy;
      empty_sum += e * both;
    }
#else
    for (int k = 0; k < 2; k++) {
      sum->velocity[k] += share * velocity[k];
      if (acceleration)
        sum->acceleration[k] += share * corner_acc[k];
      if (gradient) {
        for (int b = 0; b < 2; b++)
          sum->gradient[k][b] += velocity[k] * g[b];
        sum->empty[k] += empty * g[k];
      }
    }
#endif
  }
#if defined(__GNUC__) /* the sums start at 0, as sum's: the same bits */
  for (int k = 0; k < 2; k++) {
    sum->acceleration[k] = acc[k];
    sum->velocity[k] = vel[k];
    sum->gradient[k][0] = column_x[k];
    sum->gradient[k][1] = column_y[k];
    sum->empty[k] = empty_sum[k];
  }
#endif
}

/* gather_cpdi_corners_kind with the mass tests only where the tile
 * copied a node without a positive mass (tile->all_mass false): two
 * specialisations, so that the common one carries no test at all (a test
 * of the flag per corner kept the compiler from unrolling the corners). */
static GM_ALWAYS_INLINE void
gather_cpdi_corners_2d(const gm_tile_values *tile, const int cell_node[4],
                       const double *axis, const double *gradient_c,
                       double share, point_gather *sum, const bool acceleration,
                       const bool gradient) {
  if (gradient && !tile->all_mass)
    gather_cpdi_corners_kind(tile, cell_node, axis, gradient_c, share, sum,
                             acceleration, true, true);
  else
    gather_cpdi_corners_kind(tile, cell_node, axis, gradient_c, share, sum,
                             acceleration, gradient, false);
}

/* The same from a whole support (support_cpdi.h) of reach `reach` that
 * fits the tile. base: the block's base node; tile: its values, whose rows
 * the support reaches are copied here. */
static GM_ALWAYS_INLINE void
gather_cpdi_2d(const gather_view *v, gm_tile_values *tile,
               const int64_t base[2], const gm_cpdi_support *support,
               const int64_t reach[2], point_gather *sum,
               const bool acceleration, const bool gradient) {
  /* fits the block's 16 x 16 tile (gm_wide_support_fits) */
  int cell_node[4]; /* tile node x + 16 y of each corner's cell */
  for (int c = 0; c < 4; c++)
    cell_node[c] = (int)(support->cell[c][0] - base[0]) +
                   GM_TILE_EDGE_2D * (int)(support->cell[c][1] - base[1]);
  int first_row = (int)(support->lowest[1] - base[1]);
  gm_tile_values_reach(v, tile, first_row, first_row + (int)reach[1] + 1,
                       acceleration, gradient);
  gather_cpdi_corners_2d(tile, cell_node, &support->axis[0][0][0],
                         &support->corner_gradient[0][0], support->share, sum,
                         acceleration, gradient);
}

/* The rows of the tile a kept support (cpdi_cache.h) reaches, copied:
 * called before its fractions are formed, so that the copy's loop does
 * not hold them (17 fewer instructions per point-step at 99 856 points
 * than copying inside gather_cpdi_kept_2d, 2026-11-30-cpdi21.md). */
static GM_ALWAYS_INLINE void gather_cpdi_kept_rows(const gather_view *v,
                                                   gm_tile_values *tile,
                                                   const gm_cpdi_kept *kept,
                                                   const bool acceleration,
                                                   const bool gradient) {
  int first_row = (int)kept->lowest[1];
  gm_tile_values_reach(v, tile, first_row, first_row + (int)kept->reach[1] + 1,
                       acceleration, gradient);
}

/* The same from a kept support whose rows are copied
 * (gather_cpdi_kept_rows). */
static GM_ALWAYS_INLINE void
gather_cpdi_kept_2d(const gm_tile_values *tile, const gm_cpdi_kept *kept,
                    const double *gradient_c, point_gather *sum,
                    const bool acceleration, const bool gradient) {
  double share = 0.25; /* gm_cpdi_support_2d's */
  gather_cpdi_corners_2d(tile, kept->tile, &kept->axis[0][0][0], gradient_c,
                         share, sum, acceleration, gradient);
}

#endif
