/*
 * test_materials_3d.c - every built-in material on general 3D states (all
 * six stress and strain-increment components non-zero, as a
 * GM_GEOMETRY_3D batch will carry them), through the public update
 * functions:
 *   - isotropy: the update of a rotated state (R sigma R^T, R d_eps R^T) is
 *     the rotated update, for random rotations about arbitrary axes, for
 *     elastic, Mohr-Coulomb, Drucker-Prager, von Mises, Perzyna, mu(I),
 *     filling and stress-free, with states that stay elastic, yield, reach
 *     the Mohr-Coulomb edges and apex, or are in tension. A model that
 *     treated yz, zx as a plane model does (dropped, counted once, or left
 *     out of an invariant) fails this by O(1);
 *   - the yield surfaces in 3D: a trial driven past yield returns onto the
 *     surface, Mohr-Coulomb's (s1 - s3) = 2 c cos(phi) - (s1 + s3) sin(phi)
 *     (000 eq 16, tension positive, principal stresses from the Jacobi
 *     reference) keeping the trial's principal directions, Drucker-Prager's
 *     q = m p and von Mises's q = sigma_y keeping p and the deviator's
 *     direction;
 *   - plane states (yz = zx = 0) against the same states turned by a
 *     quarter turn about x (an exact permutation with signs, after which
 *     zx != 0): the plane closed form of Mohr-Coulomb against its general
 *     3D path, and every other model against itself.
 *
 * Tolerances are relative to the stress scale S of each case (the larger
 * of |sigma| and |C : d_eps|): the inputs of the two sides differ by the
 * rounding of the rotation (a few eps S), the returns are Lipschitz
 * projections (they do not amplify that by more than a small factor), and
 * the iterative solves (Perzyna N != 1, mu(I)'s regularised branch)
 * converge to 1e-14-1e-15 relative: 1e-12 S bounds all of it with margin
 * while a 2D-only treatment of a shear component errs by O(S). Measured:
 * under 2e-15 S for every model but filling, 3e-13 S for filling, whose
 * bulk-viscous pressure (up to ~1e6 Pa at these compaction rates) is far
 * above its S (so its round-off, 1e-16 of it, is 1e-13 of S).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "test_util.h"

#include <check.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "granmpm.h"
#include "granmpm/drucker_prager.h"
#include "granmpm/filling.h"
#include "granmpm/mohr_coulomb.h"
#include "granmpm/mu_i.h"
#include "granmpm/perzyna.h"
#include "granmpm/stress_free.h"
#include "granmpm/von_mises.h"
#include "materials/principal.h"
#include "test_random.h"
#include "test_tensor3.h"

enum { POINTS = 2000, STATES = 2 };

/* A hand-built 3D batch of POINTS points with STATES state columns. */
typedef struct batch3d {
  double strain[6][POINTS]; /* -, tensor shear components */
  double stress[6][POINTS]; /* Pa */
  double density[POINTS];   /* kg/m^3 */
  double state[STATES][POINTS];
  double *state_columns[STATES];
  int64_t id[POINTS];
  gm_material_batch batch;
} batch3d;

static batch3d *batch_create(void) {
  batch3d *b = calloc(1, sizeof *b);
  ck_assert_ptr_nonnull(b);
  b->batch.struct_size = sizeof b->batch;
  b->batch.count = POINTS;
  b->batch.geometry = GM_GEOMETRY_3D;
  b->batch.dt = 1e-4; /* s */
  for (int c = 0; c < 6; c++) {
    b->batch.strain_increment[c] = b->strain[c];
    b->batch.stress[c] = b->stress[c];
  }
  for (int k = 0; k < STATES; k++)
    b->state_columns[k] = b->state[k];
  b->batch.state = b->state_columns;
  b->batch.state_count = STATES;
  b->batch.density = b->density;
  b->batch.point_id = b->id;
  for (int i = 0; i < POINTS; i++)
    b->id[i] = i;
  return b;
}

/* --------------------------------------------------------- tensor helpers */

/* A random rotation (about a random axis by a random angle, Rodrigues). */
static void random_rotation(double r[3][3]) {
  double axis[3];
  random_unit_axis(axis);
  double angle = lcg_between(-3.14159265358979, 3.14159265358979);
  double k[3][3] = {{0.0, -axis[2], axis[1]},
                    {axis[2], 0.0, -axis[0]},
                    {-axis[1], axis[0], 0.0}};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      double k2 = 0.0;
      for (int q = 0; q < 3; q++)
        k2 += k[i][q] * k[q][j];
      r[i][j] = (i == j) + sin(angle) * k[i][j] + (1.0 - cos(angle)) * k2;
    }
}

/* ------------------------------------------------------------- materials */

/* One built-in model with its parameters and the scales of its states. */
typedef struct model_case {
  const char *name;
  gm_material_update_fn *update;
  void *parameters;
  double stress_scale; /* S, Pa: the size of the states tested */
  double stiffness;    /* E, Pa: strain increments of size S / E */
  double density;      /* kg/m^3 of the points */
  double state_scale;  /* the size of the state's change, for its bound */
} model_case;

static gm_elastic_def elastic;
static gm_mohr_coulomb_def mohr_coulomb;
static gm_drucker_prager_def drucker_prager;
static gm_von_mises_def von_mises;
static gm_perzyna_def perzyna, perzyna_power;
static gm_mu_i_def mu_i;
static gm_filling_def filling;
static gm_stress_free_def stress_free;

enum { MODEL_COUNT = 9 };
static model_case models[MODEL_COUNT];

static void setup_models(void) {
  elastic = gm_elastic_def_default();
  mohr_coulomb = gm_mohr_coulomb_def_default();
  mohr_coulomb.youngs_modulus = 1e7;
  mohr_coulomb.dilation_angle = 0.2;
  mohr_coulomb.bagnold_viscosity = 0.15; /* the rate term in play */
  drucker_prager = gm_drucker_prager_def_default();
  von_mises = gm_von_mises_def_default();
  perzyna = gm_perzyna_def_default();
  perzyna_power = gm_perzyna_def_default();
  perzyna_power.exponent = 2.5; /* the iterated return */
  perzyna_power.reference_stress = 500.0;
  mu_i = gm_mu_i_def_default();
  filling = gm_filling_def_default();
  stress_free = gm_stress_free_def_default();
  /* state_scale: the states are strains, computed from stress drops over
   * the shear modulus: S / G ~ 3 S / E. */
  models[0] = (model_case){"elastic", gm_elastic_update,      &elastic,
                           1e3,       elastic.youngs_modulus, 1000.0,
                           0.0};
  models[1] = (model_case){"mohr_coulomb",
                           gm_mohr_coulomb_update,
                           &mohr_coulomb,
                           1e4,
                           1e7,
                           2250.0,
                           3e-3};
  models[2] = (model_case){"drucker_prager",
                           gm_drucker_prager_update,
                           &drucker_prager,
                           1e3,
                           1e6,
                           1500.0,
                           3e-3};
  models[3] = (model_case){
      "von_mises", gm_von_mises_update, &von_mises, 1.5e7, 2e11, 7800.0, 6e-4};
  models[4] = (model_case){
      "perzyna", gm_perzyna_update, &perzyna, 1e3, 1e6, 1500.0, 3e-3};
  models[5] = (model_case){"perzyna N=2.5",
                           gm_perzyna_update,
                           &perzyna_power,
                           1e3,
                           1e6,
                           1500.0,
                           3e-3};
  models[6] =
      (model_case){"mu_i", gm_mu_i_update, &mu_i, 1e3, 1e6, 1500.0, 3e-3};
  /* Filling: the pressure comes from the density (points a little denser
   * than rho0 carry ~1-5 kPa); its shear modulus grows with it. */
  models[7] = (model_case){
      "filling", gm_filling_update, &filling, 2e3, 3e5, 1520.0, 3e-2};
  models[8] = (model_case){"stress_free",
                           gm_stress_free_update,
                           &stress_free,
                           1e3,
                           1e6,
                           1500.0,
                           0.0};
}

/* Random 3D states of scale S: a compressive mean of 0.3-1.5 S (one point
 * in six in tension instead) plus a deviator of up to S per component,
 * and strain increments of up to 2 S / E per component, one point in three
 * with a larger deviatoric stretch: elastic points, yielding points (the
 * Mohr-Coulomb main plane, edges, apex), tension cut-offs. */
static void random_states(batch3d *b, const model_case *m) {
  double s = m->stress_scale, strain = s / m->stiffness;
  for (int i = 0; i < POINTS; i++) {
    double mean = -s * lcg_between(0.3, 1.5);
    if (i % 6 == 5)
      mean = s * lcg_between(0.0, 0.5);
    for (int c = 0; c < 6; c++) {
      b->stress[c][i] = (c < 3 ? mean : 0.0) + s * lcg_between(-1.0, 1.0);
      b->strain[c][i] = strain * lcg_between(-2.0, 2.0);
      if (i % 3 == 0)
        b->strain[c][i] *= 5.0;
    }
    b->density[i] = m->density * lcg_between(1.0, 1.02);
    for (int k = 0; k < STATES; k++)
      b->state[k][i] = 0.0;
  }
}

static void run(const model_case *m, batch3d *b) {
  char message[256] = "";
  int result = m->update(&b->batch, m->parameters, message, sizeof message);
  ck_assert_msg(result == 0, "%s: update returned %d: %s", m->name, result,
                message);
}

/* The isotropy check of one model: b holds the inputs; returns the worst
 * error in units of S. */
static double check_rotated_update(const model_case *m, const batch3d *b,
                                   double (*rotations)[3][3]) {
  batch3d *plain = malloc(sizeof *plain), *turned = malloc(sizeof *turned);
  ck_assert(plain && turned);
  memcpy(plain, b, sizeof *b);
  memcpy(turned, b, sizeof *b);
  for (batch3d *x = plain; x; x = x == plain ? turned : NULL) {
    for (int c = 0; c < 6; c++) {
      x->batch.strain_increment[c] = x->strain[c];
      x->batch.stress[c] = x->stress[c];
    }
    for (int k = 0; k < STATES; k++)
      x->state_columns[k] = x->state[k];
    x->batch.state = x->state_columns;
    x->batch.density = x->density;
    x->batch.point_id = x->id;
  }
  for (int i = 0; i < POINTS; i++) {
    double in[6], out[6];
    for (int c = 0; c < 6; c++)
      in[c] = b->stress[c][i];
    voigt_rotate(rotations[i], in, out);
    for (int c = 0; c < 6; c++) {
      turned->stress[c][i] = out[c];
      in[c] = b->strain[c][i];
    }
    voigt_rotate(rotations[i], in, out);
    for (int c = 0; c < 6; c++)
      turned->strain[c][i] = out[c];
  }
  run(m, plain);
  run(m, turned);
  double worst = 0.0;
  for (int i = 0; i < POINTS; i++) {
    double sigma[6], increment[6], expected[6], got[6];
    for (int c = 0; c < 6; c++) {
      sigma[c] = b->stress[c][i];
      increment[c] = b->strain[c][i];
      got[c] = turned->stress[c][i];
    }
    double scale =
        fmax(voigt_norm(sigma), m->stiffness * voigt_norm(increment));
    double result[6];
    for (int c = 0; c < 6; c++)
      result[c] = plain->stress[c][i];
    voigt_rotate(rotations[i], result, expected);
    for (int c = 0; c < 6; c++) {
      double error = fabs(got[c] - expected[c]) / scale;
      worst = fmax(worst, error);
      ck_assert_msg(error <= 1e-12,
                    "%s point %d: component %d of the rotated update %.17g, "
                    "rotated plain update %.17g (%g S)",
                    m->name, i, c, got[c], expected[c], error);
    }
    for (int k = 0; k < STATES; k++) {
      double error = fabs(turned->state[k][i] - plain->state[k][i]);
      ck_assert_msg(error <= 1e-12 * fmax(m->state_scale, 1e-300) ||
                        error <= 1e-12 * fabs(plain->state[k][i]),
                    "%s point %d: state %d %.17g against %.17g", m->name, i, k,
                    turned->state[k][i], plain->state[k][i]);
    }
  }
  free(plain);
  free(turned);
  return worst;
}

START_TEST(test_rotated_update_is_rotated) {
  setup_models();
  const model_case *m = &models[_i];
  lcg_state = 1000u + (unsigned)_i;
  batch3d *b = batch_create();
  random_states(b, m);
  double(*rotations)[3][3] = malloc(POINTS * sizeof *rotations);
  ck_assert_ptr_nonnull(rotations);
  for (int i = 0; i < POINTS; i++)
    random_rotation(rotations[i]);
  double worst = check_rotated_update(m, b, rotations);
  printf("isotropy %-14s worst %.2g S\n", m->name, worst);
  free(rotations);
  free(b);
}
END_TEST

/* Plane states against the same states after a quarter turn about x:
 * (x, y, z) -> (x, -z, y), exact in floating point, which moves xy into zx
 * so the turned state is general. */
START_TEST(test_plane_states_against_general_path) {
  setup_models();
  const model_case *m = &models[_i];
  lcg_state = 2000u + (unsigned)_i;
  batch3d *b = batch_create();
  random_states(b, m);
  for (int i = 0; i < POINTS; i++)
    b->stress[GM_YZ][i] = b->stress[GM_ZX][i] = b->strain[GM_YZ][i] =
        b->strain[GM_ZX][i] = 0.0;
  double(*rotations)[3][3] = malloc(POINTS * sizeof *rotations);
  ck_assert_ptr_nonnull(rotations);
  static const double quarter[3][3] = {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}};
  for (int i = 0; i < POINTS; i++)
    memcpy(rotations[i], quarter, sizeof quarter);
  double worst = check_rotated_update(m, b, rotations);
  printf("plane vs general %-14s worst %.2g S\n", m->name, worst);
  free(rotations);
  free(b);
}
END_TEST

/* --------------------------------------------------------- yield surfaces */

/* Mohr-Coulomb: trials with random principal values in random
 * orientations, past the surface; the rate term on (c = eta gammadot^2,
 * gammadot = sqrt(2 d':d') / dt, 000 eq 16). */
START_TEST(test_mohr_coulomb_surface_3d) {
  setup_models();
  lcg_state = 3001u;
  gm_mohr_coulomb_def def = mohr_coulomb;
  double sin_phi = sin(def.friction_angle), cos_phi = cos(def.friction_angle);
  double shear = def.youngs_modulus / (2.0 * (1.0 + def.poisson_ratio));
  double lame = def.youngs_modulus * def.poisson_ratio /
                ((1.0 + def.poisson_ratio) * (1.0 - 2.0 * def.poisson_ratio));
  batch3d *b = batch_create();
  random_states(b, &models[1]);
  double trial[6][POINTS];
  for (int i = 0; i < POINTS; i++) { /* elastic predictor, in the test */
    double e[6];
    for (int c = 0; c < 6; c++)
      e[c] = b->strain[c][i];
    double volumetric = e[0] + e[1] + e[2];
    for (int c = 0; c < 6; c++)
      trial[c][i] = b->stress[c][i] + 2.0 * shear * e[c] +
                    (c < 3 ? lame * volumetric : 0.0);
  }
  run(&models[1], b);
  int plastic = 0, apex = 0;
  for (int i = 0; i < POINTS; i++) {
    double e[6], out[6], in[6];
    for (int c = 0; c < 6; c++) {
      e[c] = b->strain[c][i];
      out[c] = b->stress[c][i];
      in[c] = trial[c][i];
    }
    double mean = (e[0] + e[1] + e[2]) / 3.0, dd = 0.0;
    for (int c = 0; c < 6; c++)
      dd += (c < 3 ? 1.0 : 2.0) * (e[c] - (c < 3 ? mean : 0.0)) *
            (e[c] - (c < 3 ? mean : 0.0));
    double rate = sqrt(2.0 * dd) / b->batch.dt;            /* 1/s */
    double cohesion = def.bagnold_viscosity * rate * rate; /* Pa */
    gm_principal before, after;
    ck_assert_int_eq(gm_principal_decompose_jacobi(in, &before), 0);
    ck_assert_int_eq(gm_principal_decompose_jacobi(out, &after), 0);
    double scale = voigt_norm(in);
    double f_trial = (before.value[0] - before.value[2]) +
                     (before.value[0] + before.value[2]) * sin_phi -
                     2.0 * cohesion * cos_phi;
    double f = (after.value[0] - after.value[2]) +
               (after.value[0] + after.value[2]) * sin_phi -
               2.0 * cohesion * cos_phi;
    if (f_trial <= -1e-12 * scale) {
      /* Inside: the trial itself, to the rounding of the predictor written
       * two ways (here and in the library). */
      for (int c = 0; c < 6; c++)
        ck_assert_double_le(fabs(out[c] - in[c]), 1e-14 * scale);
      continue;
    }
    if (f_trial <= 1e-12 * scale)
      continue; /* on the surface to round-off: either answer is right */
    plastic++;
    /* On the surface, to round-off of the stress (1e-12 S, see top). */
    ck_assert_msg(fabs(f) <= 1e-12 * scale,
                  "point %d: f = %g after the return (trial f %g, |s| %g)", i,
                  f, f_trial, scale);
    if (after.value[0] - after.value[2] <= 1e-12 * scale)
      apex++;
    /* Principal directions kept: the result commutes with the trial. */
    double a[3][3], t[3][3];
    voigt_to_matrix(out, a);
    voigt_to_matrix(in, t);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        double commutator = 0.0;
        for (int k = 0; k < 3; k++)
          commutator += a[r][k] * t[k][c] - t[r][k] * a[k][c];
        ck_assert_msg(fabs(commutator) <= 1e-12 * scale * scale,
                      "point %d: [sigma, trial] (%d,%d) = %g", i, r, c,
                      commutator);
      }
  }
  printf("mohr-coulomb 3D: %d of %d points returned (%d to the apex)\n",
         plastic, POINTS, apex);
  ck_assert_int_gt(plastic, POINTS / 4); /* the returns were exercised */
  ck_assert_int_gt(apex, 0);
  free(b);
}
END_TEST

/* p and q (Pa) of a Voigt stress, and its deviator. */
static void split(const double v[6], double *p, double *q, double s[6]) {
  *p = -(v[0] + v[1] + v[2]) / 3.0;
  for (int c = 0; c < 6; c++)
    s[c] = v[c] + (c < 3 ? *p : 0.0);
  *q = sqrt(1.5 * (s[0] * s[0] + s[1] * s[1] + s[2] * s[2] +
                   2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])));
}

/* Drucker-Prager (q = m p, m = 18 sin(phi) / (9 - sin^2(phi)), 002 sec 2.2)
 * and von Mises (q = sigma_y): returned trials sit on the surface with the
 * trial's p and deviator direction. */
START_TEST(test_invariant_surfaces_3d) {
  setup_models();
  for (int which = 0; which < 2; which++) {
    const model_case *m = &models[which == 0 ? 2 : 3];
    lcg_state = 3100u + (unsigned)which;
    batch3d *b = batch_create();
    random_states(b, m);
    double trial[6][POINTS];
    double young =
        which == 0 ? drucker_prager.youngs_modulus : von_mises.youngs_modulus;
    double nu =
        which == 0 ? drucker_prager.poisson_ratio : von_mises.poisson_ratio;
    double shear = young / (2.0 * (1.0 + nu));
    double lame = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    for (int i = 0; i < POINTS; i++) {
      double volumetric = b->strain[0][i] + b->strain[1][i] + b->strain[2][i];
      for (int c = 0; c < 6; c++)
        trial[c][i] = b->stress[c][i] + 2.0 * shear * b->strain[c][i] +
                      (c < 3 ? lame * volumetric : 0.0);
    }
    run(m, b);
    double sin_phi = sin(drucker_prager.friction_angle);
    double slope = 18.0 * sin_phi / (9.0 - sin_phi * sin_phi);
    int plastic = 0;
    for (int i = 0; i < POINTS; i++) {
      double in[6], out[6], s_in[6], s_out[6], p_in, q_in, p, q;
      for (int c = 0; c < 6; c++) {
        in[c] = trial[c][i];
        out[c] = b->stress[c][i];
      }
      split(in, &p_in, &q_in, s_in);
      split(out, &p, &q, s_out);
      double scale = voigt_norm(in);
      double limit = which == 0 ? slope * p_in : von_mises.yield_stress;
      if (q_in <= limit * (1.0 - 1e-12))
        continue;                      /* inside */
      if (which == 0 && p_in <= 0.0) { /* tension: separated */
        ck_assert_double_le(voigt_norm(out), 0.0);
        continue;
      }
      plastic++;
      ck_assert_msg(fabs(q - limit) <= 1e-12 * scale,
                    "%s point %d: q = %.17g, surface %.17g", m->name, i, q,
                    limit);
      ck_assert_double_le(fabs(p - p_in), 1e-12 * scale);
      for (int c = 0; c < 6; c++) /* s parallel to the trial deviator */
        ck_assert_double_le(fabs(s_out[c] * q_in - s_in[c] * q),
                            1e-12 * scale * q_in);
    }
    printf("%s 3D: %d of %d points returned\n", m->name, plastic, POINTS);
    ck_assert_int_gt(plastic, POINTS / 10);
    free(b);
  }
}
END_TEST

int main(void) {
  Suite *suite = suite_create("materials_3d");
  TCase *tc = tcase_create("materials_3d");
  tcase_set_timeout(tc, 60);
  tcase_add_loop_test(tc, test_rotated_update_is_rotated, 0, MODEL_COUNT);
  tcase_add_loop_test(tc, test_plane_states_against_general_path, 0,
                      MODEL_COUNT);
  tcase_add_test(tc, test_mohr_coulomb_surface_3d);
  tcase_add_test(tc, test_invariant_surfaces_3d);
  suite_add_tcase(suite, tc);
  return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
