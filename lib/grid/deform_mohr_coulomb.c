/*
 * deform_mohr_coulomb.c - the deformation pass of Mohr-Coulomb plane points
 * fused, on the pattern of deform_elastic.c: F <- (I + L dt) F and V =
 * det F V0 (004 eq 3.23) in one loop; the Jaumann rotation of the stress
 * (002 sec 4.1, 004 eqs 3.20-3.21) and the elastic predictor (Hooke's law,
 * the same arithmetic as gm_mohr_coulomb_update's and gm_elastic_update's)
 * in a second, the trial stress written once to the next buffer; then the
 * material's own screen and plane return (gm_mohr_coulomb_plane_returns,
 * 000 eqs 16-17) on those rows while they are in L1.
 *
 * The general path (g2p.c deform_chunk, stress_update.c prepare_rows and
 * call_material, then gm_check_stress_chunk) streams the chunk through
 * scratch rows of strain increments, densities and stress components yz,
 * zx, copies the state columns in and out, and runs the predictor as a
 * separate loop over the stress it has just rotated. This pass gives every
 * bit of F, V, the stress and the plastic shear strain that path gives:
 * the same expressions in the same order (no FMA contraction under ISO C),
 * and the corrector is the material's. It is taken for a chunk whose one
 * material is the built-in Mohr-Coulomb model without the rate term
 * (bagnold_viscosity = 0: the screen then needs no strain rows), in plane
 * strain with committed F and stress. A chunk with a non-finite trial
 * stress is handed back to the general stress update, which reports it
 * with the material's message; an inverted point is reported as in the
 * general path.
 */
#include "grid/grid.h"

#include "grid/transfer.h"
#include "materials/materials.h"

#include <math.h>
#include <string.h>

bool gm_mohr_coulomb_chunk_fits(const gm_domain *domain, int material) {
  const gm_material *m = &domain->materials[material];
  if (m->update != gm_mohr_coulomb_update)
    return false;
  const gm_mohr_coulomb_def *def = m->user;
  return def->bagnold_viscosity == 0.0;
}

bool gm_deform_mohr_coulomb_chunk(gm_domain *domain, const gather_view *v,
                                  gm_worker_scratch *scratch, size_t first,
                                  size_t count, const chunk_gather *g,
                                  double dt) {
  gm_points *points = &domain->points;
  const gm_material *material = &domain->materials[points->material[first]];
  const gm_mohr_coulomb_def *def = material->user;
  /* The moduli exactly as gm_mohr_coulomb_update derives them. */
  double young = def->youngs_modulus;                         /* Pa */
  double nu = def->poisson_ratio;                             /* - */
  double shear = young / (2.0 * (1.0 + nu));                  /* Pa, G */
  double lame = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); /* Pa */
  const gm_point_buffers *from = &points->buffer[points->cur];
  gm_point_buffers *to = &points->buffer[points->cur ^ 1];
  /* Committed and next buffers are distinct arrays (not in place). */
  const double *restrict f_xx = v->deformation[F_XX] + first;
  const double *restrict f_xy = v->deformation[F_XY] + first;
  const double *restrict f_yx = v->deformation[F_YX] + first;
  const double *restrict f_yy = v->deformation[F_YY] + first;
  double *restrict n_xx = v->next_deformation[F_XX] + first;
  double *restrict n_xy = v->next_deformation[F_XY] + first;
  double *restrict n_yx = v->next_deformation[F_YX] + first;
  double *restrict n_yy = v->next_deformation[F_YY] + first;
  const double *restrict initial_volume = v->initial_volume + first;
  double *restrict volume = v->next_volume + first;
  const double *restrict l_xx = g->gradient[0], *restrict l_xy = g->gradient[1];
  const double *restrict l_yx = g->gradient[2], *restrict l_yy = g->gradient[3];
  const double *restrict l_zz = g->gradient[4];
  bool positive = true;
  for (size_t j = 0; j < count; j++) { /* deform_chunk (g2p.c) */
    double jacobian = gm_deform_plane_point(
        dt, l_xx[j], l_xy[j], l_yx[j], l_yy[j], f_xx[j], f_xy[j], f_yx[j],
        f_yy[j], &n_xx[j], &n_xy[j], &n_yx[j], &n_yy[j]);
    volume[j] = jacobian * initial_volume[j];
    positive &= jacobian > 0.0 && jacobian < INFINITY;
  }
  if (v->next_domain_map[0]) /* CPDI: D takes F's increment (g2p.c) */
    gm_deform_domain_map_chunk(v, first, count, g, dt);
  if (!positive) { /* the general path skips the material call: so do we */
    gm_report_inverted_chunk(domain, v, scratch, first, count, dt);
    return false;
  }
  const double *restrict sxx = from->stress[0] + first;
  const double *restrict syy = from->stress[1] + first;
  const double *restrict szz = from->stress[2] + first;
  const double *restrict sxy = from->stress[3] + first;
  double *restrict rxx = to->stress[0] + first;
  double *restrict ryy = to->stress[1] + first;
  double *restrict rzz = to->stress[2] + first;
  double *restrict rxy = to->stress[3] + first;
  /* x * 0 is NaN exactly when x is not finite (a sum that overflows only
   * sends the chunk to the general path, which decides exactly) */
  double screen = 0.0;
  for (size_t j = 0; j < count; j++) {
    /* Jaumann rotation and the elastic trial (elastic_trials, mohr_coulomb.c)
     * (transfer.h) */
    const double s[4] = {sxx[j], syy[j], szz[j], sxy[j]}; /* Pa */
    double r[4];                                          /* Pa */
    gm_plane_hooke_trial(dt, lame, shear, l_xx[j], l_xy[j], l_yx[j], l_yy[j],
                         l_zz[j], s, r);
    rxx[j] = r[0];
    ryy[j] = r[1];
    rzz[j] = r[2];
    rxy[j] = r[3];
    screen += (r[0] + r[1] + r[2] + r[3]) * 0.0;
  }
  /* The state columns (call_material): committed values into the next
   * buffer, where the return adds its plastic shear strain. */
  size_t stride = points->state_stride;
  const double *state_from = from->state + first * stride;
  double *state_to = to->state + first * stride;
  if (stride == material->state_count) /* the chunk's states contiguous */
    memcpy(state_to, state_from, count * stride * sizeof *state_to);
  else
    for (size_t k = 0; k < material->state_count; k++)
      for (size_t j = 0; j < count; j++)
        state_to[j * stride + k] = state_from[j * stride + k];
  if (screen != 0.0) { /* a trial stress not finite: the general path */
    const double *gradient[5] = {l_xx, l_xy, l_yx, l_yy, l_zz};
    gm_stress_update_chunk(domain, scratch, first, count, dt, gradient, false);
    return true;
  }
  double *const trial[4] = {rxx, ryy, rzz, rxy};
  /* Only a returned stress can have stopped being finite (an overflow):
   * the general path's check then names the point. */
  if (!gm_mohr_coulomb_plane_returns(
          def, trial, count, state_to + GM_MOHR_COULOMB_PLASTIC_SHEAR_STRAIN,
          stride, scratch->mohr_coulomb_prepared))
    gm_check_stress_chunk(domain, scratch, first, count, dt);
  return true;
}
