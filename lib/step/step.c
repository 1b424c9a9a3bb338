/*
 * step.c - the explicit MPM cycle for USL, MUSL and USF, made
 * transactional: every phase reads the committed point buffer and writes
 * the spare one, so a failure anywhere simply leaves the committed buffer
 * as it was. Recoverable material failures retry the interval as two
 * halves (recursively, up to max_retries), from a snapshot.
 *
 * The whole cycle, in order (gm_domain_step, then one attempt per
 * try_step; the stages are the step_stage enum below, and each scheme is
 * the ordered list of them in scheme_stages[]). Equations: 004 (Kumar
 * thesis ch. 3, sec 3.2).
 *
 *   gm_domain_step   hook GM_HOOK_BEFORE_STEP; sources inject; choose dt
 *                    (004 eqs 3.11-3.12, stable_dt.c)
 *   try_step, every scheme:
 *     BIN                  points sorted into grid blocks, grid built
 *     GRANULAR_PREPARE     parallel grids of the granular family (000)
 *     SCATTER              P2G mass m_i (3.13), momentum m_i v_i (3.14),
 *                          force f_i from sigma_t (3.15)  [USL]
 *     SCATTER_MOMENTUM     P2G mass (3.13), momentum (3.14)  [USF, MUSL]
 *     FOLD_PERIODIC_IMAGES after every scatter: periodic x faces, each
 *                          image node's sums onto its owner a box length
 *                          away (periodic.c)
 *     FOLD_BSPLINE_GHOSTS  after every scatter: B-splines, each ghost
 *                          node's sums onto its mirror node, held
 *                          components negated (bspline_faces.c)
 *     MARK_RIGID_NODES     nodes a rigid material holds (rigid.c)
 *     MEASURE_WALL_GAPS    per node, gap to each wall and face (wall_gaps.c)
 *     GRID_SOLVE           v_i = p_i/m_i (3.14), a_i = f_i/m_i (3.15),
 *                          v_i^L = v_i + a_i dt (3.16), walls, rigid nodes
 *     SHARE_WALL_FRICTION  after GRID_SOLVE: each planar wall's Coulomb
 *                          friction pooled per one-cell strip along it,
 *                          serially in block order (walls.c)
 *     GRID_VELOCITIES      v_i = p_i/m_i (3.14), walls, rigid nodes
 *     MIRROR_BSPLINE_GHOSTS after every grid update: B-splines, each ghost
 *                          node takes its mirror's reflected velocity (and
 *                          acceleration after GRID_SOLVE)
 *     COPY_PERIODIC_IMAGES after every grid update: periodic x faces, each
 *                          image takes its owner's mass, velocity (and
 *                          acceleration after GRID_SOLVE)
 *     STRESS_FIRST_HALF    USF, MUSL: L, F, V, stress over dt/2 from v_t
 *                          (3.18-3.24)
 *     SCATTER_FORCES       USF, MUSL: P2G momentum again and f_i (3.15)
 *                          from the half-updated stress
 *     UPDATE_POINTS        v_p += dt sum N a_i, x_p += dt sum N v_i^L (3.17)
 *     UPDATE_VELOCITIES    MUSL: v_p += dt sum N a_i only (3.17, first half)
 *     REMAP_MOMENTUM       P2G momentum of the updated v_p (Sulsky, Zhou &
 *                          Schreyer 1995), then GRID_VELOCITIES gives v^L
 *     MOVE_AND_REMAP       USL: UPDATE_POINTS and REMAP_MOMENTUM in one
 *                          sweep over the points where gm_move_remap_fits
 *                          (move_remap.c, bitwise the same) or, for uGIMP,
 *                          cpGIMP and CPDI, gm_move_remap_wide_fits
 *                          (move_remap_wide.c), else the two stages in turn
 *     DEFORM               USL: strain increment (3.18), Jaumann spin
 *                          (3.20-3.21), stress (3.19, 3.22), V = J V0
 *                          (3.23), density (3.24), from the re-mapped v^L
 *                          (and in every deforming pass, per chunk of
 *                          points while they are in cache: the granular
 *                          density control, 000 eqs 13-15, 18, and CPDI's
 *                          domain reset; g2p.c)
 *     STRESS_SECOND_HALF   USF: as DEFORM over dt/2, in the next buffer
 *     MOVE_AND_STRESS_SECOND_HALF
 *                          MUSL: x_p += dt sum N v^L over the whole dt,
 *                          then as STRESS_SECOND_HALF
 *     RIGID_POINTS         rigid points take their prescribed velocity
 *                          (with the B-splines their position, F and V
 *                          too: they hold only their cells' nodes,
 *                          rigid.c); their nodes' impulse goes to the body
 *   commit (try_step): flip the point buffers, granular summary, wall
 *     impulse, signal speed for the next dt, time and step count, reorder
 *     every GM_REORDER_INTERVAL steps
 *   on a recoverable failure: step_with_retries -> retry_in_halves
 *   gm_domain_step   wall and rigid force reports; sinks remove; hook
 *                    GM_HOOK_AFTER_STEP
 *
 * After every stage the workers' errors are collected: only the scatters
 * that check host inputs and the G2P passes can raise one, and the first
 * one found abandons the attempt.
 */
#include "step/step.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Physical re-sorting of points every this many steps (amortised cost). */
#define GM_REORDER_INTERVAL 16

/* The phases of one attempt, each one call below (run_stage). */
typedef enum step_stage {
  STAGE_BIN,
  STAGE_GRANULAR_PREPARE,
  STAGE_SCATTER,
  STAGE_SCATTER_MOMENTUM,
  STAGE_FOLD_PERIODIC_IMAGES,
  STAGE_FOLD_BSPLINE_GHOSTS,
  STAGE_MARK_RIGID_NODES,
  STAGE_MEASURE_WALL_GAPS,
  STAGE_GRID_SOLVE,
  STAGE_SHARE_WALL_FRICTION,
  STAGE_GRID_VELOCITIES,
  STAGE_MIRROR_BSPLINE_GHOSTS,
  STAGE_COPY_PERIODIC_IMAGES,
  STAGE_STRESS_FIRST_HALF,
  STAGE_SCATTER_FORCES,
  STAGE_UPDATE_POINTS,
  STAGE_UPDATE_VELOCITIES,
  STAGE_REMAP_MOMENTUM,
  STAGE_MOVE_AND_REMAP,
  STAGE_DEFORM,
  STAGE_STRESS_SECOND_HALF,
  STAGE_MOVE_AND_STRESS_SECOND_HALF,
  STAGE_RIGID_POINTS,
  STAGE_END /* ends a scheme's list */
} step_stage;

/* USL (004 sec 3.2, after eq 3.17: "the updated particle momentums are
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
 * ~200 steps once its sides bulged into empty cells). */
static const step_stage usl_stages[] = {STAGE_BIN,
                                        STAGE_GRANULAR_PREPARE,
                                        STAGE_SCATTER,
                                        STAGE_FOLD_PERIODIC_IMAGES,
                                        STAGE_FOLD_BSPLINE_GHOSTS,
                                        STAGE_MARK_RIGID_NODES,
                                        STAGE_MEASURE_WALL_GAPS,
                                        STAGE_GRID_SOLVE,
                                        STAGE_SHARE_WALL_FRICTION,
                                        STAGE_MIRROR_BSPLINE_GHOSTS,
                                        STAGE_COPY_PERIODIC_IMAGES,
                                        STAGE_MOVE_AND_REMAP,
                                        STAGE_FOLD_PERIODIC_IMAGES,
                                        STAGE_FOLD_BSPLINE_GHOSTS,
                                        STAGE_GRID_VELOCITIES,
                                        STAGE_MIRROR_BSPLINE_GHOSTS,
                                        STAGE_COPY_PERIODIC_IMAGES,
                                        STAGE_DEFORM,
                                        STAGE_RIGID_POINTS,
                                        STAGE_END};

/* MUSL (002 sec 4.4 steps 6-9): the point velocities are updated with
 * the nodal accelerations (step 6), their momenta re-mapped to the grid
 * (step 7), and the re-mapped velocities v^L give the strain rate (step 8)
 * and move the points (step 9). Its stress update is split as USF's below
 * (Nairn's USAVG): half the strain increment from the velocities of the
 * step's start before the forces, half from v^L after the move. Updating
 * the whole stress last, as 002 does, gains energy without bound wherever
 * points sit on a node line while the stressed body oscillates: each
 * crossing moves the point's stress onto the other cell's nodes (a force
 * jump of order V sigma / h whatever the stress gradient), and with the
 * stress last, one-sided in time, the energy errors of the steps after
 * the crossings add up (a 1D model of the free block: +3.1 times the start
 * energy summed over the 119 steps after a crossing in 600, +0.06 over the
 * others; the split update is centred in time). Measured on
 * tests/physics/test_entering_point.c's elastic block, released from 500
 * Pa, every other column and row of its points 1e-3 cells past a node
 * line: kinetic plus elastic energy 4.58 times its start after 600 steps
 * and 289 times after 4000 with the stress last; 1.03 with the split, as
 * USF. On tests/physics/test_crossing_energy.c's periodic bar, a cosine
 * stress and its points 1e-3 cells past the nodes: 1.2e5 times its start
 * within 4000 steps, 1.09 with the split. The block's outer nodes are
 * light (1e-3 of a point's mass) but are not the cause: the same block
 * with its edge points at 1e-3 and the others a quarter cell from the
 * nodes stays within 1.16 of its start over 4000 steps, and with its edge
 * points a quarter cell out and the others at 1e-3 it gains 1524 times.
 * USL updates its stress last too and gains on the periodic bar as well
 * (gm_domain_step(3), "Energy of the schemes with linear shapes"). */
static const step_stage musl_stages[] = {STAGE_BIN,
                                         STAGE_GRANULAR_PREPARE,
                                         STAGE_SCATTER_MOMENTUM,
                                         STAGE_FOLD_PERIODIC_IMAGES,
                                         STAGE_FOLD_BSPLINE_GHOSTS,
                                         STAGE_MARK_RIGID_NODES,
                                         STAGE_MEASURE_WALL_GAPS,
                                         STAGE_GRID_VELOCITIES,
                                         STAGE_MIRROR_BSPLINE_GHOSTS,
                                         STAGE_COPY_PERIODIC_IMAGES,
                                         STAGE_STRESS_FIRST_HALF,
                                         STAGE_SCATTER_FORCES,
                                         STAGE_FOLD_PERIODIC_IMAGES,
                                         STAGE_FOLD_BSPLINE_GHOSTS,
                                         STAGE_GRID_SOLVE,
                                         STAGE_SHARE_WALL_FRICTION,
                                         STAGE_MIRROR_BSPLINE_GHOSTS,
                                         STAGE_COPY_PERIODIC_IMAGES,
                                         STAGE_UPDATE_VELOCITIES,
                                         STAGE_REMAP_MOMENTUM,
                                         STAGE_FOLD_PERIODIC_IMAGES,
                                         STAGE_FOLD_BSPLINE_GHOSTS,
                                         STAGE_GRID_VELOCITIES,
                                         STAGE_MIRROR_BSPLINE_GHOSTS,
                                         STAGE_COPY_PERIODIC_IMAGES,
                                         STAGE_MOVE_AND_STRESS_SECOND_HALF,
                                         STAGE_RIGID_POINTS,
                                         STAGE_END};

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
 * increment from the step's start velocities before the forces, half from
 * the velocities re-mapped from the updated particle momenta (as in USL)
 * after the particles moved. The stress that sets the forces is then half
 * a step ahead of the committed one, the stress of the committed state is
 * centred on the step's velocities, and the block stays at rest
 * (gm_domain_step(3), "Why USF splits its stress update"). */
static const step_stage usf_stages[] = {STAGE_BIN,
                                        STAGE_GRANULAR_PREPARE,
                                        STAGE_SCATTER_MOMENTUM,
                                        STAGE_FOLD_PERIODIC_IMAGES,
                                        STAGE_FOLD_BSPLINE_GHOSTS,
                                        STAGE_MARK_RIGID_NODES,
                                        STAGE_MEASURE_WALL_GAPS,
                                        STAGE_GRID_VELOCITIES,
                                        STAGE_MIRROR_BSPLINE_GHOSTS,
                                        STAGE_COPY_PERIODIC_IMAGES,
                                        STAGE_STRESS_FIRST_HALF,
                                        STAGE_SCATTER_FORCES,
                                        STAGE_FOLD_PERIODIC_IMAGES,
                                        STAGE_FOLD_BSPLINE_GHOSTS,
                                        STAGE_GRID_SOLVE,
                                        STAGE_SHARE_WALL_FRICTION,
                                        STAGE_MIRROR_BSPLINE_GHOSTS,
                                        STAGE_COPY_PERIODIC_IMAGES,
                                        STAGE_UPDATE_POINTS,
                                        STAGE_REMAP_MOMENTUM,
                                        STAGE_FOLD_PERIODIC_IMAGES,
                                        STAGE_FOLD_BSPLINE_GHOSTS,
                                        STAGE_GRID_VELOCITIES,
                                        STAGE_MIRROR_BSPLINE_GHOSTS,
                                        STAGE_COPY_PERIODIC_IMAGES,
                                        STAGE_STRESS_SECOND_HALF,
                                        STAGE_RIGID_POINTS,
                                        STAGE_END};

static const step_stage *scheme_stages(gm_update_scheme scheme) {
  switch (scheme) {
  case GM_SCHEME_MUSL:
    return musl_stages;
  case GM_SCHEME_USF:
    return usf_stages;
  default:
    return usl_stages;
  }
}

/* The granular phase (granular/components.c) keys the points of each node
 * layer to their own blocks; with more than one layer they are binned again
 * here, because the binning (grid/) is above granular/ in the layers
 * (docs/architecture.md). The time counts as the layers' (layer_seconds of
 * gm_granular_summary). */
static gm_status prepare_granular(gm_domain *domain) {
  gm_status status = gm_granular_prepare(domain);
  gm_granular_summary *summary = &domain->granular.summary;
  if (status != GM_OK || summary->layer_count <= 1)
    return status;
  double start = gm_monotonic_seconds();
  status = gm_bin_points(domain);
  summary->layer_seconds += gm_monotonic_seconds() - start;
  return status;
}

/* What the stages of one attempt hand on to the ones after them: the
 * folds add onto the owners and mirrors the fields the last scatter wrote
 * (mass only once: a re-map adds momentum onto the folded mass), and the
 * mirror and copy take what the last grid update wrote (accelerations only
 * after a GM_GRID_FULL one). */
typedef struct step_attempt {
  gm_p2g_pass scattered; /* the last P2G pass */
  int grid_mode;         /* the last grid update's GM_GRID_* mode */
} step_attempt;

/* Runs one stage of an attempt over dt, then collects the workers'
 * errors. Every pass reads the committed buffer cur (velocities, stress)
 * or what an earlier stage of this attempt wrote to the next one. */
static gm_status run_stage(gm_domain *domain, step_stage stage, double dt,
                           step_attempt *attempt) {
  int cur = domain->points.cur;
  /* Host-written inputs are screened only when the host had the chance to
   * write them; otherwise they come from a checked step. */
  bool edited = domain->inputs_edited;
  gm_status status = GM_OK;
  switch (stage) {
  case STAGE_BIN:
    status = gm_bin_points(domain);
    break;
  case STAGE_GRANULAR_PREPARE:
    if (domain->def.family == GM_FAMILY_GRANULAR)
      status = prepare_granular(domain); /* parallel grids */
    break;
  case STAGE_SCATTER: {
    gm_p2g_pass pass = {true, true, true, cur, cur, edited};
    gm_p2g(domain, &pass);
    attempt->scattered = pass;
    break;
  }
  case STAGE_SCATTER_MOMENTUM: {
    gm_p2g_pass pass = {true, true, false, cur, cur, edited};
    gm_p2g(domain, &pass);
    attempt->scattered = pass;
    break;
  }
  case STAGE_FOLD_PERIODIC_IMAGES: /* periodic x: images onto owners */
    gm_periodic_fold_images(domain, &attempt->scattered);
    break;
  case STAGE_FOLD_BSPLINE_GHOSTS: /* B-spline faces: ghosts onto mirrors */
    gm_bspline_fold_ghosts(domain, &attempt->scattered);
    break;
  case STAGE_MARK_RIGID_NODES: /* the nodes rigid points reach (rigid.c) */
    if (domain->rigid_count > 0)
      gm_rigid_mark_nodes(domain);
    break;
  case STAGE_MEASURE_WALL_GAPS:
    if (gm_gap_plane_count(domain) > 0) {
      if (domain->dim == 3)
        gm_walls_measure_gaps_3d(domain);
      else
        gm_walls_measure_gaps(domain);
      gm_periodic_fold_gaps(domain); /* owners see across the seam */
    }
    break;
  case STAGE_GRID_SOLVE:
    gm_grid_update(domain, dt, GM_GRID_FULL);
    attempt->grid_mode = GM_GRID_FULL;
    break;
  case STAGE_SHARE_WALL_FRICTION:
    /* Only the full update exchanges momentum with the walls
     * (grid_update.c, wall_friction); 3D has no planar walls yet. */
    if (domain->dim < 3)
      gm_walls_share_friction(domain, dt, GM_GRID_FULL);
    break;
  case STAGE_GRID_VELOCITIES:
    gm_grid_update(domain, dt, GM_GRID_VELOCITY_ONLY);
    attempt->grid_mode = GM_GRID_VELOCITY_ONLY;
    break;
  case STAGE_MIRROR_BSPLINE_GHOSTS: /* ghosts reflect their mirrors */
    gm_bspline_mirror_ghosts(domain, attempt->grid_mode);
    break;
  case STAGE_COPY_PERIODIC_IMAGES: /* images take their owners' values */
    gm_periodic_copy_images(domain, attempt->grid_mode);
    break;
  case STAGE_STRESS_FIRST_HALF: {
    gm_g2p_pass pass = {false, false, true, false, 0.5 * dt, false, 0.0};
    gm_g2p(domain, &pass);
    break;
  }
  case STAGE_SCATTER_FORCES: {
    /* Momentum is scattered again with the forces: the first grid update
     * turned it into wall-constrained velocities, and the walls'
     * acceleration correction -v/dt needs the unconstrained ones. The
     * forces come from the half-updated stress in the next buffer. */
    gm_p2g_pass pass = {false, true, true, cur, cur ^ 1, false};
    gm_p2g(domain, &pass);
    attempt->scattered = pass;
    break;
  }
  case STAGE_UPDATE_POINTS: {
    gm_g2p_pass pass = {true, true, false, false, dt, false, 0.0};
    gm_g2p(domain, &pass);
    if (domain->rigid_count > 0) /* the remap scatters prescribed momenta */
      gm_rigid_hold_remap_velocities(domain);
    break;
  }
  case STAGE_UPDATE_VELOCITIES: {
    gm_g2p_pass pass = {true, false, false, false, dt, false, 0.0};
    gm_g2p(domain, &pass);
    if (domain->rigid_count > 0)
      gm_rigid_hold_remap_velocities(domain);
    break;
  }
  case STAGE_REMAP_MOMENTUM: {
    /* m_i v_i = sum_p N_ip m_p v_p^{t+dt}, from the updated velocities in
     * the next buffer (Sulsky, Zhou & Schreyer 1995). */
    gm_p2g_pass pass = {false, true, false, cur ^ 1, cur, false};
    gm_p2g(domain, &pass);
    attempt->scattered = pass;
    break;
  }
  case STAGE_MOVE_AND_REMAP: {
    bool linear = gm_move_remap_fits(domain);
    if (linear || gm_move_remap_wide_fits(domain)) {
      if (linear)
        gm_move_remap(domain, dt);
      else
        gm_move_remap_wide(domain, dt);
      gm_p2g_pass pass = {false, true, false, cur ^ 1, cur, false};
      attempt->scattered = pass; /* what REMAP_MOMENTUM scatters */
      break;
    }
    status = run_stage(domain, STAGE_UPDATE_POINTS, dt, attempt);
    if (status == GM_OK)
      status = run_stage(domain, STAGE_REMAP_MOMENTUM, dt, attempt);
    break;
  }
  case STAGE_DEFORM: {
    gm_g2p_pass pass = {false, false, true, true, dt, false, 0.0};
    gm_g2p(domain, &pass);
    break;
  }
  case STAGE_STRESS_SECOND_HALF: {
    gm_g2p_pass pass = {false, false, true, true, 0.5 * dt, true, 0.0};
    gm_g2p(domain, &pass);
    break;
  }
  case STAGE_MOVE_AND_STRESS_SECOND_HALF: {
    gm_g2p_pass pass = {false, true, true, true, 0.5 * dt, true, dt};
    gm_g2p(domain, &pass);
    break;
  }
  case STAGE_RIGID_POINTS:
    if (domain->rigid_count > 0) { /* prescribed, not FLIP, velocities */
      status = gm_rigid_move_points(domain, dt);
      if (status != GM_OK)
        return status;
      gm_rigid_set_point_velocities(domain);
      gm_rigid_add_impulse(domain);
    }
    break;
  case STAGE_END:
    break;
  }
  if (status != GM_OK)
    return status;
  return gm_collect_worker_errors(domain);
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
    step_attempt attempt = {.grid_mode = GM_GRID_FULL}; /* set before read */
    for (const step_stage *stage = scheme_stages(domain->def.scheme);
         *stage != STAGE_END && status == GM_OK; stage++)
      status = run_stage(domain, *stage, dt, &attempt);
    if (status != GM_OK)
      return status;
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

static gm_status step_with_retries(gm_domain *domain, double dt,
                                   int retries_left, bool allow_reorder);

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
  gm_status status =
      step_with_retries(domain, 0.5 * dt, retries_left - 1, false);
  if (status == GM_OK)
    status = step_with_retries(domain, 0.5 * dt, retries_left - 1, false);
  domain->retry_depth--;
  if (status == GM_OK)
    domain->time = time + dt; /* exactly the interval asked for */
  if (status != GM_OK) {
    points->cur = cur;
    points->keys_valid = false;
    if (outermost) {
      gm_buffers_copy(&points->buffer[cur], &domain->snapshot, points->count,
                      points->state_stride);
      domain->granular.labels_kept = false; /* labels of the interval start */
    }
    domain->time = time;
    domain->max_signal_speed = speed;
    domain->step_count = steps;
  }
  return status;
}

static gm_status step_with_retries(gm_domain *domain, double dt,
                                   int retries_left, bool allow_reorder) {
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
    for (int k = 0; k < 3; k++)
      domain->materials[m].rigid_impulse[k] = 0.0;
  /* Sources inject now; the injection is undone if the step fails. */
  gm_injection_undo undo;
  gm_status status = gm_sources_inject(domain, &undo);
  /* After the hook and the injection: velocities the hook edited and the
   * new points count for the stable dt. */
  if (status == GM_OK)
    status = choose_dt(domain, &dt);
  if (status == GM_OK)
    status = step_with_retries(domain, dt, domain->def.max_retries, true);
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
    gm_force_report_commit(&domain->wall_report[w], domain->wall_impulse[w],
                           domain->dim == 3 ? 3 : 2, dt, tau);
  for (int m = 0; m < domain->material_count; m++)
    if (domain->materials[m].rigid)
      gm_force_report_commit(&domain->materials[m].rigid_report,
                             domain->materials[m].rigid_impulse,
                             domain->dim == 3 ? 3 : 2, dt, tau);
  gm_sinks_remove(domain);
  run_hook(domain, GM_HOOK_AFTER_STEP);
  domain->busy = false;
  return status;
}
