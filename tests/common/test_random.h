/*
 * test_random.h - the tests' random numbers: a deterministic 64-bit LCG
 * (Knuth's MMIX constants), so a failure reproduces from its seed; the top
 * 53 bits give a double uniform in [0, 1). Each test program has its own
 * state (static); set lcg_state to seed it.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef TEST_RANDOM_H
#define TEST_RANDOM_H

#include <stdint.h>

static uint64_t lcg_state;

static inline double lcg_uniform(void) {
  lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(lcg_state >> 11) * (1.0 / 9007199254740992.0);
}

/* Uniform in [low, high). */
static inline double lcg_between(double low, double high) {
  return low + (high - low) * lcg_uniform();
}

#endif
