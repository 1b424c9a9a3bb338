/*
 * mohr_coulomb.c - built-in Mohr-Coulomb material with the Bagnold rate term
 * (000 sec 2.2 and 4.2, eqs 16-17): elastic predictor, then a return mapping
 * in principal stresses (the method of de Souza Neto, Peric & Owen,
 * "Computational methods for plasticity", sec 8.2, for perfect plasticity).
 *
 * Principal stresses are sorted sigma_1 >= sigma_2 >= sigma_3, tension
 * positive. Eq 16, written for tension positive (the paper's sigma_1 is the
 * most compressive stress, compression positive), is linear in them:
 *   f = n . sigma - 2 c cos(phi),  n = (1 + sin phi, 0, -(1 - sin phi)),
 * with the rate-dependent cohesion c = eta gammadot^2 (Pa). The potential
 * eq 17 has the flow direction b = (1 + sin psi, 0, -(1 - sin psi)). A
 * return along the elastic image D b of the flow direction is exact in one
 * step because f is linear and the model is perfectly plastic:
 *   main plane  sigma = sigma_tr - dl D b,  dl = f(sigma_tr) / (n . D b);
 *   edges       when that breaks the ordering: sigma_1 = sigma_2 (triaxial
 *               compression edge) or sigma_2 = sigma_3 (triaxial extension
 *               edge), two planes active, a 2x2 solve for dl_a, dl_b >= 0;
 *   apex        when no edge return is admissible (tension beyond the apex):
 *               hydrostatic stress c cot(phi), the tension cut-off. A trial
 *               whose edge points both come out unordered by far more than
 *               the edge returns' rounding goes there without them
 *               (apex_certain: two dot products, the same bits).
 * The returned principal values go back along the trial eigenvectors, so
 * the principal directions are those of the trial stress.
 *
 * Cost: the elastic predictor runs as one vectorised loop per chunk of
 * points, then a vectorised screen (screen_chunk) takes each plane point's
 * yield value from its Mohr circle and lists the points that are not
 * clearly elastic; the corrector visits only those, so an elastic point
 * costs no scalar work and no unpredictable branch. 1D, plane-strain and
 * axisymmetric points (yz = zx = 0) take a closed form (return_planar: a
 * Mohr circle, no eigen-solver, no eigenvectors). General 3D stresses
 * (any of yz, zx non-zero) are first decided from their principal values
 * alone (gm_principal_estimate, from the characteristic cubic);
 * only points outside or within the estimate's error of the surface take
 * the full closed-form decomposition of principal.c, whose eigenvectors
 * carry the return back to the stress components. Every step of the return
 * (predictor, principal values, planes, recomposition) is frame
 * indifferent, so the update of a rotated state is the rotated update
 * (tests/unit/test_materials_3d.c). The domain's plane chunks without the
 * rate term do not call gm_mohr_coulomb_update: grid/deform_mohr_coulomb.c
 * writes the rotated trial stress and calls gm_mohr_coulomb_plane_returns,
 * the same screen and plane return on those rows (the same bits), with
 * the planes prepared once per worker and the screen's circle and yield
 * value handed to the return.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "materials/materials.h"

#include "materials/invariants.h"
#include "materials/principal.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

/* Constants of one update call. */
typedef struct mc_constants {
  double shear;                /* G, Pa */
  double inverse_double_shear; /* 1 / (2 G), 1/Pa */
  double lame;                 /* lambda, Pa */
  double sin_friction;         /* sin(phi) */
  double cos_friction;         /* cos(phi) */
  double sin_dilation;         /* sin(psi) */
  double yield_offset;         /* 2 c cos(phi), Pa, this point's rate term */
} mc_constants;

/* One yield plane over the sorted principal stresses: f = normal . sigma -
 * yield_offset, flow direction `flow` (eq 17), its elastic image D flow. */
typedef struct mc_plane {
  double normal[3];       /* - */
  double elastic_flow[3]; /* Pa per unit plastic multiplier */
} mc_plane;

/* An edge where the main plane a meets a second plane b, with the 2x2
 * system of the two-plane return: coupling[i][j] = normal_i . D flow_j
 * (Pa; i, j: 0 = a, 1 = b) and its determinant (Pa^2). */
typedef struct mc_edge {
  mc_plane plane; /* b */
  double coupling[2][2];
  double determinant;
  /* The edge return's ordering test as an affine function of the trial
   * (see apex_certain): D(t) = order_trial . t + order_offset y (Pa), in
   * exact arithmetic on the stored constants above; the edge point is
   * ordered iff D >= 0. */
  double order_trial[3]; /* - */
  double order_offset;   /* - */
  /* Bounds of the rounding of D (edge return and the test itself): sums of
   * the absolute values of every term, per unit of max |t_i| and of y. */
  double order_size_trial, order_size_offset; /* - */
  bool order_bounded; /* the constants lie in the test's range */
} mc_edge;

/* The planes of one update call, built once per batch: the main plane
 * (0, 2) and the edges with the plane (1, 2) (compression) and (0, 1)
 * (extension), see return_to_edge. */
typedef struct mc_planes {
  mc_plane main;
  double main_compliance; /* 1 / (normal . D flow) of the main plane, 1/Pa */
  mc_edge compression, extension;
  /* Largest |entry| of each plane's D flow (Pa), for the edge returns'
   * round-off test: main, compression edge's plane, extension edge's. */
  double main_flow_size, compression_flow_size, extension_flow_size;
  /* apex_certain's margin per unit max |t_i| and per unit y (-), and
   * whether it may be used (both edges bounded). */
  double apex_margin_trial, apex_margin_offset;
  bool apex_test;
} mc_planes;

/* The plane on which principal stress `major` plays sigma_1 and `minor`
 * plays sigma_3 (main plane: 0, 2). */
static mc_plane make_plane(const mc_constants *k, int major, int minor) {
  mc_plane plane;
  double flow[3] = {0.0, 0.0, 0.0};
  memset(plane.normal, 0, sizeof plane.normal);
  plane.normal[major] = 1.0 + k->sin_friction;
  plane.normal[minor] = -(1.0 - k->sin_friction);
  flow[major] = 1.0 + k->sin_dilation;
  flow[minor] = -(1.0 - k->sin_dilation);
  /* Isotropic elasticity in principal space: D b = 2 G b + lambda tr(b) 1. */
  double trace = flow[0] + flow[1] + flow[2];
  for (int i = 0; i < 3; i++)
    plane.elastic_flow[i] = 2.0 * k->shear * flow[i] + k->lame * trace;
  return plane;
}

static double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Largest |entry| of finite a[3]: fmax's value (of finite numbers, the
 * larger), with plain comparisons instead of libm calls. */
static double max_abs3(const double a[3]) {
  double x = fabs(a[0]), y = fabs(a[1]), z = fabs(a[2]);
  double yz = y > z ? y : z;
  return x > yz ? x : yz;
}

static double sum_abs3(const double a[3]) {
  return fabs(a[0]) + fabs(a[1]) + fabs(a[2]);
}

/* x is 0 or of a magnitude in [2^-200, 2^200]. */
static bool in_test_range(double x) {
  double size = fabs(x);
  return size == 0.0 || (size >= 0x1p-200 && size <= 0x1p200);
}

/* The edge return's ordering test D = order_trial . t + order_offset y as
 * an affine function of the trial t and the yield offset y, and bounds of
 * its rounding (apex_certain). With the edge pair's weights w (compression:
 * the edge value (o_0 + o_1)/2 against o_2, w = (1/2, 1/2, -1); extension:
 * o_0 against (o_1 + o_2)/2, w = (1, -1/2, -1/2)), the returned point o = t
 * - l_a D b_a - l_b D b_b with [l_a, l_b] the 2x2 solve of [f_a, f_b],
 * f = n . t - y:
 *   D = w . o = w . t - c_a f_a - c_b f_b,
 *   c_a = (bb p_a - ba p_b) / det,  c_b = (aa p_b - ab p_a) / det,
 * p = w . D b. */
static void make_order_test(const mc_plane *a, mc_edge *edge,
                            bool compression) {
  const double w[3] = {compression ? 0.5 : 1.0, compression ? 0.5 : -0.5,
                       compression ? -1.0 : -0.5};
  const mc_plane *b = &edge->plane;
  double aa = edge->coupling[0][0], ab = edge->coupling[0][1];
  double ba = edge->coupling[1][0], bb = edge->coupling[1][1];
  double det = edge->determinant;
  double pa = dot3(w, a->elastic_flow), pb = dot3(w, b->elastic_flow);
  double ca = (bb * pa - ba * pb) / det, cb = (aa * pb - ab * pa) / det;
  for (int i = 0; i < 3; i++)
    edge->order_trial[i] = w[i] - ca * a->normal[i] - cb * b->normal[i];
  edge->order_offset = ca + cb;
  /* |D| evaluated with the absolute value of every term bounds what the
   * rounding of each operation can add: per unit max |t_i|, |w|_1 (1 +
   * 2 E cond N) with E the largest |D b_i|, cond = (|aa| + |ab| + |ba| +
   * |bb|) / det, N = |n_a|_1 + |n_b|_1; per unit y, 4 E cond. The
   * coefficients' own rounding is bounded by the same sums. */
  double flow = max_abs3(a->elastic_flow) > max_abs3(b->elastic_flow)
                    ? max_abs3(a->elastic_flow)
                    : max_abs3(b->elastic_flow);
  double cond = (fabs(aa) + fabs(ab) + fabs(ba) + fabs(bb)) / det;
  double normals = sum_abs3(a->normal) + sum_abs3(b->normal);
  edge->order_size_trial =
      2.0 + 4.0 * flow * cond * normals + sum_abs3(edge->order_trial);
  edge->order_size_offset = 4.0 * flow * cond + fabs(edge->order_offset);
  /* The bounds are relative ones: every constant 0 or within 2^+-200 (no
   * product of them and a trial in 2^+-300 overflows, nor underflows by
   * more than the margin allows), det > 0. */
  bool bounded = det > 0.0 && in_test_range(det);
  for (int i = 0; i < 3; i++)
    bounded =
        bounded && in_test_range(a->normal[i]) && in_test_range(b->normal[i]) &&
        in_test_range(a->elastic_flow[i]) && in_test_range(b->elastic_flow[i]);
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      bounded = bounded && in_test_range(edge->coupling[i][j]);
  edge->order_bounded = bounded && isfinite(edge->order_size_trial) &&
                        isfinite(edge->order_size_offset);
}

static mc_edge make_edge(const mc_plane *a, mc_plane b, bool compression) {
  mc_edge edge;
  edge.plane = b;
  edge.coupling[0][0] = dot3(a->normal, a->elastic_flow);
  edge.coupling[0][1] = dot3(a->normal, b.elastic_flow);
  edge.coupling[1][0] = dot3(b.normal, a->elastic_flow);
  edge.coupling[1][1] = dot3(b.normal, b.elastic_flow);
  edge.determinant = edge.coupling[0][0] * edge.coupling[1][1] -
                     edge.coupling[0][1] * edge.coupling[1][0];
  make_order_test(a, &edge, compression);
  return edge;
}

static double plane_value(const mc_plane *plane, const mc_constants *k,
                          const double sigma[3]) {
  return dot3(plane->normal, sigma) - k->yield_offset;
}

/* Return to the main plane, whose yield value at the trial is main_value
 * (plane_value's, Pa); false if the result breaks the ordering. */
static bool return_to_main_plane(const mc_planes *planes, const double trial[3],
                                 double main_value, double out[3]) {
  const mc_plane *main = &planes->main;
  double multiplier = main_value * planes->main_compliance;
  for (int i = 0; i < 3; i++)
    out[i] = trial[i] - multiplier * main->elastic_flow[i];
  return out[0] >= out[1] && out[1] >= out[2];
}

/* Return to the edge where the main plane meets a second plane: with
 * `compression` the plane (1, 2), the triaxial compression edge sigma_1 =
 * sigma_2, otherwise the plane (0, 1), the triaxial extension edge sigma_2 =
 * sigma_3. False
 * unless both plastic multipliers are >= 0 and the edge point is ordered
 * (not past the apex). */
static GM_ALWAYS_INLINE bool return_to_edge(const mc_constants *k,
                                            const mc_planes *planes,
                                            const double trial[3],
                                            bool compression, double out[3]) {
  const mc_edge *edge_system =
      compression ? &planes->compression : &planes->extension;
  double b_flow_size =
      compression ? planes->compression_flow_size : planes->extension_flow_size;
  const mc_plane *a = &planes->main, *b = &edge_system->plane;
  double aa = edge_system->coupling[0][0], ab = edge_system->coupling[0][1];
  double ba = edge_system->coupling[1][0], bb = edge_system->coupling[1][1];
  double fa = plane_value(a, k, trial), fb = plane_value(b, k, trial);
  double determinant = edge_system->determinant;
  if (!(determinant > 0.0))
    return false;
  double multiplier_a = (fa * bb - ab * fb) / determinant;
  double multiplier_b = (aa * fb - ba * fa) / determinant;
  /* A multiplier negative only by round-off (its stress change below the
   * rounding of the trial's largest principal value) is zero: the
   * main-plane return then lands on the edge itself, to the last bit on
   * either side, and rejecting the edge sent such a point to the apex (a
   * zero stress for a cohesionless material in compression). */
  double rounding = 64.0 * DBL_EPSILON * max_abs3(trial);
  if (multiplier_a < 0.0 && -multiplier_a * planes->main_flow_size <= rounding)
    multiplier_a = 0.0;
  if (multiplier_b < 0.0 && -multiplier_b * b_flow_size <= rounding)
    multiplier_b = 0.0;
  if (multiplier_a < 0.0 || multiplier_b < 0.0)
    return false;
  for (int i = 0; i < 3; i++)
    out[i] = trial[i] - multiplier_a * a->elastic_flow[i] -
             multiplier_b * b->elastic_flow[i];
  /* Both planes hold, so the edge pair is equal up to round-off: make it
   * exact so the ordering test below sees the edge itself. */
  int pair_low = compression ? 0 : 1; /* first index of the equal pair */
  double edge = 0.5 * (out[pair_low] + out[pair_low + 1]);
  out[pair_low] = out[pair_low + 1] = edge;
  return out[0] >= out[2];
}

/* True only if both edge returns would fail, so the return ends at the
 * apex (the main-plane return having failed): a trial beyond the apex,
 * where each edge point comes out unordered. Each edge's ordering value D
 * (make_order_test) is exact arithmetic's; the edge return computes it
 * with at most 13 roundings along any path (u = 2^-53 each, so at most
 * 13.1 u times the absolute-value sum order_size), its round-off rule
 * zeroes multipliers whose stress change is at most 64 eps max |t_i| (D
 * moves by at most 4 x that, 2^-44 max |t_i|), and this test's own
 * evaluation and coefficients add at most 20 u order_size more. The margin
 * 2^-30 order_size exceeds all of it more than 2^13-fold (order_size >= 2
 * max |t_i|), so a D below minus the margin here is below 0 in the edge
 * return too, which then fails: the shortcut gives the apex exactly when
 * the three returns would, to the bit, and costs two dot products instead
 * of two 2x2 solves. Trials (and y) outside 2^+-300 take the returns. */
static GM_ALWAYS_INLINE bool apex_certain(const mc_constants *k,
                                          const mc_planes *planes,
                                          const double trial[3]) {
  if (!planes->apex_test)
    return false;
  double size = max_abs3(trial), y = k->yield_offset; /* Pa */
  if (!(size >= 0x1p-300 && size <= 0x1p300 && fabs(y) <= 0x1p300))
    return false;
  double margin = planes->apex_margin_trial * size; /* Pa */
  double compression = dot3(planes->compression.order_trial, trial);
  double extension = dot3(planes->extension.order_trial, trial);
  if (y != 0.0) { /* a constant 0 folds these away */
    margin += planes->apex_margin_offset * fabs(y);
    compression += planes->compression.order_offset * y;
    extension += planes->extension.order_offset * y;
  }
  return compression < -margin && extension < -margin;
}

/* Principal stresses after the return (sorted trial in, result out);
 * main_value = plane_value(&planes->main, k, trial) > 0, which the caller's
 * yield test has computed already. */
static GM_ALWAYS_INLINE void
return_principal(const mc_constants *k, const mc_planes *planes,
                 const double trial[3], double main_value, double out[3]) {
  if (return_to_main_plane(planes, trial, main_value, out))
    return;
  /* The main-plane result tells which ordering it broke: sigma_2 > sigma_1
   * points to the compression edge, otherwise the extension edge. */
  bool compression_first = out[1] > out[0];
  if (apex_certain(k, planes, trial))
    goto apex;
  if (return_to_edge(k, planes, trial, compression_first, out))
    return;
  if (return_to_edge(k, planes, trial, !compression_first, out))
    return;
  /* Apex: f = 2 sigma sin(phi) - 2 c cos(phi) = 0 at sigma_i = sigma. */
apex:;
  double apex = k->yield_offset / (2.0 * k->sin_friction);
  out[0] = out[1] = out[2] = apex;
}

/* Shear rate gammadot = sqrt(2 d':d') (1/s) of the step, d' the deviatoric
 * rate of deformation: in simple shear dv_x/dy = r it gives r, the "rate of
 * simple shear" of eq 16. Zero for dt <= 0 (no rate is defined). */
static double shear_rate(const double increment[6], double dt) {
  if (!(dt > 0.0))
    return 0.0;
  double mean = (increment[GM_XX] + increment[GM_YY] + increment[GM_ZZ]) / 3.0;
  double contraction = 0.0; /* d':d' dt^2, shear terms counted twice */
  for (int c = GM_XX; c <= GM_ZZ; c++)
    contraction += (increment[c] - mean) * (increment[c] - mean);
  for (int c = GM_XY; c <= GM_ZX; c++)
    contraction += 2.0 * increment[c] * increment[c];
  return sqrt(2.0 * contraction) / dt;
}

/* Plastic shear strain of a return: the deviatoric plastic strain is
 * dev(sigma_tr - sigma)/(2G) (same principal axes); measure sqrt(2 e:e). */
static double plastic_shear_strain(const mc_constants *k, const double trial[3],
                                   const double out[3]) {
  double drop[3];
  for (int i = 0; i < 3; i++)
    drop[i] = trial[i] - out[i];
  double mean = (drop[0] + drop[1] + drop[2]) * (1.0 / 3.0);
  double contraction = 0.0;
  for (int i = 0; i < 3; i++)
    contraction += (drop[i] - mean) * (drop[i] - mean);
  return sqrt(2.0 * contraction) * k->inverse_double_shear;
}

/* Points per chunk: the predictor runs over a chunk, then the corrector
 * reads the chunk's trial stresses back while they are still in L1/L2
 * (6 x 256 x 8 bytes = 12 KiB). */
enum { MC_CHUNK = 256 };

/* Elastic predictor over points [begin, end) of the batch, sigma += C : d_eps:
 * the same arithmetic as gm_elastic_update (one SoA loop the compiler
 * vectorises), so a point that stays elastic ends bit-identical to the elastic
 * model. */
static void elastic_trials(const mc_constants *k,
                           const gm_material_batch *batch, size_t begin,
                           size_t end) {
  const double *const *de = batch->strain_increment;
  double *const *s = batch->stress;
  double shear = k->shear, lame = k->lame;
  for (size_t i = begin; i < end; i++) {
    double volumetric = de[GM_XX][i] + de[GM_YY][i] + de[GM_ZZ][i];
    double lame_term = lame * volumetric;
    s[GM_XX][i] += lame_term + 2.0 * shear * de[GM_XX][i];
    s[GM_YY][i] += lame_term + 2.0 * shear * de[GM_YY][i];
    s[GM_ZZ][i] += lame_term + 2.0 * shear * de[GM_ZZ][i];
    s[GM_XY][i] += 2.0 * shear * de[GM_XY][i];
    s[GM_YZ][i] += 2.0 * shear * de[GM_YZ][i];
    s[GM_ZX][i] += 2.0 * shear * de[GM_ZX][i];
  }
}

static bool all_finite(const double values[6]) {
  for (int c = 0; c < 6; c++)
    if (!isfinite(values[c]))
      return false;
  return true;
}

/* Plastic corrector of one point whose trial stress (Pa, in place) is
 * outside the surface, decomposed into `trial` (general 3D stress); adds to
 * the accumulated plastic shear strain. */
static void plastic_correction(const mc_constants *k, const mc_planes *planes,
                               const gm_principal *trial, double main_value,
                               double stress[6], double *plastic_shear) {
  double returned[3], drop[3], correction[6];
  return_principal(k, planes, trial->value, main_value, returned);
  *plastic_shear += plastic_shear_strain(k, trial->value, returned);
  if (returned[0] == returned[2]) { /* apex: purely hydrostatic */
    for (int c = 0; c < 6; c++)
      stress[c] = c <= GM_ZZ ? returned[0] : 0.0;
    return;
  }
  /* sigma = sigma_tr - sum_k (trial_k - returned_k) v_k v_k: only the
   * principal values change, the eigenvectors stay. */
  for (int i = 0; i < 3; i++)
    drop[i] = trial->value[i] - returned[i];
  gm_principal_compose(trial, drop, correction);
  for (int c = 0; c < 6; c++)
    stress[c] -= correction[c];
}

/* What a return did with a point. */
typedef enum mc_outcome {
  MC_NOT_FINITE, /* the trial stress is not finite */
  MC_ELASTIC,    /* inside the surface: stress untouched */
  MC_PLASTIC     /* returned to the surface: stress changed */
} mc_outcome;

/* Return mapping of a trial stress with yz = zx = 0 (1D, plane strain,
 * axisymmetry; Pa, in place). z is principal and the xy block is a Mohr
 * circle, centre m, radius r, half difference d = (xx - yy)/2: in-plane
 * values m + r and m - r. The yield test needs only the largest and
 * smallest principal values, so an elastic point is decided from the circle
 * alone. A plastic point needs no eigenvectors either: a correction with
 * in-plane principal drops a (along the major direction) and b (minor) is
 * (a + b)/2 I + (a - b)/2 P, where P = [[d/r, xy/r], [xy/r, -d/r]] is the
 * trial's own unit in-plane deviator (P = v1 v1 - v2 v2 = (cos 2 theta,
 * sin 2 theta) without trigonometry), so the result commutes with the trial
 * as the general path's composition does. At r = 0 every in-plane direction
 * is principal and P = diag(1, -1) is as right as any. */
static GM_ALWAYS_INLINE mc_outcome return_planar(const mc_constants *k,
                                                 const mc_planes *planes,
                                                 double stress[6],
                                                 double *plastic_shear);

/* The plastic part of return_planar, given the trial's circle
 * (gm_principal_in_plane's) and its main-plane yield value main_value > 0
 * (or NaN) from the largest and smallest principal values. That value is
 * plane_value's at the sorted trial too: the two sums differ only in the
 * middle value's term, 0 x sigma_2 = +-0 against 0 x 0 = +0, and in the
 * sign of a zero from the equal values of a tie (major = z), which change
 * only a sum that is zero, not one that is > 0. */
static GM_ALWAYS_INLINE mc_outcome return_planar_plastic(
    const mc_constants *k, const mc_planes *planes, gm_principal_circle circle,
    double main_value, double stress[6], double *plastic_shear) {
  double major = circle.centre + circle.radius;
  double minor = circle.centre - circle.radius;
  double zz = stress[GM_ZZ];
  /* Slots of the in-plane pair and of z in the descending order (ties in
   * the order major, minor, z, as gm_principal_decompose sorts them). */
  int major_slot = 0, minor_slot = 1, z_slot = 2;
  if (zz > major) {
    z_slot = 0;
    major_slot = 1;
    minor_slot = 2;
  } else if (zz > minor) {
    z_slot = 1;
    minor_slot = 2;
  }
  double trial[3], returned[3];
  trial[major_slot] = major;
  trial[minor_slot] = minor;
  trial[z_slot] = zz;
  return_principal(k, planes, trial, main_value, returned);
  *plastic_shear += plastic_shear_strain(k, trial, returned);
  if (returned[0] == returned[2]) { /* apex: purely hydrostatic */
    for (int c = 0; c < 6; c++)
      stress[c] = c <= GM_ZZ ? returned[0] : 0.0;
    return MC_PLASTIC;
  }
  double drop_major = major - returned[major_slot];
  double drop_minor = minor - returned[minor_slot];
  double mean_drop = 0.5 * (drop_major + drop_minor);
  double half_split = 0.5 * (drop_major - drop_minor);
  double cos_double = 1.0, sin_double = 0.0; /* of twice the major angle */
  if (circle.radius > 0.0) {
    double inverse_radius = 1.0 / circle.radius;
    cos_double = circle.half_difference * inverse_radius;
    sin_double = stress[GM_XY] * inverse_radius;
  }
  stress[GM_XX] -= mean_drop + half_split * cos_double;
  stress[GM_YY] -= mean_drop - half_split * cos_double;
  stress[GM_XY] -= half_split * sin_double;
  stress[GM_ZZ] = returned[z_slot];
  return MC_PLASTIC;
}

static GM_ALWAYS_INLINE mc_outcome return_planar(const mc_constants *k,
                                                 const mc_planes *planes,
                                                 double stress[6],
                                                 double *plastic_shear) {
  gm_principal_circle circle = gm_principal_in_plane(stress);
  double major = circle.centre + circle.radius;
  double minor = circle.centre - circle.radius;
  double zz = stress[GM_ZZ];
  double extremes[3] = {major > zz ? major : zz, 0.0, minor < zz ? minor : zz};
  double main_value = plane_value(&planes->main, k, extremes); /* Pa */
  if (main_value <= 0.0)
    return MC_ELASTIC; /* the trial stress is the answer, untouched */
  return return_planar_plastic(k, planes, circle, main_value, stress,
                               plastic_shear);
}

/* Return mapping of one point with trial stress `stress` (Pa, in place) and
 * accumulated plastic shear strain; k->yield_offset is this point's rate
 * term. */
static mc_outcome return_point(const mc_constants *k, const mc_planes *planes,
                               double stress[6], double *plastic_shear) {
  if (!all_finite(stress))
    return MC_NOT_FINITE;
  if (stress[GM_YZ] == 0.0 && stress[GM_ZX] == 0.0)
    return return_planar(k, planes, stress, plastic_shear);
  /* General 3D: the principal values alone decide a point clearly inside
   * (f below -error |n|, |n| <= 2 bounding the yield value's error); only
   * the rest pay for the eigenvectors, and the decision is then taken on
   * the accurate values. */
  gm_principal_cubic cubic;
  double estimate[3], error;
  gm_principal_estimate(stress, &cubic, estimate, &error);
  if (plane_value(&planes->main, k, estimate) <= -2.0 * error)
    return MC_ELASTIC;
  gm_principal trial;
  gm_principal_decompose_cubic(&cubic, &trial);
  double main_value = plane_value(&planes->main, k, trial.value); /* Pa */
  if (main_value <= 0.0)
    return MC_ELASTIC;
  plastic_correction(k, planes, &trial, main_value, stress, plastic_shear);
  return MC_PLASTIC;
}

/* values[j] = sqrt(values[j]) for j < count: two at a time with SSE2's
 * correctly rounded square root (the same bits as sqrt, without the errno
 * branch), one at a time elsewhere. */
static void sqrt_rows(double *values, size_t count) {
  size_t j = 0;
#ifdef __SSE2__
  for (; j + 2 <= count; j += 2)
    _mm_storeu_pd(values + j, _mm_sqrt_pd(_mm_loadu_pd(values + j)));
#endif
  for (; j < count; j++)
    values[j] = sqrt(values[j]);
}

/* The screen of a chunk [begin, end) of trial stresses (Pa): the yield
 * value of a plane point from its Mohr circle, the same expressions as
 * return_planar's test (so the same bits decide), in one loop over the
 * chunk that the compiler vectorises, then the rows that are not clearly
 * elastic (outside the surface, general 3D, or not finite: (sum) * 0 is
 * NaN exactly when a component is not finite or the sum overflows, and
 * NaN fails every test) compacted without a branch, so the corrector's
 * loop visits only them and the elastic points cost no scalar work nor a
 * mispredicted branch. With the rate term (`rated`, eta in Pa s^2) each
 * point's 2 c cos(phi) (eq 16) goes to `offset`, as the corrector reads it;
 * without it `offset` is 0 (x - 0 is x: the same value), left unwritten
 * for a plane chunk, whose corrector does not read it. `plane` (a
 * constant): yz = zx = 0 is known and stress[4], stress[5] are not read,
 * and the caller has found every row's sum xx + yy + zz + xy finite, so
 * the finiteness term (+-0) is left out; the listed rows are the same (a
 * +-0 added to the yield value changes no test, nor a value > 0). Returns the
 * number of rows written to `row` (offsets from begin). */
static GM_ALWAYS_INLINE size_t screen_chunk(
    const mc_constants *k, const mc_planes *planes, const double *const *stress,
    const double *const *strain, double dt, size_t begin, size_t end,
    double eta, const bool rated, const bool plane, double *offset,
    double *radius, double *yield, uint16_t *row) {
  size_t count = end - begin;
  if (!rated && !plane) /* the general corrector reads them */
    for (size_t j = 0; j < count; j++)
      offset[j] = 0.0;
  if (rated)
    for (size_t j = 0; j < count; j++) {
      double increment[6];
      for (int c = 0; c < 6; c++)
        increment[c] = strain[c][begin + j];
      double rate = shear_rate(increment, dt);
      offset[j] = 2.0 * eta * rate * rate * k->cos_friction; /* eq 16 */
    }
  const double *restrict xx = stress[GM_XX] + begin;
  const double *restrict yy = stress[GM_YY] + begin;
  const double *restrict zz = stress[GM_ZZ] + begin;
  const double *restrict xy = stress[GM_XY] + begin;
  const double *restrict yz = plane ? NULL : stress[GM_YZ] + begin;
  const double *restrict zx = plane ? NULL : stress[GM_ZX] + begin;
  const double n0 = planes->main.normal[0], n1 = planes->main.normal[1];
  const double n2 = planes->main.normal[2];
  /* Three loops, so that the two without a square root vectorise: GCC
   * keeps a branch to set errno around sqrt (-fmath-errno, the ISO
   * default), which stops the vectoriser; sqrt_rows takes the roots. */
  /* radius: the Mohr circle's, squared, then its radius (Pa) */
  for (size_t j = 0; j < count; j++) {
    double half_difference = 0.5 * (xx[j] - yy[j]); /* gm_principal_in_plane */
    radius[j] = half_difference * half_difference + xy[j] * xy[j];
  }
  sqrt_rows(radius, count);
  /* yield: the yield value (Pa), +inf or NaN: corrector */
  for (size_t j = 0; j < count; j++) {
    double sum = xx[j] + yy[j] + zz[j] + xy[j];
    if (!plane)
      sum += yz[j] + zx[j];
    double screen = sum * 0.0;
    double centre = 0.5 * (xx[j] + yy[j]);
    double major = centre + radius[j], minor = centre - radius[j];
    double high = major > zz[j] ? major : zz[j];
    double low = minor < zz[j] ? minor : zz[j];
    /* plane_value(&planes->main, k, {high, 0, low}) */
    double value = n0 * high + n1 * 0.0 + n2 * low - (rated ? offset[j] : 0.0);
    /* A general 3D stress (yz or zx not 0) goes to the corrector: +inf
     * (or NaN) added, selected without a branch */
    double general = plane || (yz[j] == 0.0 && zx[j] == 0.0) ? 0.0 : INFINITY;
    /* plane: the caller has checked the same sums (+-0 then; the +0 of
     * `general` too changes no test), so the yield value alone */
    yield[j] = plane ? value : value + screen + general;
  }
  size_t rows = 0;
  for (size_t j = 0; j < count; j++) {
    row[rows] = (uint16_t)j;
    rows += !(yield[j] <= 0.0);
  }
  return rows;
}

/* The constants and planes of one update call from the def. */
static void prepare(const gm_mohr_coulomb_def *def, mc_constants *k,
                    mc_planes *planes) {
  double young = def->youngs_modulus; /* Pa */
  double nu = def->poisson_ratio;     /* - */
  k->shear = young / (2.0 * (1.0 + nu));
  k->inverse_double_shear = 1.0 / (2.0 * k->shear);
  k->lame = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  k->sin_friction = sin(def->friction_angle);
  k->cos_friction = cos(def->friction_angle);
  k->sin_dilation = sin(def->dilation_angle);
  k->yield_offset = 0.0; /* stays 0 without the rate term (eta = 0) */
  planes->main = make_plane(k, 0, 2);
  planes->main_compliance =
      1.0 / dot3(planes->main.normal, planes->main.elastic_flow);
  planes->compression = make_edge(&planes->main, make_plane(k, 1, 2), true);
  planes->extension = make_edge(&planes->main, make_plane(k, 0, 1), false);
  planes->main_flow_size = max_abs3(planes->main.elastic_flow);
  planes->compression_flow_size =
      max_abs3(planes->compression.plane.elastic_flow);
  planes->extension_flow_size = max_abs3(planes->extension.plane.elastic_flow);
  const mc_edge *c = &planes->compression, *e = &planes->extension;
  planes->apex_test = c->order_bounded && e->order_bounded;
  planes->apex_margin_trial =
      0x1p-30 * (c->order_size_trial > e->order_size_trial
                     ? c->order_size_trial
                     : e->order_size_trial);
  planes->apex_margin_offset =
      0x1p-30 * (c->order_size_offset > e->order_size_offset
                     ? c->order_size_offset
                     : e->order_size_offset);
}

int gm_mohr_coulomb_update(const gm_material_batch *batch, void *user,
                           char *message, size_t message_size) {
  const gm_mohr_coulomb_def *def = user;
  mc_constants k;
  mc_planes planes;
  prepare(def, &k, &planes);
  if (batch->state_count < GM_MOHR_COULOMB_STATE_COUNT) {
    if (message && message_size > 0)
      snprintf(message, message_size,
               "mohr_coulomb: batch has %zu state variables, needs %d",
               batch->state_count, GM_MOHR_COULOMB_STATE_COUNT);
    return -1;
  }
  double *plastic_shear = batch->state[GM_MOHR_COULOMB_PLASTIC_SHEAR_STRAIN];
  double eta = def->bagnold_viscosity; /* Pa s^2 */
  const double *const *trial_rows = (const double *const *)batch->stress;
  for (size_t begin = 0; begin < batch->count; begin += MC_CHUNK) {
    size_t end =
        batch->count - begin < MC_CHUNK ? batch->count : begin + MC_CHUNK;
    elastic_trials(&k, batch, begin, end);
    double offset[MC_CHUNK]; /* 2 c cos(phi) of each point, Pa */
    double radius[MC_CHUNK], yield[MC_CHUNK]; /* the screen's, Pa */
    uint16_t row[MC_CHUNK]; /* the rows the screen leaves, ascending */
    size_t rows =
        eta > 0.0 ? screen_chunk(&k, &planes, trial_rows,
                                 batch->strain_increment, batch->dt, begin, end,
                                 eta, true, false, offset, radius, yield, row)
                  : screen_chunk(&k, &planes, trial_rows,
                                 batch->strain_increment, batch->dt, begin, end,
                                 0.0, false, false, offset, radius, yield, row);
    for (size_t r = 0; r < rows; r++) {
      size_t i = begin + row[r];
      double stress[6];
      for (int c = 0; c < 6; c++)
        stress[c] = batch->stress[c][i];
      k.yield_offset = offset[row[r]];
      mc_outcome outcome = return_point(&k, &planes, stress, &plastic_shear[i]);
      if (outcome == MC_NOT_FINITE) {
        if (message && message_size > 0)
          snprintf(message, message_size,
                   "mohr_coulomb: point %lld: trial stress is not finite",
                   batch->point_id ? (long long)batch->point_id[i]
                                   : (long long)i);
        return -1;
      }
      if (outcome == MC_PLASTIC)
        for (int c = 0; c < 6; c++)
          batch->stress[c][i] = stress[c];
    }
  }
  return 0;
}

/* The constants and planes of a def, kept by a worker between chunks
 * (gm_worker_scratch.mohr_coulomb_prepared) with the parameters they were
 * derived from: prepare is deterministic, so equal parameters give the
 * same bits. */
typedef struct mc_prepared {
  bool ready;       /* false in a zeroed record */
  double source[4]; /* E (Pa), nu, phi, psi (rad) it was prepared from */
  mc_constants k;
  mc_planes planes;
} mc_prepared;

_Static_assert(sizeof(mc_prepared) <= GM_MOHR_COULOMB_PREPARED_BYTES,
               "mc_prepared outgrew the worker scratch's bytes");

static const mc_prepared *prepared_for(const gm_mohr_coulomb_def *def,
                                       void *bytes) {
  mc_prepared *p = bytes;
  const double source[4] = {def->youngs_modulus, def->poisson_ratio,
                            def->friction_angle, def->dilation_angle};
  if (!p->ready || memcmp(p->source, source, sizeof source) != 0) {
    prepare(def, &p->k, &p->planes);
    memcpy(p->source, source, sizeof source);
    p->ready = true;
  }
  return p;
}

bool gm_mohr_coulomb_plane_returns(const gm_mohr_coulomb_def *def,
                                   double *const stress[4], size_t count,
                                   double *plastic_shear, size_t stride,
                                   void *prepared_bytes) {
  const mc_prepared *prepared = prepared_for(def, prepared_bytes);
  mc_constants k = prepared->k;
  const mc_planes *planes = &prepared->planes;
  k.yield_offset = 0.0; /* no rate term: a constant the returns fold */
  const double *const rows_in[4] = {stress[0], stress[1], stress[2], stress[3]};
  double screen = 0.0; /* x * 0 is NaN exactly when x is not finite */
  for (size_t begin = 0; begin < count; begin += MC_CHUNK) {
    size_t end = count - begin < MC_CHUNK ? count : begin + MC_CHUNK;
    double offset[MC_CHUNK];                  /* not written: no rate term */
    double radius[MC_CHUNK], yield[MC_CHUNK]; /* the screen's, Pa */
    uint16_t row[MC_CHUNK];
    size_t rows = screen_chunk(&k, planes, rows_in, NULL, 0.0, begin, end, 0.0,
                               false, true, offset, radius, yield, row);
    for (size_t r = 0; r < rows; r++) {
      size_t j = row[r], i = begin + j;
      double point[6] = {stress[GM_XX][i],
                         stress[GM_YY][i],
                         stress[GM_ZZ][i],
                         stress[GM_XY][i],
                         0.0,
                         0.0};
      double *shear = &plastic_shear[i * stride];
      mc_outcome outcome;
      /* The screen's circle and yield value are return_planar's (the same
       * expressions): reused, not recomputed. A NaN yield value (products
       * that overflowed) takes return_planar, which decides afresh. */
      if (yield[j] > 0.0) {
        gm_principal_circle circle = {.centre = 0.5 * (point[0] + point[1]),
                                      .half_difference =
                                          0.5 * (point[0] - point[1]),
                                      .radius = radius[j]};
        outcome =
            return_planar_plastic(&k, planes, circle, yield[j], point, shear);
      } else {
        outcome = return_planar(&k, planes, point, shear);
      }
      if (outcome == MC_PLASTIC) {
        for (int c = 0; c < 4; c++)
          stress[c][i] = point[c];
        screen += (point[0] + point[1] + point[2] + point[3]) * 0.0;
      }
    }
  }
  return screen == 0.0;
}

/* Validates the Mohr-Coulomb specific fields (angles in rad). */
static gm_status check_parameters(gm_domain *domain, const void *parameters) {
  const gm_mohr_coulomb_def *def = parameters;
  static const char *def_name = "gm_mohr_coulomb_def";
  gm_status status = gm_check_elastic_constants(
      domain, def_name, def->youngs_modulus, def->poisson_ratio);
  if (status == GM_OK)
    status = gm_check_positive(domain, def_name, "density", def->density,
                               "kg/m^3", false);
  if (status != GM_OK)
    return status;
  double phi = def->friction_angle, psi = def->dilation_angle;
  if (!(phi > 0.0 && phi < 0.5 * GM_PI))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.friction_angle is %g rad, must be in (0, pi/2) "
                        "rad",
                        def_name, phi);
  if (!(psi >= 0.0 && psi <= phi))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "%s.dilation_angle is %g rad, must be in [0, "
                        "friction_angle = %g] rad",
                        def_name, psi, phi);
  return gm_check_positive(domain, def_name, "bagnold_viscosity",
                           def->bagnold_viscosity, "Pa s^2", true);
}

/* The rate term raises strength, not stiffness: the P-wave modulus
 * M = K + 4G/3 = E(1-nu)/((1+nu)(1-2nu)) bounds the wave speed. */
static double mohr_coulomb_p_wave_modulus(const void *parameters) {
  const gm_mohr_coulomb_def *def = parameters;
  return gm_p_wave_modulus(def->youngs_modulus, def->poisson_ratio);
}

const gm_builtin_model gm_mohr_coulomb_model = {
    .caller = "gm_domain_add_mohr_coulomb",
    .layout = GM_LAYOUT_MOHR_COULOMB_DEF,
    .default_name = "mohr_coulomb",
    .update = gm_mohr_coulomb_update,
    .state_count = GM_MOHR_COULOMB_STATE_COUNT, /* no plastic shear yet */
    .check = check_parameters,
    .p_wave_modulus = mohr_coulomb_p_wave_modulus,
    .density_offset = offsetof(gm_mohr_coulomb_def, density),
    .record_end = GM_FIELD_END(gm_mohr_coulomb_def, bagnold_viscosity),
};

gm_status gm_domain_add_mohr_coulomb(gm_domain *domain,
                                     const gm_mohr_coulomb_def *def,
                                     int *material_id) {
  return gm_register_builtin(domain, &gm_mohr_coulomb_model, def, material_id);
}
