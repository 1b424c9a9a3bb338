/*
 * fuzz/fuzz_input.h - reads a fuzzer's bytes as a stream of typed values
 * for the harnesses: integers, and doubles that are either raw bits (any
 * NaN, infinity, denormal) or one of the values that usually break
 * numerical code (0, -0, +-1, tiny, huge, NaN, infinity). An exhausted
 * stream reads zeros, so every input is a complete program.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#ifndef GM_FUZZ_INPUT_H
#define GM_FUZZ_INPUT_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct fuzz_input {
  const uint8_t *data;
  size_t size, offset;
} fuzz_input;

static inline int fuzz_done(const fuzz_input *in) {
  return in->offset >= in->size;
}

static inline uint8_t fuzz_u8(fuzz_input *in) {
  return in->offset < in->size ? in->data[in->offset++] : 0;
}

static inline uint32_t fuzz_u32(fuzz_input *in) {
  uint32_t value = 0;
  for (int i = 0; i < 4; i++)
    value = value << 8 | fuzz_u8(in);
  return value;
}

/* A double: one selector byte, then (for raw) eight bytes of bits. */
static inline double fuzz_double(fuzz_input *in) {
  static const double special[] = {0.0,    -0.0,    1.0,   -1.0,   0.5,  2.0,
                                   1e-300, -1e-300, 1e300, -1e300, 1e-9, 1e9,
                                   0.01,   0.1,     10.0,  1000.0};
  uint8_t selector = fuzz_u8(in);
  if (selector < 160) /* a moderate value: most inputs should get far */
    return ((double)selector - 80.0) / 16.0;
  if (selector < 224)
    return special[selector % (sizeof special / sizeof special[0])];
  if (selector == 224)
    return NAN;
  if (selector == 225)
    return INFINITY;
  if (selector == 226)
    return -INFINITY;
  uint64_t bits = 0;
  for (int i = 0; i < 8; i++)
    bits = bits << 8 | fuzz_u8(in);
  double value;
  memcpy(&value, &bits, sizeof value);
  return value;
}

#endif
