/*
 * force_report.c - what the wall and rigid-material force getters report
 * about the last gm_domain_step() call and about the run so far.
 *
 * Walls and rigid points act on grid nodes as velocity constraints: the
 * impulse they apply in one step is the momentum of the nodes moving into
 * them, whatever the step's length. A step of 1e-12 s right after a gap
 * closed still transfers a finite impulse (1.6 N s per metre measured for
 * a 40 kg/m elastic block landing at 1 m/s on a wall), so impulse / dt
 * reads 1.6e12 N there. The impulse is the well-defined quantity; the
 * forces are derived from it:
 *  - force: impulse / dt of the last call (the report of earlier versions);
 *  - total_impulse over total_duration: sums over every successful call,
 *    so the difference of two readings gives the exact mean force of the
 *    window between them, however it was split into steps;
 *  - smoothed_force F: the force f(t) through a first-order low-pass
 *    filter, tau dF/dt = f - F, with f constant over each call (J / dt).
 *    Integrated exactly over a call of length dt:
 *      F <- F e^{-dt/tau} + (J / tau) (1 - e^{-dt/tau}) / (dt / tau),
 *    so a call raises |F| by at most |J| / tau however short it is, and
 *    a constant force split into any number of calls gives the same F.
 */
#include "boundaries/boundaries.h"

#include <math.h>

/* (1 - e^{-x}) / x for x >= 0, accurate down to x = 0 (where it is 1). */
static double relaxed_fraction(double x) {
  return x > 0.0 ? -expm1(-x) / x : 1.0;
}

void gm_force_report_commit(gm_force_report *report, const double *impulse,
                            int components, double dt, double tau) {
  double x = dt / tau;
  double decay = exp(-x), gain = relaxed_fraction(x) / tau; /* 1, 1/s */
  for (int k = 0; k < components; k++) {
    report->impulse[k] = impulse[k];
    report->force[k] = impulse[k] / dt;
    report->total_impulse[k] += impulse[k];
    report->smoothed_force[k] =
        report->smoothed_force[k] * decay + impulse[k] * gain;
  }
  report->duration = dt;
  report->total_duration += dt;
}

gm_status gm_domain_set_force_smoothing_time(gm_domain *domain,
                                             double seconds) {
  if (!domain)
    return GM_ERR_NULL;
  if (domain->busy && !domain->in_hook)
    return gm_set_error(domain, GM_ERR_BUSY,
                        "gm_domain_set_force_smoothing_time: called during "
                        "a step");
  if (!(seconds > 0.0) || !isfinite(seconds))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_set_force_smoothing_time: %g s, must be "
                        "finite and > 0",
                        seconds);
  domain->force_smoothing_time = seconds;
  return GM_OK;
}
