/*
 * stable_dt.c - the explicit time-step bound. The critical step is the
 * cell size over the fastest signal (004 eq 3.11), with the P-wave speed
 * c = sqrt((K + 4G/3)/rho) (eq 3.12 needs the square root) plus the
 * points' own speed, scaled by the Courant number cfl. The fastest signal
 * is bounded by max c_p + max |v_p| (>= max (c_p + |v_p|)): a safe bound
 * that needs no square root per point. The bound is that of linear
 * elements with lumped mass; the wider supports (GIMP, CPDI, B-splines)
 * have no higher grid frequencies, so it holds for them too (for the
 * B-splines: power iteration on a 1D bar with 1-3 points per cell gave
 * omega^2 h^2 / c^2 <= 4 for the quadratic, <= 2 for the cubic, against 4
 * for the tents; gm_domain_create(3)). In 3D the same bound holds for the
 * trilinear tents: a cube with every mode excited stays bounded at cfl 1
 * and at 1.5x the bound, and blows up at 2x, as the plane square does
 * (tests/physics/test_3d.c).
 */
#include "core/core.h"

#include "core/domain.h"

#include <math.h>

void gm_recompute_signal_speed(gm_domain *domain) {
  const gm_points *points = &domain->points;
  const gm_point_buffers *b = &points->buffer[points->cur];
  double wave = 0.0, flow = 0.0; /* m^2/s^2 */
  for (size_t i = 0; i < points->count; i++) {
    double speed_squared = 0.0;
    for (int k = 0; k < domain->dim; k++)
      speed_squared += b->velocity[k][i] * b->velocity[k][i];
    double modulus = domain->materials[points->material[i]].p_wave_modulus;
    double wave_squared = modulus * b->volume[i] / points->mass[i];
    wave = wave_squared > wave ? wave_squared : wave;
    flow = speed_squared > flow ? speed_squared : flow;
  }
  domain->max_signal_speed = sqrt(wave) + sqrt(flow);
}

gm_status gm_domain_stable_dt(const gm_domain *domain, double *dt) {
  if (!domain)
    return GM_ERR_NULL;
  gm_domain *mutable_domain = (gm_domain *)domain; /* last_error only */
  if (!dt)
    return gm_set_error(mutable_domain, GM_ERR_NULL,
                        "gm_domain_stable_dt: dt is NULL");
  if (domain->velocity_edited) { /* logically const: a cached maximum */
    gm_recompute_signal_speed(mutable_domain);
    mutable_domain->velocity_edited = false;
  }
  if (domain->points.count == 0 || !(domain->max_signal_speed > 0.0))
    return gm_set_error(mutable_domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_stable_dt: the domain has no points, so "
                        "no stable time step is defined");
  *dt = domain->def.cfl * domain->def.cell_size / domain->max_signal_speed;
  if (!(*dt > 0.0) || !isfinite(*dt))
    return gm_set_error(mutable_domain, GM_ERR_NOT_FINITE,
                        "gm_domain_stable_dt: fastest signal %g m/s gives no "
                        "finite time step (non-finite velocity?)",
                        domain->max_signal_speed);
  return GM_OK;
}
