/*
 * elastic.c - built-in isotropic linear (hypo)elastic material, written
 * against the public gm_material_update_fn interface exactly as a user
 * material would be. The library has already applied the Jaumann rotation
 * to the incoming stress (002 sec 4.1), so this is sigma += C : d_eps.
 */
#include "granmpm.h"

int gm_elastic_update(const gm_material_batch *batch, void *user, char *message,
                      size_t message_size) {
  (void)message;
  (void)message_size;
  const gm_elastic_def *elastic = user;
  double young = elastic->youngs_modulus;                     /* Pa */
  double nu = elastic->poisson_ratio;                         /* - */
  double shear = young / (2.0 * (1.0 + nu));                  /* Pa, G = mu */
  double lame = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); /* Pa */
  const double *const *de = batch->strain_increment;
  double *const *s = batch->stress;
  for (size_t i = 0; i < batch->count; i++) {
    double volumetric = de[GM_XX][i] + de[GM_YY][i] + de[GM_ZZ][i];
    double lame_term = lame * volumetric;
    s[GM_XX][i] += lame_term + 2.0 * shear * de[GM_XX][i];
    s[GM_YY][i] += lame_term + 2.0 * shear * de[GM_YY][i];
    s[GM_ZZ][i] += lame_term + 2.0 * shear * de[GM_ZZ][i];
    /* Tensor shear strains: sigma_xy = 2 G eps_xy. */
    s[GM_XY][i] += 2.0 * shear * de[GM_XY][i];
    s[GM_YZ][i] += 2.0 * shear * de[GM_YZ][i];
    s[GM_ZX][i] += 2.0 * shear * de[GM_ZX][i];
  }
  return 0;
}
