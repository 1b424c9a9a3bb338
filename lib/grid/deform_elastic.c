/*
 * deform_elastic.c - the deformation pass of elastic plane points fused:
 * F <- (I + L dt) F and V = det F V0 (004 eq 3.23) in one loop, then the
 * Jaumann rotation of the stress (002 sec 4.1, 004 eqs 3.20-3.21) and
 * Hooke's law (gm_elastic_update) in a second, each point's F, V and
 * stress read and written once.
 *
 * The general path (g2p.c deform_chunk, stress_update.c prepare_rows and
 * the material call through its callback) streams the chunk through four
 * loops and the worker's strain and density rows; this is its fast path
 * for the commonest case, with the same expressions in the same order, so
 * every bit of F, V and the stress is what the general path gives (no
 * contraction into FMAs: the library is built as ISO C, where GCC keeps
 * -ffp-contract=off). It starts from the gathered velocity gradient, so it
 * serves every shape: CPDI's domain map D takes F's increment in a loop
 * of its own, as in the general path (gm_deform_domain_map_chunk), and its
 * reset follows in g2p.c. Anything else (axisymmetry, USF's in-place
 * second half, another material or a chunk mixing materials) takes the
 * general path.
 *
 * Two loops, not one: with all 23 point and chunk streams in one loop the
 * pass was 12 % slower than the general path (block-1e5, loads stalled on
 * the stress reads); F and V (10 streams), then the stress (12), made it
 * 7-9 % faster.
 */
#include "grid/grid.h"

#include "grid/transfer.h"

#include <math.h>

int gm_plane_chunk_material(const gm_domain *domain, const gather_view *v,
                            const gm_g2p_pass *pass, size_t first,
                            size_t count) {
  if (v->dim != 2 || v->axisymmetric || pass->in_place || count == 0)
    return -1;
  const int32_t *material = domain->points.material + first;
  int32_t differ = 0; /* no early exit: the scan vectorises */
  for (size_t j = 1; j < count; j++)
    differ |= material[j] ^ material[0];
  return differ ? -1 : material[0];
}

bool gm_deform_elastic_chunk(gm_domain *domain, const gather_view *v,
                             gm_worker_scratch *scratch, size_t first,
                             size_t count, const chunk_gather *g, double dt) {
  gm_points *points = &domain->points;
  const gm_elastic_def *elastic =
      domain->materials[points->material[first]].user;
  /* The moduli exactly as gm_elastic_update derives them. */
  double young = elastic->youngs_modulus;                     /* Pa */
  double nu = elastic->poisson_ratio;                         /* - */
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
  const double *restrict sxx = from->stress[0] + first;
  const double *restrict syy = from->stress[1] + first;
  const double *restrict szz = from->stress[2] + first;
  const double *restrict sxy = from->stress[3] + first;
  double *restrict rxx = to->stress[0] + first;
  double *restrict ryy = to->stress[1] + first;
  double *restrict rzz = to->stress[2] + first;
  double *restrict rxy = to->stress[3] + first;
  const double *restrict l_xx = g->gradient[0], *restrict l_xy = g->gradient[1];
  const double *restrict l_yx = g->gradient[2], *restrict l_yy = g->gradient[3];
  const double *restrict l_zz = g->gradient[4];
  bool positive = true;
  /* x * 0 is NaN exactly when x is not finite (a sum that overflows only
   * sends the chunk to the exact check) */
  double screen = 0.0;
  for (size_t j = 0; j < count; j++) {
    /* deform_chunk (g2p.c) */
    double jacobian = gm_deform_plane_point(
        dt, l_xx[j], l_xy[j], l_yx[j], l_yy[j], f_xx[j], f_xy[j], f_yx[j],
        f_yy[j], &n_xx[j], &n_xy[j], &n_yx[j], &n_yy[j]);
    volume[j] = jacobian * initial_volume[j];
    positive &= jacobian > 0.0 && jacobian < INFINITY;
  }
  if (v->next_domain_map[0]) /* CPDI: D takes F's increment (g2p.c) */
    gm_deform_domain_map_chunk(v, first, count, g, dt);
  for (size_t j = 0; j < count; j++) {
    /* Jaumann rotation and the elastic law (gm_elastic_update, elastic.c)
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
  if (!positive) { /* the general path skips the material call: so do we */
    gm_report_inverted_chunk(domain, v, scratch, first, count, dt);
    return false;
  }
  if (screen != 0.0)
    gm_check_stress_chunk(domain, scratch, first, count, dt);
  return true;
}
