/*
 * step.c - the explicit MPM cycle for USL, MUSL and USF, made
 * transactional: every phase reads the committed point buffer and writes
 * the spare one, so a failure anywhere simply leaves the committed buffer
 * as it was. Recoverable material failures retry the interval as two
 * halves (recursively, up to max_retries), from a snapshot.
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Physical re-sorting of points every this many steps (amortised cost). */
#define GM_REORDER_INTERVAL 16

static gm_status collect(gm_domain *domain) {
  return gm_collect_worker_errors(domain);
}

/* The nodal velocities re-mapped from the updated particle momenta
 * (Sulsky, Zhou & Schreyer 1995): m_i v_i = sum_p N_ip m_p v_p^{t+dt},
 * with the wall conditions applied again. */
static void remap_velocities(gm_domain *domain, double dt) {
  int cur = domain->points.cur;
  gm_p2g_pass remap = {false, true, false, cur ^ 1, cur, false};
  gm_p2g(domain, &remap);
  gm_grid_update(domain, dt, GM_GRID_VELOCITY_ONLY);
}

/* USL and MUSL share the first half: mass, momentum and forces to the
 * grid, nodal update, particle velocities (004 eqs 3.13-3.17).
 *
 * USL (004 sec 3.2, after eq 3.17: "the updated particle momentums are
 * used to calculate the nodal velocities, which are then used to update
 * the particle strain and stress"): points move with the updated nodal
 * velocities v_i^L = v_i + a_i dt (eq 3.17), and the strain rate comes
 * from the nodal velocities re-mapped from the updated particle momenta,
 * the remedy of Sulsky, Zhou & Schreyer (1995) for the cell-crossing
 * instability (004 sec 3.3). Taking the strain rate from v_i^L itself,
 * as Sulsky, Chen & Schreyer (1994) do, is unstable with linear shape
 * functions: a point that has just entered a cell gives its new nodes a
 * mass N m_p with N -> 0 while its stress gradient force on them does not
 * vanish, so a_i = f_i / m_i grows without bound and the next strain
 * increment inverts F (an elastic block resting on a floor failed after
 * ~200 steps once its sides bulged into empty cells).
 *
 * MUSL (002 sec 4.4 steps 6-9): the re-mapped velocities also move the
 * points. */
static gm_status run_usl(gm_domain *domain, double dt, bool modified) {
  int cur = domain->points.cur;
  /* Host-written inputs are screened only when the host had the chance to
   * write them; otherwise they come from a checked step. */
  gm_p2g_pass scatter = {true, true, true, cur, cur, domain->inputs_edited};
  gm_p2g(domain, &scatter);
  gm_status status = collect(domain);
  if (status != GM_OK)
    return status;
  gm_grid_update(domain, dt, GM_GRID_FULL);
  gm_g2p_pass velocities = {true, !modified, false, false, dt, false};
  gm_g2p(domain, &velocities);
  if ((status = collect(domain)) != GM_OK)
    return status;
  remap_velocities(domain, dt);
  gm_g2p_pass strain = {false, modified, true, true, dt, false};
  gm_g2p(domain, &strain);
  return collect(domain);
}

/* USF: the stress is updated first, from the nodal velocities of the
 * momenta at the step's start, and sets the forces of the step. Updating
 * it over the whole dt there (Bardenhagen 2002, 004 sec 3.2) gains energy
 * on an elastic block resting on a floor (measured: kinetic energy 0.6 J/m
 * at step 500, 55 J/m at step 3500, then a point thrown out of the box),
 * however small dt or the FLIP fraction: points that sit on a node row
 * while the block oscillates are compressed on every crossing and the
 * stress that answers lags the motion. The update is therefore split as
 * in Nairn's USAVG (Nairn 2003, CMES 4:649; tabulated next to USF, USL
 * and MUSL by Kularathna 2018, PhD thesis, Cambridge): half the strain
 * increment from the step's start velocities before the forces, half from the
 * velocities re-mapped from the updated particle momenta (remap_velocities, as
 * in USL) after the particles moved. The stress that sets the forces is then
 * half a step ahead of the committed one, the stress of the committed state is
 * centred on the step's velocities, and the block stays at rest
 * (gm_domain_step(3), "Why USF splits its stress update"). */
static gm_status run_usf(gm_domain *domain, double dt) {
  int cur = domain->points.cur;
  gm_p2g_pass momentum = {true, true, false, cur, cur, domain->inputs_edited};
  gm_p2g(domain, &momentum);
  gm_status status = collect(domain);
  if (status != GM_OK)
    return status;
  gm_grid_update(domain, dt, GM_GRID_VELOCITY_ONLY);
  gm_g2p_pass first_half = {false, false, true, false, 0.5 * dt, false};
  gm_g2p(domain, &first_half);
  if ((status = collect(domain)) != GM_OK)
    return status;
  /* Momentum is scattered again with the forces: the first update turned
   * it into wall-constrained velocities, and the walls' acceleration
   * correction -v/dt needs the unconstrained ones. */
  gm_p2g_pass forces = {false, true, true, cur, cur ^ 1, false};
  gm_p2g(domain, &forces);
  gm_grid_update(domain, dt, GM_GRID_FULL);
  gm_g2p_pass motion = {true, true, false, false, dt, false};
  gm_g2p(domain, &motion);
  if ((status = collect(domain)) != GM_OK)
    return status;
  remap_velocities(domain, dt);
  gm_g2p_pass second_half = {false, false, true, true, 0.5 * dt, true};
  gm_g2p(domain, &second_half);
  return collect(domain);
}

/* One attempt over dt; commits on success, touches nothing committed on
 * failure. */
static gm_status try_step(gm_domain *domain, double dt, bool allow_reorder) {
  gm_clear_worker_errors(domain);
  domain->wall_profile_valid = false; /* the grid is about to be reused */
  for (int w = 0; w < domain->worker_count; w++) {
    domain->scratch[w].max_wave_speed_squared = 0.0;
    domain->scratch[w].max_point_speed_squared = 0.0;
    domain->scratch[w].density_control_seconds = 0.0;
  }
  domain->current_dt = dt;
  gm_status status = GM_OK;
  if (domain->points.count > 0) {
    status = gm_bin_points(domain);
    if (status == GM_OK && domain->def.family == GM_FAMILY_GRANULAR)
      status = gm_granular_prepare(domain); /* parallel grids */
    if (status == GM_OK)
      status = domain->def.scheme == GM_SCHEME_USF
                   ? run_usf(domain, dt)
                   : run_usl(domain, dt, domain->def.scheme == GM_SCHEME_MUSL);
    if (status != GM_OK)
      return status;
    if (domain->rigid_count > 0) { /* prescribed, not FLIP, velocities */
      gm_rigid_set_point_velocities(domain);
      gm_rigid_add_impulse(domain);
    }
    domain->points.cur ^= 1;
    domain->points.keys_valid = true; /* the move pass keyed the new state */
    if (domain->def.family == GM_FAMILY_GRANULAR) {
      gm_granular_summary *summary = &domain->granular_summary;
      *summary = domain->granular.summary;
      summary->density_control_seconds = 0.0;
      for (int w = 0; w < domain->worker_count; w++)
        summary->density_control_seconds +=
            domain->scratch[w].density_control_seconds;
    }
    if (domain->wall_count > 0)
      gm_walls_add_impulse(domain, dt);
    domain->wall_profile_valid = true;
    domain->inputs_edited = false; /* this step screened them */
    double wave = 0.0, flow = 0.0; /* m^2/s^2 */
    for (int w = 0; w < domain->worker_count; w++) {
      gm_worker_scratch *scratch = &domain->scratch[w];
      wave = fmax(wave, scratch->max_wave_speed_squared);
      flow = fmax(flow, scratch->max_point_speed_squared);
    }
    domain->max_signal_speed = sqrt(wave) + sqrt(flow);
  }
  domain->time += dt;
  domain->step_count++;
  if (allow_reorder && ++domain->steps_since_reorder >= GM_REORDER_INTERVAL &&
      domain->points.count > 0) {
    gm_reorder_points(domain);
    domain->steps_since_reorder = 0;
  }
  return GM_OK;
}

/* A failure that a smaller dt may avoid: a material's recoverable return
 * (> 0), or an inverted F (finite det F <= 0) and nothing else. */
static bool recoverable_failure(const gm_domain *domain, gm_status status) {
  if (status == GM_ERR_NOT_FINITE) {
    bool inverted = false;
    for (int w = 0; w < domain->worker_count; w++) {
      const gm_worker_scratch *scratch = &domain->scratch[w];
      if (scratch->error_status == GM_OK)
        continue;
      if (!scratch->error_inverted)
        return false;
      inverted = true;
    }
    return inverted;
  }
  if (status != GM_ERR_CALLBACK)
    return false;
  bool recoverable = false;
  for (int w = 0; w < domain->worker_count; w++) {
    int result = domain->scratch[w].callback_result;
    if (result < 0)
      return false;
    recoverable = recoverable || result > 0;
  }
  return recoverable;
}

/* Saves or restores the committed state around a dt-halving retry. */
static gm_status save_snapshot(gm_domain *domain) {
  gm_points *points = &domain->points;
  if (domain->snapshot_capacity < points->capacity) {
    gm_buffers_free(&domain->snapshot);
    domain->snapshot_capacity = 0;
    if (gm_buffers_reserve(domain, &domain->snapshot, 0, points->capacity) !=
        GM_OK) {
      gm_buffers_free(&domain->snapshot);
      return GM_ERR_NO_MEMORY;
    }
    domain->snapshot_capacity = points->capacity;
  }
  gm_buffers_copy(&domain->snapshot, &points->buffer[points->cur],
                  points->count, points->state_stride);
  return GM_OK;
}

static gm_status advance(gm_domain *domain, double dt, int retries_left,
                         bool allow_reorder);

/* Retries the interval as two halves; restores the snapshot on failure. */
/* Only the outermost retry saves and restores the snapshot: a nested
 * retry's failure always propagates up to it, and saving again at a nested
 * level would overwrite the start of the interval with a mid-interval
 * state. */
static gm_status retry_in_halves(gm_domain *domain, double dt,
                                 int retries_left) {
  bool outermost = domain->retry_depth == 0;
  if (outermost && save_snapshot(domain) != GM_OK)
    return gm_set_error(domain, GM_ERR_NO_MEMORY,
                        "step: out of memory for the retry snapshot");
  domain->retry_depth++;
  gm_points *points = &domain->points;
  double time = domain->time, speed = domain->max_signal_speed;
  uint64_t steps = domain->step_count;
  int cur = points->cur;
  gm_status status = advance(domain, 0.5 * dt, retries_left - 1, false);
  if (status == GM_OK)
    status = advance(domain, 0.5 * dt, retries_left - 1, false);
  domain->retry_depth--;
  if (status == GM_OK)
    domain->time = time + dt; /* exactly the interval asked for */
  if (status != GM_OK) {
    points->cur = cur;
    points->keys_valid = false;
    if (outermost)
      gm_buffers_copy(&points->buffer[cur], &domain->snapshot, points->count,
                      points->state_stride);
    domain->time = time;
    domain->max_signal_speed = speed;
    domain->step_count = steps;
  }
  return status;
}

static gm_status advance(gm_domain *domain, double dt, int retries_left,
                         bool allow_reorder) {
  gm_status status = try_step(domain, dt, allow_reorder);
  if (!recoverable_failure(domain, status))
    return status;
  if (retries_left <= 0) {
    char reason[GM_ERROR_MESSAGE_SIZE];
    snprintf(reason, sizeof reason, "%s", domain->last_error);
    return gm_set_error(domain, status,
                        "%.380s; still failing after %d halvings of dt "
                        "(max_retries)",
                        reason, domain->def.max_retries);
  }
  return retry_in_halves(domain, dt, retries_left);
}

/* Runs the hook at a stage; nonzero return cancels the step. */
static int run_hook(gm_domain *domain, gm_hook_stage stage) {
  if (!domain->hook)
    return 0;
  domain->in_hook = true;
  int result = domain->hook(domain, stage, domain->hook_user);
  domain->in_hook = false;
  return result;
}

static gm_status choose_dt(gm_domain *domain, double *dt) {
  if (domain->points.count == 0) {
    if (*dt <= 0.0)
      return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                          "gm_domain_step: dt <= 0 asks for the stable dt, "
                          "undefined without points");
    return GM_OK;
  }
  double stable;
  gm_status status = gm_domain_stable_dt(domain, &stable);
  if (status != GM_OK)
    return status;
  if (*dt <= 0.0) {
    *dt = stable;
    return GM_OK;
  }
  if (domain->def.refuse_unstable_dt && *dt > stable)
    return gm_set_error(domain, GM_ERR_UNSTABLE_DT,
                        "gm_domain_step: dt = %g s exceeds the stable bound "
                        "%g s (cfl %g, cell %g m, fastest signal %g m/s)",
                        *dt, stable, domain->def.cfl, domain->def.cell_size,
                        domain->max_signal_speed);
  return GM_OK;
}

gm_status gm_domain_step(gm_domain *domain, double dt) {
  if (!domain)
    return GM_ERR_NULL;
  if (domain->busy)
    return gm_set_error(domain, GM_ERR_BUSY,
                        "gm_domain_step: called during a step (from a hook "
                        "or callback)");
  if (isnan(dt) || isinf(dt))
    return gm_set_error(domain, GM_ERR_INVALID_ARGUMENT,
                        "gm_domain_step: dt is %g s, must be finite (<= 0 "
                        "means the stable dt)",
                        dt);
  domain->busy = true;
  if (run_hook(domain, GM_HOOK_BEFORE_STEP) != 0) {
    domain->busy = false;
    return gm_set_error(domain, GM_ERR_CALLBACK,
                        "gm_domain_step: the step hook cancelled the step at "
                        "t = %g s",
                        domain->time);
  }
  memset(domain->wall_impulse, 0, sizeof domain->wall_impulse);
  for (int m = 0; m < domain->material_count; m++)
    domain->materials[m].rigid_impulse[0] =
        domain->materials[m].rigid_impulse[1] = 0.0;
  /* Sources inject now; the injection is undone if the step fails. */
  gm_injection_undo undo;
  gm_status status = gm_sources_inject(domain, &undo);
  /* After the hook and the injection: velocities the hook edited and the
   * new points count for the stable dt. */
  if (status == GM_OK)
    status = choose_dt(domain, &dt);
  if (status == GM_OK)
    status = advance(domain, dt, domain->def.max_retries, true);
  if (status != GM_OK) {
    gm_sources_undo(domain, &undo);
    domain->busy = false;
    return status;
  }
  /* The wall and rigid loads reported for this call: the impulse of its
   * committed sub-steps over the whole interval (a failed call reports
   * none), and the running totals and smoothed forces (force_report.c). */
  double tau = domain->force_smoothing_time; /* s */
  for (int w = 0; w < domain->wall_count; w++)
    gm_force_report_commit(&domain->wall_report[w], domain->wall_impulse[w], dt,
                           tau);
  for (int m = 0; m < domain->material_count; m++)
    if (domain->materials[m].rigid)
      gm_force_report_commit(&domain->materials[m].rigid_report,
                             domain->materials[m].rigid_impulse, dt, tau);
  gm_sinks_remove(domain);
  run_hook(domain, GM_HOOK_AFTER_STEP);
  domain->busy = false;
  return status;
}
