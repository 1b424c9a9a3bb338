/*
 * test_interaction3d.c - white-box test of the 3D overlap test of domains
 * of interaction (lib/granular/interaction.c, gm_interaction_overlap3: the
 * separating-axis theorem with 15 candidate axes; issue 16 item 2):
 *
 *  - against an exact reference written here without separating axes: the
 *    interiors of a and b intersect iff the linear programme "maximise t
 *    with |u_i| + t <= 1 and |(M u + w)_j| + t <= 1" has t* > 0, where
 *    u are a's parametric coordinates and M u + w the same point in b's
 *    (M = Rb^-1 Ra, w = Rb^-1 (ca - cb)). Its optimum lies on a vertex of
 *    four active constraints, so it is found by enumerating all 495
 *    four-constraint systems. Pairs with |t*| below 1e-9 (touching within
 *    round-off) are the only ones not decided, and are counted;
 *  - random pairs of generic parallelepipeds, axis-aligned boxes, rotated
 *    boxes, thin ones (one edge 1e-3 of the others), one nested in the
 *    other, and a pair whose edges are parallel (the cross-product axes
 *    of those edges vanish);
 *  - the 2D test on extruded parallelograms: with r3 = (0, 0, h) for both
 *    and overlapping heights the 3D answer is the 2D one;
 *  - exact configurations with dyadic numbers: shared faces, edges and
 *    corners (false), nesting and identity (true), a pair separated only
 *    by an edge-edge axis, zero volume (false), and the scaling to a
 *    volume.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "granular/interaction.h"

#include "test_random.h"
#include "test_util.h"

#include <check.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>

static const double pi = 3.14159265358979323846; /* M_PI is not C11 */

enum { PAIRS_PER_KIND = 2000 };

/* ------------------------------------------------------ small algebra */

static double dot(const double u[3], const double v[3]) {
  return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

static void cross(const double u[3], const double v[3], double out[3]) {
  out[0] = u[1] * v[2] - u[2] * v[1];
  out[1] = u[2] * v[0] - u[0] * v[2];
  out[2] = u[0] * v[1] - u[1] * v[0];
}

/* Columns of R are d's half edges: x = c + R u. */
static double determinant(const gm_interaction_domain3 *d) {
  double n[3];
  cross(d->half_edge[1], d->half_edge[2], n);
  return dot(d->half_edge[0], n);
}

/* Row j of R^-1 for R with columns r0, r1, r2: (r_{j+1} x r_{j+2}) / det. */
static void inverse_rows(const gm_interaction_domain3 *d, double rows[3][3]) {
  double det = determinant(d);
  for (int j = 0; j < 3; j++) {
    cross(d->half_edge[(j + 1) % 3], d->half_edge[(j + 2) % 3], rows[j]);
    for (int k = 0; k < 3; k++)
      rows[j][k] /= det;
  }
}

/* Solves the 4 x 4 system A x = b by Gaussian elimination with partial
 * pivoting; false if A is (nearly) singular. */
static bool solve4(double a[4][5], double x[4]) {
  for (int col = 0; col < 4; col++) {
    int pivot = col;
    for (int r = col + 1; r < 4; r++)
      if (fabs(a[r][col]) > fabs(a[pivot][col]))
        pivot = r;
    if (fabs(a[pivot][col]) < 1e-12)
      return false;
    for (int k = 0; k < 5; k++) {
      double swap = a[col][k];
      a[col][k] = a[pivot][k];
      a[pivot][k] = swap;
    }
    for (int r = col + 1; r < 4; r++) {
      double factor = a[r][col] / a[col][col];
      for (int k = col; k < 5; k++)
        a[r][k] -= factor * a[col][k];
    }
  }
  for (int r = 3; r >= 0; r--) {
    double sum = a[r][4];
    for (int k = r + 1; k < 4; k++)
      sum -= a[r][k] * x[k];
    x[r] = sum / a[r][r];
  }
  return true;
}

/* ---------------------------------------------- the exact reference */

/* t* of the linear programme at the top of this file: > 0 iff the
 * interiors intersect, < 0 iff they are disjoint (and -inf if no vertex
 * was found, which the programme rules out for volumes > 0). Each
 * constraint is g . (u, t) <= h. */
static double reference_depth(const gm_interaction_domain3 *a,
                              const gm_interaction_domain3 *b) {
  double inverse[3][3];
  inverse_rows(b, inverse);
  double g[12][4], h[12];
  for (int i = 0; i < 3; i++)
    for (int s = 0; s < 2; s++) { /* +-u_i + t <= 1 */
      int c = 2 * i + s;
      for (int k = 0; k < 3; k++)
        g[c][k] = k == i ? (s ? -1.0 : 1.0) : 0.0;
      g[c][3] = 1.0;
      h[c] = 1.0;
    }
  double offset[3]; /* ca - cb, m */
  for (int k = 0; k < 3; k++)
    offset[k] = a->centre[k] - b->centre[k];
  for (int j = 0; j < 3; j++) {
    double m[3], w = dot(inverse[j], offset); /* row j of M and w_j */
    for (int k = 0; k < 3; k++) {
      double column[3] = {a->half_edge[k][0], a->half_edge[k][1],
                          a->half_edge[k][2]};
      m[k] = dot(inverse[j], column);
    }
    for (int s = 0; s < 2; s++) { /* +-(m . u + w) + t <= 1 */
      int c = 6 + 2 * j + s;
      double sign = s ? -1.0 : 1.0;
      for (int k = 0; k < 3; k++)
        g[c][k] = sign * m[k];
      g[c][3] = 1.0;
      h[c] = 1.0 - sign * w;
    }
  }
  double best = -INFINITY;
  int chosen[4];
  for (chosen[0] = 0; chosen[0] < 12; chosen[0]++)
    for (chosen[1] = chosen[0] + 1; chosen[1] < 12; chosen[1]++)
      for (chosen[2] = chosen[1] + 1; chosen[2] < 12; chosen[2]++)
        for (chosen[3] = chosen[2] + 1; chosen[3] < 12; chosen[3]++) {
          double system[4][5], x[4];
          for (int r = 0; r < 4; r++) {
            for (int k = 0; k < 4; k++)
              system[r][k] = g[chosen[r]][k];
            system[r][4] = h[chosen[r]];
          }
          if (!solve4(system, x))
            continue;
          bool feasible = true;
          for (int c = 0; c < 12 && feasible; c++) {
            double lhs = g[c][0] * x[0] + g[c][1] * x[1] + g[c][2] * x[2] +
                         g[c][3] * x[3];
            feasible = lhs <= h[c] + 1e-10;
          }
          if (feasible && x[3] > best)
            best = x[3];
        }
  return best;
}

/* ---------------------------------------------------- random domains */

static double random_sign(void) {
  return lcg_uniform() < 0.5 ? -1.0 : 1.0;
}

/* A unit vector uniform on the sphere. */
static void random_direction(double v[3]) {
  double z = lcg_between(-1.0, 1.0), phi = lcg_between(0.0, 2.0 * pi);
  double r = sqrt(1.0 - z * z);
  v[0] = r * cos(phi);
  v[1] = r * sin(phi);
  v[2] = z;
}

/* A random rotation: the columns of an orthonormal frame. */
static void random_frame(double frame[3][3]) {
  random_direction(frame[0]);
  double trial[3];
  do {
    random_direction(trial);
    cross(frame[0], trial, frame[1]);
  } while (sqrt(dot(frame[1], frame[1])) < 0.3);
  double norm = sqrt(dot(frame[1], frame[1]));
  for (int k = 0; k < 3; k++)
    frame[1][k] /= norm;
  cross(frame[0], frame[1], frame[2]);
}

typedef enum pair_kind {
  KIND_GENERIC,       /* parallelepipeds of similar size */
  KIND_BOXES,         /* axis-aligned boxes (MPM, uGIMP, cpGIMP) */
  KIND_ROTATED_BOXES, /* boxes in random orientations */
  KIND_THIN,          /* one edge of one domain 1e-3 of the others */
  KIND_NESTED,        /* a small one near the inside of a large one */
  KIND_PARALLEL,      /* b shares an edge direction with a */
  KIND_COUNT
} pair_kind;

static const char *const kind_name[KIND_COUNT] = {
    "generic", "boxes", "rotated boxes", "thin", "nested", "parallel edges"};

/* Edges of length 0.1 to 1 in random directions, not nearly coplanar. */
static void random_edges(gm_interaction_domain3 *d) {
  double n[3];
  do {
    for (int e = 0; e < 3; e++) {
      random_direction(d->half_edge[e]);
      double length = lcg_between(0.1, 1.0);
      for (int k = 0; k < 3; k++)
        d->half_edge[e][k] *= length;
    }
    cross(d->half_edge[1], d->half_edge[2], n);
  } while (fabs(dot(d->half_edge[0], n)) <
           0.2 * sqrt(dot(d->half_edge[0], d->half_edge[0]) *
                      dot(d->half_edge[1], d->half_edge[1]) *
                      dot(d->half_edge[2], d->half_edge[2])));
}

static void box_edges(gm_interaction_domain3 *d, double frame[3][3]) {
  for (int e = 0; e < 3; e++) {
    double length = random_sign() * lcg_between(0.1, 1.0);
    for (int k = 0; k < 3; k++)
      d->half_edge[e][k] = length * frame[e][k];
  }
}

static void random_pair(pair_kind kind, gm_interaction_domain3 *a,
                        gm_interaction_domain3 *b) {
  for (int k = 0; k < 3; k++) {
    a->centre[k] = lcg_between(-1.0, 1.0);
    b->centre[k] = a->centre[k] + lcg_between(-1.5, 1.5);
  }
  if (kind == KIND_BOXES || kind == KIND_ROTATED_BOXES) {
    double frame[2][3][3] = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                             {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    if (kind == KIND_ROTATED_BOXES) {
      random_frame(frame[0]);
      random_frame(frame[1]);
    }
    box_edges(a, frame[0]);
    box_edges(b, frame[1]);
    return;
  }
  random_edges(a);
  random_edges(b);
  if (kind == KIND_NESTED) { /* b's centre inside a, b 0.05..0.3 of a */
    double u[3] = {lcg_between(-0.7, 0.7), lcg_between(-0.7, 0.7),
                   lcg_between(-0.7, 0.7)};
    double scale = lcg_between(0.05, 0.3);
    for (int k = 0; k < 3; k++) {
      b->centre[k] = a->centre[k];
      for (int e = 0; e < 3; e++) {
        b->centre[k] += u[e] * a->half_edge[e][k];
        b->half_edge[e][k] *= scale;
      }
    }
  } else if (kind == KIND_THIN) {
    gm_interaction_domain3 *thin = lcg_uniform() < 0.5 ? a : b;
    for (int k = 0; k < 3; k++)
      thin->half_edge[2][k] *= 1e-3;
  } else if (kind == KIND_PARALLEL) {
    double scale = random_sign() * lcg_between(0.2, 2.0);
    for (int k = 0; k < 3; k++)
      b->half_edge[0][k] = scale * a->half_edge[1][k];
  }
}

START_TEST(test_overlap_against_reference) {
  pair_kind kind = (pair_kind)_i;
  lcg_state = 3000 + (uint64_t)kind;
  int undecided = 0, overlapping = 0, disjoint = 0;
  for (int n = 0; n < PAIRS_PER_KIND; n++) {
    gm_interaction_domain3 a, b;
    random_pair(kind, &a, &b);
    double depth = reference_depth(&a, &b);
    REQUIRE(isfinite(depth), "%s pair %d: no vertex", kind_name[kind], n);
    if (fabs(depth) < 1e-9) {
      undecided++;
      continue;
    }
    bool expected = depth > 0.0, library = gm_interaction_overlap3(&a, &b);
    REQUIRE(library == expected,
            "%s pair %d: gm_interaction_overlap3 says %d, the reference %d "
            "(depth %g)",
            kind_name[kind], n, library, expected, depth);
    REQUIRE(gm_interaction_overlap3(&b, &a) == library,
            "%s pair %d: the test is not symmetric", kind_name[kind], n);
    if (expected)
      overlapping++;
    else
      disjoint++;
  }
  /* Random real-valued pairs touch within 1e-9 with probability ~1e-9:
   * a count above one would mean the reference is not deciding. Both
   * answers must be well represented, or the kind tests nothing (nested
   * pairs always overlap). */
  ck_assert_int_le(undecided, 1);
  ck_assert_int_ge(overlapping, PAIRS_PER_KIND / 10);
  if (kind != KIND_NESTED)
    ck_assert_int_ge(disjoint, PAIRS_PER_KIND / 10);
}
END_TEST

/* -------------------------------------------- extruded parallelograms */

/* A 2D parallelogram with edges at 17..163 degrees, and its extrusion. */
START_TEST(test_extrusion_matches_2d) {
  lcg_state = 4242;
  for (int n = 0; n < 20000; n++) {
    gm_interaction_domain flat[2];
    gm_interaction_domain3 solid[2];
    for (int d = 0; d < 2; d++) {
      double theta = lcg_between(0.0, 2.0 * pi);
      double turn = theta + random_sign() * lcg_between(0.3, pi - 0.3);
      double l1 = lcg_between(0.1, 1.0), l2 = lcg_between(0.1, 1.0);
      flat[d].centre[0] = lcg_between(-1.0, 1.0);
      flat[d].centre[1] = lcg_between(-1.0, 1.0);
      flat[d].half_edge[0][0] = l1 * cos(theta);
      flat[d].half_edge[0][1] = l1 * sin(theta);
      flat[d].half_edge[1][0] = l2 * cos(turn);
      flat[d].half_edge[1][1] = l2 * sin(turn);
      double height = lcg_between(0.1, 1.0);
      for (int k = 0; k < 2; k++) {
        solid[d].centre[k] = flat[d].centre[k];
        for (int e = 0; e < 2; e++)
          solid[d].half_edge[e][k] = flat[d].half_edge[e][k];
        solid[d].half_edge[2][k] = 0.0;
      }
      solid[d].half_edge[0][2] = solid[d].half_edge[1][2] = 0.0;
      solid[d].half_edge[2][2] = height;
      solid[d].centre[2] = 0.0;
    }
    /* b's centre height: within the heights' overlap (the 2D answer), or
     * beyond their sum (disjoint whatever the 2D answer). */
    double sum = solid[0].half_edge[2][2] + solid[1].half_edge[2][2];
    bool stacked = lcg_uniform() < 0.25;
    solid[1].centre[2] =
        random_sign() *
        (stacked ? lcg_between(1.0, 1.5) * sum : lcg_between(0.0, 0.999) * sum);
    bool expected = !stacked && gm_interaction_overlap(2, &flat[0], &flat[1]);
    REQUIRE(gm_interaction_overlap3(&solid[0], &solid[1]) == expected,
            "extruded pair %d: 3D says %d, 2D %d (stacked %d)", n, !expected,
            expected, stacked);
  }
}
END_TEST

/* ------------------------------------------------ exact configurations */

static gm_interaction_domain3 cube(double x, double y, double z, double h) {
  gm_interaction_domain3 d = {{x, y, z}, {{h, 0, 0}, {0, h, 0}, {0, 0, h}}};
  return d;
}

START_TEST(test_exact_configurations) {
  gm_interaction_domain3 unit = cube(0, 0, 0, 0.5);
  /* Shared face, edge and corner of unit cubes: touching, not overlapping. */
  gm_interaction_domain3 face = cube(1, 0, 0, 0.5);
  gm_interaction_domain3 edge = cube(1, 1, 0, 0.5);
  gm_interaction_domain3 corner = cube(1, 1, 1, 0.5);
  ck_assert(!gm_interaction_overlap3(&unit, &face));
  ck_assert(!gm_interaction_overlap3(&unit, &edge));
  ck_assert(!gm_interaction_overlap3(&unit, &corner));
  /* A sliver of overlap (2^-20 m) is an overlap. */
  gm_interaction_domain3 sliver = cube(1.0 - 0x1p-20, 0, 0, 0.5);
  ck_assert(gm_interaction_overlap3(&unit, &sliver));
  /* Identity and nesting, either way round. */
  gm_interaction_domain3 inner = cube(0.125, -0.125, 0.25, 0.125);
  ck_assert(gm_interaction_overlap3(&unit, &unit));
  ck_assert(gm_interaction_overlap3(&unit, &inner));
  ck_assert(gm_interaction_overlap3(&inner, &unit));
  /* Two square sticks turned 45 degrees about their long axes, crossing
   * at right angles, ridge on ridge: A along x with its top ridge at
   * z = 1, B along y with its bottom ridge at z = c - 1. No face normal
   * separates them (on A's (0, 1, 1), say, the radii are 1 and 5 against
   * a distance c); only the cross product of the long edges, z, does,
   * when c >= 2. */
  gm_interaction_domain3 ridge_x = {{0, 0, 0},
                                    {{4, 0, 0}, {0, 0.5, 0.5}, {0, -0.5, 0.5}}};
  gm_interaction_domain3 ridge_y = {{0, 0, 2.25},
                                    {{0, 4, 0}, {0.5, 0, 0.5}, {-0.5, 0, 0.5}}};
  ck_assert(!gm_interaction_overlap3(&ridge_x, &ridge_y));
  ridge_y.centre[2] = 2.0; /* ridges touch */
  ck_assert(!gm_interaction_overlap3(&ridge_x, &ridge_y));
  ridge_y.centre[2] = 1.75; /* ridges cross */
  ck_assert(gm_interaction_overlap3(&ridge_x, &ridge_y));
  ck_assert(gm_interaction_overlap3(&ridge_y, &ridge_x));
  /* A flat domain (zero volume) has no interior. */
  gm_interaction_domain3 flat = unit;
  flat.half_edge[2][2] = 0.0;
  ck_assert(!gm_interaction_overlap3(&unit, &flat));
  ck_assert(!gm_interaction_overlap3(&flat, &unit));
}
END_TEST

START_TEST(test_scale_to_volume) {
  gm_interaction_domain3 d = {{1, 2, 3}, {{1, 0, 0}, {0.5, 2, 0}, {0, 0, 1}}};
  gm_interaction_scale3(&d, 2.0); /* from 8 * 2 = 16 m^3 to 2: halves edges */
  ck_assert_double_eq_tol(d.half_edge[0][0], 0.5, 1e-15);
  ck_assert_double_eq_tol(d.half_edge[1][0], 0.25, 1e-15);
  ck_assert_double_eq_tol(d.half_edge[1][1], 1.0, 1e-15);
  ck_assert_double_eq_tol(d.half_edge[2][2], 0.5, 1e-15);
  ck_assert_double_eq(d.centre[2], 3.0);
  gm_interaction_domain3 kept = d;
  gm_interaction_scale3(&d, 0.0); /* no volume asked: unchanged */
  ck_assert_double_eq(d.half_edge[1][1], kept.half_edge[1][1]);
}
END_TEST

static Suite *interaction3d_suite(void) {
  Suite *s = suite_create("interaction3d");
  TCase *random = tcase_create("random pairs");
  tcase_set_timeout(random, 120);
  tcase_add_loop_test(random, test_overlap_against_reference, 0, KIND_COUNT);
  tcase_add_test(random, test_extrusion_matches_2d);
  suite_add_tcase(s, random);
  TCase *exact = tcase_create("exact configurations");
  tcase_add_test(exact, test_exact_configurations);
  tcase_add_test(exact, test_scale_to_volume);
  suite_add_tcase(s, exact);
  return s;
}

int main(void) {
  return test_run_suite(interaction3d_suite()) == 0 ? EXIT_SUCCESS
                                                    : EXIT_FAILURE;
}
