/*
 * advance.c - gm_domain_advance: a run to a given time, with a progress
 * callback for long runs.
 */
#include "step/step.h"

#include <math.h>

/* dt (s) of the next step towards end_time: the requested or stable dt,
 * with the last two steps evened out so none is a sliver. */
static gm_status next_dt(gm_domain *domain, double end_time, double dt,
                         double *out, bool *last) {
  double step = dt;
  if (!(step > 0.0)) {
    gm_status status = gm_domain_stable_dt(domain, &step);
    if (status != GM_OK)
      return status;
  }
  double remaining = end_time - domain->time; /* s, > 0 */
  *last = step >= remaining;
  if (*last)
    step = remaining;
  else if (2.0 * step > remaining)
    step = 0.5 * remaining;
  *out = step;
  return GM_OK;
}

gm_status gm_domain_advance(gm_domain *domain, double end_time, double dt,
                            gm_progress_fn *progress, void *user) {
  if (!domain)
    return GM_ERR_NULL;
  if (!isfinite(end_time) || !isfinite(dt))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_advance: end_time %g s and dt %g s must "
                        "be finite",
                        end_time, dt);
  if (end_time < domain->time)
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_advance: end_time %g s is before the "
                        "domain's time %g s",
                        end_time, domain->time);
  while (domain->time < end_time) {
    double step = 0.0;
    bool last = false;
    gm_status status = next_dt(domain, end_time, dt, &step, &last);
    if (status == GM_OK)
      status = gm_domain_step(domain, step);
    if (status != GM_OK)
      return status;
    if (last) /* exactly end_time, whatever the rounding of time + dt */
      domain->time = end_time;
    if (progress && progress(domain, domain->time, end_time, user) != 0)
      return gm_set_error(domain, GM_ERR_CALLBACK,
                          "gm_domain_advance: stopped by the progress "
                          "callback at t = %g s (end_time %g s)",
                          domain->time, end_time);
  }
  return GM_OK;
}
