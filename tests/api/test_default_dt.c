/*
 * test_default_dt.c - the stable time step each built-in material gives
 * with its default def, against the number its man page prints (issue 12
 * item 7: the built-in materials default to the papers' data, 000 Table 3
 * for Mohr-Coulomb with E = 1 GPa, and each page says what that does to
 * the stable dt). A block of points at rest, 0.01 m cells, the default
 * Courant number 0.5: gm_domain_stable_dt gives cfl h / c_p with c_p =
 * sqrt(M / rho) (gm_domain_step(3)), which must equal the printed value
 * to its last printed digit (half a unit of it: the rounding).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_util.h"

#include "granmpm/drucker_prager.h"
#include "granmpm/filling.h"
#include "granmpm/mohr_coulomb.h"
#include "granmpm/mu_i.h"
#include "granmpm/perzyna.h"
#include "granmpm/stress_free.h"
#include "granmpm/von_mises.h"

enum {
  ELASTIC,
  MOHR_COULOMB,
  DRUCKER_PRAGER,
  PERZYNA,
  FILLING,
  VON_MISES,
  STRESS_FREE,
  MU_I,
  MATERIAL_COUNT
};

/* The printed step (s) and the unit of its last printed digit (s). */
typedef struct printed_dt {
  const char *page;
  double dt;
  double unit;
} printed_dt;

static const printed_dt PRINTED[MATERIAL_COUNT] = {
    {"gm_materials(3), built-in elastic", 1.36e-4, 0.01e-4},
    {"gm_plasticity(3), Mohr-Coulomb", 6.46e-6, 0.01e-6},
    {"gm_plasticity(3), Drucker-Prager", 1.67e-4, 0.01e-4},
    {"gm_plasticity(3), Perzyna", 1.67e-4, 0.01e-4},
    {"gm_plasticity(3), filling", 4.94e-5, 0.01e-5},
    {"gm_plasticity(3), von Mises", 8.51e-7, 0.01e-7},
    {"gm_plasticity(3), stress-free", 1.67e-4, 0.01e-4},
    {"gm_plasticity(3), mu(I)", 1.67e-4, 0.01e-4},
};

static int add_default(gm_domain *domain, int which) {
  int id = -1;
  gm_status status = GM_ERR_INVALID_ARGUMENT;
  switch (which) {
  case ELASTIC: {
    gm_elastic_def def = gm_elastic_def_default();
    status = gm_domain_add_elastic(domain, &def, &id);
    break;
  }
  case MOHR_COULOMB: {
    gm_mohr_coulomb_def def = gm_mohr_coulomb_def_default();
    status = gm_domain_add_mohr_coulomb(domain, &def, &id);
    break;
  }
  case DRUCKER_PRAGER: {
    gm_drucker_prager_def def = gm_drucker_prager_def_default();
    status = gm_domain_add_drucker_prager(domain, &def, &id);
    break;
  }
  case PERZYNA: {
    gm_perzyna_def def = gm_perzyna_def_default();
    status = gm_domain_add_perzyna(domain, &def, &id);
    break;
  }
  case FILLING: {
    gm_filling_def def = gm_filling_def_default();
    status = gm_domain_add_filling(domain, &def, &id);
    break;
  }
  case VON_MISES: {
    gm_von_mises_def def = gm_von_mises_def_default();
    status = gm_domain_add_von_mises(domain, &def, &id);
    break;
  }
  case STRESS_FREE: {
    gm_stress_free_def def = gm_stress_free_def_default();
    status = gm_domain_add_stress_free(domain, &def, &id);
    break;
  }
  case MU_I: {
    gm_mu_i_def def = gm_mu_i_def_default();
    status = gm_domain_add_mu_i(domain, &def, &id);
    break;
  }
  default:
    break;
  }
  TEST_ASSERT_OK(domain, status);
  return id;
}

START_TEST(test_printed_stable_dt) {
  const printed_dt *printed = &PRINTED[_i];
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = 0.01; /* m */
  def.extent[0] = def.extent[1] = 0.1;
  gm_domain *domain = test_create_domain(&def);
  int id = add_default(domain, _i);
  const double lower[3] = {0.03, 0.03, 0.0}, upper[3] = {0.05, 0.05, 0.0};
  test_fill_box(domain, id, lower, upper, 2, NULL);
  double dt = 0.0;
  TEST_ASSERT_OK(domain, gm_domain_stable_dt(domain, &dt));
  if (getenv("GM_VERBOSE"))
    fprintf(stderr, "%s: %.6g s, printed %.3g s\n", printed->page, dt,
            printed->dt);
  ck_assert_msg(fabs(dt - printed->dt) <= 0.5 * printed->unit,
                "%s: stable dt %.6g s with the defaults, the page prints "
                "%.3g s",
                printed->page, dt, printed->dt);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("default_dt");
  TCase *tcase = tcase_create("printed");
  tcase_add_loop_test(tcase, test_printed_stable_dt, 0, MATERIAL_COUNT);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
