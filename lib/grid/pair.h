/*
 * pair.h - two doubles in one vector register for the wide kernels.
 */
#ifndef GM_PAIR_H
#define GM_PAIR_H

#if defined(__GNUC__)
/* Two doubles, the x and y components of one sum, in one vector register
 * (GCC and Clang vector extension; SSE2 on x86-64), for the wide kernels
 * (gather_wide.h, p2g_wide.c, cpdi_cache.h): each lane does the scalar
 * code's operation on its component, so every sum keeps its bits (the
 * library is built with -std=c11, which keeps a * b + c two roundings).
 * Other compilers take the scalar code. */
typedef double gm_pair __attribute__((vector_size(2 * sizeof(double))));
#endif

#endif
