/*
 * test_mohr_coulomb.c - the built-in Mohr-Coulomb model with the Bagnold
 * rate term (000 eqs 16-17), driven through gm_mohr_coulomb_update with
 * hand-built batches:
 *   - the spectral decomposition it relies on (lib/materials/principal.h,
 *     white-box) recovers known eigenvalues and rebuilds the tensor;
 *   - thousands of random trial states (seeded LCG) covering the elastic
 *     region, the main plane, both edges and the apex: the returned stress
 *     is on the yield surface, keeps the trial principal directions and
 *     ordering, flows along the plastic potential (psi = 0: no volume
 *     change; psi = phi: along the gradient of f), and elastic trials come
 *     back bit-identical to gm_elastic_update;
 *   - triaxial compression plateaus q/p = 6 sin(phi) / (3 - sin(phi));
 *   - the Bagnold term raises the triaxial strength by exactly eq 16;
 *   - invalid parameters are refused naming the field.
 * Stress is tension positive; sigma_1 >= sigma_2 >= sigma_3.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "materials/principal.h"
#include "test_util.h"

static const double DEG = 3.14159265358979323846 / 180.0; /* rad per degree */

/* ---------------------------------------------------------------- helpers */

/* 64-bit LCG (Knuth's MMIX constants), uniform doubles in [0, 1). */
typedef struct test_lcg {
  uint64_t state;
} test_lcg;

static double lcg_uniform(test_lcg *lcg) {
  lcg->state = lcg->state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(lcg->state >> 11) * (1.0 / 9007199254740992.0);
}

static double lcg_range(test_lcg *lcg, double low, double high) {
  return low + (high - low) * lcg_uniform(lcg);
}

/* Random rotation matrix from a random unit quaternion. */
static void random_rotation(test_lcg *lcg, double r[3][3]) {
  double q[4], norm = 0.0;
  for (int k = 0; k < 4; k++) {
    q[k] = lcg_range(lcg, -1.0, 1.0);
    norm += q[k] * q[k];
  }
  norm = sqrt(norm);
  double w = q[0] / norm, x = q[1] / norm, y = q[2] / norm, z = q[3] / norm;
  double m[3][3] = {
      {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  memcpy(r, m, sizeof m);
}

/* A random rotation about z: R[0][2] = R[1][2] = R[2][0] = R[2][1] = 0 and
 * R[2][2] = 1 exactly, so R diag(values) R^T has yz = zx = 0 exactly (the
 * plane-strain and axisymmetric states, which principal.c solves in closed
 * form) and values[2] is the zz principal value. */
static void random_z_rotation(test_lcg *lcg, double r[3][3]) {
  double angle = lcg_range(lcg, 0.0, 2.0 * 3.14159265358979323846);
  double m[3][3] = {{cos(angle), -sin(angle), 0.0},
                    {sin(angle), cos(angle), 0.0},
                    {0.0, 0.0, 1.0}};
  memcpy(r, m, sizeof m);
}

/* Voigt (xx, yy, zz, xy, yz, zx) of R diag(values) R^T. */
static void rotate_diagonal(double r[3][3], const double values[3],
                            double voigt[6]) {
  static const int row[6] = {0, 1, 2, 0, 1, 2}, col[6] = {0, 1, 2, 1, 2, 0};
  for (int c = 0; c < 6; c++) {
    voigt[c] = 0.0;
    for (int k = 0; k < 3; k++)
      voigt[c] += r[row[c]][k] * values[k] * r[col[c]][k];
  }
}

static void voigt_to_matrix(const double v[6], double m[3][3]) {
  double full[3][3] = {
      {v[0], v[3], v[5]}, {v[3], v[1], v[4]}, {v[5], v[4], v[2]}};
  memcpy(m, full, sizeof full);
}

static double voigt_norm(const double v[6]) { /* Frobenius, shear twice */
  return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] +
              2.0 * (v[3] * v[3] + v[4] * v[4] + v[5] * v[5]));
}

/* u^T A v for a Voigt tensor A. */
static double bilinear(const double voigt[6], const double u[3],
                       const double v[3]) {
  double m[3][3];
  voigt_to_matrix(voigt, m);
  double sum = 0.0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      sum += u[i] * m[i][j] * v[j];
  return sum;
}

/* Yield function of eq 16 (tension positive) from sorted principal stresses. */
static double yield_value(const double principal[3], double sin_phi,
                          double cohesion) {
  return (principal[0] - principal[2]) +
         (principal[0] + principal[2]) * sin_phi -
         2.0 * cohesion * sqrt(1.0 - sin_phi * sin_phi);
}

/* The test's own gammadot = sqrt(2 d':d'), d' = dev(increment)/dt (1/s). */
static double test_shear_rate(const double e[6], double dt) {
  double mean = (e[0] + e[1] + e[2]) / 3.0, sum = 0.0;
  for (int c = 0; c < 3; c++)
    sum += (e[c] - mean) * (e[c] - mean);
  for (int c = 3; c < 6; c++)
    sum += 2.0 * e[c] * e[c];
  return sqrt(2.0 * sum) / dt;
}

/* SoA storage for a batch of `count` points. */
typedef struct test_points {
  size_t count;
  double *increment[6];
  double *stress[6];
  double *state_rows[1];
  double *density;
  int64_t *id;
} test_points;

static test_points points_create(size_t count) {
  test_points p;
  p.count = count;
  for (int c = 0; c < 6; c++) {
    p.increment[c] = calloc(count, sizeof(double));
    p.stress[c] = calloc(count, sizeof(double));
    ck_assert(p.increment[c] && p.stress[c]);
  }
  p.state_rows[0] = calloc(count, sizeof(double));
  p.density = calloc(count, sizeof(double));
  p.id = calloc(count, sizeof(int64_t));
  ck_assert(p.state_rows[0] && p.density && p.id);
  for (size_t i = 0; i < count; i++) {
    p.density[i] = 2000.0;
    p.id[i] = (int64_t)i + 100;
  }
  return p;
}

static void points_free(test_points *p) {
  for (int c = 0; c < 6; c++) {
    free(p->increment[c]);
    free(p->stress[c]);
  }
  free(p->state_rows[0]);
  free(p->density);
  free(p->id);
}

static gm_material_batch points_batch(test_points *p, double dt) {
  gm_material_batch batch;
  memset(&batch, 0, sizeof batch);
  batch.struct_size = sizeof batch;
  batch.count = p->count;
  batch.geometry = GM_GEOMETRY_AXISYMMETRIC;
  batch.dt = dt;
  for (int c = 0; c < 6; c++) {
    batch.strain_increment[c] = p->increment[c];
    batch.stress[c] = p->stress[c];
  }
  batch.density = p->density;
  batch.state = p->state_rows;
  batch.state_count = 1;
  batch.point_id = p->id;
  return batch;
}

static gm_mohr_coulomb_def make_def(double phi, double psi, double eta) {
  gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
  def.youngs_modulus = 1e7; /* Pa */
  def.poisson_ratio = 0.25;
  def.density = 2000.0; /* kg/m^3 */
  def.friction_angle = phi;
  def.dilation_angle = psi;
  def.bagnold_viscosity = eta; /* Pa s^2 */
  return def;
}

/* ------------------------------------------------------ principal stresses */

/* Known eigenvalues (some repeated) under random rotations are recovered,
 * and composing them on the computed basis rebuilds the tensor. The
 * decomposition is backward stable: errors are a few eps times the tensor norm,
 * so 1e-13 of the norm (about 450 eps) is a safe bound that still catches any
 * bug. */
/* The loop runs twice: _i = 0 with general rotations (the general closed
 * form; tests/unit/test_principal.c compares it with Jacobi), _i = 1
 * with rotations about z (yz = zx = 0: the closed-form Mohr-circle path),
 * where the repeated pairs are the in-plane pair (n % 3 == 1: the circle
 * has radius 0) and an in-plane value equal to zz (n % 5 == 3), same
 * bounds: the closed form is backward stable too (one square root for the
 * radius, one for the direction, no cancellation; see principal.c). */
START_TEST(test_principal_decomposition) {
  bool planar = _i == 1;
  test_lcg lcg = {planar ? 54321u : 12345u};
  double worst = 0.0;
  for (int n = 0; n < 2000; n++) {
    double values[3], r[3][3], voigt[6], rebuilt[6];
    for (int k = 0; k < 3; k++)
      values[k] = lcg_range(&lcg, -1e5, 1e5);
    if (n % 3 == 1)
      values[1] = values[0]; /* repeated pair */
    if (planar && n % 5 == 3)
      values[2] = values[n % 2]; /* an in-plane value equal to zz */
    if (n % 7 == 2)
      values[2] = values[1] = values[0]; /* isotropic */
    if (planar)
      random_z_rotation(&lcg, r);
    else
      random_rotation(&lcg, r);
    rotate_diagonal(r, values, voigt);
    if (planar)
      ck_assert(voigt[4] == 0.0 && voigt[5] == 0.0);
    gm_principal principal;
    ck_assert_int_eq(gm_principal_decompose(voigt, &principal), 0);
    /* Sort the reference descending. */
    for (int i = 0; i < 2; i++)
      for (int j = i + 1; j < 3; j++)
        if (values[j] > values[i]) {
          double t = values[i];
          values[i] = values[j];
          values[j] = t;
        }
    double scale = voigt_norm(voigt);
    for (int k = 0; k < 3; k++) {
      double error = fabs(principal.value[k] - values[k]) / scale;
      worst = fmax(worst, error);
      ck_assert_msg(error < 1e-13, "eigenvalue %d off by %g", k, error);
      double length = 0.0;
      for (int c = 0; c < 3; c++)
        length += principal.vector[k][c] * principal.vector[k][c];
      ck_assert_double_le(fabs(length - 1.0), 1e-13);
      for (int j = 0; j < k; j++) { /* orthogonal to the earlier ones */
        double overlap = 0.0;
        for (int c = 0; c < 3; c++)
          overlap += principal.vector[k][c] * principal.vector[j][c];
        ck_assert_double_le(fabs(overlap), 1e-13);
      }
    }
    gm_principal_compose(&principal, principal.value, rebuilt);
    for (int c = 0; c < 6; c++)
      ck_assert_double_le(fabs(rebuilt[c] - voigt[c]), 1e-13 * scale);
  }
  ck_assert_double_lt(worst, 1e-13);
}
END_TEST

/* -------------------------------------------------- random return mapping */

enum {
  REGION_ELASTIC,
  REGION_MAIN,
  REGION_COMPRESSION_EDGE,
  REGION_EXTENSION_EDGE,
  REGION_APEX,
  REGION_COUNT
};

typedef struct sweep_case {
  double phi, psi; /* rad */
  uint64_t seed;
  bool planar; /* yz = zx = 0 (the closed-form plane-strain path) */
} sweep_case;

static const sweep_case SWEEP_CASES[] = {
    {30.0 * 3.14159265358979323846 / 180.0, 0.0, 1, false},
    {30.0 * 3.14159265358979323846 / 180.0,
     30.0 * 3.14159265358979323846 / 180.0, 2, false},
    {40.0 * 3.14159265358979323846 / 180.0,
     15.0 * 3.14159265358979323846 / 180.0, 3, false},
    {30.0 * 3.14159265358979323846 / 180.0, 0.0, 4, true},
    {30.0 * 3.14159265358979323846 / 180.0,
     30.0 * 3.14159265358979323846 / 180.0, 5, true},
    {40.0 * 3.14159265358979323846 / 180.0,
     15.0 * 3.14159265358979323846 / 180.0, 6, true}};

enum { SWEEP_POINTS = 6000 };
static const double SWEEP_STRESS = 1e5; /* Pa, stress scale S */
static const double SWEEP_DT = 4e-6;    /* s: c = eta gammadot^2 ~ 1e4 Pa */
static const double SWEEP_ETA = 0.15;   /* Pa s^2, 000 Table 3 */

/* Random input stress and strain increment: mean stress in [-S, S]
 * (tension beyond the apex too), deviator radius up to 1.5 S at a uniform
 * Lode angle, random axes; increments up to 1e-3 (about 1e4 Pa). `planar`:
 * axes rotated about z only and yz = zx = 0 in the increment too, as the
 * library passes plane-strain and axisymmetric points. */
static void random_state(test_lcg *lcg, bool planar, double stress[6],
                         double increment[6]) {
  double mean = lcg_range(lcg, -1.0, 1.0) * SWEEP_STRESS;
  double radius = lcg_range(lcg, 0.0, 1.5) * SWEEP_STRESS;
  double lode = lcg_range(lcg, 0.0, 2.0 * 3.14159265358979323846);
  double values[3], r[3][3];
  for (int k = 0; k < 3; k++) /* deviatoric principal values of norm radius */
    values[k] = mean + radius * sqrt(2.0 / 3.0) *
                           cos(lode - 2.0 * 3.14159265358979323846 * k / 3.0);
  if (planar)
    random_z_rotation(lcg, r);
  else
    random_rotation(lcg, r);
  rotate_diagonal(r, values, stress);
  for (int c = 0; c < 6; c++)
    increment[c] = lcg_range(lcg, -1e-3, 1e-3);
  if (planar)
    increment[GM_YZ] = increment[GM_ZX] = 0.0;
}

/* Trial stress, the same formula as the elastic model. */
static void trial_stress(const gm_mohr_coulomb_def *def, const double in[6],
                         const double e[6], double out[6]) {
  double young = def->youngs_modulus, nu = def->poisson_ratio;
  double shear = young / (2.0 * (1.0 + nu));
  double lame = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  double lame_term = lame * (e[0] + e[1] + e[2]);
  for (int c = 0; c < 3; c++)
    out[c] = in[c] + (lame_term + 2.0 * shear * e[c]);
  for (int c = 3; c < 6; c++)
    out[c] = in[c] + 2.0 * shear * e[c];
}

/* Plastic strain increment in the trial principal frame: C^-1 (sigma_tr -
 * sigma), e_k = v_k . eps_p . v_k. */
static void plastic_strain_principal(const gm_mohr_coulomb_def *def,
                                     const gm_principal *trial,
                                     const double drop[6], double e[3]) {
  double young = def->youngs_modulus, nu = def->poisson_ratio;
  double shear = young / (2.0 * (1.0 + nu));
  double bulk = young / (3.0 * (1.0 - 2.0 * nu));
  double mean = (drop[0] + drop[1] + drop[2]) / 3.0;
  for (int k = 0; k < 3; k++) {
    double along = bilinear(drop, trial->vector[k], trial->vector[k]);
    e[k] = (along - mean) / (2.0 * shear) + mean / (3.0 * bulk);
  }
}

/* The flow rule: e must lie in the cone of the active planes' flow vectors
 * built with sin_angle (sin psi for the potential of eq 17; with psi = phi
 * this is the gradient of f itself). Returns the largest violation. */
static double flow_violation(int region, const double e[3], double s) {
  double up = 1.0 + s, down = 1.0 - s;
  double a, b, predicted, residual;
  switch (region) {
  case REGION_MAIN: /* e = a (up, 0, -down) */
    a = e[0] / up;
    residual = fmax(fabs(e[1]), fabs(e[2] + down * a));
    return fmax(residual, -a);
  case REGION_COMPRESSION_EDGE: /* a (up, 0, -down) + b (0, up, -down) */
    a = e[0] / up;
    b = e[1] / up;
    predicted = -down * (a + b);
    return fmax(fabs(e[2] - predicted), fmax(-a, -b));
  case REGION_EXTENSION_EDGE: /* a (up, 0, -down) + b (up, -down, 0) */
    a = -e[2] / down;
    b = -e[1] / down;
    predicted = up * (a + b);
    return fmax(fabs(e[0] - predicted), fmax(-a, -b));
  case REGION_APEX: {
    /* Normal cone of the apex of the pyramid: e . r <= 0 for every edge
     * ray r of the yield surface leaving the apex, the permutations of
     * -(down, down, up) (compression meridian) and -(down, up, up)
     * (extension meridian). */
    double worst = 0.0;
    for (int j = 0; j < 3; j++) {
      double sum = e[0] + e[1] + e[2];
      double compression = down * (sum - e[j]) + up * e[j];
      double extension = up * (sum - e[j]) + down * e[j];
      worst = fmax(worst, fmax(-compression, -extension));
    }
    return worst;
  }
  default:
    return 0.0;
  }
}

/* Region of a return from the returned principal values r (trial order). */
static int classify(const double r[3], double tolerance) {
  bool top = fabs(r[0] - r[1]) <= tolerance;
  bool bottom = fabs(r[1] - r[2]) <= tolerance;
  if (top && bottom)
    return REGION_APEX;
  if (top)
    return REGION_COMPRESSION_EDGE;
  if (bottom)
    return REGION_EXTENSION_EDGE;
  return REGION_MAIN;
}

/* Tolerances, all relative to scale = |sigma_tr| + 2c (Pa). Round-off of
 * the eigen-decomposition and the composition is a few eps * scale
 * (~1e-15); the bounds below leave >= 3 orders of magnitude of margin. */
static const double TOL_YIELD = 1e-10;    /* |f(sigma)| / scale */
static const double TOL_ROUNDOFF = 1e-12; /* commutator, ordering, p */
static const double TOL_FLOW = 1e-11;     /* strain, times 2G / scale */

START_TEST(test_random_returns) {
  const sweep_case *sc = &SWEEP_CASES[_i];
  gm_mohr_coulomb_def def = make_def(sc->phi, sc->psi, SWEEP_ETA);
  double shear = def.youngs_modulus / (2.0 * (1.0 + def.poisson_ratio));
  double sin_phi = sin(sc->phi), sin_psi = sin(sc->psi);
  test_lcg lcg = {sc->seed};
  test_points p = points_create(SWEEP_POINTS);
  test_points elastic = points_create(SWEEP_POINTS);
  double(*inputs)[6] = malloc(SWEEP_POINTS * sizeof *inputs);
  ck_assert_ptr_nonnull(inputs);
  for (size_t i = 0; i < p.count; i++) {
    double e[6];
    random_state(&lcg, sc->planar, inputs[i], e);
    for (int c = 0; c < 6; c++) {
      p.stress[c][i] = elastic.stress[c][i] = inputs[i][c];
      p.increment[c][i] = elastic.increment[c][i] = e[c];
    }
  }
  gm_material_batch batch = points_batch(&p, SWEEP_DT);
  char message[256] = "";
  ck_assert_int_eq(
      gm_mohr_coulomb_update(&batch, &def, message, sizeof message), 0);
  gm_elastic_def elastic_def = gm_elastic_def_default();
  elastic_def.youngs_modulus = def.youngs_modulus;
  elastic_def.poisson_ratio = def.poisson_ratio;
  gm_material_batch elastic_batch = points_batch(&elastic, SWEEP_DT);
  ck_assert_int_eq(
      gm_elastic_update(&elastic_batch, &elastic_def, message, sizeof message),
      0);

  int count[REGION_COUNT] = {0};
  double worst_yield = 0.0, worst_flow = 0.0, worst_pressure = 0.0;
  for (size_t i = 0; i < p.count; i++) {
    double e[6], trial[6], out[6];
    for (int c = 0; c < 6; c++) {
      e[c] = p.increment[c][i];
      out[c] = p.stress[c][i];
    }
    trial_stress(&def, inputs[i], e, trial);
    double rate = test_shear_rate(e, SWEEP_DT);
    double cohesion = SWEEP_ETA * rate * rate; /* eq 16, Pa */
    double scale = voigt_norm(trial) + 2.0 * cohesion;
    gm_principal tp;
    ck_assert_int_eq(gm_principal_decompose(trial, &tp), 0);
    if (yield_value(tp.value, sin_phi, cohesion) <= 0.0) {
      /* Elastic: bit-identical to the elastic model, no plastic strain. */
      count[REGION_ELASTIC]++;
      for (int c = 0; c < 6; c++)
        ck_assert_msg(memcmp(&out[c], &elastic.stress[c][i], sizeof(double)) ==
                          0,
                      "point %zu comp %d not bit-identical", i, c);
      ck_assert(p.state_rows[0][i] == 0.0);
      continue;
    }
    /* On the yield surface. */
    gm_principal op;
    ck_assert_int_eq(gm_principal_decompose(out, &op), 0);
    double f = fabs(yield_value(op.value, sin_phi, cohesion)) / scale;
    worst_yield = fmax(worst_yield, f);
    ck_assert_msg(f <= TOL_YIELD, "point %zu: |f|/scale = %g", i, f);
    /* Commutes with the trial stress: same principal directions. */
    double a[3][3], b[3][3];
    voigt_to_matrix(trial, a);
    voigt_to_matrix(out, b);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        double commutator = 0.0;
        for (int k = 0; k < 3; k++)
          commutator += a[r][k] * b[k][c] - b[r][k] * a[k][c];
        ck_assert_double_le(fabs(commutator), TOL_ROUNDOFF * scale * scale);
      }
    /* Returned principal values in the trial frame keep the ordering. */
    double returned[3];
    for (int k = 0; k < 3; k++)
      returned[k] = bilinear(out, tp.vector[k], tp.vector[k]);
    ck_assert_double_ge(returned[0] - returned[1], -TOL_ROUNDOFF * scale);
    ck_assert_double_ge(returned[1] - returned[2], -TOL_ROUNDOFF * scale);
    int region = classify(returned, TOL_ROUNDOFF * scale);
    count[region]++;
    /* Flow along the potential (eq 17). */
    double drop[6], ep[3];
    for (int c = 0; c < 6; c++)
      drop[c] = trial[c] - out[c];
    plastic_strain_principal(&def, &tp, drop, ep);
    /* At the apex the hydrostatic return is a tension cut-off, consistent
     * with a flow rule only when the flow is associated (psi = phi): then
     * the plastic strain must lie in the normal cone of the apex. */
    bool check_flow = region != REGION_APEX || sc->psi == sc->phi;
    double violation =
        check_flow ? flow_violation(region, ep, sin_psi) * 2.0 * shear / scale
                   : 0.0;
    worst_flow = fmax(worst_flow, violation);
    ck_assert_msg(violation <= TOL_FLOW, "point %zu region %d: flow off by %g",
                  i, region, violation);
    if (sc->psi == 0.0 && region != REGION_APEX) {
      /* Isochoric flow: the trial pressure is preserved. */
      double change = fabs((drop[0] + drop[1] + drop[2]) / 3.0) / scale;
      worst_pressure = fmax(worst_pressure, change);
      ck_assert_double_le(change, TOL_ROUNDOFF);
    }
    double apex = cohesion * sqrt(1.0 - sin_phi * sin_phi) / sin_phi; /* Pa */
    double trial_mean = (trial[0] + trial[1] + trial[2]) / 3.0;
    if (sc->psi == 0.0 && fabs(trial_mean - apex) > TOL_ROUNDOFF * scale)
      /* psi = 0 keeps the pressure on the plane and the edges, and no
       * point of the surface is in tension beyond the apex: exactly the
       * trials past the apex go to the apex. */
      ck_assert_msg((region == REGION_APEX) == (trial_mean > apex),
                    "point %zu: region %d, trial mean %g, apex %g", i, region,
                    trial_mean, apex);
    if (region == REGION_APEX) { /* hydrostatic at c cot(phi) */
      for (int c = 0; c < 6; c++)
        ck_assert_double_le(fabs(out[c] - (c < 3 ? apex : 0.0)),
                            TOL_ROUNDOFF * scale);
    }
    /* State: accumulated sqrt(2 e_p:e_p) of the deviatoric plastic strain. */
    double mean = (ep[0] + ep[1] + ep[2]) / 3.0, contraction = 0.0;
    for (int k = 0; k < 3; k++)
      contraction += (ep[k] - mean) * (ep[k] - mean);
    double expected = sqrt(2.0 * contraction);
    ck_assert_double_le(fabs(p.state_rows[0][i] - expected),
                        TOL_FLOW * scale / (2.0 * shear));
  }
  /* Every region is exercised (>= 2% of the points each). */
  for (int region = 0; region < REGION_COUNT; region++)
    ck_assert_msg(count[region] >= SWEEP_POINTS / 50,
                  "region %d reached by only %d points", region, count[region]);
  fprintf(stderr,
          "random returns%s phi %.0f psi %.0f: elastic %d main %d compression "
          "edge %d extension edge %d apex %d; worst |f|/scale %.2e, flow "
          "%.2e, pressure %.2e\n",
          sc->planar ? " (planar)" : "", sc->phi / DEG, sc->psi / DEG, count[0],
          count[1], count[2], count[3], count[4], worst_yield, worst_flow,
          worst_pressure);
  points_free(&p);
  points_free(&elastic);
  free(inputs);
}
END_TEST

/* --------------------------------------------------------------- triaxial */

/* One point in triaxial compression (axisymmetric batch: xx radial, yy
 * axial, zz hoop). Each step prescribes the axial strain increment and
 * solves the lateral increment by secant iteration until both lateral
 * stresses equal -confinement within 1e-9 of it. */
typedef struct triaxial {
  const gm_mohr_coulomb_def *def;
  double dt;          /* s */
  double confinement; /* Pa, > 0 (compressive) */
  double stress[6];   /* Pa */
  double plastic;     /* accumulated plastic shear strain */
  double lateral;     /* last lateral increment (initial guess) */
} triaxial;

/* Lateral stress residual (Pa) of a trial lateral increment x; writes the
 * updated stress and state. */
static double triaxial_try(const triaxial *t, double axial, double x,
                           double stress[6], double *plastic) {
  test_points p = points_create(1);
  double e[6] = {x, axial, x, 0.0, 0.0, 0.0};
  for (int c = 0; c < 6; c++) {
    p.increment[c][0] = e[c];
    p.stress[c][0] = t->stress[c];
  }
  p.state_rows[0][0] = t->plastic;
  gm_material_batch batch = points_batch(&p, t->dt);
  char message[256] = "";
  ck_assert_int_eq(
      gm_mohr_coulomb_update(&batch, (void *)t->def, message, sizeof message),
      0);
  for (int c = 0; c < 6; c++)
    stress[c] = p.stress[c][0];
  *plastic = p.state_rows[0][0];
  points_free(&p);
  return stress[GM_XX] + t->confinement;
}

static void triaxial_step(triaxial *t, double axial) {
  double stress[6], plastic;
  double x0 = t->lateral, x1 = t->lateral + 1e-2 * axial;
  double r0 = triaxial_try(t, axial, x0, stress, &plastic);
  double tolerance = 1e-9 * t->confinement;
  for (int iteration = 0; fabs(r0) >= tolerance; iteration++) {
    ck_assert_msg(iteration < 60, "lateral iteration did not converge");
    double r1 = triaxial_try(t, axial, x1, stress, &plastic);
    if (fabs(r1) < tolerance) {
      x0 = x1;
      r0 = r1;
      break;
    }
    ck_assert(r1 != r0);
    double next = x1 - r1 * (x1 - x0) / (r1 - r0);
    x0 = x1;
    r0 = r1;
    x1 = next;
  }
  ck_assert_double_lt(fabs(stress[GM_ZZ] + t->confinement), tolerance);
  t->lateral = x0;
  memcpy(t->stress, stress, sizeof stress);
  t->plastic = plastic;
}

static triaxial triaxial_start(const gm_mohr_coulomb_def *def, double dt,
                               double confinement) {
  triaxial t;
  memset(&t, 0, sizeof t);
  t.def = def;
  t.dt = dt;
  t.confinement = confinement;
  for (int c = 0; c < 3; c++)
    t.stress[c] = -confinement;
  t.lateral = 0.0;
  return t;
}

enum { TRIAXIAL_STEPS = 1000, TRIAXIAL_PLATEAU = 100 };
static const double TRIAXIAL_AXIAL = -1e-4; /* axial increment per step */
static const double TRIAXIAL_CONFINE = 1e5; /* Pa */

/* q/p of the plateau equals 6 sin(phi)/(3 - sin(phi)) (Bagnold off). The
 * brief allows 0.5%; a perfectly plastic return lands exactly on the
 * compression edge, so the error is the lateral-stress tolerance (1e-9)
 * plus round-off. */
START_TEST(test_triaxial_ratio) {
  static const double angles[2][2] = {{20.0, 0.0}, {35.0, 10.0}}; /* deg */
  for (int n = 0; n < 2; n++) {
    gm_mohr_coulomb_def def =
        make_def(angles[n][0] * DEG, angles[n][1] * DEG, 0.0);
    triaxial t = triaxial_start(&def, 1e-3, TRIAXIAL_CONFINE);
    double s = sin(def.friction_angle);
    double expected = 6.0 * s / (3.0 - s);
    double worst = 0.0;
    for (int step = 0; step < TRIAXIAL_STEPS; step++) {
      triaxial_step(&t, TRIAXIAL_AXIAL);
      if (step < TRIAXIAL_STEPS - TRIAXIAL_PLATEAU)
        continue;
      double pressure = -(t.stress[0] + t.stress[1] + t.stress[2]) / 3.0;
      double q = fabs(t.stress[GM_YY] - t.stress[GM_XX]);
      double error = fabs(q / pressure - expected) / expected;
      worst = fmax(worst, error);
    }
    ck_assert_msg(worst < 5e-3, "phi %g: q/p off by %g", angles[n][0], worst);
    ck_assert_double_gt(t.plastic, 0.0);
    fprintf(stderr,
            "triaxial phi %.0f psi %.0f: q/p = %.12f, expected %.12f, "
            "worst relative error %.2e (allowed 5e-3)\n",
            angles[n][0], angles[n][1],
            fabs(t.stress[1] - t.stress[0]) /
                (-(t.stress[0] + t.stress[1] + t.stress[2]) / 3.0),
            expected, worst);
  }
}
END_TEST

/* With psi = 0 the plateau flow is isochoric and the stress constant, so
 * the lateral increment is -axial/2, d' = diag(1, -1/2, -1/2) axial/dt and
 * gammadot = sqrt(3) |axial| / dt. Eq 16 on the compression edge (sigma_1 =
 * sigma_2 = -confinement, sigma_3 = -axial stress) gives
 *   sigma_a = (sigma_c (1 + sin phi) + 2 eta gammadot^2 cos phi)
 *             / (1 - sin phi).
 * The only errors are the lateral tolerance (1e-9 sigma_c, which shifts the
 * rate by ~1e-9 relative) and round-off, so 1e-6 is a loose bound. The
 * plastic shear strain grows by gammadot dt = sqrt(3) |axial| per step. */
START_TEST(test_bagnold_strength) {
  double phi = 30.0 * DEG, eta = 0.15; /* Pa s^2 */
  double dt = 4e-7;                    /* s: c ~ 2.8e4 Pa */
  gm_mohr_coulomb_def def = make_def(phi, 0.0, eta);
  gm_mohr_coulomb_def rate_free = make_def(phi, 0.0, 0.0);
  triaxial t = triaxial_start(&def, dt, TRIAXIAL_CONFINE);
  triaxial t0 = triaxial_start(&rate_free, dt, TRIAXIAL_CONFINE);
  double before = 0.0;
  for (int step = 0; step < TRIAXIAL_STEPS; step++) {
    before = t.plastic;
    triaxial_step(&t, TRIAXIAL_AXIAL);
    triaxial_step(&t0, TRIAXIAL_AXIAL);
  }
  double s = sin(phi), c = cos(phi);
  double rate = sqrt(3.0) * fabs(TRIAXIAL_AXIAL) / dt; /* 1/s */
  double cohesion = eta * rate * rate;                 /* Pa */
  double expected =
      (TRIAXIAL_CONFINE * (1.0 + s) + 2.0 * cohesion * c) / (1.0 - s);
  double expected_rise = 2.0 * cohesion * c / (1.0 - s);
  double axial_stress = -t.stress[GM_YY];
  double rise = -t.stress[GM_YY] + t0.stress[GM_YY];
  double error = fabs(axial_stress - expected) / expected;
  double rise_error = fabs(rise - expected_rise) / expected_rise;
  double strain_error =
      fabs((t.plastic - before) - sqrt(3.0) * fabs(TRIAXIAL_AXIAL)) /
      (sqrt(3.0) * fabs(TRIAXIAL_AXIAL));
  fprintf(stderr,
          "bagnold: axial stress %.10e Pa, expected %.10e (rel %.2e); rise "
          "%.6e Pa, expected %.6e (rel %.2e); plastic shear per step rel "
          "%.2e\n",
          axial_stress, expected, error, rise, expected_rise, rise_error,
          strain_error);
  ck_assert_double_lt(error, 1e-6);
  ck_assert_double_lt(rise_error, 1e-6);
  ck_assert_double_lt(strain_error, 1e-6);
}
END_TEST

/* ------------------------------------------------------- flowing friction */

/* What phi means in a flow (docs/convergence.md section 10; Davis 1968,
 * derived there): with psi = 0 the plastic flow is isochoric, so in steady
 * constant-volume simple shear the stress is coaxial with the strain rate,
 * its principal axes at 45 degrees to the shear plane. On that plane tau is
 * the radius of Mohr's circle and sigma_n its centre, so a flowing layer
 * resists at
 *   tau / sigma_n = sin(phi)   (not tan(phi), the friction at failure).
 * One point in plane strain from an isotropic 1 kPa, sheared by gamma =
 * 1e-4 per step (no rate term, no spin: the material update alone) for 20
 * 000 steps (gamma = 2): the ratio settles at sin(phi) (measured equal to
 * six digits at 25, 35 and 44.4 degrees). Asserted within 1e-3 of
 * sin(phi): the steady state is reached by gamma ~ 0.1, and tan(phi) is
 * 0.03-0.2 away, so the check separates the two readings of phi by far. */
START_TEST(test_simple_shear_flows_at_sin_phi) {
  static const double angles[] = {25.0, 35.0, 44.4}; /* degrees */
  double phi = angles[_i] * DEG;
  gm_mohr_coulomb_def def = make_def(phi, 0.0, 0.0);
  test_points p = points_create(1);
  for (int c = GM_XX; c <= GM_ZZ; c++)
    p.stress[c][0] = -1000.0;     /* Pa, isotropic */
  p.increment[GM_XY][0] = 0.5e-4; /* tensor shear strain: gamma = 1e-4 */
  gm_material_batch batch = points_batch(&p, 1e-4);
  batch.geometry = GM_GEOMETRY_PLANE_STRAIN;
  char message[256] = "";
  for (int step = 0; step < 20000; step++)
    ck_assert_msg(
        gm_mohr_coulomb_update(&batch, &def, message, sizeof message) == 0,
        "step %d: %s", step, message);
  double ratio = p.stress[GM_XY][0] / -p.stress[GM_YY][0];
  fprintf(stderr, "phi %.1f: tau/sigma_n %.6f, sin phi %.6f, tan phi %.6f\n",
          angles[_i], ratio, sin(phi), tan(phi));
  ck_assert_msg(fabs(ratio - sin(phi)) < 1e-3,
                "phi %.1f deg: flowing tau/sigma_n %.6f, sin phi %.6f",
                angles[_i], ratio, sin(phi));
  points_free(&p);
}
END_TEST

/* ------------------------------------------------------ invalid parameters */

/* A non-finite stress or a batch without the state slot is a fatal (< 0)
 * failure whose message names the point id or the cause. */
/* A trial whose main-plane return lands exactly on the triaxial
 * compression edge (sigma_1 = sigma_2 after the return, in exact
 * arithmetic): round-off then breaks the ordering by an ulp on one side or
 * the other and makes the second plane's multiplier -1e-20 or so. Such a
 * point belongs on the edge (or the main plane: the same stress to
 * round-off), never at the apex, which for c = 0 is the zero stress. With
 * psi = 0 every non-apex return keeps the mean stress, so the returned mean
 * must equal the trial's to round-off (1e-12 of |sigma|), and f = 0.
 * Before the fix 74 (planar path, _i = 0) and 66 (general path, _i = 1)
 * of these 4000 states went to the apex. The edge is reached
 * from sigma = (s2 + delta, s2, s3): with b = (1, 0, -1), D b = 2 G b and
 * n . D b = 4 G, the return moves sigma_1 by -f / 2 and keeps sigma_2, so it
 * lands on the edge when delta = f / 2, f = f0 + (1 + sin phi) delta with
 * f0 = (1 + sin phi) s2 - (1 - sin phi) s3, i.e. delta = f0 / (1 - sin phi)
 * (f0 > 0 when s3 < s2 (1 + sin phi) / (1 - sin phi)). */
START_TEST(test_return_onto_edge_is_not_apex) {
  bool general = _i == 1;
  test_lcg lcg = {general ? 8080u : 9090u};
  gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
  def.youngs_modulus = 1e7;
  def.friction_angle = 0.5;
  def.dilation_angle = 0.0;
  def.bagnold_viscosity = 0.0;
  double sin_phi = sin(def.friction_angle);
  enum { STATES = 4000 };
  test_points points = points_create(STATES);
  double trial[STATES][6];
  for (int n = 0; n < STATES; n++) {
    double s2 = -lcg_range(&lcg, 1e3, 2e4); /* Pa */
    double s3 = s2 * lcg_range(&lcg, 3.0, 6.0);
    double f0 = (1.0 + sin_phi) * s2 - (1.0 - sin_phi) * s3;
    double values[3] = {s2 + f0 / (1.0 - sin_phi), s2, s3};
    double r[3][3];
    if (general)
      random_rotation(&lcg, r);
    else /* the principal axes along x, y, z in a random order */
      memset(r, 0, sizeof r);
    if (!general) {
      int first = n % 3, second = (first + 1 + (n / 3) % 2) % 3;
      r[first][0] = r[second][1] = r[3 - first - second][2] = 1.0;
    }
    rotate_diagonal(r, values, trial[n]);
    for (int c = 0; c < 6; c++)
      points.stress[c][n] = trial[n][c];
  }
  gm_material_batch batch = points_batch(&points, 1e-4);
  char message[256];
  ck_assert_int_eq(
      gm_mohr_coulomb_update(&batch, &def, message, sizeof message), 0);
  for (int n = 0; n < STATES; n++) {
    double out[6];
    for (int c = 0; c < 6; c++)
      out[c] = points.stress[c][n];
    double scale = voigt_norm(trial[n]);
    double mean_trial = (trial[n][0] + trial[n][1] + trial[n][2]) / 3.0;
    double mean = (out[0] + out[1] + out[2]) / 3.0;
    ck_assert_msg(fabs(mean - mean_trial) <= 1e-12 * scale,
                  "state %d: mean stress %g after the return, %g before "
                  "(returned to the apex?)",
                  n, mean, mean_trial);
    gm_principal principal;
    ck_assert_int_eq(gm_principal_decompose_jacobi(out, &principal), 0);
    ck_assert_double_le(fabs(yield_value(principal.value, sin_phi, 0.0)),
                        1e-12 * scale);
  }
  points_free(&points);
}
END_TEST

/* The screen (mohr_coulomb.c, screen_chunk) decides per chunk of 256 which
 * points the corrector visits: a point's update must not depend on where it
 * lies in the batch. 600 random states (plane and general 3D, inside and
 * outside the surface, with the rate term), updated in one batch across
 * three chunks, must give every point's stress and plastic shear strain
 * bit for bit as the same point updated alone. Guards the screen's row
 * compaction and offsets (an off-by-one there mixes up points). */
START_TEST(test_batch_position) {
  const size_t count = 600;
  gm_mohr_coulomb_def def = make_def(30.0 * DEG, 10.0 * DEG, SWEEP_ETA);
  test_lcg lcg = {20261128u};
  test_points all = points_create(count);
  test_points alone = points_create(1);
  test_points lone = points_create(count); /* each point's lone result */
  for (size_t i = 0; i < count; i++) {
    double stress[6], e[6];
    /* mostly plane points, as the library passes them; every fifth 3D */
    random_state(&lcg, i % 5 != 0, stress, e);
    if (i % 3 == 0) /* a third with a small increment: mostly elastic */
      for (int c = 0; c < 6; c++)
        e[c] *= 1e-3;
    for (int c = 0; c < 6; c++) {
      all.stress[c][i] = stress[c];
      all.increment[c][i] = e[c];
    }
  }
  char message[256] = "";
  size_t plastic = 0;
  for (size_t i = 0; i < count; i++) {
    for (int c = 0; c < 6; c++) {
      alone.stress[c][0] = all.stress[c][i];
      alone.increment[c][0] = all.increment[c][i];
    }
    alone.state_rows[0][0] = 0.0;
    gm_material_batch one = points_batch(&alone, SWEEP_DT);
    ck_assert_int_eq(
        gm_mohr_coulomb_update(&one, &def, message, sizeof message), 0);
    for (int c = 0; c < 6; c++)
      lone.stress[c][i] = alone.stress[c][0];
    lone.state_rows[0][i] = alone.state_rows[0][0];
    plastic += alone.state_rows[0][0] > 0.0;
  }
  gm_material_batch batch = points_batch(&all, SWEEP_DT);
  ck_assert_int_eq(
      gm_mohr_coulomb_update(&batch, &def, message, sizeof message), 0);
  for (size_t i = 0; i < count; i++) {
    for (int c = 0; c < 6; c++)
      ck_assert_msg(
          memcmp(&all.stress[c][i], &lone.stress[c][i], sizeof(double)) == 0,
          "point %zu component %d: %.17g in the batch, %.17g alone", i, c,
          all.stress[c][i], lone.stress[c][i]);
    ck_assert_msg(memcmp(&all.state_rows[0][i], &lone.state_rows[0][i],
                         sizeof(double)) == 0,
                  "point %zu: plastic shear %.17g in the batch, %.17g alone", i,
                  all.state_rows[0][i], lone.state_rows[0][i]);
  }
  /* both outcomes occur, in every chunk */
  ck_assert_uint_gt(plastic, count / 10);
  ck_assert_uint_lt(plastic, count - count / 10);
  points_free(&all);
  points_free(&alone);
  points_free(&lone);
}
END_TEST

/* A non-finite component among elastic points at rest is reported with its
 * point, whichever component and chunk it is in: the screen must send it to
 * the corrector (a NaN in xx, yy or xy makes the Mohr circle NaN, whose
 * yield value alone could pass as elastic). */
START_TEST(test_non_finite_in_any_component) {
  gm_mohr_coulomb_def def = make_def(30.0 * DEG, 0.0, 0.0);
  const double bad[3] = {NAN, INFINITY, -INFINITY};
  for (int c = 0; c < 6; c++)
    for (int v = 0; v < 3; v++) {
      test_points p = points_create(520);  /* three chunks of 256 */
      for (size_t i = 0; i < p.count; i++) /* compressed, at rest */
        p.stress[GM_XX][i] = p.stress[GM_YY][i] = p.stress[GM_ZZ][i] = -1e4;
      p.stress[c][300] = bad[v]; /* point id 400, second chunk */
      gm_material_batch batch = points_batch(&p, 1e-3);
      char message[256] = "";
      ck_assert_int_lt(
          gm_mohr_coulomb_update(&batch, &def, message, sizeof message), 0);
      ck_assert_msg(strstr(message, "400") != NULL, "component %d: %s", c,
                    message);
      points_free(&p);
    }
}
END_TEST

START_TEST(test_update_failures) {
  gm_mohr_coulomb_def def = make_def(30.0 * DEG, 0.0, 0.0);
  test_points p = points_create(2);
  p.stress[GM_XY][1] = NAN;
  gm_material_batch batch = points_batch(&p, 1e-3);
  char message[256] = "";
  ck_assert_int_lt(
      gm_mohr_coulomb_update(&batch, &def, message, sizeof message), 0);
  ck_assert_msg(strstr(message, "101") != NULL, "message: %s", message);
  batch.state_count = 0;
  ck_assert_int_lt(
      gm_mohr_coulomb_update(&batch, &def, message, sizeof message), 0);
  ck_assert_msg(strstr(message, "state") != NULL, "message: %s", message);
  points_free(&p);
}
END_TEST

static Suite *mohr_coulomb_suite(void) {
  Suite *suite = suite_create("mohr_coulomb");
  TCase *tc = tcase_create("mohr_coulomb");
  tcase_set_timeout(tc, 120);
  tcase_add_loop_test(tc, test_principal_decomposition, 0, 2);
  tcase_add_loop_test(tc, test_random_returns, 0,
                      (int)(sizeof SWEEP_CASES / sizeof SWEEP_CASES[0]));
  tcase_add_test(tc, test_triaxial_ratio);
  tcase_add_test(tc, test_bagnold_strength);
  tcase_add_loop_test(tc, test_simple_shear_flows_at_sin_phi, 0, 3);
  tcase_add_test(tc, test_update_failures);
  tcase_add_test(tc, test_batch_position);
  tcase_add_test(tc, test_non_finite_in_any_component);
  tcase_add_loop_test(tc, test_return_onto_edge_is_not_apex, 0, 2);
  suite_add_tcase(suite, tc);
  return suite;
}

int main(void) {
  return test_run_suite(mohr_coulomb_suite()) ? 1 : 0;
}
