/*
 * test_components.c - public-API test of the parallel grids of the
 * granular family (000 sec 3.3-3.4, Tables A1-A3):
 *
 *  1. GM_FIELD_COMPONENT against connected components found here by
 *     breadth-first search over all pairs, on random clouds (sparse and
 *     clustered, 1D and 2D, every shape variant, a granular and a plain
 *     elastic material mixed), step after step while the points move and
 *     deform. The reference is built from the committed state before each
 *     step (components are computed at a step's start) with the rules of
 *     the library's contract, re-derived from the public fields:
 *      - candidate pairs share a grid node: their support node boxes
 *        (support.h: the point's cell for linear MPM, floor(s - l) ..
 *        floor(s + l) + 1 per axis for GIMP, the corners' cells for CPDI,
 *        s and l in cells from the ghost node 0) overlap;
 *      - a granular point's domain of interaction is its current domain
 *        (GM_FIELD_DOMAIN_CORNERS) scaled about its centre to the area
 *        A0 (m / V0) / rho_cr (length in 1D; 000 sec 3.3, Table A2 with
 *        V_cr = m / rho_cr); a plain point uses its own domain;
 *      - a pair of candidates interacts if those domains strictly overlap,
 *        decided here by clipping one polygon against the other
 *        (Sutherland-Hodgman) and testing the area of the intersection; two
 *        plain points always interact (plain MPM between them);
 *      - labels 0, 1, ... in order of each component's smallest id; a
 *        point alone in its component is GM_STATE_DISCONNECTED after the
 *        step.
 *     The summary's component_count must match too.
 *  2. The example of 000 Fig. 5 (sec 3.4): ten points on a linear-MPM grid
 *     whose grids are {1, 2, 3, 6, 7, 8}, {4, 5, 9} and {10}.
 *  3. A rain of 300 disconnected granular points onto a granular layer
 *     under gravity: bitwise identical fields, states and labels at every
 *     step with 1, 2 and 4 workers; more than 100 grids at the start and
 *     fewer at the end (the grids merged).
 *  4. The same rain in all three families: the total mass is bitwise
 *     constant; in the granular family the summary's state counts are
 *     those of GM_FIELD_STATE, outside it every point is quasi-static and
 *     there are no grids.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include "granular/granular.h"
#include "test_random.h"

#include <check.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const gm_shape all_shapes[4] = {GM_SHAPE_LINEAR, GM_SHAPE_UGIMP,
                                       GM_SHAPE_CPGIMP, GM_SHAPE_CPDI};

/* ------------------------------------------------ the committed state */

/* The public fields the rules need, in id order (ids 0 .. count - 1). */
typedef struct snapshot {
  size_t count;
  int dim;
  double *position;    /* m, count * dim */
  double *deformation; /* count * 9, row-major F */
  double *domain_size; /* m, count * dim */
  double *corners;     /* m, count * 2 (1D) or count * 8 (2D) */
  double *mass;        /* kg */
  double *initial_volume;
  double *material;
} snapshot;

/* A field in id order (ids must be 0 .. count - 1); the caller frees it.
 * Checks only fail loudly: a passing ck_assert costs a pipe write, and
 * this runs for every field at every step. */
static double *read_field(const gm_domain *domain, gm_field field,
                          size_t count) {
  size_t components = 0;
  gm_status status = gm_domain_field_components(domain, field, &components);
  REQUIRE(status == GM_OK && gm_domain_point_count(domain) == count,
          "field %d: %s", (int)field, gm_domain_last_error(domain));
  double *by_index = malloc(count * components * sizeof *by_index);
  double *out = malloc(count * components * sizeof *out);
  const int64_t *ids = NULL;
  REQUIRE(by_index && out, "out of memory");
  status = gm_domain_get_field(domain, field, by_index, count * components);
  if (status == GM_OK)
    status = gm_domain_view_ids(domain, &ids);
  REQUIRE(status == GM_OK, "field %d: %s", (int)field,
          gm_domain_last_error(domain));
  for (size_t i = 0; i < count; i++) {
    REQUIRE(ids[i] >= 0 && (size_t)ids[i] < count, "id %lld out of range",
            (long long)ids[i]);
    memcpy(out + (size_t)ids[i] * components, by_index + i * components,
           components * sizeof *out);
  }
  free(by_index);
  return out;
}

static snapshot take_snapshot(const gm_domain *domain, int dim) {
  snapshot s;
  s.count = gm_domain_point_count(domain);
  s.dim = dim;
  s.position = read_field(domain, GM_FIELD_POSITION, s.count);
  s.deformation = read_field(domain, GM_FIELD_DEFORMATION_GRADIENT, s.count);
  s.domain_size = read_field(domain, GM_FIELD_DOMAIN_SIZE, s.count);
  s.corners = read_field(domain, GM_FIELD_DOMAIN_CORNERS, s.count);
  s.mass = read_field(domain, GM_FIELD_MASS, s.count);
  s.initial_volume = read_field(domain, GM_FIELD_INITIAL_VOLUME, s.count);
  s.material = read_field(domain, GM_FIELD_MATERIAL, s.count);
  return s;
}

static void free_snapshot(snapshot *s) {
  free(s->position);
  free(s->deformation);
  free(s->domain_size);
  free(s->corners);
  free(s->mass);
  free(s->initial_volume);
  free(s->material);
}

/* ----------------------------------------------------- the grid rules */

/* The background grid: box lower corner (m), cell edge (m). */
typedef struct grid_frame {
  double origin[2];
  double cell;
} grid_frame;

/* floor(x) for the support rules; *fragile is set when x is within 1e-9
 * cells of an integer, where the rounding of the library's arithmetic
 * (not the rule) could decide the node. */
static int64_t node_floor(double x, bool *fragile) {
  double below = floor(x);
  if (x - below < 1e-9 || below + 1.0 - x < 1e-9)
    *fragile = true;
  return (int64_t)below;
}

/* Support node box of point p (support.h): node indices count from the
 * ghost node 0 one cell below the box; s, l in cells. */
static void support_box(gm_shape shape, const grid_frame *grid,
                        const snapshot *s, size_t p, int64_t low[2],
                        int64_t high[2], bool *fragile) {
  int dim = s->dim;
  low[1] = high[1] = 0;
  for (int k = 0; k < dim; k++) {
    double ghost_origin = grid->origin[k] - grid->cell; /* m, node 0 */
    double inverse = 1.0 / grid->cell;                  /* 1/m */
    if (shape == GM_SHAPE_CPDI) {
      double lowest = INFINITY, highest = -INFINITY; /* cells */
      for (int c = 0; c < (dim == 1 ? 2 : 4); c++) {
        double x = dim == 1 ? s->corners[p * 2 + (size_t)c]
                            : s->corners[p * 8 + (size_t)(2 * c + k)];
        lowest = fmin(lowest, (x - ghost_origin) * inverse);
        highest = fmax(highest, (x - ghost_origin) * inverse);
      }
      low[k] = node_floor(lowest, fragile);
      high[k] = node_floor(highest, fragile) + 1;
      continue;
    }
    double centre =
        (s->position[p * (size_t)dim + (size_t)k] - ghost_origin) * inverse;
    double half = 0.0; /* cells; linear MPM: the point's cell */
    if (shape != GM_SHAPE_LINEAR)
      half = 0.5 * s->domain_size[p * (size_t)dim + (size_t)k] * inverse;
    if (shape == GM_SHAPE_CPGIMP) /* F_xx or F_yy */
      half *= fabs(s->deformation[p * 9 + (size_t)(4 * k)]);
    if (half < 1e-6) { /* the tent (shape_gimp.h's limit) */
      low[k] = node_floor(centre, fragile);
      high[k] = low[k] + 1;
    } else {
      low[k] = node_floor(centre - half, fragile);
      high[k] = node_floor(centre + half, fragile) + 1;
    }
  }
}

/* The current domain's corners (m) from F, the initial edges and the
 * position, as gm_shape defines them, against GM_FIELD_DOMAIN_CORNERS:
 * both are position +- r1 +- r2, so they agree to a few ulps of the
 * coordinates (|x| < 3 m): 1e-13 m. */
static void check_corners(gm_shape shape, const snapshot *s, size_t p) {
  int dim = s->dim;
  const double *f = s->deformation + p * 9; /* row-major */
  double lx = 0.5 * s->domain_size[p * (size_t)dim];
  double ly = dim > 1 ? 0.5 * s->domain_size[p * 2 + 1] : 0.0;
  double r1[2] = {lx, 0.0}, r2[2] = {0.0, ly};
  if (shape == GM_SHAPE_CPGIMP) {
    r1[0] *= fabs(f[0]);
    r2[1] *= fabs(f[4]);
  } else if (shape == GM_SHAPE_CPDI) {
    r1[0] = f[0] * lx;
    r1[1] = dim > 1 ? f[3] * lx : 0.0;
    r2[0] = f[1] * ly;
    r2[1] = f[4] * ly;
  }
  static const double s1[4] = {-1.0, 1.0, 1.0, -1.0};
  static const double s2[4] = {-1.0, -1.0, 1.0, 1.0};
  for (int c = 0; c < (dim == 1 ? 2 : 4); c++) {
    for (int k = 0; k < dim; k++) {
      double expected = s->position[p * (size_t)dim + (size_t)k] +
                        s1[c] * r1[k] + s2[c] * r2[k];
      double actual = dim == 1 ? s->corners[p * 2 + (size_t)c]
                               : s->corners[p * 8 + (size_t)(2 * c + k)];
      REQUIRE(fabs(actual - expected) <= 1e-13,
              "%s: point %zu corner %d[%d] is %.17g m, expected %.17g m",
              test_shape_name(shape), p, c, k, actual, expected);
    }
  }
}

/* ---------------------------------------------- domains of interaction */

typedef struct reference_point {
  int64_t low[2], high[2]; /* support node box */
  double polygon[4][2];    /* m, domain of interaction (1D: ends in x) */
  double measure;          /* m^2 (m in 1D) */
} reference_point;

static double shoelace(const double (*polygon)[2], int count) {
  double twice = 0.0;
  for (int i = 0; i < count; i++) {
    const double *a = polygon[i], *b = polygon[(i + 1) % count];
    twice += a[0] * b[1] - a[1] * b[0];
  }
  return 0.5 * twice;
}

/* The domain of interaction of point p: its corners scaled about its
 * position to A0 (m / V0) / rho_cr if its material is granular. */
static void interaction_domain(const snapshot *s, size_t p,
                               const double critical_density[2],
                               reference_point *out) {
  int dim = s->dim, count = dim == 1 ? 2 : 4;
  const double *centre = s->position + p * (size_t)dim;
  double own; /* m^2 (m in 1D) */
  if (dim == 1) {
    out->polygon[0][0] = s->corners[p * 2];
    out->polygon[1][0] = s->corners[p * 2 + 1];
    own = fabs(out->polygon[1][0] - out->polygon[0][0]);
  } else {
    memcpy(out->polygon, s->corners + p * 8, sizeof out->polygon);
    own = fabs(shoelace((const double(*)[2])out->polygon, 4));
  }
  double rho_cr = critical_density[(int)s->material[p]]; /* kg/m^3 */
  out->measure = own;
  if (!(rho_cr > 0.0)) /* not granular: its own domain */
    return;
  double initial = s->domain_size[p * (size_t)dim] *
                   (dim > 1 ? s->domain_size[p * 2 + 1] : 1.0);
  out->measure = initial * s->mass[p] / s->initial_volume[p] / rho_cr;
  double factor = dim == 1 ? out->measure / own : sqrt(out->measure / own);
  for (int c = 0; c < count; c++)
    for (int k = 0; k < dim; k++)
      out->polygon[c][k] =
          centre[k] + factor * (out->polygon[c][k] - centre[k]);
}

/* Sutherland-Hodgman: clips `in` (count vertices) to the side of the line
 * through a, b where the signed area with orientation `sign` is positive. */
static int clip_by_edge(const double (*in)[2], int count, const double a[2],
                        const double b[2], double sign, double (*out)[2]) {
  int written = 0;
  for (int i = 0; i < count; i++) {
    const double *p = in[i], *q = in[(i + 1) % count];
    double dp =
        sign * ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]));
    double dq =
        sign * ((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]));
    if (dp > 0.0) {
      out[written][0] = p[0];
      out[written][1] = p[1];
      written++;
    }
    if ((dp > 0.0) != (dq > 0.0) && dp != dq) {
      double t = dp / (dp - dq);
      out[written][0] = p[0] + t * (q[0] - p[0]);
      out[written][1] = p[1] + t * (q[1] - p[1]);
      written++;
    }
  }
  return written;
}

/* Area (m^2) of the intersection of two convex quadrilaterals. */
static double intersection_area(const double (*a)[2], const double (*b)[2]) {
  double buffer[2][16][2];
  memcpy(buffer[0], a, 4 * sizeof a[0]);
  int count = 4, from = 0;
  double sign = shoelace(b, 4) > 0.0 ? 1.0 : -1.0;
  for (int e = 0; e < 4 && count > 0; e++) {
    count = clip_by_edge((const double(*)[2])buffer[from], count, b[e],
                         b[(e + 1) % 4], sign, buffer[from ^ 1]);
    from ^= 1;
  }
  return count < 3 ? 0.0
                   : fabs(shoelace((const double(*)[2])buffer[from], count));
}

/* Distance (m) from x to the segment a b. */
static double segment_distance(const double x[2], const double a[2],
                               const double b[2]) {
  double e[2] = {b[0] - a[0], b[1] - a[1]};
  double t = ((x[0] - a[0]) * e[0] + (x[1] - a[1]) * e[1]) /
             (e[0] * e[0] + e[1] * e[1]);
  t = fmin(1.0, fmax(0.0, t));
  return hypot(x[0] - a[0] - t * e[0], x[1] - a[1] - t * e[1]);
}

/* Distance (m) between the boundaries of two quadrilaterals (their
 * distance when disjoint). */
static double boundary_distance(const double (*a)[2], const double (*b)[2]) {
  double best = INFINITY;
  for (int i = 0; i < 4; i++)
    for (int e = 0; e < 4; e++) {
      best = fmin(best, segment_distance(a[i], b[e], b[(e + 1) % 4]));
      best = fmin(best, segment_distance(b[i], a[e], a[(e + 1) % 4]));
    }
  return best;
}

/* Strict overlap of two domains of interaction. *ambiguous is set when the
 * pair is within 1e-12 of the domains' size of touching: there rounding,
 * not the rule, decides (the library and this test compute the domains
 * with different roundings, of order 1e-15 relative). */
static bool domains_overlap(int dim, const reference_point *a,
                            const reference_point *b, bool *ambiguous) {
  if (dim == 1) {
    double low = fmax(fmin(a->polygon[0][0], a->polygon[1][0]),
                      fmin(b->polygon[0][0], b->polygon[1][0]));
    double high = fmin(fmax(a->polygon[0][0], a->polygon[1][0]),
                       fmax(b->polygon[0][0], b->polygon[1][0]));
    if (fabs(high - low) <= 1e-12 * fmax(a->measure, b->measure))
      *ambiguous = true;
    return high > low;
  }
  const double(*pa)[2] = (const double(*)[2])a->polygon;
  const double(*pb)[2] = (const double(*)[2])b->polygon;
  double area = intersection_area(pa, pb);
  double smaller = fmin(a->measure, b->measure);
  if (area > 1e-12 * smaller)
    return true;
  double size = sqrt(fmax(a->measure, b->measure)); /* m */
  if (area > 0.0 || boundary_distance(pa, pb) <= 1e-12 * size)
    *ambiguous = true;
  return false;
}

static bool boxes_share_node(int dim, const reference_point *a,
                             const reference_point *b) {
  for (int k = 0; k < dim; k++)
    if (a->low[k] > b->high[k] || b->low[k] > a->high[k])
      return false;
  return true;
}

/* ---------------------------------------------------- the partition */

typedef struct reference {
  size_t count, components, interactions;
  bool *interacts;        /* count x count */
  bool *shares;           /* count x count: the supports share a node */
  int32_t *label;         /* by id */
  size_t *component_size; /* by label */
} reference;

static void free_reference(reference *r) {
  free(r->interacts);
  free(r->shares);
  free(r->label);
  free(r->component_size);
}

/* Labels by breadth-first search from the smallest unlabelled id. */
static void label_components(reference *r) {
  size_t n = r->count;
  size_t *queue = malloc(n * sizeof *queue);
  ck_assert_ptr_nonnull(queue);
  for (size_t p = 0; p < n; p++)
    r->label[p] = -1;
  r->components = 0;
  for (size_t seed = 0; seed < n; seed++) {
    if (r->label[seed] >= 0)
      continue;
    int32_t label = (int32_t)r->components++;
    size_t head = 0, tail = 0;
    queue[tail++] = seed;
    r->label[seed] = label;
    while (head < tail) {
      size_t p = queue[head++];
      for (size_t q = 0; q < n; q++)
        if (r->label[q] < 0 && r->interacts[p * n + q]) {
          r->label[q] = label;
          queue[tail++] = q;
        }
    }
    r->component_size[label] = tail;
  }
  free(queue);
}

/* The partition the rules give for the committed state `s`. */
static reference build_reference(gm_shape shape, const grid_frame *grid,
                                 const snapshot *s,
                                 const double critical_density[2]) {
  size_t n = s->count;
  reference r;
  r.count = n;
  r.interactions = 0;
  r.interacts = calloc(n * n, sizeof *r.interacts);
  r.shares = calloc(n * n, sizeof *r.shares);
  r.label = malloc(n * sizeof *r.label);
  r.component_size = calloc(n, sizeof *r.component_size);
  reference_point *points = malloc(n * sizeof *points);
  ck_assert(r.interacts && r.shares && r.label && r.component_size && points);
  bool fragile = false;
  for (size_t p = 0; p < n; p++) {
    check_corners(shape, s, p);
    support_box(shape, grid, s, p, points[p].low, points[p].high, &fragile);
    interaction_domain(s, p, critical_density, &points[p]);
  }
  REQUIRE(!fragile,
          "%s: a support bound lies within 1e-9 cells of a node: "
          "the reference cannot decide it",
          test_shape_name(shape));
  size_t ambiguous_pairs = 0;
  for (size_t p = 0; p < n; p++) {
    for (size_t q = p + 1; q < n; q++) {
      if (!boxes_share_node(s->dim, &points[p], &points[q]))
        continue;
      r.shares[p * n + q] = r.shares[q * n + p] = true;
      bool plain_p = !(critical_density[(int)s->material[p]] > 0.0);
      bool plain_q = !(critical_density[(int)s->material[q]] > 0.0);
      bool ambiguous = false;
      bool interacts =
          (plain_p && plain_q) ||
          domains_overlap(s->dim, &points[p], &points[q], &ambiguous);
      if (ambiguous && !(plain_p && plain_q))
        ambiguous_pairs++;
      r.interacts[p * n + q] = r.interacts[q * n + p] = interacts;
      r.interactions += interacts;
    }
  }
  REQUIRE(ambiguous_pairs == 0,
          "%s: %zu pairs touch to within rounding: the reference cannot "
          "decide them",
          test_shape_name(shape), ambiguous_pairs);
  free(points);
  label_components(&r);
  return r;
}

/* Compares the step's labels, states and summary with the reference. */
static void check_against_reference(const gm_domain *domain, const reference *r,
                                    const char *what) {
  size_t n = r->count;
  double *label = read_field(domain, GM_FIELD_COMPONENT, n);
  double *state = read_field(domain, GM_FIELD_STATE, n);
  size_t state_count[3] = {0, 0, 0};
  for (size_t p = 0; p < n; p++) {
    REQUIRE(label[p] == (double)r->label[p],
            "%s: point id %zu is on grid %g, the reference says %d", what, p,
            label[p], r->label[p]);
    bool alone = r->component_size[r->label[p]] == 1;
    REQUIRE((state[p] == GM_STATE_DISCONNECTED) == alone,
            "%s: point id %zu has state %g but is %s in its component", what, p,
            state[p], alone ? "alone" : "not alone");
    REQUIRE(state[p] >= 0 && state[p] <= 2, "%s: state %g", what, state[p]);
    state_count[(int)state[p]]++;
  }
  /* White box: two components whose points share a node must be on
   * different node layers (parallel grids), or the grid would couple
   * them. Labels equal the reference's (checked above). */
  const int32_t *layer = domain->granular.component_layer;
  for (size_t p = 0; p < n; p++)
    for (size_t q = p + 1; q < n; q++)
      if (r->shares[p * n + q] && r->label[p] != r->label[q])
        REQUIRE(layer[r->label[p]] != layer[r->label[q]],
                "%s: points id %zu and %zu share a node, are on grids %d and "
                "%d, but both on node layer %d",
                what, p, q, r->label[p], r->label[q], layer[r->label[p]]);
  gm_granular_summary summary = gm_granular_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
  ck_assert_msg(summary.component_count == r->components,
                "%s: %zu grids, the reference has %zu", what,
                summary.component_count, r->components);
  for (int k = 0; k < 3; k++)
    ck_assert_uint_eq(summary.state_count[k], state_count[k]);
  free(label);
  free(state);
}

/* ------------------------------------------------ 1. random clouds */

/* 20 steps: past the library's periodic point reordering (every 16). */
enum { CLOUD_POINTS = 300, CLOUD_STEPS = 20 };

/* Materials: 0 elastic made granular (rho_cr 1000 kg/m^3), 1 plain
 * elastic. E = 1e4 Pa keeps the stable step large enough for the points
 * to deform visibly in a few steps. */
static const double cloud_critical_density[2] = {1000.0, 0.0}; /* kg/m^3 */

static gm_domain *cloud_domain(gm_shape shape, int dim,
                               const grid_frame *grid) {
  gm_domain_def def = gm_domain_def_default();
  def.geometry = dim == 1 ? GM_GEOMETRY_1D : GM_GEOMETRY_PLANE_STRAIN;
  def.family = GM_FAMILY_GRANULAR;
  def.scheme = GM_SCHEME_MUSL;
  def.shape = shape;
  def.cell_size = grid->cell;
  for (int k = 0; k < 2; k++) {
    def.origin[k] = grid->origin[k];
    def.extent[k] = 2.0; /* m */
  }
  gm_domain *domain = test_create_domain(&def);
  int granular = test_add_elastic(domain, 1e4, 0.3, 1000.0);
  test_add_elastic(domain, 1e4, 0.3, 1000.0);
  gm_granular_def critical = gm_granular_def_default();
  critical.critical_density = cloud_critical_density[0];
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, granular, &critical));
  return domain;
}

/* One point of `material` with its own domain size (m), volume (m^3) and
 * density (kg/m^3). */
static void add_sized_point(gm_domain *domain, int material,
                            const double *position, const double *velocity,
                            const double *size, double volume, double density) {
  gm_points_def points = gm_points_def_default();
  points.count = 1;
  points.material = material;
  points.position = position;
  points.velocity = velocity;
  points.volume = &volume;
  points.density = &density;
  points.domain_size = size;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
}

/* Adds CLOUD_POINTS points, one call each (ids 0, 1, ...), at random in
 * [0.3, 1.6] m from the box corner (sparse) or around 5 centres
 * (clustered, spread 0.06 m in 2D, 0.02 m in 1D), with domains of 0.4 to
 * 0.7 cells (2D; 0.04 to 0.1 cells in 1D, where points are denser),
 * densities 1000 to 2000 kg/m^3, from rho_cr up (the granular family
 * refuses granular points placed below rho_cr - TOL: their domains of
 * interaction would be smaller than the points, gm_granular(3)), so
 * domains of interaction are 1 to 1.41 times the domains in 2D (1 to 2 in
 * 1D), one in five plain, and velocities from a uniform velocity gradient
 * (shear and dilation, ~2 1/s) plus noise so that the connected points
 * deform (and the dilating ones meet density control). Measured over the
 * 16 variants: never fewer than 5 grids, and a grid of 9 or more points in
 * each, so the checks at the end of test_components_match_reference (2 and
 * 5) hold with a margin and still exercise the rules. */
static void add_cloud(gm_domain *domain, int dim, const grid_frame *grid,
                      bool clustered) {
  double centres[5][2];
  for (int c = 0; c < 5; c++)
    for (int k = 0; k < 2; k++)
      centres[c][k] = grid->origin[k] + lcg_between(0.5, 1.4);
  static const double gradient[2][2] = {{0.8, 2.0}, {-1.2, -0.5}}; /* 1/s */
  for (int i = 0; i < CLOUD_POINTS; i++) {
    double position[2], velocity[2], size[2];
    const double *centre = centres[i % 5];
    for (int k = 0; k < dim; k++) {
      if (clustered) { /* sum of 3 uniforms: a bell of the given spread */
        double spread = dim == 1 ? 0.02 : 0.06; /* m */
        double u = lcg_uniform() + lcg_uniform() + lcg_uniform() - 1.5;
        position[k] = centre[k] + 2.0 * spread * u;
      } else {
        position[k] = grid->origin[k] + lcg_between(0.3, 1.6);
      }
      size[k] = grid->cell *
                (dim == 1 ? lcg_between(0.04, 0.1) : lcg_between(0.4, 0.7));
    }
    for (int k = 0; k < dim; k++) {
      velocity[k] = lcg_between(-0.2, 0.2);
      for (int j = 0; j < dim; j++)
        velocity[k] += gradient[k][j] * (position[j] - grid->origin[j] - 1.0);
    }
    double volume = size[0] * (dim > 1 ? size[1] : 1.0);
    double density = lcg_between(1000.0, 2000.0); /* kg/m^3, >= rho_cr */
    add_sized_point(domain, lcg_uniform() < 0.2 ? 1 : 0, position, velocity,
                    size, volume, density);
  }
}

/* _i: variant all_shapes[_i / 4], (_i / 2) % 2 + 1 dimensions, clustered
 * if _i is odd. */
START_TEST(test_components_match_reference) {
  gm_shape shape = all_shapes[_i / 4];
  int dim = (_i / 2) % 2 + 1;
  bool clustered = _i % 2 == 1;
  lcg_state = 2026 + (uint64_t)_i;
  const grid_frame grid = {{-0.3, 0.2}, 0.05};
  gm_domain *domain = cloud_domain(shape, dim, &grid);
  add_cloud(domain, dim, &grid, clustered);
  size_t fewest = CLOUD_POINTS, largest = 0;
  for (int step = 0; step < CLOUD_STEPS; step++) {
    snapshot before = take_snapshot(domain, dim);
    reference r =
        build_reference(shape, &grid, &before, cloud_critical_density);
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    char what[96];
    snprintf(what, sizeof what, "%s %dD %s, step %d", test_shape_name(shape),
             dim, clustered ? "clustered" : "sparse", step + 1);
    check_against_reference(domain, &r, what);
    fewest = r.components < fewest ? r.components : fewest;
    for (size_t c = 0; c < r.components; c++)
      largest = r.component_size[c] > largest ? r.component_size[c] : largest;
    free_reference(&r);
    free_snapshot(&before);
  }
  /* The clouds must exercise the rules: several grids, and some with
   * many points (sparse clouds in 2D give mostly small grids). */
  ck_assert_uint_ge(fewest, 2);
  ck_assert_uint_ge(largest, 5);
  gm_domain_destroy(domain);
}
END_TEST

/* A connected granular block that dilates until it breaks up, linear 2D:
 * 12 x 12 points 0.5 cells apart, domains of 0.5 cells at 1.21 rho_cr, so
 * each domain of interaction is a square of 0.55 cells (0.5 sqrt(1.21))
 * that overlaps its neighbours' by 0.05 cells, under the 0.45 cells half
 * edge where an overlap alone decides a kept forest edge (components.c,
 * overlap_shares_node). A uniform dilation of 5 1/s (the soft E = 1e4 Pa
 * barely resists it) stretches the 0.5-cell spacing past 0.55 cells, so
 * the kept spanning tree's edges break: every step's grids must match the
 * brute-force reference, the first step one grid, and the last more than
 * one (the break-up is the point of the test). */
START_TEST(test_dilating_block_breaks_up) {
  const grid_frame grid = {{-0.3, 0.2}, 0.05};
  gm_domain *domain = cloud_domain(GM_SHAPE_LINEAR, 2, &grid);
  const double rate = 5.0;       /* 1/s */
  double centre[2] = {0.5, 0.8}; /* m, the block's middle */
  for (int i = 0; i < 12; i++)
    for (int j = 0; j < 12; j++) {
      double position[2] = {centre[0] + (i - 5.5) * 0.5 * grid.cell,
                            centre[1] + (j - 5.5) * 0.5 * grid.cell};
      double velocity[2] = {rate * (position[0] - centre[0]),
                            rate * (position[1] - centre[1])};
      double size[2] = {0.5 * grid.cell, 0.5 * grid.cell};
      double volume = size[0] * size[1];
      double density = 1.21 * cloud_critical_density[0]; /* kg/m^3 */
      add_sized_point(domain, 0 /* granular */, position, velocity, size,
                      volume, density);
    }
  size_t first = 0, last = 0;
  for (int step = 0; step < CLOUD_STEPS; step++) {
    snapshot before = take_snapshot(domain, 2);
    reference r = build_reference(GM_SHAPE_LINEAR, &grid, &before,
                                  cloud_critical_density);
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    char what[64];
    snprintf(what, sizeof what, "dilating block, step %d", step + 1);
    check_against_reference(domain, &r, what);
    first = step == 0 ? r.components : first;
    last = r.components;
    free_reference(&r);
    free_snapshot(&before);
  }
  ck_assert_uint_eq(first, 1);
  ck_assert_uint_ge(last, 2);
  gm_domain_destroy(domain);
}
END_TEST

/* --------------------------------------- 2. the example of Fig. 5 */

/*
 * 000 sec 3.4 describes ten points on an original-MPM grid: point 5 sends
 * data to nodes shared with 4, 6, 8 and 9 (not 7: "the pre-task utilizes
 * the original MPM"), and its domain of interaction meets those of 4 and
 * 9 only; point 6 interacts with 7 and 8; 1-2, 2-3 and 3-7 interact; 10 is
 * alone. Task 2 then finds the grids {1, 2, 3, 6, 7, 8}, {4, 5, 9}, {10}.
 *
 * Construction, in cells (h = 0.1 m): every point has a square domain of
 * 0.5 cells and density 2.56 rho_cr, so every domain of interaction is a
 * square of side 0.5 sqrt(2.56) = 0.8 cells, and two points interact iff
 * their centres are closer than 0.8 cells along both axes. On linear MPM
 * two points share a node iff their cells differ by at most one along
 * each axis. Point 5 sits in cell (5, 5); 4, 6, 8, 9 in neighbouring cells;
 * 7, 3, 2, 1 and 10 in cells two or more away. Gaps that must not
 * interact are >= 0.85 cells, gaps that must are <= 0.72 cells, and no
 * point, nor GIMP domain end (+- 0.25 cells), is within 0.03 cells of a
 * grid line, so no rounding decides anything. In uGIMP, cpGIMP and CPDI,
 * 5 and 7 also share nodes, as the paper says, but their domains of
 * interaction do not meet: the grids are the same for every variant.
 */
static const double fig5_cells[10][2] = {
    {8.9, 3.4},  /* 1 */ {8.2, 4.1}, /* 2 */ {7.5, 4.5},   /* 3 */
    {4.78, 5.5}, /* 4 */ {5.5, 5.5}, /* 5 */ {6.5, 5.5},   /* 6 */
    {7.2, 5.2},  /* 7 */ {6.6, 6.2}, /* 8 */ {5.65, 4.78}, /* 9 */
    {2.5, 8.5},                                            /* 10 */
};

START_TEST(test_fig5_grids) {
  gm_shape shape = all_shapes[_i];
  const grid_frame grid = {{0.0, 0.0}, 0.1};
  gm_domain_def def = gm_domain_def_default();
  def.family = GM_FAMILY_GRANULAR;
  def.shape = shape;
  def.cell_size = grid.cell;
  def.extent[0] = def.extent[1] = 1.2; /* m */
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 1e5, 0.3, 2560.0);
  gm_granular_def critical = gm_granular_def_default();
  critical.critical_density = 1000.0; /* kg/m^3 */
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &critical));
  double position[20], size[20], volume[10];
  for (int p = 0; p < 10; p++) {
    for (int k = 0; k < 2; k++) {
      position[2 * p + k] = fig5_cells[p][k] * grid.cell;
      size[2 * p + k] = 0.5 * grid.cell;
    }
    volume[p] = size[2 * p] * size[2 * p + 1];
  }
  gm_points_def points = gm_points_def_default();
  points.count = 10;
  points.material = material;
  points.position = position;
  points.volume = volume;
  points.domain_size = size;
  int64_t first = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, &first));
  ck_assert_int_eq(first, 0);
  /* The construction itself, through the rules of this file: point 5's
   * rows of the paper's connection and interaction arrays. */
  snapshot s = take_snapshot(domain, 2);
  const double critical_density[2] = {1000.0, 0.0}; /* material 0 only */
  reference r = build_reference(shape, &grid, &s, critical_density);
  int64_t low[2], high[2], other_low[2], other_high[2];
  bool fragile = false;
  support_box(shape, &grid, &s, 4, low, high, &fragile);
  for (int q = 0; q < 10; q++) {
    support_box(shape, &grid, &s, (size_t)q, other_low, other_high, &fragile);
    bool shares = other_low[0] <= high[0] && low[0] <= other_high[0] &&
                  other_low[1] <= high[1] && low[1] <= other_high[1];
    /* Paper numbers q + 1: 4, 5, 6, 8, 9, and 7 beyond linear MPM. */
    bool expected = q == 3 || q == 4 || q == 5 || q == 7 || q == 8 ||
                    (q == 6 && shape != GM_SHAPE_LINEAR);
    ck_assert_msg(shares == expected, "%s: point 5 and %d share a node: %d",
                  test_shape_name(shape), q + 1, shares);
  }
  ck_assert(r.interacts[4 * 10 + 3] && r.interacts[4 * 10 + 8]);
  ck_assert(!r.interacts[4 * 10 + 5] && !r.interacts[4 * 10 + 7]);
  ck_assert(r.interacts[5 * 10 + 6] && r.interacts[5 * 10 + 7]);
  ck_assert_uint_eq(r.interactions, 7);
  TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
  /* The three grids, labelled by their smallest paper number. */
  static const double expected_grid[10] = {0, 0, 0, 1, 1, 0, 0, 0, 1, 2};
  double *label = read_field(domain, GM_FIELD_COMPONENT, 10);
  double *state = read_field(domain, GM_FIELD_STATE, 10);
  for (int p = 0; p < 10; p++) {
    ck_assert_msg(label[p] == expected_grid[p],
                  "%s: point %d on grid %g, expected %g",
                  test_shape_name(shape), p + 1, label[p], expected_grid[p]);
    ck_assert_msg((state[p] == GM_STATE_DISCONNECTED) == (p == 9),
                  "%s: point %d state %g", test_shape_name(shape), p + 1,
                  state[p]);
  }
  gm_granular_summary summary = gm_granular_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
  ck_assert_uint_eq(summary.component_count, 3);
  check_against_reference(domain, &r, "Fig. 5");
  free(label);
  free(state);
  free_reference(&r);
  free_snapshot(&s);
  gm_domain_destroy(domain);
}
END_TEST

/* ------------------------------- touching domains of interaction */

/*
 * Strict overlap through the API: two points whose domains of interaction
 * touch exactly are on different grids; moved 2^-10 m closer, on one.
 * Dyadic numbers make the domains exact: edges 2^-4 m and volume 2^-8 m^2
 * (2D) or edge and volume 2^-5 m (1D), density 4 rho_cr, so the domain of
 * interaction is the domain scaled by sqrt(4) = 2 (by 4 in 1D, a length):
 * half edges 2^-4 m, touching at centre distance 1/8 m. The centres, at
 * 3.125 and 4.375 cells, are in neighbouring cells: they share nodes.
 */
START_TEST(test_touching_domains) {
  gm_shape shape = all_shapes[_i / 2];
  int dim = _i % 2 + 1;
  for (int closer = 0; closer < 2; closer++) {
    gm_domain_def def = gm_domain_def_default();
    def.geometry = dim == 1 ? GM_GEOMETRY_1D : GM_GEOMETRY_PLANE_STRAIN;
    def.family = GM_FAMILY_GRANULAR;
    def.shape = shape;
    def.cell_size = 0.1;
    gm_domain *domain = test_create_domain(&def);
    int material = test_add_elastic(domain, 1e5, 0.3, 4000.0);
    gm_granular_def critical = gm_granular_def_default();
    critical.critical_density = 1000.0; /* kg/m^3 */
    TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &critical));
    double second = 0.4375 - (closer ? 0x1p-10 : 0.0); /* m */
    /* 2D: the pair lies along x at y = 0.53125 m. */
    double position[4] = {0.3125, 0.53125, second, 0.53125};
    if (dim == 1)
      position[1] = second;
    double edge = dim == 1 ? 0x1p-5 : 0x1p-4; /* m */
    double size[4] = {edge, edge, edge, edge};
    double volume[2] = {dim == 1 ? edge : edge * edge,
                        dim == 1 ? edge : edge * edge};
    gm_points_def points = gm_points_def_default();
    points.count = 2;
    points.material = material;
    points.position = position;
    points.volume = volume;
    points.domain_size = size;
    TEST_ASSERT_OK(domain, gm_domain_add_points(domain, &points, NULL));
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-9));
    gm_granular_summary summary = gm_granular_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
    ck_assert_msg(summary.component_count == (closer ? 1u : 2u),
                  "%s %dD, %s: %zu grids", test_shape_name(shape), dim,
                  closer ? "overlapping" : "touching", summary.component_count);
    gm_domain_destroy(domain);
  }
}
END_TEST

/* ------------------------------------- 3 and 4. rain onto a layer */

enum { RAIN_STEPS = 300, RAIN_DROPS_X = 20, RAIN_DROPS_Y = 15 };

/* A closed box 2 m x 2.6 m of 0.05 m cells (fixed bottom, slip sides and
 * top), gravity 9.81 m/s^2, MUSL (USL's small-mass nodes invert points
 * when drops collide); a granular elastic material (E = 2e5 Pa,
 * rho = 1500 kg/m^3, rho_cr = 1400 kg/m^3); a layer 0.2 m deep, 2 x 2
 * points per cell, at rest; above it, from 0.5 m up, a 20 x 15 lattice of
 * single points (0.025 m domains, lattice spacing 0.095 m x 0.06 m,
 * jittered by up to 0.01 m, so no two domains of interaction (0.026 m)
 * meet) with random velocities up to 1 m/s per axis: 301 grids at the
 * start, merging as the drops hit each other and the layer (the highest
 * lands after ~0.5 s, 300 steps are ~0.45 s). */
static gm_domain *rain_domain(gm_family family, int workers) {
  gm_domain_def def = gm_domain_def_default();
  def.family = family;
  def.scheme = GM_SCHEME_MUSL;
  def.worker_count = workers;
  def.cell_size = 0.05;
  def.extent[0] = 2.0;
  def.extent[1] = 2.6;
  def.gravity[1] = -9.81;
  def.walls[GM_FACE_XMIN] = def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  def.walls[GM_FACE_YMAX] = GM_WALL_SLIP;
  gm_domain *domain = test_create_domain(&def);
  int material = test_add_elastic(domain, 2e5, 0.3, 1500.0);
  gm_granular_def critical = gm_granular_def_default();
  critical.critical_density = 1400.0;
  TEST_ASSERT_OK(domain, gm_domain_set_granular(domain, material, &critical));
  const double lower[3] = {0.0, 0.0, 0.0}, upper[3] = {2.0, 0.2, 0.0};
  test_fill_box(domain, material, lower, upper, 2, NULL);
  lcg_state = 31415;
  enum { DROPS = RAIN_DROPS_X * RAIN_DROPS_Y };
  double position[2 * DROPS], velocity[2 * DROPS], volume[DROPS];
  for (int j = 0; j < RAIN_DROPS_Y; j++)
    for (int i = 0; i < RAIN_DROPS_X; i++) {
      int p = j * RAIN_DROPS_X + i;
      position[2 * p] = 0.1 + 0.095 * i + lcg_between(-0.01, 0.01);
      position[2 * p + 1] = 0.5 + 0.06 * j + lcg_between(-0.01, 0.01);
      velocity[2 * p] = lcg_between(-1.0, 1.0);
      velocity[2 * p + 1] = lcg_between(-1.0, 1.0);
      volume[p] = 0.025 * 0.025;
    }
  test_add_points(domain, material, DROPS, position, velocity, volume);
  return domain;
}

/* FNV-1a over bytes, to compare whole states step by step. */
static uint64_t fnv1a(uint64_t hash, const void *data, size_t size) {
  const unsigned char *bytes = data;
  for (size_t i = 0; i < size; i++) {
    hash ^= bytes[i];
    hash *= 1099511628211ULL;
  }
  return hash;
}

/* Hash of every field that evolves (id order) and of the time. */
static uint64_t state_hash(const gm_domain *domain) {
  static const gm_field fields[] = {GM_FIELD_POSITION,
                                    GM_FIELD_VELOCITY,
                                    GM_FIELD_VOLUME,
                                    GM_FIELD_STRESS,
                                    GM_FIELD_DEFORMATION_GRADIENT,
                                    GM_FIELD_STATE,
                                    GM_FIELD_COMPONENT,
                                    GM_FIELD_MASS};
  size_t n = gm_domain_point_count(domain);
  uint64_t hash = 14695981039346656037ULL;
  for (size_t f = 0; f < sizeof fields / sizeof fields[0]; f++) {
    size_t components = 0;
    TEST_ASSERT_OK(domain,
                   gm_domain_field_components(domain, fields[f], &components));
    double *values = read_field(domain, fields[f], n);
    hash = fnv1a(hash, values, n * components * sizeof(double));
    free(values);
  }
  double time = 0.0;
  TEST_ASSERT_OK(domain, gm_domain_get_time(domain, &time, NULL));
  return fnv1a(hash, &time, sizeof time);
}

/* Labels are 0 .. count - 1 in order of first appearance by id, and a
 * point is disconnected iff alone on its grid. */
static void check_labels_and_states(const gm_domain *domain, size_t count) {
  size_t n = gm_domain_point_count(domain);
  double *label = read_field(domain, GM_FIELD_COMPONENT, n);
  double *state = read_field(domain, GM_FIELD_STATE, n);
  size_t *size = calloc(n, sizeof *size);
  ck_assert_ptr_nonnull(size);
  double next = 0.0;
  for (size_t p = 0; p < n; p++) {
    REQUIRE(label[p] >= 0.0 && label[p] <= next,
            "point id %zu: grid %g before grid %g was seen", p, label[p], next);
    if (label[p] == next)
      next += 1.0;
    size[(size_t)label[p]]++;
  }
  ck_assert_msg(next == (double)count, "%g labels, %zu grids", next, count);
  for (size_t p = 0; p < n; p++)
    REQUIRE((state[p] == GM_STATE_DISCONNECTED) ==
                (size[(size_t)label[p]] == 1),
            "point id %zu: state %g on a grid of %zu", p, state[p],
            size[(size_t)label[p]]);
  free(label);
  free(state);
  free(size);
}

/* Runs the rain; writes the state hash and grid count after every step. */
static void run_rain(gm_family family, int workers, uint64_t *hashes,
                     size_t *grids) {
  gm_domain *domain = rain_domain(family, workers);
  for (int step = 0; step < RAIN_STEPS; step++) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    gm_granular_summary summary = gm_granular_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
    grids[step] = summary.component_count;
    hashes[step] = state_hash(domain);
  }
  gm_domain_destroy(domain);
}

START_TEST(test_rain_is_deterministic) {
  static uint64_t hashes[3][RAIN_STEPS];
  static size_t grids[3][RAIN_STEPS];
  static const int workers[3] = {1, 2, 4};
  for (int w = 0; w < 3; w++)
    run_rain(GM_FAMILY_GRANULAR, workers[w], hashes[w], grids[w]);
  for (int w = 1; w < 3; w++)
    for (int step = 0; step < RAIN_STEPS; step++) {
      ck_assert_msg(grids[w][step] == grids[0][step],
                    "step %d: %zu grids with %d workers, %zu with 1", step + 1,
                    grids[w][step], workers[w], grids[0][step]);
      ck_assert_msg(hashes[w][step] == hashes[0][step],
                    "step %d: the state with %d workers differs from 1 worker",
                    step + 1, workers[w]);
    }
  /* 300 drops + the layer at the start; collisions and landings merge. */
  ck_assert_uint_eq(grids[0][0], RAIN_DROPS_X * RAIN_DROPS_Y + 1);
  ck_assert_uint_gt(grids[0][0], 100);
  ck_assert_uint_lt(grids[0][RAIN_STEPS - 1], grids[0][0] / 2);
}
END_TEST

/* Bitwise sum of GM_FIELD_MASS in id order. */
static double mass_sum(const gm_domain *domain) {
  size_t n = gm_domain_point_count(domain);
  double *mass = read_field(domain, GM_FIELD_MASS, n);
  double sum = 0.0; /* kg */
  for (size_t p = 0; p < n; p++)
    sum += mass[p];
  free(mass);
  return sum;
}

/* _i: the family. */
START_TEST(test_rain_conserves_mass) {
  gm_family family = (gm_family)_i;
  gm_domain *domain = rain_domain(family, 1);
  double initial_sum = mass_sum(domain);
  gm_summary totals = gm_summary_default();
  TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &totals));
  double initial_total = totals.mass;
  size_t count = gm_domain_point_count(domain);
  for (int step = 0; step < RAIN_STEPS; step++) {
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 0.0));
    ck_assert_uint_eq(gm_domain_point_count(domain), count);
    /* No step creates or destroys mass: the same numbers, summed in the
     * same order, give the same bits. */
    double sum = mass_sum(domain);
    TEST_ASSERT_OK(domain, gm_domain_get_summary(domain, &totals));
    REQUIRE(memcmp(&sum, &initial_sum, sizeof sum) == 0 &&
                memcmp(&totals.mass, &initial_total, sizeof sum) == 0,
            "family %d step %d: mass %.17g (summary %.17g), was %.17g",
            (int)family, step + 1, sum, totals.mass, initial_sum);
    double *state = read_field(domain, GM_FIELD_STATE, count);
    size_t state_count[3] = {0, 0, 0};
    for (size_t p = 0; p < count; p++) {
      REQUIRE(state[p] >= 0.0 && state[p] <= 2.0, "state %g", state[p]);
      state_count[(int)state[p]]++;
    }
    free(state);
    gm_granular_summary summary = gm_granular_summary_default();
    TEST_ASSERT_OK(domain, gm_domain_get_granular_summary(domain, &summary));
    if (family == GM_FAMILY_GRANULAR) {
      for (int k = 0; k < 3; k++)
        REQUIRE(summary.state_count[k] == state_count[k],
                "step %d: %zu points in state %d, the field has %zu", step + 1,
                summary.state_count[k], k, state_count[k]);
      check_labels_and_states(domain, summary.component_count);
    } else { /* header: no states or grids outside the granular family */
      REQUIRE(state_count[GM_STATE_QUASI_STATIC] == count &&
                  summary.component_count == 0,
              "family %d: states or grids outside the granular family",
              (int)family);
    }
  }
  gm_domain_destroy(domain);
}
END_TEST

/* The labels through the id map (no sort) equal the sorted ones: random
 * unions over 3000 elements whose ids are a shuffled subset of 0..3999
 * (the holes are removed points). Both must give every element the rank of
 * its set's smallest id, exactly. */
START_TEST(test_labels_by_id_match_sorted) {
  enum { ELEMENTS = 3000, IDS = 4000 };
  static uint32_t parent[ELEMENTS], size[ELEMENTS], index_of_id[IDS];
  static int64_t id[ELEMENTS];
  static uint32_t scratch_first[ELEMENTS], scratch_order[ELEMENTS];
  static int32_t sorted[ELEMENTS], by_id[ELEMENTS], scratch[ELEMENTS];
  lcg_state = 271828;
  int64_t pool[IDS];
  for (int k = 0; k < IDS; k++)
    pool[k] = k;
  for (int k = IDS - 1; k > 0; k--) { /* Fisher-Yates */
    int j = (int)(lcg_uniform() * (k + 1));
    int64_t swap = pool[k];
    pool[k] = pool[j];
    pool[j] = swap;
  }
  for (int k = 0; k < IDS; k++)
    index_of_id[k] = UINT32_MAX;
  for (uint32_t e = 0; e < ELEMENTS; e++) {
    id[e] = pool[e];
    index_of_id[pool[e]] = e;
  }
  gm_union_find_init(parent, size, ELEMENTS);
  for (int u = 0; u < ELEMENTS * 3 / 4; u++)
    gm_union_find_join(parent, size, (uint32_t)(lcg_uniform() * ELEMENTS),
                       (uint32_t)(lcg_uniform() * ELEMENTS));
  size_t sets = gm_union_find_labels(parent, id, ELEMENTS, sorted,
                                     scratch_first, scratch_order);
  size_t sets_by_id = gm_union_find_labels_by_id(
      parent, index_of_id, IDS, UINT32_MAX, ELEMENTS, by_id, scratch);
  ck_assert_uint_eq(sets, sets_by_id);
  ck_assert_uint_gt(sets, 100); /* many sets, so the order matters */
  for (int e = 0; e < ELEMENTS; e++)
    ck_assert_int_eq(sorted[e], by_id[e]);
}
END_TEST

static Suite *components_suite(void) {
  Suite *suite = suite_create("components");
  TCase *rules = tcase_create("rules");
  tcase_set_timeout(rules, 120);
  /* 4 variants x {1D, 2D} x {sparse, clustered}. */
  tcase_add_loop_test(rules, test_components_match_reference, 0, 16);
  tcase_add_test(rules, test_labels_by_id_match_sorted);
  tcase_add_test(rules, test_dilating_block_breaks_up);
  tcase_add_loop_test(rules, test_fig5_grids, 0, 4);
  /* _i: variant all_shapes[_i / 2] in _i % 2 + 1 dimensions. */
  tcase_add_loop_test(rules, test_touching_domains, 0, 8);
  suite_add_tcase(suite, rules);
  TCase *rain = tcase_create("rain");
  tcase_set_timeout(rain, 120);
  tcase_add_test(rain, test_rain_is_deterministic);
  tcase_add_loop_test(rain, test_rain_conserves_mass, GM_FAMILY_PLAIN,
                      GM_FAMILY_GRANULAR + 1);
  suite_add_tcase(suite, rain);
  return suite;
}

int main(void) {
  return test_run_suite(components_suite()) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
