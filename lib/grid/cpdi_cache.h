/*
 * cpdi_cache.h - the corner cells of a 2D CPDI point's support, kept from
 * USL's scatter for the two later passes of the same step that take the
 * support again from the same committed position and domain map: the
 * fused move and re-map sweep (move_remap_wide.c) and the deformation
 * gather (g2p_wide.c). With the cells known, they form the bilinear
 * fractions (and the gather the corner gradients) from the corners
 * without the ten floor conversions, the minimum and maximum and the
 * bounds tests of support_cpdi.h (bench/results/2026-11-29-cpdi.md).
 *
 * One 64-bit word per point, in the point's slot of the block key array:
 * dead from the binning, which reads the keys, until the deformation
 * pass, which keys each point again after its gather of the point's chunk
 * (gm_wide_keys_chunk); a failed step clears keys_valid, so the next
 * binning keys every point afresh. Keys are >= 0; a kept word is negative
 * (INT64_MIN plus the packed bits below), so a word is negative only
 * where this step's scatter kept it. No new memory.
 *
 * Tried and measured against this: keeping the fractions too (8 more
 * arrays, the next buffer's stress and domain map) cut more instructions
 * but its stores cost the scatter more than the later passes saved.
 *
 * A point the scatter refused (the step fails) leaves its word
 * non-negative, and the later passes compute its support as before,
 * recording the same error.
 */
#ifndef GM_CPDI_CACHE_H
#define GM_CPDI_CACHE_H

#include "shapes/shapes.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* Where the cells are kept; packed == NULL: not kept this step. */
typedef struct gm_cpdi_cache {
  int64_t *packed; /* the block key array (see above) */
} gm_cpdi_cache;

/* Bit offsets in the packed word: the cell of corner c along axis k as its
 * offset from the block's base node (0..14) in the nibble 2 c + k (bits
 * 0..31), the lowest node per axis in 32..39, the reach per axis in
 * 40..47. */
#define GM_CPDI_CACHE_LOWEST 32
#define GM_CPDI_CACHE_REACH  40

/* A kept support as the two later passes read it: each corner's cell
 * as the tile node x + 16 y of its lower left node (x, y from the block's
 * base node: the byte the word stores, so one shift and mask per corner;
 * the gathers' tile of values and the sweep's tile take it as it is), its
 * bilinear factors, and the lowest node and reach from the base. */
typedef struct gm_cpdi_kept {
  int tile[4];          /* corner c's cell, tile node x + 16 y */
  uint32_t tile_bytes;  /* the same, tile[c] in bits 8 c .. 8 c + 7 */
  double axis[4][2][2]; /* (1 - f, f) per corner and axis, as axis */
  int64_t lowest[2];    /* the lowest node from the base */
  int64_t reach[2];     /* nodes past lowest per axis */
} gm_cpdi_kept;

/* Point p's kept cells into kept (cells, lowest node and reach from the
 * base); false if this step's scatter kept none for it. */
static inline bool gm_cpdi_kept_load(const gm_cpdi_cache *cache, size_t p,
                                     gm_cpdi_kept *kept) {
  int64_t key = cache->packed[p];
  if (key >= 0)
    return false;
  uint64_t packed = (uint64_t)key; /* modulo 2^64: the low bits as stored */
  kept->tile_bytes = (uint32_t)packed;
  for (int c = 0; c < 4; c++) /* nibbles x, y: the byte x + 16 y */
    kept->tile[c] = (int)((packed >> (8 * c)) & 255);
  for (int k = 0; k < 2; k++) {
    kept->lowest[k] =
        (int64_t)((packed >> (GM_CPDI_CACHE_LOWEST + 4 * k)) & 15);
    kept->reach[k] = (int64_t)((packed >> (GM_CPDI_CACHE_REACH + 4 * k)) & 15);
  }
  return true;
}

/* A whole support s (support_cpdi.h) of reach `reach` that fits the
 * block's 16 x 16 tile, as a kept one (base: the block's base node). */
static inline void gm_cpdi_kept_from_support(const gm_cpdi_support *s,
                                             const int64_t base[2],
                                             const int64_t reach[2],
                                             gm_cpdi_kept *kept) {
  kept->tile_bytes = 0;
  for (int c = 0; c < 4; c++) {
    kept->tile[c] =
        (int)(s->cell[c][0] - base[0]) + 16 * (int)(s->cell[c][1] - base[1]);
    kept->tile_bytes |= (uint32_t)kept->tile[c] << (8 * c);
    for (int k = 0; k < 2; k++)
      for (int a = 0; a < 2; a++)
        kept->axis[c][k][a] = s->axis[c][k][a];
  }
  for (int k = 0; k < 2; k++) {
    kept->lowest[k] = s->lowest[k] - base[k];
    kept->reach[k] = reach[k];
  }
}

/* Keeps point p's support, in its kept form, as p's word (the bits
 * above: corner c's byte x + 16 y is its two nibbles); the support fits
 * the block's 16 x 16 tile. Below 2^48, so INT64_MIN + packed is negative
 * and keeps the low bits. */
static inline void gm_cpdi_cache_store_kept(const gm_cpdi_cache *cache,
                                            size_t p,
                                            const gm_cpdi_kept *kept) {
  uint64_t packed = kept->tile_bytes;
  for (int k = 0; k < 2; k++) {
    packed |= (uint64_t)kept->lowest[k] << (GM_CPDI_CACHE_LOWEST + 4 * k);
    packed |= (uint64_t)kept->reach[k] << (GM_CPDI_CACHE_REACH + 4 * k);
  }
  cache->packed[p] = INT64_MIN + (int64_t)packed;
}

/* Point p's whole support (gm_cpdi_point_support_2d: the same tests in
 * the same order, the same bits) straight into the kept form of the
 * block of base node base, with the corner gradients g_c (1/m); false
 * where gm_cpdi_point_support_2d refuses or the support does not fit the
 * block's 16 x 16 tile (gm_wide_support_fits). map: the domain map D.
 *
 * Why: the scatter took the floors of the eight corner cells one at a
 * time and the cells as integers, then their offsets from the base for
 * the tile and again for the kept word (bench/results/2026-11-29-cpdi20.md).
 * Here a corner's x and y go as one pair: its position past the lowest
 * node, local = cell - lowest, is exact (lowest is an integer with
 * 0 <= lowest <= cell < 2^52, so cell's last bit is at or below lowest's
 * units) and not negative, so its truncation (SSE2's cvttpd2dq, both
 * lanes; the values are below 16) is floor(cell) - lowest, and the
 * fraction local - floor(local) is cell - floor(cell) exactly, as is
 * gm_cpdi_support_2d's (both are exact: Sterbenz). The lowest and
 * highest nodes keep gm_floor_index, so every refusal is the same. A NaN
 * corner that the extremes skip cannot pass: the corners share their
 * terms, so a non-finite term makes corner 0 non-finite, which the bounds
 * test refuses. */
static inline bool gm_cpdi_kept_support_2d(
    const gm_shape_grid *grid, const double *const position[2],
    const double *const map[4], const double *const domain_size[2], size_t p,
    const int64_t base[2], gm_cpdi_kept *kept, double gradient[4][2]) {
#if defined(__GNUC__) && defined(__SSE2__)
  gm_pair corner[4], cell[4], low, high; /* m, cells */
  gm_cpdi_cells_pair_2d(grid, position[0][p], position[1][p], map[0][p],
                        map[1][p], map[2][p], map[3][p],
                        0.5 * domain_size[0][p], 0.5 * domain_size[1][p],
                        corner, cell, &low, &high);
  int64_t lowest[2];
  for (int k = 0; k < 2; k++) { /* gm_cpdi_corners_2d's tests */
    if (!(low[k] >= -1.0 && high[k] < (double)grid->last_node[k] + 1.0))
      return false; /* also catches NaN; keeps the casts in range */
    lowest[k] = gm_floor_index(low[k]);
    int64_t highest = gm_floor_index(high[k]) + 1;
    if (lowest[k] < 0 || highest > grid->last_node[k] ||
        highest - lowest[k] + 1 > GM_SUPPORT_MAX_SPAN)
      return false; /* as bounds_valid */
    kept->lowest[k] = lowest[k] - base[k];
    kept->reach[k] = highest - lowest[k];
  }
  double corners[4][2]; /* m */
  memcpy(corners, corner, sizeof corners);
  if (!gm_cpdi_corner_gradients_2d(corners, gradient))
    return false;
  const int64_t edge = 16; /* the tile's (gm_wide_support_fits) */
  if (!(kept->lowest[0] >= 0 && kept->lowest[1] >= 0 &&
        kept->lowest[0] + kept->reach[0] < edge &&
        kept->lowest[1] + kept->reach[1] < edge))
    return false;
  gm_pair lowest_cell = {(double)lowest[0], (double)lowest[1]}; /* cells */
  int first = (int)kept->lowest[0] + 16 * (int)kept->lowest[1]; /* x + 16 y */
  gm_pair one = {1.0, 1.0};
  __m128i whole[4]; /* int32 (x, y, 0, 0): corner c's cell past lowest */
  for (int c = 0; c < 4; c++) {
    gm_pair local = cell[c] - lowest_cell; /* exact, >= 0 (see above) */
    whole[c] = _mm_cvttpd_epi32((__m128d)local);
    gm_pair fraction = local - (gm_pair)_mm_cvtepi32_pd(whole[c]);
    gm_pair lower = one - fraction;
    gm_pair axis_x = {lower[0], fraction[0]}, axis_y = {lower[1], fraction[1]};
    memcpy(kept->axis[c][0], &axis_x, sizeof axis_x);
    memcpy(kept->axis[c][1], &axis_y, sizeof axis_y);
  }
  /* The four bytes x + 16 y at once, where taking each corner's x and y
   * out of its vector, then packing the bytes, took about 36
   * instructions: the cells as int16 (x0, y0, .., x3, y3), each x + 16 y
   * by one multiply-add, packed to bytes (all below 16, so below 256 with
   * the 16 y), then first added to each byte (no carry: first + x + 16 y
   * is the tile node, below 256, as the fit test above ensures). */
  __m128i xy = _mm_packs_epi32(_mm_unpacklo_epi64(whole[0], whole[1]),
                               _mm_unpacklo_epi64(whole[2], whole[3]));
  __m128i sums = _mm_madd_epi16(xy, _mm_set1_epi32(1 | 16 << 16));
  __m128i bytes = _mm_packus_epi16(_mm_packs_epi32(sums, sums), sums);
  kept->tile_bytes = (uint32_t)_mm_cvtsi128_si32(bytes) +
                     (uint32_t)first * UINT32_C(0x01010101);
  for (int c = 0; c < 4; c++)
    kept->tile[c] = (int)((kept->tile_bytes >> (8 * c)) & 255);
  return true;
#else
  gm_cpdi_support support;
  int64_t reach[2];
  if (!gm_cpdi_point_support_2d(grid, position, map, domain_size, p, &support,
                                reach))
    return false;
  int64_t x0 = support.lowest[0] - base[0], y0 = support.lowest[1] - base[1];
  if (!(x0 >= 0 && y0 >= 0 && x0 + reach[0] < 16 && y0 + reach[1] < 16))
    return false;
  gm_cpdi_kept_from_support(&support, base, reach, kept);
  memcpy(gradient, support.corner_gradient, sizeof support.corner_gradient);
  return true;
#endif
}

/* Truncations of a pair of values in [0, 16): their floors, exact (as
 * doubles). SSE2 converts both lanes at once. */
#if defined(__GNUC__)
static inline gm_pair gm_cpdi_truncate_local(gm_pair local) {
#if defined(__SSE2__)
  return (gm_pair)_mm_cvtepi32_pd(_mm_cvttpd_epi32((__m128d)local));
#else
  return (gm_pair){(double)(int)local[0], (double)(int)local[1]};
#endif
}
#endif

/* The bilinear factors (1 - f, f) of point p's kept support, whose cells
 * are known: each corner's position in cells less its cell, the
 * expressions of gm_cpdi_corners_2d and gm_cpdi_support_2d
 * (support_cpdi.h), so the same bits. map: the domain map D; base: the
 * block's base node. Its corners (m) into corners, for the corner
 * gradients (gm_cpdi_corner_gradients_2d).
 *
 * The fraction is the corner's position past its cell, f = cell -
 * floor(cell), an exact difference (Sterbenz) whichever way the floor is
 * had. Here as gm_cpdi_kept_support_2d takes it: the position past the
 * lowest node, local = cell - lowest, is exact and in [0, 16) (the
 * scatter kept the support from the same position and domain map), so
 * its truncation is floor(cell) - lowest, and f = local - trunc(local)
 * (SSE2: two conversions for both axes), where a table of the block's
 * cells as doubles, two lookups per corner and one table per block (in
 * the deformation gather, per change of block in index order), cost more
 * (bench/results/2026-11-30-cpdi21.md). */
static inline void gm_cpdi_kept_fractions(
    const gm_shape_grid *grid, const double *const position[2],
    const double *const map[4], const double *const domain_size[2], size_t p,
    const int64_t base[2], gm_cpdi_kept *kept, double corners[4][2]) {
#if defined(__GNUC__)
  /* x and y as one pair through gm_cpdi_corner_positions_2d's and the
   * fractions' expressions: the same operation per lane, the same bits,
   * and a corner's two (1 - f, f) stored as two pairs */
  double half_x = 0.5 * domain_size[0][p], half_y = 0.5 * domain_size[1][p];
  gm_pair centre = {position[0][p], position[1][p]};     /* m */
  gm_pair r1 = (gm_pair){map[0][p], map[2][p]} * half_x; /* m, D r1_0 */
  gm_pair r2 = (gm_pair){map[1][p], map[3][p]} * half_y; /* m, D r2_0 */
  gm_pair corner[4] = {
      centre + -1.0 * r1 + -1.0 * r2, centre + 1.0 * r1 + -1.0 * r2,
      centre + 1.0 * r1 + 1.0 * r2, centre + -1.0 * r1 + 1.0 * r2};
  gm_pair origin = {grid->origin[0], grid->origin[1]};
  gm_pair lowest = {(double)(base[0] + kept->lowest[0]),
                    (double)(base[1] + kept->lowest[1])}; /* cells */
  gm_pair one = {1.0, 1.0};
  for (int c = 0; c < 4; c++) {
    gm_pair cell = (corner[c] - origin) * grid->inv_cell; /* cells */
    gm_pair local = cell - lowest; /* exact, in [0, 16) (see above) */
    gm_pair fraction = local - gm_cpdi_truncate_local(local);
    gm_pair low = one - fraction;
    gm_pair x = {low[0], fraction[0]}, y = {low[1], fraction[1]};
    memcpy(kept->axis[c][0], &x, sizeof x);
    memcpy(kept->axis[c][1], &y, sizeof y);
    memcpy(corners[c], &corner[c], sizeof corner[c]);
  }
#else
  gm_cpdi_corner_positions_2d(
      position[0][p], position[1][p], map[0][p], map[1][p], map[2][p],
      map[3][p], 0.5 * domain_size[0][p], 0.5 * domain_size[1][p], corners);
  for (int k = 0; k < 2; k++) {
    double origin = grid->origin[k], inv_cell = grid->inv_cell;
    for (int c = 0; c < 4; c++) {
      double cell = (corners[c][k] - origin) * inv_cell; /* cells */
      int local = (kept->tile[c] >> (4 * k)) & 15; /* x or y of x + 16 y */
      double fraction = cell - (double)(base[k] + local);
      kept->axis[c][k][0] = 1.0 - fraction;
      kept->axis[c][k][1] = fraction;
    }
  }
#endif
}

#endif
