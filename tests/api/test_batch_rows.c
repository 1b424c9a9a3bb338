/*
 * test_batch_rows.c - the out-of-plane rows of a material batch in 1D and
 * 2D, as granmpm.h (the GM_XX..GM_ZX enum) and gm_materials(3) (the
 * update callback, strain_increment and stress) both say: all six
 * pointers of strain_increment and stress are valid in every geometry;
 * in 1D, plane strain and axisymmetry the yz and zx rows arrive zero and
 * what a material writes into the stress ones is discarded; the points do
 * not store those components (gm_domain_view_field gives
 * GM_ERR_UNSUPPORTED, gm_domain_get_field copies zeros). Issue 12 item 7:
 * the header had said the rows were "not stored" while the man page said
 * all six pointers are valid.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <stdlib.h>

#include "test_util.h"

/* What the callback saw over all its calls. */
typedef struct rows_seen {
  int calls;
  int null_pointers; /* NULL strain_increment or stress rows */
  int nonzero_yz_zx; /* nonzero yz or zx entries on entry */
  int nonzero_plane; /* nonzero in-plane strain increments (the scene
                        deforms, so the rows carry something) */
} rows_seen;

static int write_out_of_plane(const gm_material_batch *batch, void *user,
                              char *message, size_t message_size) {
  (void)message;
  (void)message_size;
  rows_seen *seen = user;
  seen->calls++;
  for (int c = 0; c < 6; c++)
    if (!batch->strain_increment[c] || !batch->stress[c])
      seen->null_pointers++;
  if (seen->null_pointers)
    return 0;
  for (size_t i = 0; i < batch->count; i++) {
    if (batch->strain_increment[GM_YZ][i] != 0.0 ||
        batch->strain_increment[GM_ZX][i] != 0.0 ||
        batch->stress[GM_YZ][i] != 0.0 || batch->stress[GM_ZX][i] != 0.0)
      seen->nonzero_yz_zx++;
    if (batch->strain_increment[GM_XX][i] != 0.0)
      seen->nonzero_plane++;
    /* A linear elastic response in xx (Pa), and values in the rows that
     * must be discarded. */
    batch->stress[GM_XX][i] += 1e6 * batch->strain_increment[GM_XX][i];
    batch->stress[GM_YZ][i] = 123.0;
    batch->stress[GM_ZX][i] = -45.0;
  }
  return 0;
}

/* _i: 1D, plane strain, axisymmetric. */
START_TEST(test_out_of_plane_rows) {
  static const gm_geometry geometries[3] = {
      GM_GEOMETRY_1D, GM_GEOMETRY_PLANE_STRAIN, GM_GEOMETRY_AXISYMMETRIC};
  gm_geometry geometry = geometries[_i];
  gm_domain_def def = gm_domain_def_default();
  def.geometry = geometry;
  def.cell_size = 0.1;
  def.origin[0] = 0.1; /* off the axis in axisymmetry */
  gm_domain *domain = test_create_domain(&def);
  rows_seen seen = {0, 0, 0, 0};
  gm_material_def material = gm_material_def_default();
  material.update = write_out_of_plane;
  material.user = &seen;
  material.p_wave_modulus = 1e6; /* Pa */
  material.density = 1000.0;     /* kg/m^3 */
  int id = -1;
  TEST_ASSERT_OK(domain, gm_domain_add_material(domain, &material, &id));
  /* A block stretched along x: v_x = x (1/s) - 0.5. */
  const double lower[3] = {0.3, 0.3, 0.0}, upper[3] = {0.7, 0.7, 0.0};
  size_t count = test_fill_box(domain, id, lower, upper, 2, NULL);
  double *velocity = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_edit_field(domain, GM_FIELD_VELOCITY, 0, &velocity));
  const double *x = NULL;
  TEST_ASSERT_OK(domain,
                 gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x));
  for (size_t p = 0; p < count; p++)
    velocity[p] = x[p] - 0.5;
  for (int step = 0; step < 5; step++)
    TEST_ASSERT_OK(domain, gm_domain_step(domain, 1e-3));
  ck_assert_int_gt(seen.calls, 0);
  ck_assert_msg(seen.null_pointers == 0, "geometry %d: %d NULL rows",
                (int)geometry, seen.null_pointers);
  ck_assert_msg(seen.nonzero_yz_zx == 0,
                "geometry %d: %d points saw nonzero yz/zx rows on entry "
                "(the values written in the previous step were kept)",
                (int)geometry, seen.nonzero_yz_zx);
  ck_assert_msg(seen.nonzero_plane > 0, "geometry %d: no strain increment",
                (int)geometry);
  double *stress = malloc(6 * count * sizeof *stress);
  ck_assert_ptr_nonnull(stress);
  TEST_ASSERT_OK(
      domain, gm_domain_get_field(domain, GM_FIELD_STRESS, stress, 6 * count));
  int stretched = 0;
  for (size_t p = 0; p < count; p++) {
    ck_assert_msg(stress[6 * p + GM_YZ] == 0.0 && stress[6 * p + GM_ZX] == 0.0,
                  "geometry %d, point %zu: stored yz %g, zx %g", (int)geometry,
                  p, stress[6 * p + GM_YZ], stress[6 * p + GM_ZX]);
    stretched += stress[6 * p + GM_XX] > 0.0;
  }
  ck_assert_msg(stretched > 0, "geometry %d: the xx stress was not kept",
                (int)geometry);
  free(stress);
  const double *view = NULL;
  ck_assert_int_eq(gm_domain_view_field(domain, GM_FIELD_STRESS, GM_YZ, &view),
                   GM_ERR_UNSUPPORTED);
  ck_assert_int_eq(gm_domain_view_field(domain, GM_FIELD_STRESS, GM_ZX, &view),
                   GM_ERR_UNSUPPORTED);
  gm_domain_destroy(domain);
}
END_TEST

int main(void) {
  Suite *suite = suite_create("batch_rows");
  TCase *tcase = tcase_create("out of plane");
  tcase_add_loop_test(tcase, test_out_of_plane_rows, 0, 3);
  suite_add_tcase(suite, tcase);
  return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
