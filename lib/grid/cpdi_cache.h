/*
 * cpdi_cache.h - a 2D CPDI point's support kept from USL's scatter for the
 * fused move and re-map sweep of the same step (move_remap_wide.c), which
 * takes it again from the same committed position and domain map and
 * visits the points in the same order (block by block, order[]). Without
 * it the sweep computed the support anew, about 290 instructions, a third
 * of them the ten floor conversions and the bounds tests of support_cpdi.h
 * (bench/results/2026-11-29-cpdi.md).
 *
 * Indexed by the point's place k in order[], not by the point: the
 * scatter writes and the sweep reads the entries in sequence, where a
 * block's points are runs of indices far apart. Kept by point index, the
 * same stores made the scatter 28 % slower (9 more streams in block
 * order) and CPDI's step slower overall; kept by place, the step is faster
 * (that file). The deformation gather, which walks the points by index,
 * gained nothing from a kept support and computes its own.
 *
 * No new memory: the cache lives in arrays that are dead from the scatter
 * until the deformation pass writes them (after the sweep):
 *   - the 8 bilinear fractions f (corner c, axis k in slot 2 c + k) in
 *     the next buffer's stress (4) and domain map (4);
 *   - each corner's cell as its offset from the block's base node (0..14,
 *     a nibble each), the support's lowest node and reach per axis, in
 *     the block key array, negative (the top bit) to say it holds them.
 *     The binning keys every point (>= 0) before the scatter, the
 *     deformation pass keys every point again, and a failed step clears
 *     keys_valid, so the next binning keys them afresh: an entry is
 *     negative only where this step's scatter stored.
 *
 * A point the scatter refused (the step fails) leaves its entry
 * non-negative, and the sweep computes its support as before, recording
 * the same error. 1 - f is recomputed from f, the same operation on the
 * same value, so every weight has the bits of the support it was kept
 * from.
 */
#ifndef GM_CPDI_CACHE_H
#define GM_CPDI_CACHE_H

#include "shapes/support.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Where the cache lives; packed == NULL: no cache this step. */
typedef struct gm_cpdi_cache {
  double *fraction[8]; /* -, f of corner c along axis k in slot 2 c + k */
  int64_t *packed;     /* the points' block keys (see above) */
} gm_cpdi_cache;

/* Bit offsets in the packed word: the 8 corner cells in bits 0..31, the
 * lowest node per axis in 32..39, the reach per axis in 40..47. */
#define GM_CPDI_CACHE_LOWEST 32
#define GM_CPDI_CACHE_REACH  40

/* Keeps the support of the point at place `place` of order[] (its cells from
 * the block's base node base, reach per axis), which fits the block's
 * 16 x 16 tile. */
static inline void gm_cpdi_cache_store(const gm_cpdi_cache *cache, size_t place,
                                       const gm_cpdi_support *s,
                                       const int64_t base[2],
                                       const int64_t reach[2]) {
  uint64_t packed = 0;
  for (int c = 0; c < 4; c++)
    for (int k = 0; k < 2; k++) {
      cache->fraction[2 * c + k][place] = s->axis[c][k][1];
      packed |= (uint64_t)(s->cell[c][k] - base[k]) << (4 * (2 * c + k));
    }
  for (int k = 0; k < 2; k++) {
    packed |= (uint64_t)(s->lowest[k] - base[k])
              << (GM_CPDI_CACHE_LOWEST + 4 * k);
    packed |= (uint64_t)reach[k] << (GM_CPDI_CACHE_REACH + 4 * k);
  }
  /* below 2^48: INT64_MIN + packed is negative and keeps the low bits */
  cache->packed[place] = INT64_MIN + (int64_t)packed;
}

/* The kept support of the point at place `place` of order[] into s (cells,
 * fractions, lowest node; not the gradients), its lowest node from the base and
 * its reach; false if this step's scatter kept none for it. */
static inline bool gm_cpdi_cache_load(const gm_cpdi_cache *cache, size_t place,
                                      const int64_t base[2], gm_cpdi_support *s,
                                      int64_t lowest[2], int64_t reach[2]) {
  int64_t key = cache->packed[place];
  if (key >= 0)
    return false;
  uint64_t packed = (uint64_t)key; /* modulo 2^64: the low bits as stored */
  for (int c = 0; c < 4; c++)
    for (int k = 0; k < 2; k++) {
      double f = cache->fraction[2 * c + k][place];
      s->cell[c][k] = base[k] + (int64_t)((packed >> (4 * (2 * c + k))) & 15);
      s->axis[c][k][0] = 1.0 - f;
      s->axis[c][k][1] = f;
    }
  for (int k = 0; k < 2; k++) {
    lowest[k] = (int64_t)((packed >> (GM_CPDI_CACHE_LOWEST + 4 * k)) & 15);
    reach[k] = (int64_t)((packed >> (GM_CPDI_CACHE_REACH + 4 * k)) & 15);
    s->lowest[k] = base[k] + lowest[k];
  }
  s->corner_count = 4;
  s->share = 0.25;
  return true;
}

#endif
