/*
 * test_interaction.c - white-box test of the domains of interaction of the
 * granular method (lib/granular/interaction.c; 000 sec 3.3, Fig. 4, Table A2):
 *
 *  - gm_interaction_overlap in 2D on thousands of random parallelogram
 *    pairs (generic, axis-aligned rectangles, thin ones of aspect 1e-3,
 *    one nested in the other, zero-area segments against parallelograms)
 *    against dense point sampling: 200 x 200 points of each domain, tested
 *    for strict membership in the other by inverting its half-edge matrix;
 *  - exact configurations: shared edges and corners (strict overlap: must
 *    be false), nesting and identity (true), rotated and degenerate cases,
 *    all with dyadic numbers so that no rounding decides them;
 *  - 1D segments, sampled the same way, and their exact cases;
 *  - gm_interaction_domain_of: the requested area (length in 1D), the same
 *    centre and edges proportional to the domain's, for every variant.
 *
 * Sampling cannot decide pairs that overlap by less than its resolution,
 * so each random pair is first classified, with a test written here
 * (separating intervals of projected corners, not the library's
 * centre-and-radius form), on domains grown or eroded by the resolution:
 * "surely disjoint" (still disjoint when one is grown), "surely
 * overlapping" (still overlapping when the sampled one's partner is eroded:
 * then some sample must land inside it), or in the band between. Outside
 * the band, sampling must give the class and the library must agree with
 * sampling; band pairs are only counted, and must be a small fraction.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "granular/interaction.h"

#include "test_random.h"
#include "test_util.h"

#include <check.h>
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const double pi = 3.14159265358979323846; /* M_PI is not C11 */

enum {
  SAMPLES_PER_EDGE = 200, /* sampling grid of a 2D domain: n x n points */
  SAMPLES_1D = 2000,      /* points along a 1D segment */
  PAIRS_PER_KIND = 1000   /* random pairs per kind */
};

static double random_sign(void) {
  return lcg_uniform() < 0.5 ? -1.0 : 1.0;
}

/* A domain from its centre and half edges (m). */
static gm_interaction_domain make_domain(double cx, double cy, double r1x,
                                         double r1y, double r2x, double r2y) {
  gm_interaction_domain d;
  d.centre[0] = cx;
  d.centre[1] = cy;
  d.half_edge[0][0] = r1x;
  d.half_edge[0][1] = r1y;
  d.half_edge[1][0] = r2x;
  d.half_edge[1][1] = r2y;
  return d;
}

static double cross(const double u[2], const double v[2]) {
  return u[0] * v[1] - u[1] * v[0];
}

static double length(const double v[2]) {
  return hypot(v[0], v[1]);
}

/* Area (m^2) of a 2D domain: |r1 x r2| times 4. */
static double area_of(const gm_interaction_domain *d) {
  return 4.0 * fabs(cross(d->half_edge[0], d->half_edge[1]));
}

/* ------------------------------------------------------ sampling (2D) */

/* Is x strictly inside d (positive area)? Solves x - c = s r1 + t r2 by
 * Cramer's rule, i.e. inverts d's half-edge matrix. */
static bool strictly_inside(const gm_interaction_domain *d, const double x[2]) {
  double offset[2] = {x[0] - d->centre[0], x[1] - d->centre[1]};
  double det = cross(d->half_edge[0], d->half_edge[1]);
  double s = cross(offset, d->half_edge[1]) / det;
  double t = cross(d->half_edge[0], offset) / det;
  return fabs(s) < 1.0 && fabs(t) < 1.0;
}

/* Does a sample of `from` lie strictly inside `to` (positive area)? The
 * samples are the centres of an n x n parametric grid on `from` (n points
 * along r1 if `from` is a segment). */
static bool sample_hits(const gm_interaction_domain *from,
                        const gm_interaction_domain *to) {
  const double *r1 = from->half_edge[0], *r2 = from->half_edge[1];
  int rows = area_of(from) > 0.0 ? SAMPLES_PER_EDGE : 1;
  for (int j = 0; j < rows; j++) {
    double v = rows == 1 ? 0.0 : -1.0 + (2.0 * j + 1.0) / SAMPLES_PER_EDGE;
    for (int i = 0; i < SAMPLES_PER_EDGE; i++) {
      double u = -1.0 + (2.0 * i + 1.0) / SAMPLES_PER_EDGE;
      double x[2] = {from->centre[0] + u * r1[0] + v * r2[0],
                     from->centre[1] + u * r1[1] + v * r2[1]};
      if (strictly_inside(to, x))
        return true;
    }
  }
  return false;
}

/* Every point of d lies within this distance (m) of one of its samples:
 * half the diagonal of a sample cell, |2 r1 / n| / 2 + |2 r2 / n| / 2. */
static double sample_resolution(const gm_interaction_domain *d) {
  return (length(d->half_edge[0]) + length(d->half_edge[1])) / SAMPLES_PER_EDGE;
}

/* Overlap as seen by sampling each domain into the other. */
static bool sampled_overlap(const gm_interaction_domain *a,
                            const gm_interaction_domain *b) {
  return (area_of(b) > 0.0 && sample_hits(a, b)) ||
         (area_of(a) > 0.0 && sample_hits(b, a));
}

/* ------------------------------------------ classification of a pair */

/* The four corners (m) of d. */
static void corners_of(const gm_interaction_domain *d, double corners[4][2]) {
  static const double s1[4] = {-1.0, 1.0, 1.0, -1.0};
  static const double s2[4] = {-1.0, -1.0, 1.0, 1.0};
  for (int c = 0; c < 4; c++)
    for (int k = 0; k < 2; k++)
      corners[c][k] = d->centre[k] + s1[c] * d->half_edge[0][k] +
                      s2[c] * d->half_edge[1][k];
}

/* Strict overlap of two convex quadrilaterals by their corners' projected
 * intervals on the edge normals of both (open intervals must intersect on
 * every axis). Used only to classify pairs for the sampling. */
static bool corner_projection_overlap(const gm_interaction_domain *a,
                                      const gm_interaction_domain *b) {
  double corners[2][4][2];
  corners_of(a, corners[0]);
  corners_of(b, corners[1]);
  const gm_interaction_domain *both[2] = {a, b};
  for (int d = 0; d < 2; d++) {
    for (int e = 0; e < 2; e++) {
      double axis[2] = {-both[d]->half_edge[e][1], both[d]->half_edge[e][0]};
      if (axis[0] == 0.0 && axis[1] == 0.0)
        continue;
      double low[2] = {INFINITY, INFINITY}, high[2] = {-INFINITY, -INFINITY};
      for (int s = 0; s < 2; s++)
        for (int c = 0; c < 4; c++) {
          double p = corners[s][c][0] * axis[0] + corners[s][c][1] * axis[1];
          low[s] = fmin(low[s], p);
          high[s] = fmax(high[s], p);
        }
      if (!(high[0] > low[1] && high[1] > low[0]))
        return false;
    }
  }
  return true;
}

/* d with each pair of opposite edges moved apart by 2 offset (m; negative
 * moves them together); false if that empties d. A segment (r2 = 0)
 * grows into a rectangle of half width offset. */
static bool offset_domain(const gm_interaction_domain *d, double offset,
                          gm_interaction_domain *out) {
  *out = *d;
  const double *r1 = d->half_edge[0], *r2 = d->half_edge[1];
  double area = fabs(cross(r1, r2)); /* a quarter of the area, m^2 */
  if (!(area > 0.0)) {
    if (offset <= 0.0)
      return false;
    double l1 = length(r1);
    for (int k = 0; k < 2; k++)
      out->half_edge[0][k] = r1[k] * (l1 + offset) / l1;
    out->half_edge[1][0] = -r1[1] / l1 * offset;
    out->half_edge[1][1] = r1[0] / l1 * offset;
    return true;
  }
  /* Half widths across the edges along r1 and along r2. */
  double across_r1 = area / length(r1), across_r2 = area / length(r2);
  if (across_r1 + offset <= 0.0 || across_r2 + offset <= 0.0)
    return false;
  for (int k = 0; k < 2; k++) {
    out->half_edge[1][k] = r2[k] * (across_r1 + offset) / across_r1;
    out->half_edge[0][k] = r1[k] * (across_r2 + offset) / across_r2;
  }
  return true;
}

typedef enum pair_class {
  SURELY_DISJOINT,
  SURELY_OVERLAPPING,
  IN_BAND
} pair_class;

/* Class of a pair for sampling (see the top of this file). */
static pair_class classify(const gm_interaction_domain *a,
                           const gm_interaction_domain *b) {
  double resolution = fmax(sample_resolution(a), sample_resolution(b));
  gm_interaction_domain grown;
  offset_domain(a, resolution, &grown);
  if (!corner_projection_overlap(&grown, b))
    return SURELY_DISJOINT;
  gm_interaction_domain eroded;
  if (offset_domain(b, -sample_resolution(a), &eroded) &&
      corner_projection_overlap(a, &eroded))
    return SURELY_OVERLAPPING;
  if (offset_domain(a, -sample_resolution(b), &eroded) &&
      corner_projection_overlap(b, &eroded))
    return SURELY_OVERLAPPING;
  return IN_BAND;
}

/* ----------------------------------------------------- random pairs */

typedef enum pair_kind {
  KIND_GENERIC,    /* parallelograms of similar size */
  KIND_RECTANGLES, /* axis-aligned rectangles (MPM, uGIMP, cpGIMP) */
  KIND_THIN,       /* one of aspect ratio 1e-3 */
  KIND_NESTED,     /* a small one near the inside of a large one */
  KIND_SEGMENT,    /* a zero-area segment against a parallelogram */
  KIND_COUNT
} pair_kind;

static const char *const kind_name[KIND_COUNT] = {"generic", "rectangles",
                                                  "thin", "nested", "segment"};

/* A vector of length in [low, high] (m) at angle theta (rad). */
static void polar(double low, double high, double theta, double v[2]) {
  double r = lcg_between(low, high);
  v[0] = r * cos(theta);
  v[1] = r * sin(theta);
}

/* A parallelogram centred at c whose edges meet at 17 to 163 degrees,
 * in either orientation. */
static gm_interaction_domain random_parallelogram(const double c[2]) {
  gm_interaction_domain d = make_domain(c[0], c[1], 0, 0, 0, 0);
  double theta = lcg_between(0.0, 2.0 * pi);
  polar(0.1, 1.0, theta, d.half_edge[0]);
  polar(0.1, 1.0, theta + random_sign() * lcg_between(0.3, pi - 0.3),
        d.half_edge[1]);
  return d;
}

static gm_interaction_domain random_rectangle(const double c[2]) {
  return make_domain(c[0], c[1], random_sign() * lcg_between(0.1, 1.0), 0.0,
                     0.0, random_sign() * lcg_between(0.1, 1.0));
}

static void random_pair(pair_kind kind, gm_interaction_domain *a,
                        gm_interaction_domain *b) {
  double ca[2] = {lcg_between(-1.0, 1.0), lcg_between(-1.0, 1.0)};
  double cb[2] = {ca[0] + lcg_between(-1.5, 1.5),
                  ca[1] + lcg_between(-1.5, 1.5)};
  if (kind == KIND_RECTANGLES) {
    *a = random_rectangle(ca);
    *b = random_rectangle(cb);
    return;
  }
  *a = random_parallelogram(ca);
  if (kind == KIND_NESTED) { /* b's centre inside a, b 0.05 .. 0.3 of a */
    double u = lcg_between(-0.7, 0.7), v = lcg_between(-0.7, 0.7);
    for (int k = 0; k < 2; k++)
      cb[k] = ca[k] + u * a->half_edge[0][k] + v * a->half_edge[1][k];
    *b = random_parallelogram(cb);
    double scale = lcg_between(0.05, 0.3);
    for (int e = 0; e < 2; e++)
      for (int k = 0; k < 2; k++)
        b->half_edge[e][k] *= scale;
    return;
  }
  *b = random_parallelogram(cb);
  if (kind == KIND_THIN || kind == KIND_SEGMENT) {
    double scale = kind == KIND_THIN ? 1e-3 : 0.0;
    gm_interaction_domain *thin = lcg_uniform() < 0.5 ? a : b;
    if (kind == KIND_SEGMENT)
      thin = b; /* the sampling needs one domain of positive area */
    for (int k = 0; k < 2; k++)
      thin->half_edge[1][k] *= scale;
  }
}

START_TEST(test_overlap_against_sampling) {
  pair_kind kind = (pair_kind)_i;
  lcg_state = 1000 + (uint64_t)kind;
  int band = 0, overlapping = 0, disjoint = 0;
  for (int n = 0; n < PAIRS_PER_KIND; n++) {
    gm_interaction_domain a, b;
    random_pair(kind, &a, &b);
    pair_class class = classify(&a, &b);
    if (class == IN_BAND) {
      band++;
      continue;
    }
    bool sampled = sampled_overlap(&a, &b);
    REQUIRE(sampled == (class == SURELY_OVERLAPPING),
            "%s pair %d: sampling says %d but the pair is surely %s",
            kind_name[kind], n, sampled,
            class == SURELY_OVERLAPPING ? "overlapping" : "disjoint");
    bool library = gm_interaction_overlap(2, &a, &b);
    REQUIRE(library == sampled,
            "%s pair %d: gm_interaction_overlap says %d, sampling %d "
            "(a: c (%g, %g) r1 (%g, %g) r2 (%g, %g); b: c (%g, %g) r1 (%g, "
            "%g) r2 (%g, %g))",
            kind_name[kind], n, library, sampled, a.centre[0], a.centre[1],
            a.half_edge[0][0], a.half_edge[0][1], a.half_edge[1][0],
            a.half_edge[1][1], b.centre[0], b.centre[1], b.half_edge[0][0],
            b.half_edge[0][1], b.half_edge[1][0], b.half_edge[1][1]);
    REQUIRE(gm_interaction_overlap(2, &b, &a) == library,
            "%s pair %d: the overlap test is not symmetric", kind_name[kind],
            n);
    if (sampled)
      overlapping++;
    else
      disjoint++;
  }
  /* The band is a strip of width ~2 resolutions (1 % of a domain's edge)
   * around the touching configurations, so a few per cent of pairs at
   * most; more would mean the classification lost its meaning. */
  ck_assert_msg(band <= PAIRS_PER_KIND / 20,
                "%s: %d of %d pairs in the sampling band", kind_name[kind],
                band, PAIRS_PER_KIND);
  /* Both outcomes must be exercised (nested pairs mostly overlap). */
  ck_assert_msg(overlapping >= PAIRS_PER_KIND / 10 &&
                    (kind == KIND_NESTED || disjoint >= PAIRS_PER_KIND / 10),
                "%s: %d overlapping and %d disjoint pairs", kind_name[kind],
                overlapping, disjoint);
}
END_TEST

/* ---------------------------------------------------- exact 2D cases */

typedef struct exact_case {
  const char *name;
  gm_interaction_domain a, b;
  bool expected;
} exact_case;

/* Dyadic numbers throughout (products and sums exact in binary), so the
 * touching cases touch exactly. The rotated domain has half edges
 * (3, 4) / 8 and (-4, 3) / 16: a rectangle turned by atan(4/3). */
START_TEST(test_exact_cases_2d) {
  const exact_case cases[] = {
      {"shared edge", make_domain(0, 0, 1, 0, 0, 0.5),
       make_domain(2, 0, 1, 0, 0, 0.5), false},
      {"part of an edge shared", make_domain(0, 0, 1, 0, 0, 0.5),
       make_domain(1.5, 0.75, 0.5, 0, 0, 0.5), false},
      {"shared corner", make_domain(0, 0, 1, 0, 0, 0.5),
       make_domain(2, 1, 1, 0, 0, 0.5), false},
      {"overlap by a quarter", make_domain(0, 0, 1, 0, 0, 0.5),
       make_domain(1.75, 0, 1, 0, 0, 0.5), true},
      {"negative half edges", make_domain(0, 0, -1, 0, 0, -0.5),
       make_domain(2, 0, 1, 0, 0, 0.5), false},
      {"nested", make_domain(0, 0, 1, 0, 0, 0.5),
       make_domain(0.25, 0.125, 0.25, 0, 0, 0.125), true},
      {"nested against the edge", make_domain(0, 0, 1, 0, 0, 0.5),
       make_domain(0.75, 0, 0.25, 0, 0, 0.25), true},
      {"identical", make_domain(0.5, 0.5, 0.375, 0.5, -0.25, 0.1875),
       make_domain(0.5, 0.5, 0.375, 0.5, -0.25, 0.1875), true},
      {"rotated, shared long edge",
       make_domain(0, 0, 0.375, 0.5, -0.25, 0.1875),
       make_domain(-0.5, 0.375, 0.375, 0.5, -0.25, 0.1875), false},
      {"rotated, shared short edge",
       make_domain(0, 0, 0.375, 0.5, -0.25, 0.1875),
       make_domain(0.75, 1, 0.375, 0.5, -0.25, 0.1875), false},
      {"rotated, shared corner", make_domain(0, 0, 0.375, 0.5, -0.25, 0.1875),
       make_domain(0.25, 1.375, 0.375, 0.5, -0.25, 0.1875), false},
      {"rotated, slightly shifted in",
       make_domain(0, 0, 0.375, 0.5, -0.25, 0.1875),
       make_domain(0.7265625, 0.96875, 0.375, 0.5, -0.25, 0.1875), true},
      /* A diamond whose left corner touches the square's right edge. */
      {"corner on an edge", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(2, 0, 0.5, 0.5, -0.5, 0.5), false},
      {"corner through an edge", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(1.875, 0, 0.5, 0.5, -0.5, 0.5), true},
      /* Diamond beside the square's corner: the bounding boxes overlap but
       * the diamond's edge normal separates them (an axis-aligned test
       * would say true). */
      {"near a corner, bounding boxes overlap", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(1.75, 1.75, 0.5, 0.5, -0.5, 0.5), false},
      {"thin through a square", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(0, 0, 2, 0, 0, 0x1p-30), true},
      {"thin along an edge, outside", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(0, 1 + 0x1p-30, 2, 0, 0, 0x1p-30), false},
      /* Zero-area segments: a segment crossing the interior overlaps (its
       * relative interior meets the interior; every thin rectangle around
       * it overlaps too), one ending on the boundary does not. */
      {"segment across a square", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(0.5, 0.25, 1, 0.5, 0, 0), true},
      {"segment ending on an edge", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(1.5, 0, 0.5, 0, 0, 0), false},
      {"segment outside", make_domain(0, 0, 1, 0, 0, 1),
       make_domain(3, 3, 1, -0.5, 0, 0), false},
      {"crossing segments", make_domain(0, 0, 1, 0.25, 0, 0),
       make_domain(0.25, 0, -0.25, 1, 0, 0), true},
      {"segments in a T", make_domain(0, 0, 1, 0, 0, 0),
       make_domain(0, 1, 0, 1, 0, 0), false},
  };
  for (size_t n = 0; n < sizeof cases / sizeof cases[0]; n++) {
    const exact_case *c = &cases[n];
    ck_assert_msg(gm_interaction_overlap(2, &c->a, &c->b) == c->expected &&
                      gm_interaction_overlap(2, &c->b, &c->a) == c->expected,
                  "%s: expected overlap %d", c->name, c->expected);
  }
}
END_TEST

/* --------------------------------------------------------------- 1D */

static gm_interaction_domain segment_1d(double centre, double half) {
  return make_domain(centre, 0.0, half, 0.0, 0.0, 0.0);
}

/* Does a sample of `from` lie strictly inside `to` (1D)? */
static bool sample_hits_1d(const gm_interaction_domain *from,
                           const gm_interaction_domain *to) {
  for (int i = 0; i < SAMPLES_1D; i++) {
    double u = -1.0 + (2.0 * i + 1.0) / SAMPLES_1D;
    double x = from->centre[0] + u * from->half_edge[0][0];
    if (fabs(x - to->centre[0]) < fabs(to->half_edge[0][0]))
      return true;
  }
  return false;
}

START_TEST(test_segments_1d) {
  lcg_state = 77;
  int band = 0, overlapping = 0, disjoint = 0;
  for (int n = 0; n < 10 * PAIRS_PER_KIND; n++) {
    gm_interaction_domain a =
        segment_1d(lcg_between(-1, 1), random_sign() * lcg_between(0.01, 0.5));
    gm_interaction_domain b =
        segment_1d(lcg_between(-1, 1), random_sign() * lcg_between(0.01, 0.5));
    double ha = fabs(a.half_edge[0][0]), hb = fabs(b.half_edge[0][0]); /* m */
    /* Samples of a segment are 2 h / n apart, so a common part longer
     * than that holds a sample of the shorter segment; a gap means no
     * sample lands in the other segment. */
    double resolution = 2.0 * fmax(ha, hb) / SAMPLES_1D; /* m */
    double low = fmax(a.centre[0] - ha, b.centre[0] - hb);
    double high = fmin(a.centre[0] + ha, b.centre[0] + hb);
    if (fabs(high - low) <= resolution) {
      band++;
      continue;
    }
    bool sampled = sample_hits_1d(&a, &b) || sample_hits_1d(&b, &a);
    REQUIRE(sampled == (high > low),
            "1D pair %d: sampling disagrees with the interval ends", n);
    REQUIRE(gm_interaction_overlap(1, &a, &b) == sampled,
            "1D pair %d: library %d, sampling %d (a %g +- %g, b %g +- %g)", n,
            !sampled, sampled, a.centre[0], ha, b.centre[0], hb);
    if (sampled)
      overlapping++;
    else
      disjoint++;
  }
  /* The band is 2 resolutions (<= 1/500 of the longest half edge) wide
   * around touching: a fraction of a per cent of pairs. */
  ck_assert_int_le(band, PAIRS_PER_KIND / 10);
  ck_assert_int_ge(overlapping, PAIRS_PER_KIND);
  ck_assert_int_ge(disjoint, PAIRS_PER_KIND);
  /* Exact cases (dyadic): touching ends, nesting, negative half edges; the
   * y data must be ignored. */
  gm_interaction_domain unit = segment_1d(0, 1);
  gm_interaction_domain touching = segment_1d(2, -1);
  gm_interaction_domain touching_small = segment_1d(1.5, 0.5);
  gm_interaction_domain nested = segment_1d(0.75, 0.25);
  gm_interaction_domain identical = segment_1d(0, -1);
  gm_interaction_domain far_in_y = make_domain(0.5, 100, 0.25, 7, 3, 9);
  ck_assert(!gm_interaction_overlap(1, &unit, &touching));
  ck_assert(!gm_interaction_overlap(1, &touching_small, &unit));
  ck_assert(gm_interaction_overlap(1, &unit, &nested));
  ck_assert(gm_interaction_overlap(1, &nested, &unit));
  ck_assert(gm_interaction_overlap(1, &unit, &identical));
  ck_assert(gm_interaction_overlap(1, &unit, &far_in_y));
}
END_TEST

/* --------------------------------------------- gm_interaction_domain_of */

/* Half edges (m) of a point's current domain, from the definitions of
 * gm_shape (not from support.c): the initial rectangle for MPM and uGIMP,
 * stretched by |F_xx|, |F_yy| for cpGIMP, F r1, F r2 for CPDI. */
static void expected_half_edges(gm_shape shape, int dim,
                                const gm_point_domain *point, double r[2][2]) {
  const double *f = point->deformation; /* F_xx, F_xy, F_yx, F_yy */
  double lx = point->half_size[0], ly = dim > 1 ? point->half_size[1] : 0.0;
  r[0][0] = lx;
  r[0][1] = r[1][0] = 0.0;
  r[1][1] = ly;
  if (shape == GM_SHAPE_CPGIMP) {
    r[0][0] = fabs(f[0]) * lx;
    r[1][1] = fabs(f[3]) * ly;
  } else if (shape == GM_SHAPE_CPDI) {
    r[0][0] = f[0] * lx;
    r[0][1] = dim > 1 ? f[2] * lx : 0.0;
    r[1][0] = f[1] * ly;
    r[1][1] = f[3] * ly;
  }
}

/* A point at |x| <= 2 m with half sizes 0.05 .. 0.5 m and F = R [[a, g],
 * [0, b]] (a, b in [0.5, 2], shear g in [-0.5, 0.5], any rotation) with
 * |F_xx|, |F_yy| >= 0.25, so no edge of any variant is below 0.0125 m; in
 * 1D F_xx = a or -a and the rest junk the 1D code must ignore. */
static void random_point(int dim, gm_point_domain *point) {
  memset(point, 0, sizeof *point);
  double a, b, *f = point->deformation;
  do {
    a = lcg_between(0.5, 2.0);
    b = lcg_between(0.5, 2.0);
    double g = lcg_between(-0.5, 0.5), theta = lcg_between(-pi, pi);
    double c = cos(theta), s = sin(theta);
    f[0] = c * a;
    f[1] = c * g - s * b;
    f[2] = s * a;
    f[3] = s * g + c * b;
  } while (fabs(f[0]) < 0.25 || fabs(f[3]) < 0.25);
  if (dim == 1) {
    f[0] = random_sign() * a;
    f[1] = 3.0;
    f[2] = -5.0;
    f[3] = 0.0;
  }
  for (int k = 0; k < dim; k++) {
    point->position[k] = lcg_between(-2.0, 2.0);
    point->half_size[k] = lcg_between(0.05, 0.5);
  }
}

START_TEST(test_domain_of) {
  gm_shape shape = (gm_shape)(_i / 2);
  int dim = _i % 2 + 1;
  lcg_state = 500 + (uint64_t)_i;
  for (int n = 0; n < 2000; n++) {
    gm_point_domain point;
    random_point(dim, &point);
    double r[2][2];
    expected_half_edges(shape, dim, &point, r);
    double own = dim == 1 ? 2.0 * fabs(r[0][0]) : 4.0 * fabs(cross(r[0], r[1]));
    /* Every third case keeps the domain (measure <= 0). */
    double measure =
        n % 3 == 0 ? -(double)(n % 2) : own * lcg_between(0.2, 5.0);
    gm_interaction_domain out;
    gm_interaction_domain_of(shape, dim, &point, measure, &out);
    double scale =
        measure > 0.0 ? (dim == 1 ? measure / own : sqrt(measure / own)) : 1.0;
    /* The library takes the edges from corners position +- r1 +- r2: each
     * loses up to ~|x| eps (|x| <= 2.5 m) against edges >= 0.0125 m, i.e.
     * ~5e-14 relative; 1e-12 leaves a wide margin while any wrong rule
     * (edge, stretch, scaling) is off by far more. */
    double edge_scale = fmax(length(r[0]), length(r[1]));
    for (int e = 0; e < 2; e++)
      for (int k = 0; k < 2; k++)
        REQUIRE(fabs(out.half_edge[e][k] - scale * r[e][k]) <=
                    1e-12 * scale * edge_scale,
                "shape %d, %dD, case %d: half edge %d[%d] = %.17g, expected "
                "%.17g",
                (int)shape, dim, n, e, k, out.half_edge[e][k], scale * r[e][k]);
    for (int k = 0; k < 2; k++)
      REQUIRE(fabs(out.centre[k] - point.position[k]) <=
                  4.0 * DBL_EPSILON * fabs(point.position[k]),
              "shape %d, %dD, case %d: centre moved", (int)shape, dim, n);
    if (measure > 0.0) {
      /* The area of the scaled edges, from the library's own edges: only
       * a few roundings, so 1e-12 relative. */
      double area = dim == 1 ? 2.0 * fabs(out.half_edge[0][0]) : area_of(&out);
      REQUIRE(fabs(area - measure) <= 1e-12 * measure,
              "shape %d, %dD, case %d: measure %.17g, asked %.17g", (int)shape,
              dim, n, area, measure);
    }
  }
}
END_TEST

static Suite *interaction_suite(void) {
  Suite *suite = suite_create("interaction");
  TCase *sampling = tcase_create("sampling");
  tcase_set_timeout(sampling, 120);
  tcase_add_loop_test(sampling, test_overlap_against_sampling, 0, KIND_COUNT);
  tcase_add_test(sampling, test_segments_1d);
  suite_add_tcase(suite, sampling);
  TCase *exact = tcase_create("exact");
  tcase_add_test(exact, test_exact_cases_2d);
  /* _i: variant _i / 2 (GM_SHAPE_LINEAR .. GM_SHAPE_CPDI), _i % 2 + 1 D. */
  /* Every shape in 1D and 2D; a B-spline point's domain is its initial
   * rectangle, as uGIMP's (the default branch of expected_half_edges). */
  tcase_add_loop_test(exact, test_domain_of, 0, 12);
  suite_add_tcase(suite, exact);
  return suite;
}

int main(void) {
  SRunner *runner = srunner_create(interaction_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
