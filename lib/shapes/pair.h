/*
 * pair.h - two doubles in one vector register for the wide kernels.
 */
#ifndef GM_PAIR_H
#define GM_PAIR_H

#if defined(__GNUC__)
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* Two doubles, the x and y components of one sum, in one vector register
 * (GCC and Clang vector extension; SSE2 on x86-64), for the wide kernels
 * (gather_wide.h, p2g_wide.c, cpdi_cache.h, support_cpdi.h): each lane does the
 * scalar code's operation on its component, so every sum keeps its bits (the
 * library is built with -std=c11, which keeps a * b + c two roundings).
 * Other compilers take the scalar code. */
typedef double gm_pair __attribute__((vector_size(2 * sizeof(double))));

/* A lane mask (all ones or zeros) of a comparison of pairs. */
typedef long long gm_pair_mask __attribute__((vector_size(sizeof(gm_pair))));

/* Per lane a < b ? a : b and a > b ? a : b, the scalar expressions' values
 * bit for bit (NaN included: b where a comparison is false): SSE2's
 * minpd and maxpd are defined so, where the masks take four instructions. */
static inline gm_pair gm_pair_min(gm_pair a, gm_pair b) {
#if defined(__SSE2__)
  return (gm_pair)_mm_min_pd((__m128d)a, (__m128d)b);
#else
  gm_pair_mask less = (gm_pair_mask)(a < b);
  return (gm_pair)(((gm_pair_mask)a & less) | ((gm_pair_mask)b & ~less));
#endif
}

static inline gm_pair gm_pair_max(gm_pair a, gm_pair b) {
#if defined(__SSE2__)
  return (gm_pair)_mm_max_pd((__m128d)a, (__m128d)b);
#else
  gm_pair_mask more = (gm_pair_mask)(a > b);
  return (gm_pair)(((gm_pair_mask)a & more) | ((gm_pair_mask)b & ~more));
#endif
}
#endif

#endif
