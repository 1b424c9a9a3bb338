/*
 * energy_budget.c - the energy budget of a run, integrated in time, every
 * term in J/m (plane strain, unit thickness), for docs/convergence.md
 * section 15:
 *
 *   dPE   released potential energy, sum m g (y0 - y) = M g (yc0 - yc)
 *   KE    kinetic energy of the points (gm_summary)
 *   W_int internal (stress) work, the sum over steps and points of
 *         V sigma_mid : d_eps, sigma_mid = (sigma_old + sigma_new) / 2 with
 *         sigma_old the Jaumann-rotated stress the batch delivers, d_eps its
 *         strain increment and V = m / rho (rho at the end of the step),
 *         shear components counted twice (tensor shear strains)
 *   E_el  elastic energy, sum V w with w = ((1 + nu) s:s - nu (tr s)^2)/(2E)
 *         the isotropic strain-energy density of the point stress, as the
 *         column_collapse example's second ENERGY line
 *   W_p   = W_int - (E_el - E_el(0)), the plastic dissipation
 *   num   = dPE + KE(0) - KE - W_int: > 0 is energy the discretisation
 *         removed (transfers, grid, and the nodes the no-slip floor holds),
 *         < 0 energy it created
 *
 * The material is registered as a USER material (gm_material_def) whose
 * update calls the library's public gm_mohr_coulomb_update (or
 * gm_elastic_update) on the batch and accumulates V sigma_mid : d_eps per
 * worker; --builtin registers the built-in material instead (no W_int), to
 * check that the wrapper leaves the run bitwise unchanged. In the granular
 * family points in the stress-free state do not call the material, and
 * stress the family zeroes is not seen by W_int: their E_el loss shows up in
 * W_p, and the plain family gives the clean budget.
 *
 * Scenes (the first argument):
 *   collapse  the planar column collapse of examples/column_collapse (a, L0,
 *             grid box, walls, fill and the connected deposit's front
 *             from collapse_scene.c; 6 tau_c in 200 rows), Mohr-Coulomb,
 *             rho 1800, nu 0.3, E 0.5 MPa; --floor wall|face as the
 *             example, or slip (a frictionless box face: no floor
 *             friction, to tell the floor's share)
 *   bar       an elastic free-free bar (1 m x 0.1 m, E --youngs, rho 1000,
 *             no gravity, no walls) started in its first axial mode,
 *             v_x = v0 cos(pi x / L): KE + E_el must stay KE(0)
 *   drop      an elastic block (0.15 m square, the collapse's material made
 *             elastic) falling from rest --gap above the no-slip floor:
 *             free fall until t = sqrt(2 gap / g), then landing
 *   slide     a Mohr-Coulomb block (0.3 m x 0.06 m) launched at --speed on
 *             the no-slip floor under gravity: it must come to rest, with
 *             KE(0) + dPE dissipated; with --floor-mu MU on a Coulomb wall
 *             floor of that friction instead
 *
 * Prints BUDGET (end of the run, J/m; floor_friction_J is the Coulomb
 * floor wall's slip work, an estimate, see friction_progress), SHARES (of
 * dPE + KE(0)), PHASES (the budget at 1..6 tau_c of the collapse, or
 * sixths of the run), CHECK (the sum of the final positions in %a, to
 * compare with --builtin) and, for the collapse, PROFILE (the deposit's
 * surface) and RESULT runout and height (H_inf / L0, the profile's
 * highest top); --history FILE writes one CSV row per output
 * row. --floor-mu MU sets the floor wall's friction (collapse; default
 * tan phi) or puts the slide scene's block on such a wall.
 * Other options: --cell --ppc --method --family --workers --rows --t-end
 * --aspect --friction --dilation --youngs --cfl --gap --speed --floor
 * --floor-mu; --material perzyna --fluidity GAMMA (1/s) replaces
 * Mohr-Coulomb with the Perzyna Drucker-Prager material (psi = 0, N =
 * --exponent, default 1, sigma_n = max(m p, --reference-stress Pa), default
 * 0: the paper's m p),
 * its cone matched to --friction's flow in plane strain
 * (collapse_scene_dp_friction).
 * Build and run from the worktree after `make`:
 *   gcc -std=c11 -O2 -Iinclude -Iexamples bench/convergence/energy_budget.c \
 *     bench/convergence/collapse_scene.c -Lbuild/lib/.libs -lgranmpm -lm \
 *     -o energy_budget
 *   LD_LIBRARY_PATH=build/lib/.libs ./energy_budget collapse --aspect 1.3 \
 *     --method bspline2 --friction 37 --floor face --family plain \
 *     --cell 0.015 --ppc 2
 * bench/convergence/energy.sh runs the sweep of section 15,
 * energy_validate.sh the scenes with a known budget.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include "collapse_scene.h"

#include <granmpm.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = COLLAPSE_PI;
static const double GRAVITY = COLLAPSE_GRAVITY; /* m/s^2 */
enum { MAX_WORKERS = 64, PAD = 8 };             /* one cache line per worker */
enum { PHASE_COUNT = 6 };                       /* budgets at 1..6 tau_c */

/* The wrapped material and its accumulated work. */
typedef struct budget_material {
  int plastic;                        /* 1: Mohr-Coulomb, 0: elastic */
  int perzyna;                        /* plastic: 1 Perzyna instead of MC */
  gm_mohr_coulomb_def mc;             /* used when plastic */
  gm_perzyna_def viscoplastic;        /* used when plastic and perzyna */
  gm_elastic_def elastic;             /* used otherwise */
  const double *mass_by_id;           /* kg/m, indexed by point id */
  double work[MAX_WORKERS * PAD];     /* J/m, W_int per worker */
  long long calls[MAX_WORKERS * PAD]; /* point updates per worker */
} budget_material;

/* sigma : d_eps of one point, Voigt rows, shear rows counted twice because
 * the batch holds tensor (not engineering) shear strains. */
static double contract(const gm_material_batch *batch, size_t i) {
  double sum = 0.0;
  for (int c = 0; c < 6; c++)
    sum += (c < 3 ? 1.0 : 2.0) * batch->stress[c][i] *
           batch->strain_increment[c][i];
  return sum;
}

/* User update: W_int += V (sigma_old + sigma_new)/2 : d_eps, split as half
 * the old stress's work before the wrapped update and half the new one's
 * after (no scratch copy of the old stress needed). */
static int budget_update(const gm_material_batch *batch, void *user,
                         char *message, size_t message_size) {
  budget_material *material = user;
  double old_work = 0.0, new_work = 0.0;
  for (size_t i = 0; i < batch->count; i++)
    old_work += material->mass_by_id[batch->point_id[i]] / batch->density[i] *
                contract(batch, i);
  int status =
      !material->plastic
          ? gm_elastic_update(batch, &material->elastic, message, message_size)
      : material->perzyna
          ? gm_perzyna_update(batch, &material->viscoplastic, message,
                              message_size)
          : gm_mohr_coulomb_update(batch, &material->mc, message, message_size);
  if (status != 0)
    return status;
  for (size_t i = 0; i < batch->count; i++)
    new_work += material->mass_by_id[batch->point_id[i]] / batch->density[i] *
                contract(batch, i);
  int slot = PAD * (batch->worker < MAX_WORKERS ? batch->worker : 0);
  material->work[slot] += 0.5 * (old_work + new_work);
  material->calls[slot] += (long long)batch->count;
  return 0;
}

typedef struct options {
  const char *scene; /* collapse | bar | drop | slide */
  gm_shape shape;
  gm_family family;
  int ppc, workers, rows, builtin;
  double cell, t_end; /* m, s (0: the scene's default) */
  double aspect, length, friction_deg, dilation_deg, youngs, poisson;
  double gap, speed; /* drop: m; slide: m/s */
  double cfl;        /* Courant number, 0: the library's 0.5 */
  const char *floor; /* collapse: wall (Coulomb wall, mu --floor-mu) |
                        face (no-slip box face) | slip (frictionless face) */
  double floor_mu;   /* mu of the wall floor; < 0: tan phi */
  const char *history;
  const char *material; /* mc (Mohr-Coulomb) | perzyna (Perzyna
                           Drucker-Prager, psi = 0, its cone matched to
                           --friction's plane-strain flow) */
  double fluidity;      /* perzyna: gamma, 1/s */
  double reference;     /* perzyna: sigma_n = max(m p, this), Pa */
  double exponent;      /* perzyna: N of Phi = (f / sigma_n)^N, > 0 */
} options;

/* Everything the rows need. */
typedef struct budget_run {
  const options *opt;
  collapse_scene scene; /* the collapse's geometry (scene "collapse") */
  gm_domain *domain;
  budget_material *material;
  double density;            /* kg/m^3 of the material */
  double youngs, poisson;    /* of the elastic energy density */
  double mass, centre_start; /* kg/m, m */
  double kinetic_start;      /* J/m */
  double elastic_start;      /* J/m */
  double length;             /* L0 of the collapse (m) */
  size_t count, column_count;
  double *positions, *stresses, *volumes;
  unsigned char *occupied;
  FILE *history;
  int floor_wall;     /* wall id of a Coulomb floor, -1: none */
  double *velocities; /* m/s, 2 per point (the friction estimate) */
  double *node_weight, *node_momentum; /* per floor node, column_count + 1 */
  gm_wall_traction *tractions;
  size_t traction_capacity;
  double friction_work; /* J/m, estimate of the floor's slip work */
  int friction_failed;  /* the estimate could not be taken */
} budget_run;

static double total_work(const budget_material *material) {
  double sum = 0.0;
  for (int w = 0; w < MAX_WORKERS; w++)
    sum += material->work[PAD * w];
  return sum;
}

/* Elastic energy sum V w of every point (J/m). */
static double elastic_energy(budget_run *run) {
  size_t n = run->count;
  if (gm_domain_get_field(run->domain, GM_FIELD_STRESS, run->stresses, 6 * n) !=
          GM_OK ||
      gm_domain_get_field(run->domain, GM_FIELD_VOLUME, run->volumes, n) !=
          GM_OK)
    return NAN;
  double energy = 0.0, nu = run->poisson;
  for (size_t i = 0; i < n; i++) {
    const double *t = run->stresses + 6 * i;
    double trace = t[0] + t[1] + t[2];
    double squares = t[0] * t[0] + t[1] * t[1] + t[2] * t[2] +
                     2.0 * (t[3] * t[3] + t[4] * t[4] + t[5] * t[5]);
    energy += run->volumes[i] * ((1.0 + nu) * squares - nu * trace * trace) /
              (2.0 * run->youngs);
  }
  return energy;
}

/* The right edge of the deposit connected to the back wall (m), as
 * examples/column_collapse measures it (collapse_scene_front). */
static double deposit_front(budget_run *run) {
  if (gm_domain_get_field(run->domain, GM_FIELD_POSITION, run->positions,
                          2 * run->count) != GM_OK)
    return NAN;
  return collapse_scene_front(&run->scene, run->positions, run->count,
                              run->occupied);
}

/* After every step with a Coulomb floor: the work its friction did, an
 * estimate. The wall reports each node's tangential force per cell length
 * (gm_domain_get_wall_tractions); its slip velocity is not reachable
 * through the API, so it is taken as the tent-weighted (1 - |dx|/h)
 * (1 - y/h) mean horizontal velocity of the points in the cell row on the
 * floor, what a linear node on the floor would carry. The dissipation of
 * the step is -sum F_x u_x dt (F_x = traction * h, of the wall on the
 * material). Over a continuum Coulomb floor this is mu N times the slip,
 * a physical term; the rest of the numerical term is the discretisation's
 * (including the wall's normal impacts). */
static int friction_progress(const gm_domain *domain, double time,
                             double end_time, void *user) {
  (void)time;
  (void)end_time;
  budget_run *run = user;
  if (run->floor_wall < 0 || run->friction_failed)
    return 0;
  size_t count = 0;
  for (;;) {
    gm_status status =
        gm_domain_get_wall_tractions(domain, run->floor_wall, run->tractions,
                                     run->traction_capacity, &count);
    if (status == GM_OK)
      break;
    if (count <= run->traction_capacity) {
      run->friction_failed = 1;
      return 0;
    }
    free(run->tractions);
    run->traction_capacity = 2 * count;
    run->tractions = malloc(run->traction_capacity * sizeof *run->tractions);
    if (!run->tractions) {
      run->friction_failed = 1;
      return 0;
    }
  }
  gm_wall_force force = gm_wall_force_default();
  size_t n = run->count;
  if (gm_domain_get_wall_force(domain, run->floor_wall, &force) != GM_OK ||
      gm_domain_get_field(domain, GM_FIELD_POSITION, run->positions, 2 * n) !=
          GM_OK ||
      gm_domain_get_field(domain, GM_FIELD_VELOCITY, run->velocities, 2 * n) !=
          GM_OK) {
    run->friction_failed = 1;
    return 0;
  }
  double h = run->opt->cell;
  size_t columns = run->column_count;
  memset(run->node_weight, 0, (columns + 1) * sizeof *run->node_weight);
  memset(run->node_momentum, 0, (columns + 1) * sizeof *run->node_momentum);
  for (size_t i = 0; i < n; i++) {
    double x = run->positions[2 * i] / h, y = run->positions[2 * i + 1] / h;
    if (y >= 1.0 || y < 0.0 || x < 0.0 || x >= (double)columns)
      continue;
    size_t left = (size_t)x;
    double fraction = x - (double)left;
    double weights[2] = {(1.0 - fraction) * (1.0 - y), fraction * (1.0 - y)};
    for (int side = 0; side < 2; side++) {
      run->node_weight[left + side] += weights[side];
      run->node_momentum[left + side] += weights[side] * run->velocities[2 * i];
    }
  }
  for (size_t k = 0; k < count; k++) {
    double node = floor(run->tractions[k].position / h + 0.5);
    if (node < 0.0 || node > (double)columns)
      continue;
    size_t j = (size_t)node;
    if (run->node_weight[j] > 0.0)
      run->friction_work -= run->tractions[k].tangential * h *
                            (run->node_momentum[j] / run->node_weight[j]) *
                            force.duration;
  }
  return 0;
}

/* One budget: the terms at the current time (J/m). */
typedef struct budget {
  double time, released, kinetic, work, elastic, plastic, numerical, front;
  double friction; /* the floor wall's slip work so far, an estimate */
} budget;

static budget measure(budget_run *run) {
  budget b = {0};
  gm_summary summary = gm_summary_default();
  gm_domain_get_time(run->domain, &b.time, NULL);
  gm_domain_get_summary(run->domain, &summary);
  b.released = run->mass * GRAVITY *
               (run->centre_start - summary.centre_of_mass[1]) *
               (strcmp(run->opt->scene, "bar") != 0);
  b.kinetic = summary.kinetic_energy;
  b.work = run->material ? total_work(run->material) : NAN;
  b.elastic = elastic_energy(run);
  b.plastic = b.work - (b.elastic - run->elastic_start);
  b.numerical = b.released + run->kinetic_start - b.kinetic - b.work;
  b.front = strcmp(run->opt->scene, "collapse") == 0 ? deposit_front(run) : NAN;
  b.friction = run->floor_wall >= 0 && !run->friction_failed
                   ? run->friction_work
                   : (run->floor_wall >= 0 ? NAN : 0.0);
  return b;
}

static void write_history(budget_run *run, const budget *b) {
  if (!run->history)
    return;
  fprintf(run->history, "%.6g,%.8g,%.8g,%.8g,%.8g,%.8g,%.8g,%.6g\n", b->time,
          b->released, b->kinetic, b->work, b->elastic, b->plastic,
          b->numerical, b->front);
}

/* The deposit's surface: the highest point top (centre plus half a point
 * spacing) in bins of L0/20 from the back wall, in L0, from the positions
 * last read into run->positions; to compare deposits and fronts across
 * cells and points per cell. Returns the highest top (L0), the final
 * height H_inf / L0 of Lube et al. (2005) at the end of the run. */
static double print_profile(const budget_run *run, double time) {
  enum { BINS = 240 }; /* 12 L0: the run-out of a = 8 is 7.6 L0 */
  double top[BINS] = {0}, bin = run->length / 20.0;
  double half = 0.5 * run->opt->cell / run->opt->ppc;
  for (size_t i = 0; i < run->count; i++) {
    double x = run->positions[2 * i] / bin;
    if (x >= 0.0 && x < BINS)
      top[(int)x] = fmax(top[(int)x], run->positions[2 * i + 1] + half);
  }
  printf("PROFILE t_s=%.4g bin=L0/20 top/L0:", time);
  double highest = 0.0;
  for (int k = 0; k < BINS; k++) {
    printf(" %.3f", top[k] / run->length);
    highest = fmax(highest, top[k] / run->length);
  }
  printf("\n");
  return highest;
}

static int fail(const gm_domain *domain, const char *what, gm_status status) {
  return collapse_scene_fail(domain, what, status);
}
#define CHECK COLLAPSE_CHECK

/* Registers the material (wrapped or built in); returns its id or -1. */
static int add_material(budget_run *run, int plastic) {
  const options *o = run->opt;
  gm_domain *domain = run->domain;
  budget_material *m = run->material;
  m->plastic = plastic;
  m->mc = gm_mohr_coulomb_def_default();
  m->mc.youngs_modulus = o->youngs;
  m->mc.poisson_ratio = o->poisson;
  m->mc.density = run->density;
  m->mc.friction_angle = o->friction_deg * PI / 180.0;
  m->mc.dilation_angle = o->dilation_deg * PI / 180.0;
  m->mc.bagnold_viscosity = 0.0;
  m->perzyna = strcmp(o->material, "perzyna") == 0;
  m->viscoplastic = gm_perzyna_def_default();
  m->viscoplastic.youngs_modulus = o->youngs;
  m->viscoplastic.poisson_ratio = o->poisson;
  m->viscoplastic.density = run->density;
  m->viscoplastic.friction_angle =
      collapse_scene_dp_friction(o->friction_deg * PI / 180.0);
  m->viscoplastic.fluidity = o->fluidity;
  m->viscoplastic.reference_stress = o->reference;
  m->viscoplastic.exponent = o->exponent;
  m->elastic = gm_elastic_def_default();
  m->elastic.youngs_modulus = o->youngs;
  m->elastic.poisson_ratio = o->poisson;
  m->elastic.density = run->density;
  int id = -1;
  gm_status status;
  if (o->builtin)
    status = !plastic     ? gm_domain_add_elastic(domain, &m->elastic, &id)
             : m->perzyna ? gm_domain_add_perzyna(domain, &m->viscoplastic, &id)
                          : gm_domain_add_mohr_coulomb(domain, &m->mc, &id);
  else {
    gm_material_def def = gm_material_def_default();
    def.name = !plastic     ? "elastic_budget"
               : m->perzyna ? "perzyna_budget"
                            : "mohr_coulomb_budget";
    def.update = budget_update;
    def.user = m;
    def.state_count = !plastic     ? 0
                      : m->perzyna ? GM_PERZYNA_STATE_COUNT
                                   : GM_MOHR_COULOMB_STATE_COUNT;
    /* the same expression as the built-in's, so the same stable dt */
    def.p_wave_modulus = o->youngs * (1.0 - o->poisson) /
                         ((1.0 + o->poisson) * (1.0 - 2.0 * o->poisson));
    def.density = run->density;
    status = gm_domain_add_material(domain, &def, &id);
  }
  if (status != GM_OK) {
    fail(domain, "adding the material", status);
    return -1;
  }
  if (o->family != GM_FAMILY_PLAIN) {
    gm_granular_def granular = gm_granular_def_default();
    granular.critical_density = COLLAPSE_CRITICAL_RATIO * run->density;
    status = gm_domain_set_granular(domain, id, &granular);
    if (status != GM_OK) {
      fail(domain, "gm_domain_set_granular", status);
      return -1;
    }
  }
  return id;
}

/* Builds the scene's domain and points; sets the default t_end. */
static int build(budget_run *run, double *t_end) {
  const options *o = run->opt;
  int collapse = strcmp(o->scene, "collapse") == 0;
  run->scene = (collapse_scene){
      .cell = o->cell,
      .ppc = o->ppc,
      .shape = o->shape,
      .family = o->family,
      .workers = o->workers,
      .cfl = o->cfl,
      .aspect = o->aspect,
      .length = o->length,
      .floor = o->floor,
      .floor_mu =
          o->floor_mu >= 0.0 ? o->floor_mu : tan(o->friction_deg * PI / 180)};
  gm_domain_def def = gm_domain_def_default();
  def.cell_size = o->cell;
  def.shape = o->shape;
  def.family = o->family;
  def.worker_count = o->workers;
  if (o->cfl > 0.0)
    def.cfl = o->cfl;
  gm_fill_def fill = gm_fill_def_default();
  fill.points_per_cell_axis = o->ppc;
  int plastic = 1, face_floor = 1;
  if (collapse) {
    /* examples/column_collapse's scene, collapse_scene.c */
    def = collapse_scene_domain_def(&run->scene);
    run->density = COLLAPSE_DENSITY;
    face_floor = 0; /* the scene sets its floor */
    *t_end = 6.0 * collapse_scene_tau(&run->scene);
  } else if (strcmp(o->scene, "bar") == 0) {
    def.extent[0] = 1.4;
    def.extent[1] = 0.5;
    def.origin[0] = -0.2;
    def.origin[1] = -0.2;
    run->density = 1000.0;
    fill.upper[0] = 1.0;
    fill.upper[1] = 0.1;
    plastic = face_floor = 0;
    *t_end = 2.0 * 2.0 / sqrt(o->youngs / run->density); /* 2 periods */
  } else if (strcmp(o->scene, "drop") == 0) {
    def.extent[0] = 0.6;
    def.extent[1] = o->gap + 0.45;
    def.gravity[1] = -GRAVITY;
    run->density = 1800.0;
    fill.lower[0] = 0.15;
    fill.upper[0] = 0.3;
    fill.lower[1] = o->gap;
    fill.upper[1] = o->gap + 0.15;
    plastic = 0;
    *t_end = sqrt(2.0 * o->gap / GRAVITY) + 0.3;
  } else if (strcmp(o->scene, "slide") == 0) {
    def.extent[0] = 1.5;
    def.extent[1] = 0.3;
    def.gravity[1] = -GRAVITY;
    run->density = 1800.0;
    fill.upper[0] = 0.3;
    fill.upper[1] = 0.06;
    fill.velocity[0] = o->speed;
    /* --floor-mu MU: a Coulomb wall floor instead of the no-slip face
     * (checks the friction estimate: a block sliding on it dissipates
     * KE(0) + dPE as floor friction) */
    face_floor = o->floor_mu < 0.0;
    *t_end = 1.0;
  } else {
    fprintf(stderr, "scene '%s' is not collapse, bar, drop or slide\n",
            o->scene);
    return 2;
  }
  if (face_floor)
    def.walls[GM_FACE_YMIN] = GM_WALL_FIXED;
  CHECK(NULL, gm_domain_create(&def, &run->domain));
  gm_domain *domain = run->domain;
  int material = add_material(run, plastic);
  if (material < 0)
    return 2;
  run->floor_wall = -1;
  if (collapse) {
    CHECK(domain,
          collapse_scene_add_walls(domain, &run->scene, &run->floor_wall));
    CHECK(domain, collapse_scene_fill(domain, &run->scene, material));
  } else {
    if (strcmp(o->scene, "slide") == 0 && !face_floor) {
      gm_wall_def wall = gm_wall_def_default();
      wall.normal[0] = 0.0;
      wall.normal[1] = 1.0;
      wall.friction_static = wall.friction_kinetic = o->floor_mu;
      CHECK(domain, gm_domain_add_wall(domain, &wall, &run->floor_wall));
    }
    fill.material = material;
    CHECK(domain, gm_domain_fill_box(domain, &fill, NULL, NULL));
  }
  run->count = gm_domain_point_count(domain);
  size_t n = run->count;
  run->positions = malloc(2 * n * sizeof *run->positions);
  run->stresses = malloc(6 * n * sizeof *run->stresses);
  run->volumes = malloc(n * sizeof *run->volumes);
  run->column_count = collapse ? collapse_scene_columns(&run->scene)
                               : (size_t)ceil(def.extent[0] / o->cell) + 2;
  run->occupied = malloc(run->column_count);
  run->velocities = malloc(2 * n * sizeof *run->velocities);
  run->node_weight = malloc((run->column_count + 1) * sizeof(double));
  run->node_momentum = malloc((run->column_count + 1) * sizeof(double));
  double *masses = malloc(n * sizeof *masses);
  int64_t *ids = malloc(n * sizeof *ids);
  if (!run->positions || !run->stresses || !run->volumes || !run->occupied ||
      !run->velocities || !run->node_weight || !run->node_momentum || !masses ||
      !ids)
    return 2;
  CHECK(domain, gm_domain_get_field(domain, GM_FIELD_MASS, masses, n));
  CHECK(domain, gm_domain_get_ids(domain, ids, n));
  int64_t max_id = 0;
  for (size_t i = 0; i < n; i++)
    max_id = ids[i] > max_id ? ids[i] : max_id;
  double *by_id = calloc((size_t)max_id + 1, sizeof *by_id);
  if (!by_id)
    return 2;
  for (size_t i = 0; i < n; i++)
    by_id[ids[i]] = masses[i];
  run->material->mass_by_id = by_id;
  if (strcmp(o->scene, "bar") == 0) {
    /* first free-free axial mode, v_x = v0 cos(pi x / L), v0 = 0.01 m/s */
    double *velocities = calloc(2 * n, sizeof *velocities);
    CHECK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION, run->positions,
                                      2 * n));
    for (size_t i = 0; i < n; i++)
      velocities[2 * i] = 0.01 * cos(PI * run->positions[2 * i] / 1.0);
    CHECK(domain,
          gm_domain_set_field(domain, GM_FIELD_VELOCITY, velocities, 2 * n));
    free(velocities);
  }
  gm_summary summary = gm_summary_default();
  gm_domain_get_summary(domain, &summary);
  run->mass = summary.mass;
  run->centre_start = summary.centre_of_mass[1];
  run->kinetic_start = summary.kinetic_energy;
  run->youngs = o->youngs;
  run->poisson = o->poisson;
  run->elastic_start = elastic_energy(run);
  run->length = o->length;
  free(masses);
  free(ids);
  return 0;
}

static int parse_shape(const char *word, gm_shape *shape) {
  static const char *const names[] = {"linear", "ugimp",    "cpgimp",
                                      "cpdi",   "bspline2", "bspline3"};
  for (int k = 0; k < 6; k++)
    if (strcmp(word, names[k]) == 0) {
      *shape = (gm_shape)k;
      return 0;
    }
  return 1;
}

static int parse(int argc, char **argv, options *o) {
  if (argc < 2) {
    fprintf(stderr,
            "usage: %s collapse|bar|drop|slide [--option value]...\n"
            "(see the top of energy_budget.c)\n",
            argv[0]);
    return 2;
  }
  o->scene = argv[1];
  for (int k = 2; k < argc; k++) {
    const char *name = argv[k];
    if (strcmp(name, "--builtin") == 0) {
      o->builtin = 1;
      continue;
    }
    if (k + 1 >= argc) {
      fprintf(stderr, "%s needs a value\n", name);
      return 2;
    }
    const char *value = argv[++k];
    double number = atof(value);
    if (strcmp(name, "--cell") == 0)
      o->cell = number;
    else if (strcmp(name, "--ppc") == 0)
      o->ppc = atoi(value);
    else if (strcmp(name, "--workers") == 0)
      o->workers = atoi(value);
    else if (strcmp(name, "--rows") == 0)
      o->rows = atoi(value);
    else if (strcmp(name, "--t-end") == 0)
      o->t_end = number;
    else if (strcmp(name, "--aspect") == 0)
      o->aspect = number;
    else if (strcmp(name, "--friction") == 0)
      o->friction_deg = number;
    else if (strcmp(name, "--dilation") == 0)
      o->dilation_deg = number;
    else if (strcmp(name, "--youngs") == 0)
      o->youngs = number;
    else if (strcmp(name, "--cfl") == 0)
      o->cfl = number;
    else if (strcmp(name, "--gap") == 0)
      o->gap = number;
    else if (strcmp(name, "--speed") == 0)
      o->speed = number;
    else if (strcmp(name, "--floor") == 0)
      o->floor = value;
    else if (strcmp(name, "--floor-mu") == 0)
      o->floor_mu = number;
    else if (strcmp(name, "--history") == 0)
      o->history = value;
    else if (strcmp(name, "--material") == 0)
      o->material = value;
    else if (strcmp(name, "--fluidity") == 0)
      o->fluidity = number;
    else if (strcmp(name, "--reference-stress") == 0)
      o->reference = number;
    else if (strcmp(name, "--exponent") == 0)
      o->exponent = number;
    else if (strcmp(name, "--method") == 0) {
      if (parse_shape(value, &o->shape)) {
        fprintf(stderr, "--method %s unknown\n", value);
        return 2;
      }
    } else if (strcmp(name, "--family") == 0) {
      if (strcmp(value, "plain") == 0)
        o->family = GM_FAMILY_PLAIN;
      else if (strcmp(value, "granular") == 0)
        o->family = GM_FAMILY_GRANULAR;
      else if (strcmp(value, "stress_free") == 0)
        o->family = GM_FAMILY_STRESS_FREE;
      else {
        fprintf(stderr, "--family %s unknown\n", value);
        return 2;
      }
    } else {
      fprintf(stderr, "unknown option %s\n", name);
      return 2;
    }
  }
  if (o->cell <= 0.0 || o->ppc < 1 || o->ppc > 16 || o->workers < 1 ||
      o->workers > MAX_WORKERS || o->rows < 1 || o->aspect <= 0.0 ||
      o->aspect > 10.0 || o->youngs <= 0.0) {
    fprintf(stderr, "an option is out of range (cell > 0, ppc 1..16, "
                    "workers 1..64, rows >= 1, 0 < aspect <= 10, E > 0)\n");
    return 2;
  }
  if (strcmp(o->floor, "wall") != 0 && strcmp(o->floor, "face") != 0 &&
      strcmp(o->floor, "slip") != 0) {
    fprintf(stderr, "--floor %s is not wall, face or slip\n", o->floor);
    return 2;
  }
  if ((strcmp(o->material, "mc") != 0 && strcmp(o->material, "perzyna") != 0) ||
      (strcmp(o->material, "perzyna") == 0 &&
       (!(o->fluidity > 0.0) || !(o->exponent > 0.0)))) {
    fprintf(stderr, "--material is mc or perzyna (with --fluidity > 0, "
                    "--exponent > 0)\n");
    return 2;
  }
  return 0;
}

int main(int argc, char **argv) {
  options o = {.shape = GM_SHAPE_UGIMP,
               .family = GM_FAMILY_GRANULAR,
               .ppc = 2,
               .workers = 1,
               .rows = 200,
               .cell = 0.0075,
               .aspect = 1.3,
               .length = 0.15,
               .friction_deg = 35.0,
               .youngs = 5e5,
               .poisson = 0.3,
               .gap = 0.1,
               .speed = 1.0,
               .floor = "wall",
               .floor_mu = -1.0,
               .material = "mc",
               .fluidity = 0.0,
               .exponent = 1.0};
  int status = parse(argc, argv, &o);
  if (status != 0)
    return status;
  static budget_material material; /* large; zeroed */
  budget_run run = {.opt = &o, .material = &material};
  double t_end = 0.0;
  status = build(&run, &t_end);
  if (status != 0)
    return status;
  if (o.t_end > 0.0)
    t_end = o.t_end;
  if (o.history) {
    run.history = fopen(o.history, "w");
    if (!run.history) {
      perror(o.history);
      return 2;
    }
    fprintf(run.history, "time_s,released_J,kinetic_J,internal_work_J,"
                         "elastic_J,plastic_J,numerical_J,front_m\n");
  }
  budget b = measure(&run);
  double front_start = b.front;
  write_history(&run, &b);
  /* The budget at the first row at or past each whole tau_c (collapse) or
   * each sixth of the run (other scenes): when the numerical term grows. */
  double period = strcmp(o.scene, "collapse") == 0
                      ? sqrt(o.aspect * o.length / GRAVITY)
                      : t_end / 6.0;
  budget phase[PHASE_COUNT];
  int phases = 0;
  for (int row = 1; row <= o.rows; row++) {
    double target = row == o.rows ? t_end : t_end * row / o.rows;
    gm_status step =
        gm_domain_advance(run.domain, target, 0.0,
                          run.floor_wall >= 0 ? friction_progress : NULL, &run);
    if (step != GM_OK)
      return fail(run.domain, "gm_domain_advance", step);
    b = measure(&run);
    write_history(&run, &b);
    while (phases < PHASE_COUNT &&
           (b.time >= (phases + 1) * period * (1.0 - 1e-9) || row == o.rows)) {
      if (strcmp(o.scene, "collapse") == 0)
        (void)print_profile(&run, b.time); /* positions of measure() */
      phase[phases++] = b;
    }
  }
  if (run.history)
    fclose(run.history);
  double input = b.released + run.kinetic_start;
  long long calls = 0;
  for (int w = 0; w < MAX_WORKERS; w++)
    calls += material.calls[PAD * w];
  uint64_t steps = 0;
  gm_domain_get_time(run.domain, NULL, &steps);
  printf("BUDGET scene=%s points=%zu steps=%llu point_updates=%lld "
         "released_J=%.6g kinetic_start_J=%.6g kinetic_J=%.6g "
         "internal_work_J=%.6g elastic_start_J=%.6g elastic_J=%.6g "
         "plastic_J=%.6g numerical_J=%.6g floor_friction_J=%.6g\n",
         o.scene, run.count, (unsigned long long)steps, calls, b.released,
         run.kinetic_start, b.kinetic, b.work, run.elastic_start, b.elastic,
         b.plastic, b.numerical, b.friction);
  printf("SHARES of dPE + KE(0) = %.6g J/m: kinetic=%.4f elastic_change=%.4f "
         "plastic=%.4f numerical=%.4f\n",
         input, b.kinetic / input, (b.elastic - run.elastic_start) / input,
         b.plastic / input, b.numerical / input);
  printf("PHASES t_s,released_J,kinetic_J,plastic_J,numerical_J,front_m,"
         "floor_friction_J:");
  for (int k = 0; k < phases; k++)
    printf(" %.4g,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g", phase[k].time,
           phase[k].released, phase[k].kinetic, phase[k].plastic,
           phase[k].numerical, phase[k].front, phase[k].friction);
  printf("\n");
  /* a fingerprint of the final positions, to compare --builtin runs */
  double sum = 0.0;
  if (gm_domain_get_field(run.domain, GM_FIELD_POSITION, run.positions,
                          2 * run.count) == GM_OK)
    for (size_t i = 0; i < 2 * run.count; i++)
      sum += run.positions[i];
  printf("CHECK position_sum=%a\n", sum);
  if (strcmp(o.scene, "collapse") == 0) {
    double height = print_profile(&run, b.time);
    printf("RESULT runout=%.6f height=%.4f\n",
           (b.front - front_start) / o.length, height);
  }
  gm_domain_destroy(run.domain);
  free((void *)material.mass_by_id);
  free(run.positions);
  free(run.stresses);
  free(run.volumes);
  free(run.occupied);
  free(run.velocities);
  free(run.node_weight);
  free(run.node_momentum);
  free(run.tractions);
  return 0;
}
