/*
 * wieckowski1999_silo_discharge.c - discharge of a silo through a bottom
 * orifice, compared with Beverloo's law (Wieckowski, Youn & Yeon 1999 = 002,
 * sec 5, eqs 19-20; Wieckowski 2004 = 001, sec 5.1.1).
 *
 * Scenes: plane-strain flat-bottom silo (funnel flow, 002 sec 5.1) or
 * trapezoidal hopper (--hopper DEG, mass flow), and the axisymmetric pair
 * (--geometry axisym, 002 sec 5.2 / 001 sec 5.1.1). Only half of the
 * symmetric cross-section is modelled: the axis x = 0 is a slip face. The
 * papers' figures (silo dimensions) did not survive the text extraction, so
 * the silo is sized by the validity range of Beverloo's law
 * (docs/references.md, Mankoc et al. 2007): full width >= 2.5 D, fill height
 * >= 1.2 widths. Material: Drucker-Prager of 002 sec 5 (E = 1 MPa, nu = 0.3,
 * phi = 25 deg, rho = 1500 kg/m^3), Coulomb silo and hopper walls with phi_w =
 * 20 deg.
 *
 * Two phases, as in 002 sec 5 (initial static state, then the flow):
 *  1. at rest: the orifice is closed by a rigid gate; the fill starts from
 *     a geostatic stress and settles with local damping. The wall traction
 *     profile is then compared with Janssen (optional RESULT line).
 *  2. discharge: the settled points are copied into an undamped domain
 *     without the gate; a sink just below the orifice removes every point
 *     that leaves, so the discharged mass is read at any time from
 *     gm_domain_get_sink_totals().
 * The flat floor is a rigid (no-slip) layer of points: a planar wall is an
 * infinite plane and cannot have a hole in it. Hopper walls are inclined
 * planar Coulomb walls through the orifice edges.
 *
 * Beverloo (002 eq 19, W in g/min with cgs units, i.e. C = 45/60 = 0.75 in
 * SI for W = C rho A' sqrt(g D'_h)): for a slot of width D (per unit
 * length, hydraulic diameter 2D) W' = 0.75 sqrt(2) rho sqrt(g) (D - k d)^1.5
 * with k = 0.7; for a circular orifice (eq 20) W = 0.75 pi/4 rho sqrt(g)
 * (D - k d)^2.5 = 0.59 rho sqrt(g) (D - 1.4 d)^2.5. A continuum has no
 * grain: the RESULT uses d = 0 (002 compares with d/D = 0 as well), the
 * law of a vanishing grain size. The grid does shorten the orifice (the edge
 * node is held by the floor): measured, W' ~ (D - 2.7 h)^1.5 for h = 0.025
 * m, so the flow is also compared, on a separate line, with the mesh as the
 * grain, k d = 2.7 h (tests/physics/test_beverloo.c asserts that scaling).
 *
 * Runs for at least --t-end s and until 45 % of the fill has left (use a
 * larger --t-end to watch the silo empty; --t-max stops it earlier).
 * --fill sets the fill height in full widths (2 by default). The default (D =
 * 0.3 m, 0.025 m cells, 2 x 2 points per cell) takes about 5 s on one core.
 * --window-end F ends the rate's window at F of the fill (0.4 by default;
 * the run stops at F + 0.05): validate/silo_beverloo.sh uses 0.25, which
 * costs about 0.6 of the default window in 3D.
 *
 * Steady rate: the discharged mass is sampled every --sample s; the rate is
 * the least-squares slope of mass against time over the window from the
 * moment a tenth of the fill has left (the start-up transient, a fall of a
 * few orifice widths, is over) to the moment half of it has left (the
 * free surface still stands above 1.2 widths for the default sizes).
 *
 * Prints: a table of the discharge, then
 *   RESULT wall_pressure_mid=... (Janssen, at rest; hopper: not printed)
 *   RESULT flow_rate=... reference=Beverloo (kg/(m s), or kg/s axisym)
 *   rate by window: the same fit over 10-25 % and 25-40 % of the fill
 *   (axisymmetric and 3D) the open floor nodes of the orifice and the
 *   area they open against pi D^2 / 4, and the mean v_y over the window of
 *   the points above the orifice's centre (r < h, 0 <= y < h)
 * Writes <out>/discharge.csv, <out>/rest_wall.csv and <out>/silo.pvd (in
 * 3D also slice.csv and slice.png, a vertical slice through the axis
 * coloured by speed in mid-window, silo_slice_3d.c), and
 * with --profile PATH the steady profiles across and above the orifice
 * (PATH, PATH_axis.csv; docs/convergence.md sec. 14).
 * --grain D replaces Drucker-Prager by mu(I) with grain diameter D on the
 * same cone (docs/convergence.md sec. 14: the rate's growth under
 * refinement is the same).
 * --drop L lowers the sinks L below the orifice (whole cells): the points
 * leave the opening in free fall instead of being removed at its plane
 * (docs/convergence.md sec. 25: the rate's growth is the same).
 * --youngs E sets the fill's Young's modulus (Pa; 002's 1 MPa by default),
 * and --profile also records, per bin, the mass-weighted sigma_yy,
 * sigma_xy, pressure, q / (m p) (1 at yield) and the mass share of
 * stress-free points (p <= 0), and on the axis sigma_yy, sigma_xy and
 * that share of the column x < D/12 and v_y and sigma_xy of the next,
 * D/12 <= x < D/6 (docs/convergence.md sec. 27).
 * Probes of docs/convergence.md sec. 29 (the rate's growth under refinement
 * with each removed in turn): --dilation PSI replaces Drucker-Prager by
 * Mohr-Coulomb on the same phi with dilation angle PSI (deg; PSI = phi is
 * associated flow, which does not localise on the grid, sec. 19); --pic A
 * blends PIC into the FLIP update (numerical viscosity a h^2 / dt);
 * --scheme usl|usf in place of MUSL; --wall-friction MU sets the silo and
 * hopper walls' Coulomb coefficient (002's tan 20 deg by default; the
 * Janssen reference follows it). Sec. 30: --friction PHI (deg) sets the
 * fill's friction angle (25 by default; the Janssen K follows it), --fluid S
 * replaces the fill by von Mises with yield stress S (Pa), a nearly inviscid
 * fluid whose discharge Torricelli and Kirchhoff's contraction predict.
 *
 * --edge-node held|open (flat floor): the floor layer begins at the
 * orifice's edge and holds the node on it (held, the default), or begins
 * a cell further out so that node is open (open; in 3D the open nodes are
 * those within D/2 + h/2 of the axis). The held node's zero velocity
 * reaches into the opening and the rate converges from below; the open
 * rule's opening is a cell wider in the floor's points and its rate
 * converges from above, with a much smaller error: the two bracket one
 * limit and their gap halves with the cell (docs/convergence.md sec. 38,
 * tests/scripts/silo_edge_bracket.sh).
 *
 * --geometry 3d (issue 16 items 3-4): a square silo of side 2B with a
 * circular orifice of diameter D in its flat floor, y up. Only the quarter
 * x, z >= 0 is modelled: the grid faces x = 0 and z = 0 are slip symmetry
 * planes, the side walls x = B and z = B planar Coulomb walls, the floor
 * a rigid layer with a quarter-circle hole centred on the corner: the
 * rigid floor holds every node its points touch, so the hole is cut by
 * nodes, the open ones those within D/2 - h/2 of the corner, the planar
 * and axisymmetric floors' rule on their line (silo_discharge_3d.c). The
 * sinks fill the hole in the floor layer, as in 2D. The
 * rate is 4 times the quarter's, against Beverloo's circular law (eq 20)
 * and, printed as a second RESULT, against the axisymmetric silo of the
 * same D, B, H, cell and points per cell, run in the same process (a
 * cylinder of radius B: the same hydraulic radius B/2 as the square, and
 * Beverloo's rate does not depend on the silo's width beyond 2.5 D). No
 * wall-traction profile in 3D (gm_domain_get_wall_tractions), so no
 * Janssen line; no --profile. Measured in docs/3d.md.
 * --geometry 3d --hopper DEG: a pyramidal hopper with a square outlet of
 * side D (issue 16 item 4): in the quarter, two more planar Coulomb walls
 * at DEG from the vertical through the outlet's edges x = D/2 and z = D/2
 * at y = 0, no floor layer in the discharge (the gate closes the outlet
 * while the fill settles), one sink under the quarter outlet D/2 x D/2.
 * RESULT against Beverloo's eq 19 for a square outlet (C = 0.75, D'_h = D)
 * with d = 0, no axisymmetric run. In 3D (and in 2D) the CSV's wall
 * columns sum the side walls, its hopper columns the hopper walls.
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>

#include "common.h"
#include "silo_discharge_3d.h"
#include "silo_slice_3d.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;
static const double GRAVITY = 9.81;           /* m/s^2 */
static const double DENSITY = 1500.0;         /* kg/m^3, 002 sec 5 */
static const double FRICTION_ANGLE = 25.0;    /* deg, phi of 002 */
static const double WALL_ANGLE = 20.0;        /* deg, phi_w of 002 */
static const double POISSON_RATIO = 0.3;      /* -, 002 */
static const double SETTLE_TIME = 0.6;        /* s, phase 1 */
static const double SETTLE_DAMPING = 0.1;     /* -, phase 1 only */
static const double AVERAGING_TIME = 0.1;     /* s, rest tractions */
static const double WINDOW_START = 0.1;       /* fraction discharged */
static const double WINDOW_END = 0.4;         /* fraction discharged */
static const double BEVERLOO_SI = 45.0 / 60.; /* 002 eq 19 in SI units */
static const double MESH_GRAIN =
    2.7; /* k d / h, tests/physics/test_beverloo.c */

enum { MAX_SAMPLES = 100000, MAX_TRACTIONS = 4096, MAX_SINKS = 64 };

/* What the command line chooses, and the derived geometry. */
typedef struct silo {
  example_options options;
  gm_geometry geometry;
  double orifice;         /* m, D: slot width or orifice diameter */
  double half_width;      /* m, B: axis to the silo wall */
  double fill_height;     /* m, H: initial free surface above the floor */
  double hopper_angle;    /* rad, hopper wall from the vertical; 0 = flat */
  double sample;          /* s, sampling interval of the discharge */
  double mass;            /* kg (per m, or full ring), the fill's mass */
  double fluidity;        /* 1/s, > 0: the Perzyna rate term; 0: rate-free */
  double reference;       /* Pa, sigma_ref of the Perzyna normaliser */
  double grain;           /* m, > 0: mu(I) with this grain diameter */
  double youngs;          /* Pa, > 0: E in place of 002's 1 MPa */
  double dilation;        /* rad, >= 0: Mohr-Coulomb with this psi; < 0: DP */
  double pic;             /* -, the FLIP-PIC blend a (gm_domain_def) */
  double fluid;           /* Pa, > 0: von Mises with this yield stress */
  double friction;        /* rad, phi of the fill (002's 25 deg) */
  double wall_friction;   /* -, mu_w of the silo and hopper walls */
  const char *scheme;     /* --scheme usl|musl|usf */
  const char *transfer;   /* --transfer flip|apic */
  const char *profile;    /* path of the steady profiles' CSV; "" = none */
  double cfl;             /* -, Courant number of the stable dt */
  int edge_cells;         /* 0: the floor holds the node on the orifice's
                             edge (--edge-node held); 1: it starts a cell
                             further out and that node is open */
  double drop;            /* m, free fall below the orifice before the sink
                             (whole cells); 0 = the sink at the orifice */
  double t_max;           /* s, > 0: the discharge stops here, window or not */
  double window_end;      /* -, fraction discharged that ends the window */
  int dim;                /* 2, or 3 with --geometry 3d */
  const char *volumetric; /* --volumetric point|cell */
} silo;

/* The full silo over the model: the half in plane strain, the whole ring
 * in axisymmetry, the quarter in 3D. */
static double symmetry_factor(const silo *s) {
  if (s->geometry == GM_GEOMETRY_AXISYMMETRIC)
    return 1.0;
  return s->dim == 3 ? 4.0 : 2.0;
}

/* Time-averaged loads of one sampling interval (step hook). */
typedef struct wall_loads {
  int wall_count;
  int side_count;       /* the first side_count walls are the silo's
                           sides (1, in 3D 2), the rest its hopper walls */
  int walls[4];         /* silo walls, then hopper walls */
  double last_time;     /* s */
  double span;          /* s, time accumulated */
  double normal[4];     /* N s, integral of each wall's normal force */
  double tangential[4]; /* N s, its friction force */
} wall_loads;

/* The time-averaged force (N) of the side walls (hopper = 0) or of the
 * hopper walls (hopper = 1) over `span` s: normal (tangential = 0) or
 * friction (tangential = 1). */
static double wall_load(const wall_loads *loads, int hopper, int tangential,
                        double span) {
  double sum = 0.0; /* N s */
  int first = hopper ? loads->side_count : 0;
  int last = hopper ? loads->wall_count : loads->side_count;
  for (int k = first; k < last; k++)
    sum += tangential ? loads->tangential[k] : loads->normal[k];
  return sum / span;
}

/* x of the silo's wall at height y (m): the hopper wall, then the side. */
static double wall_x(const silo *s, double y) {
  if (s->hopper_angle <= 0.0)
    return s->half_width;
  return fmin(s->half_width, 0.5 * s->orifice + y * tan(s->hopper_angle));
}

/* Volume of a point of edge `spacing` at radius r (see gm_points_def). */
static double point_volume(const silo *s, double r, double spacing) {
  double area = spacing * spacing; /* m^2 */
  if (s->dim == 3)
    return area * spacing; /* m^3 */
  return s->geometry == GM_GEOMETRY_AXISYMMETRIC ? 2.0 * PI * r * area : area;
}

/* Where the floor layer begins (m): the orifice's edge D/2, or a cell
 * beyond it with --edge-node open. */
static double floor_edge(const silo *s) {
  return 0.5 * s->orifice + s->edge_cells * s->options.cell;
}

/* The floor's hole in whole cells from the axis (silo_discharge_3d.h's
 * `holes`): D/2h, one more with --edge-node open. */
static long floor_holes(const silo *s) {
  return lround(0.5 * s->orifice / s->options.cell) + s->edge_cells;
}

static gm_status create_domain(const silo *s, double damping,
                               gm_domain **domain) {
  double cell = s->options.cell; /* m */
  gm_domain_def def = gm_domain_def_default();
  def.geometry = s->geometry;
  def.shape = s->options.shape;
  def.family = s->options.family;
  def.scheme = GM_SCHEME_MUSL; /* 001 sec 3: the smoothed velocity */
  if (strcmp(s->scheme, "usl") == 0)
    def.scheme = GM_SCHEME_USL;
  else if (strcmp(s->scheme, "usf") == 0)
    def.scheme = GM_SCHEME_USF;
  def.pic_fraction = s->pic;
  if (strcmp(s->transfer, "apic") == 0)
    def.transfer = GM_TRANSFER_APIC; /* Jiang et al. 2015 */
  def.cell_size = cell;
  /* the floor layer, the free fall of --drop and the sink below 0 */
  def.origin[1] = -3.0 * cell - s->drop;
  def.extent[0] = s->half_width + 2.0 * cell;
  def.extent[1] = s->fill_height + 5.0 * cell + s->drop;
  def.gravity[1] = -GRAVITY;
  def.walls[GM_FACE_XMIN] = GM_WALL_SLIP; /* the symmetry axis */
  def.walls[GM_FACE_XMAX] = GM_WALL_SLIP;
  if (s->dim == 3) { /* the quarter: z = 0 is the second symmetry plane */
    def.extent[2] = s->half_width + 2.0 * cell;
    /* Symmetry planes that hold their nodes whatever the gap, as the
     * axisymmetric run's axis does (released as slip faces, the 3D rate
     * of tests/scripts/silo_3d_axisym.sh rose from 56.27 to 60.07 kg/s,
     * +6.5 % against the axisymmetric 56.42). The 2D x = 0 face stays a
     * slip face, released by its gap since 2026-11-25 (docs/3d.md). */
    def.walls[GM_FACE_XMIN] = GM_WALL_SYMMETRY;
    def.walls[GM_FACE_ZMIN] = GM_WALL_SYMMETRY;
    def.walls[GM_FACE_ZMAX] = GM_WALL_SLIP;
  }
  def.damping = damping;
  def.cfl = s->cfl;
  def.worker_count = s->options.workers;
  gm_status status = gm_domain_create(&def, domain);
  if (status == GM_OK && strcmp(s->volumetric, "cell") == 0)
    status = gm_domain_set_volumetric(*domain, GM_VOLUMETRIC_CELL_MEAN);
  return status;
}

/* The granular material and, for the granular family, its critical density
 * (the poured density: denser points are quasi-static). With --fluidity the
 * same cone with the Perzyna rate term of docs/convergence.md sec. 20
 * (sigma_n = max(m p, --reference-stress), N = 1, psi = 0): the
 * rate-independent Drucker-Prager is its limit gamma -> infinity. */
static gm_status add_material(gm_domain *domain, const silo *s, int *material) {
  gm_drucker_prager_def dp = gm_drucker_prager_def_default();
  dp.density = DENSITY;
  dp.poisson_ratio = POISSON_RATIO;
  dp.friction_angle = s->friction;
  if (s->youngs > 0.0)
    dp.youngs_modulus = s->youngs; /* --youngs (docs/convergence.md sec. 27) */
  gm_status status;
  if (s->grain > 0.0) {
    /* mu(I) (Jop et al. 2006) on the same cone: mu_s = sin(phi), the
     * plane-strain match of tau = sqrt(s:s/2) = mu p to Coulomb with no
     * plastic volume change (as examples/column_collapse.c), mu_2 - mu_s
     * and I_0 of Jop's glass beads. Its grain diameter is the length scale
     * Drucker-Prager lacks (docs/convergence.md sec. 14). */
    gm_mu_i_def def = gm_mu_i_def_default();
    def.youngs_modulus = dp.youngs_modulus;
    def.poisson_ratio = dp.poisson_ratio;
    def.density = dp.density;
    def.grain_density = 2650.0; /* kg/m^3, quartz */
    def.grain_diameter = s->grain;
    def.static_friction = sin(dp.friction_angle);
    def.limit_friction = def.static_friction + (0.6435 - 0.3819);
    status = gm_domain_add_mu_i(domain, &def, material);
  } else if (s->fluid > 0.0) {
    /* A nearly inviscid fluid (docs/convergence.md sec. 30): von Mises
     * with a yield stress far below rho g D, the fill's E and nu. */
    gm_von_mises_def vm = gm_von_mises_def_default();
    vm.youngs_modulus = dp.youngs_modulus;
    vm.poisson_ratio = dp.poisson_ratio;
    vm.density = dp.density;
    vm.yield_stress = s->fluid;
    status = gm_domain_add_von_mises(domain, &vm, material);
  } else if (s->dilation >= 0.0) {
    /* Mohr-Coulomb on the same phi with dilation psi (docs/convergence.md
     * sec. 29: does the rate converge with associated flow, psi = phi,
     * which does not localise on the grid, sec. 19?). */
    gm_mohr_coulomb_def mc = gm_mohr_coulomb_def_default();
    mc.youngs_modulus = dp.youngs_modulus;
    mc.poisson_ratio = dp.poisson_ratio;
    mc.density = dp.density;
    mc.friction_angle = dp.friction_angle;
    mc.dilation_angle = s->dilation;
    status = gm_domain_add_mohr_coulomb(domain, &mc, material);
  } else if (s->fluidity > 0.0) {
    gm_perzyna_def viscoplastic = gm_perzyna_def_default();
    viscoplastic.youngs_modulus = dp.youngs_modulus;
    viscoplastic.poisson_ratio = dp.poisson_ratio;
    viscoplastic.density = dp.density;
    viscoplastic.friction_angle = dp.friction_angle;
    viscoplastic.fluidity = s->fluidity;
    viscoplastic.reference_stress = s->reference;
    status = gm_domain_add_perzyna(domain, &viscoplastic, material);
  } else
    status = gm_domain_add_drucker_prager(domain, &dp, material);
  if (status != GM_OK)
    return status;
  gm_granular_def granular = gm_granular_def_default();
  granular.critical_density = DENSITY;
  return gm_domain_set_granular(domain, *material, &granular);
}

static gm_status add_wall(gm_domain *domain, const silo *s,
                          const double point[3], const double normal[3],
                          int *id) {
  double friction = s->wall_friction; /* mu_w = tan(phi_w) */
  gm_wall_def wall = gm_wall_def_default();
  for (int k = 0; k < 3; k++) {
    wall.point[k] = point[k];
    wall.normal[k] = normal[k];
  }
  wall.friction_static = wall.friction_kinetic = friction;
  return gm_domain_add_wall(domain, &wall, id);
}

/* The vertical silo wall and, for a hopper, the inclined wall through the
 * orifice edge (normal pointing up and towards the axis); in 3D the second
 * side wall z = B and, for a hopper, the second inclined wall through the
 * square outlet's edge z = D/2 (a pyramidal hopper). */
static gm_status add_walls(gm_domain *domain, const silo *s,
                           wall_loads *loads) {
  /* The wall is meant to lie on the node line x = B. The library decides
   * contact by the exact sign of a node's distance to the plane, and its
   * node coordinates (origin + i h) can differ from B = n h by one unit in
   * the last place: the node line then counts as in front of the wall and
   * the material runs one cell into it (seen with D = 0.5, cell 0.05). A
   * shift of 1e-9 cells towards the material keeps the node line behind. */
  const double inset = s->half_width - 1e-9 * s->options.cell; /* m */
  const double side_point[3] = {inset, 0.0, 0.0};
  const double side_normal[3] = {-1, 0, 0};
  loads->wall_count = loads->side_count = 1;
  gm_status status =
      add_wall(domain, s, side_point, side_normal, &loads->walls[0]);
  if (status == GM_OK && s->dim == 3) {
    const double back_point[3] = {0.0, 0.0, inset};
    const double back_normal[3] = {0, 0, -1};
    loads->wall_count = loads->side_count = 2;
    status = add_wall(domain, s, back_point, back_normal, &loads->walls[1]);
  }
  if (status != GM_OK || s->hopper_angle <= 0.0)
    return status;
  double c = cos(s->hopper_angle), t = sin(s->hopper_angle);
  const double edge[3] = {0.5 * s->orifice, 0.0, 0.0};
  const double normal[3] = {-c, t, 0};
  status =
      add_wall(domain, s, edge, normal, &loads->walls[loads->wall_count++]);
  if (status != GM_OK || s->dim != 3)
    return status;
  const double back_edge[3] = {0.0, 0.0, 0.5 * s->orifice};
  const double back_normal[3] = {0, t, -c};
  return add_wall(domain, s, back_edge, back_normal,
                  &loads->walls[loads->wall_count++]);
}

/* The 3D floor layer, on the lattice of fill_box, out to x, z < `edge`
 * (m): the points of every rigid cell (silo3d_rigid_cell) about the
 * orifice of radius `radius` (m, a whole number of cells; 0: the gate).
 * The open nodes are then those within D/2 - h/2 of the corner axis, the
 * planar and axisymmetric floors' rule (silo_discharge_3d.c). */
static gm_status add_floor_3d(gm_domain *domain, const silo *s, int material,
                              double radius, double edge) {
  int n = s->options.ppc;
  double spacing = s->options.cell / n;          /* m */
  long holes = lround(radius / s->options.cell); /* cells */
  size_t side = (size_t)llround(edge / spacing), count = 0;
  double *position = malloc(3 * side * side * n * sizeof *position);
  double *volume = malloc(side * side * n * sizeof *volume);
  for (size_t i = 0; position && volume && i < side; i++)
    for (size_t k = 0; k < side; k++)
      for (int j = 0; j < n; j++) {
        double x = (i + 0.5) * spacing, z = (k + 0.5) * spacing; /* m */
        if (holes > 0 &&
            !silo3d_rigid_cell((long)(i / n), (long)(k / n), holes))
          continue; /* the orifice */
        position[3 * count] = x;
        position[3 * count + 1] = -s->options.cell + (j + 0.5) * spacing;
        position[3 * count + 2] = z;
        volume[count++] = spacing * spacing * spacing;
      }
  gm_status status = GM_ERR_NO_MEMORY;
  if (position && volume) {
    gm_points_def points = gm_points_def_default();
    points.count = count;
    points.material = material;
    points.position = position;
    points.volume = volume;
    status = gm_domain_add_points(domain, &points, NULL);
  }
  free(position);
  free(volume);
  return status;
}

/* A rigid layer one cell thick under the floor, from x0 to the grid edge:
 * the flat bottom (x0 = D/2) or the gate closing the orifice (x0 = 0); in
 * 3D x0 is the radius of the quarter-circle hole. */
static gm_status add_floor(gm_domain *domain, const silo *s, double x0,
                           double x1) {
  gm_rigid_def rigid = gm_rigid_def_default();
  rigid.name = "floor";
  rigid.density = DENSITY;
  int material = -1;
  gm_status status = gm_domain_add_rigid(domain, &rigid, &material);
  if (status != GM_OK)
    return status;
  if (s->dim == 3)
    return add_floor_3d(domain, s, material, x0, x1);
  gm_fill_def fill = gm_fill_def_default();
  fill.material = material;
  fill.lower[0] = x0;
  fill.upper[0] = x1;
  fill.lower[1] = -s->options.cell;
  fill.upper[1] = 0.0;
  return gm_domain_fill_box(domain, &fill, NULL, NULL);
}

/* Fills the silo on a lattice of n x n points per cell, each with the
 * geostatic stress sigma_v = -rho g (H - y), sigma_h = K0 sigma_v,
 * K0 = nu / (1 - nu) (confined elastic column): a start near equilibrium
 * so that settling needs little time. */
static gm_status fill_silo(gm_domain *domain, silo *s, int material) {
  int n = s->options.ppc;
  double spacing = s->options.cell / n; /* m */
  size_t columns = (size_t)ceil(s->half_width / spacing);
  size_t rows = (size_t)llround(s->fill_height / spacing);
  size_t layers = s->dim == 3 ? columns : 1; /* along z */
  size_t capacity = columns * rows * layers, dim = (size_t)s->dim;
  double *position = malloc(dim * capacity * sizeof *position);
  double *volume = malloc(capacity * sizeof *volume);
  double *stress = calloc(6 * capacity, sizeof *stress);
  double k0 = POISSON_RATIO / (1.0 - POISSON_RATIO);
  size_t count = 0;
  s->mass = 0.0;
  for (size_t cell = 0; position && volume && stress && cell < capacity;
       cell++) {
    size_t column = cell % columns, row = cell / columns % rows;
    double x = (column + 0.5) * spacing, y = (row + 0.5) * spacing; /* m */
    double z = (cell / columns / rows + 0.5) * spacing; /* m, 3D only */
    if (x >= wall_x(s, y) || (dim == 3 && z >= wall_x(s, y)))
      continue;
    double vertical = -DENSITY * GRAVITY * (s->fill_height - y); /* Pa */
    position[dim * count] = x;
    position[dim * count + 1] = y;
    if (dim == 3)
      position[dim * count + 2] = z;
    volume[count] = point_volume(s, x, spacing);
    stress[6 * count + GM_XX] = stress[6 * count + GM_ZZ] = k0 * vertical;
    stress[6 * count + GM_YY] = vertical;
    s->mass += DENSITY * volume[count];
    count++;
  }
  gm_status status = GM_ERR_NO_MEMORY;
  if (position && volume && stress) {
    gm_points_def points = gm_points_def_default();
    points.count = count;
    points.material = material;
    points.position = position;
    points.volume = volume;
    points.stress = stress;
    status = gm_domain_add_points(domain, &points, NULL);
  }
  free(position);
  free(volume);
  free(stress);
  return status;
}

/* Step hook: sums the walls' impulses (the call's time integral of the
 * force, exact however short the call). */
static int integrate_wall_loads(gm_domain *domain, gm_hook_stage stage,
                                void *user) {
  wall_loads *loads = user;
  double time = 0.0; /* s */
  if (stage != GM_HOOK_AFTER_STEP ||
      gm_domain_get_time(domain, &time, NULL) != GM_OK)
    return 0;
  double dt = time - loads->last_time; /* s */
  loads->last_time = time;
  loads->span += dt;
  for (int k = 0; k < loads->wall_count; k++) {
    gm_wall_force force = gm_wall_force_default();
    if (gm_domain_get_wall_force(domain, loads->walls[k], &force) != GM_OK)
      continue;
    loads->normal[k] += force.normal_impulse;
    loads->tangential[k] += force.tangential_impulse;
  }
  return 0;
}

static void reset_loads(wall_loads *loads) {
  loads->span = 0.0;
  memset(loads->normal, 0, sizeof loads->normal);
  memset(loads->tangential, 0, sizeof loads->tangential);
}

/* Janssen's wall pressure (Pa) at depth z (m) below the free surface:
 * sigma_h = K sigma_v, A/U = B for a planar silo (full width 2B between two
 * walls), B/2 for a cylinder of radius B (docs/references.md). */
static double janssen_pressure(const silo *s, double k, double z) {
  double ratio = s->geometry == GM_GEOMETRY_AXISYMMETRIC ? 0.5 * s->half_width
                                                         : s->half_width;
  double decay = s->wall_friction * k / ratio; /* 1/m */
  return k * DENSITY * GRAVITY / decay * (1.0 - exp(-decay * z));
}

/* Adds dt times each wall node's normal traction (Pa) by node row. The
 * side wall's normal is (-1, 0), so positions along it, in the direction
 * (normal_y, -normal_x) = (0, 1), are heights above the floor. */
static void record_tractions(const gm_domain *domain, int wall, double cell,
                             double dt, double *pressure, size_t rows) {
  static gm_wall_traction profile[MAX_TRACTIONS];
  size_t count = 0;
  if (gm_domain_get_wall_tractions(domain, wall, profile, MAX_TRACTIONS,
                                   &count) != GM_OK)
    return;
  for (size_t i = 0; i < count; i++) {
    long row = lround(profile[i].position / cell); /* node row */
    if (row >= 0 && (size_t)row < rows)
      pressure[row] += dt * profile[i].normal;
  }
}

/* The side wall's tractions at rest, summed over the last AVERAGING_TIME
 * of the settling. */
typedef struct rest_record {
  int wall;
  double cell;      /* m */
  double *pressure; /* Pa s, by node row */
  size_t rows;
  double averaged; /* s */
} rest_record;

/* example_step_fn of the settling. */
static void record_rest_step(const gm_domain *domain,
                             const example_run_state *state, void *user) {
  rest_record *rest = user;
  if (state->time > SETTLE_TIME - AVERAGING_TIME) {
    record_tractions(domain, rest->wall, rest->cell, state->dt, rest->pressure,
                     rest->rows);
    rest->averaged += state->dt;
  }
}

/* Phase 1: settles the closed silo (stable steps up to SETTLE_TIME, the
 * last one may pass it); returns the mid-depth wall pressure (Pa,
 * time-averaged) or a negative status. Writes rest_wall.csv. */
static gm_status settle(gm_domain *domain, silo *s, const wall_loads *loads,
                        double *mid_pressure) {
  double cell = s->options.cell, time = 0.0; /* m, s */
  size_t rows = (size_t)(s->fill_height / cell) + 4;
  double *pressure = calloc(rows, sizeof *pressure); /* Pa s */
  if (!pressure)
    return GM_ERR_NO_MEMORY;
  rest_record rest = {loads->walls[0], cell, pressure, rows, 0.0};
  const example_run_schedule schedule = {.stepping = EXAMPLE_STEPS,
                                         .t_end = SETTLE_TIME,
                                         .on_failure = EXAMPLE_FAILURE_STOP,
                                         .step = record_rest_step,
                                         .user = &rest};
  gm_status status = example_run_loop(domain, &schedule, &time);
  double averaged = rest.averaged; /* s */
  gm_summary summary = gm_summary_default();
  if (status == GM_OK)
    status = gm_domain_get_summary(domain, &summary);
  printf("at rest after %g s: kinetic energy %g J (per m or ring)\n", time,
         summary.kinetic_energy);
  FILE *csv = example_open_csv(&s->options, "rest_wall.csv",
                               "depth_m,wall_pressure_Pa,janssen_Pa");
  double k = 1.0 - sin(s->friction); /* Jaky */
  long mid_row = lround(0.5 * s->fill_height / cell);
  /* Axisymmetric wall loads are for the whole ring: per wall area, / 2 pi B */
  double ring =
      s->geometry == GM_GEOMETRY_AXISYMMETRIC ? 2.0 * PI * s->half_width : 1.0;
  *mid_pressure = 0.0;
  for (size_t row = 0; averaged > 0.0 && row < rows; row++) {
    double depth = s->fill_height - row * cell;    /* m */
    double mean = pressure[row] / averaged / ring; /* Pa */
    if (csv && depth >= 0.0)
      fprintf(csv, "%g,%g,%g\n", depth, mean, janssen_pressure(s, k, depth));
    if ((long)row == mid_row)
      *mid_pressure = mean;
  }
  if (csv)
    fclose(csv);
  free(pressure);
  return status;
}

/* Copies the settled granular points (not the rigid ones) into a new
 * domain, at rest, with their stress and current volume. */
static gm_status copy_points(const gm_domain *from, int material, gm_domain *to,
                             int to_material, size_t dim) {
  size_t count = gm_domain_point_count(from);
  double *fields = malloc(count * 12 * sizeof *fields);
  if (!fields)
    return GM_ERR_NO_MEMORY;
  double *position = fields, *volume = fields + 3 * count;
  double *mass = fields + 4 * count, *id = fields + 5 * count;
  double *stress = fields + 6 * count;
  gm_status status =
      gm_domain_get_field(from, GM_FIELD_POSITION, position, dim * count);
  if (status == GM_OK)
    status = gm_domain_get_field(from, GM_FIELD_VOLUME, volume, count);
  if (status == GM_OK)
    status = gm_domain_get_field(from, GM_FIELD_MASS, mass, count);
  if (status == GM_OK)
    status = gm_domain_get_field(from, GM_FIELD_MATERIAL, id, count);
  if (status == GM_OK)
    status = gm_domain_get_field(from, GM_FIELD_STRESS, stress, 6 * count);
  size_t kept = 0; /* compact the granular points to the front */
  for (size_t i = 0; status == GM_OK && i < count; i++) {
    if ((int)id[i] != material)
      continue;
    memmove(position + dim * kept, position + dim * i, dim * sizeof *position);
    volume[kept] = volume[i];
    mass[kept] = mass[i];
    memmove(stress + 6 * kept, stress + 6 * i, 6 * sizeof *stress);
    kept++;
  }
  if (status == GM_OK) {
    gm_points_def points = gm_points_def_default();
    points.count = kept;
    points.material = to_material;
    points.position = position;
    points.volume = volume;
    points.mass = mass;
    points.stress = stress;
    status = gm_domain_add_points(to, &points, NULL);
  }
  free(fields);
  return status;
}

/* Sinks just below the orifice, in the floor layer's hole (y in [-3h, 0)),
 * and a catch-all under the floor layer: a point is counted once its
 * centre passes the floor's top y = 0 inside the orifice. Both are lowered
 * by --drop (2D only: the points then fall freely through the opening for
 * that height before they are counted, so the stress of the flow above
 * the orifice is not cut off at its plane; docs/convergence.md sec. 25). A sink
 * removes rigid points too, so in 3D the hole is a strip per column of open
 * cells, x in [i h, (i + 1) h), z from 0 to the column's first rigid cell:
 * their union is the hole, as the planar and axisymmetric box is. Returns the
 * number of sinks in *count. */
static gm_status add_sinks(gm_domain *domain, const silo *s,
                           int sinks[MAX_SINKS], int *count) {
  double cell = s->options.cell; /* m */
  long holes = floor_holes(s);
  gm_status status = GM_OK;
  *count = 0;
  int square = s->dim == 3 && s->hopper_angle > 0.0; /* pyramidal hopper */
  long strips = s->dim == 3 && !square ? holes : 1;
  for (long i = 0; status == GM_OK && i < strips; i++) {
    gm_sink_def orifice = gm_sink_def_default();
    orifice.lower[0] = s->dim == 3 && !square ? i * cell : 0.0;
    orifice.upper[0] = s->dim == 3 && !square ? (i + 1) * cell : floor_edge(s);
    orifice.lower[1] = -3.0 * cell - s->drop;
    orifice.upper[1] = -s->drop;
    long k = 0;
    while (s->dim == 3 && !square && !silo3d_rigid_cell(i, k, holes))
      k++;
    orifice.upper[2] = k * cell; /* m, 0 in 2D (z is not read) */
    if (square) /* the hopper's square outlet, its quarter D/2 x D/2 */
      orifice.upper[2] = 0.5 * s->orifice;
    else if (s->dim == 3 && k == 0)
      continue;
    status = gm_domain_add_sink(domain, &orifice, &sinks[(*count)++]);
  }
  gm_sink_def below = gm_sink_def_default();
  below.upper[0] = below.upper[2] = s->half_width + 2.0 * cell;
  below.lower[1] = -3.0 * cell - s->drop;
  below.upper[1] = -1.5 * cell - s->drop;
  if (status == GM_OK)
    status = gm_domain_add_sink(domain, &below, &sinks[(*count)++]);
  return status;
}

/* Discharged mass (kg, per m or full ring) of all the sinks. */
static double discharged_mass(const gm_domain *domain, const int *sinks,
                              int count) {
  double total = 0.0;
  for (int k = 0; k < count; k++) {
    gm_flow_totals totals = gm_flow_totals_default();
    if (gm_domain_get_sink_totals(domain, sinks[k], &totals) == GM_OK)
      total += totals.mass;
  }
  return total;
}

/* Least-squares slope of mass against time over samples [first, last). */
static double fitted_rate(const double *time, const double *mass, size_t first,
                          size_t last) {
  double n = (double)(last - first), st = 0, sm = 0, stt = 0, stm = 0;
  for (size_t i = first; i < last; i++) {
    st += time[i];
    sm += mass[i];
    stt += time[i] * time[i];
    stm += time[i] * mass[i];
  }
  double denominator = n * stt - st * st;
  return denominator > 0.0 ? (n * stm - st * sm) / denominator : 0.0;
}

/* The fitted rate over the samples between the fractions `from` and `to`
 * of the full fill `total` (kg) discharged; 0 when fewer than 3 samples. */
static double window_rate(const double *time, const double *mass, size_t taken,
                          double total, double from, double to) {
  size_t first = 0, last = 0;
  while (first < taken && mass[first] < from * total)
    first++;
  while (last < taken && mass[last] < to * total)
    last++;
  return last > first + 2 ? fitted_rate(time, mass, first, last) : 0.0;
}

/* Whether sampling can stop: the steady window is over (a little more
 * than --window-end of the fill has left), or the flow has jammed (nothing
 * left in the last 0.5 s). */
static int past_window(const silo *s, const double *time, const double *mass,
                       size_t last) {
  double symmetry = symmetry_factor(s);
  if (mass[last] > (s->window_end + 0.05) * symmetry * s->mass)
    return 1;
  size_t back = (size_t)ceil(0.5 / s->sample);
  return last >= back && time[last] > 1.0 && mass[last] == mass[last - back];
}

/* Beverloo's rate (kg/(m s) for a slot, kg/s for an orifice) with the
 * orifice shortened by `offset` = k d (m). The 3D hopper's square outlet
 * of side D: eq 19 with A' = (D - k d)^2 and D'_h = D - k d, so C = 0.75
 * against the circle's 0.75 pi / 4. */
static double beverloo(const silo *s, double offset) {
  double width = s->orifice - offset; /* m */
  if (s->dim == 3 && s->hopper_angle > 0.0)
    return BEVERLOO_SI * DENSITY * sqrt(GRAVITY) * pow(width, 2.5);
  if (s->geometry == GM_GEOMETRY_AXISYMMETRIC || s->dim == 3)
    return BEVERLOO_SI * PI / 4.0 * DENSITY * sqrt(GRAVITY) * pow(width, 2.5);
  return BEVERLOO_SI * sqrt(2.0) * DENSITY * sqrt(GRAVITY) * pow(width, 1.5);
}

/* Steady profiles (--profile): the points in horizontal bands
 * [y0, y0 + PROFILE_BAND) at y0 = 0 (the orifice), D/2, D and 2D, binned in
 * x, summed over every sample of the steady window (docs/convergence.md
 * sec. 14, the rate's non-convergence). Per bin: mass, vertical momentum,
 * current and initial volume; the mass flux density through the band is
 * sum(m v_y) / (band area), the same on every grid where the flow is. */
enum { PROFILE_HEIGHTS = 4, PROFILE_BINS = 256, AXIS_BINS = 96 };
static const double PROFILE_BAND = 0.025; /* m, band height */
static const double AXIS_BIN = 0.0125;    /* m, height of an axis bin */

typedef struct profile_sums {
  double bin;     /* m, bin width: max(D/24, point spacing) */
  double samples; /* samples summed */
  double mass[PROFILE_HEIGHTS][PROFILE_BINS];     /* kg (per m) */
  double momentum[PROFILE_HEIGHTS][PROFILE_BINS]; /* kg m/s, m v_y */
  double volume[PROFILE_HEIGHTS][PROFILE_BINS];   /* m^2, current */
  double initial[PROFILE_HEIGHTS][PROFILE_BINS];  /* m^2, at creation */
  /* Mass times stress (tension positive) and mobilised friction: the
   * stresses that hold the flowing core back (docs/convergence.md
   * sec. 27). */
  double syy[PROFILE_HEIGHTS][PROFILE_BINS];       /* kg Pa, m sigma_yy */
  double sxy[PROFILE_HEIGHTS][PROFILE_BINS];       /* kg Pa, m sigma_xy */
  double pressure[PROFILE_HEIGHTS][PROFILE_BINS];  /* kg Pa, m p */
  double mobilised[PROFILE_HEIGHTS][PROFILE_BINS]; /* kg, m q / (m_DP p) */
  double loose[PROFILE_HEIGHTS][PROFILE_BINS];     /* kg, points at p <= 0 */
  /* The column x < D/12 above the orifice, by height (the free-fall arch):
   * mass, vertical momentum and mass times pressure. */
  double axis_mass[AXIS_BINS];     /* kg */
  double axis_momentum[AXIS_BINS]; /* kg m/s */
  double axis_pressure[AXIS_BINS]; /* kg Pa, m p, p = -tr(sigma)/3 */
  double axis_syy[AXIS_BINS];      /* kg Pa, m sigma_yy */
  double axis_sxy[AXIS_BINS];      /* kg Pa, m sigma_xy */
  double axis_loose[AXIS_BINS];    /* kg, points at p <= 0 (stress-free) */
  /* The next column, D/12 <= x < D/6: its shear stress over the distance
   * between the columns' centres is d sigma_xy / dx on the axis. */
  double next_mass[AXIS_BINS];     /* kg */
  double next_momentum[AXIS_BINS]; /* kg m/s */
  double next_sxy[AXIS_BINS];      /* kg Pa, m sigma_xy */
} profile_sums;

static double profile_height(const silo *s, int k) {
  static const double share[PROFILE_HEIGHTS] = {0.0, 0.5, 1.0, 2.0};
  return share[k] * s->orifice; /* m */
}

/* q / (m p) of a stress (Pa, tension positive): 1 on the Drucker-Prager
 * cone q = m p of --friction 25 deg (002 sec 2.2, drucker_prager.c), 0
 * where p <= 0. With --grain or --fluidity the same cone's slope. */
static double mobilised_share(const silo *s, const double sigma[6]) {
  double sin_phi = sin(s->friction);
  double slope = 18.0 * sin_phi / (9.0 - sin_phi * sin_phi);      /* - */
  double p = -(sigma[GM_XX] + sigma[GM_YY] + sigma[GM_ZZ]) / 3.0; /* Pa */
  if (!(p > 0.0))
    return 0.0;
  double sxx = sigma[GM_XX] + p, syy = sigma[GM_YY] + p; /* Pa */
  double szz = sigma[GM_ZZ] + p;                         /* Pa */
  double j2 = 0.5 * (sxx * sxx + syy * syy + szz * szz) +
              sigma[GM_XY] * sigma[GM_XY]; /* Pa^2, 2D: yz = zx = 0 */
  return sqrt(3.0 * j2) / (slope * p);
}

/* Adds the granular points of one sample to the bins. */
static gm_status add_profile(const gm_domain *domain, const silo *s,
                             profile_sums *sums) {
  size_t count = gm_domain_point_count(domain);
  double *fields = malloc(14 * (count + 1) * sizeof *fields);
  if (!fields)
    return GM_ERR_NO_MEMORY;
  double *position = fields, *velocity = fields + 2 * count;
  double *mass = fields + 4 * count, *volume = fields + 5 * count;
  double *initial = fields + 6 * count, *material = fields + 7 * count;
  double *stress = fields + 8 * count;
  gm_status status =
      gm_domain_get_field(domain, GM_FIELD_POSITION, position, 2 * count);
  if (status == GM_OK)
    status =
        gm_domain_get_field(domain, GM_FIELD_VELOCITY, velocity, 2 * count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_MASS, mass, count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_VOLUME, volume, count);
  if (status == GM_OK)
    status =
        gm_domain_get_field(domain, GM_FIELD_INITIAL_VOLUME, initial, count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_MATERIAL, material, count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_STRESS, stress, 6 * count);
  for (size_t i = 0; status == GM_OK && i < count; i++) {
    long bin = (long)floor(position[2 * i] / sums->bin);
    if (material[i] != 0.0 || bin < 0 || bin >= PROFILE_BINS)
      continue; /* material 0 is the fill (added first) */
    long row = (long)floor(position[2 * i + 1] / AXIS_BIN);
    const double *sigma = stress + 6 * i; /* Pa */
    double pressure = -(sigma[GM_XX] + sigma[GM_YY] + sigma[GM_ZZ]) / 3.0;
    if (position[2 * i] < s->orifice / 12.0 && row >= 0 && row < AXIS_BINS) {
      sums->axis_mass[row] += mass[i];
      sums->axis_momentum[row] += mass[i] * velocity[2 * i + 1];
      sums->axis_pressure[row] += mass[i] * pressure;
      sums->axis_syy[row] += mass[i] * sigma[GM_YY];
      sums->axis_sxy[row] += mass[i] * sigma[GM_XY];
      sums->axis_loose[row] += pressure > 0.0 ? 0.0 : mass[i];
    } else if (position[2 * i] < s->orifice / 6.0 && row >= 0 &&
               row < AXIS_BINS) {
      sums->next_mass[row] += mass[i];
      sums->next_momentum[row] += mass[i] * velocity[2 * i + 1];
      sums->next_sxy[row] += mass[i] * sigma[GM_XY];
    }
    for (int k = 0; k < PROFILE_HEIGHTS; k++) {
      double above = position[2 * i + 1] - profile_height(s, k); /* m */
      if (above < 0.0 || above >= PROFILE_BAND)
        continue;
      sums->mass[k][bin] += mass[i];
      sums->momentum[k][bin] += mass[i] * velocity[2 * i + 1];
      sums->volume[k][bin] += volume[i];
      sums->initial[k][bin] += initial[i];
      sums->syy[k][bin] += mass[i] * sigma[GM_YY];
      sums->sxy[k][bin] += mass[i] * sigma[GM_XY];
      sums->pressure[k][bin] += mass[i] * pressure;
      sums->mobilised[k][bin] += mass[i] * mobilised_share(s, sigma);
      sums->loose[k][bin] += pressure > 0.0 ? 0.0 : mass[i];
    }
  }
  sums->samples += 1.0;
  free(fields);
  return status;
}

/* Writes the profiles: per height and bin, the mean areal density
 * (kg/m^3, mass over the bin's area), the mean v_y (m/s, mass-weighted),
 * the flux density (kg/(m^2 s)), the points' volume over the bin's area
 * and their mean volume ratio J = V / V0. */
static void write_profile(const silo *s, const profile_sums *sums) {
  FILE *csv = fopen(s->profile, "w");
  if (!csv) {
    fprintf(stderr, "--profile: cannot write %s\n", s->profile);
    return;
  }
  fprintf(csv, "# cell %g m, ppc %d, D %g m, %g samples, band %g m\n",
          s->options.cell, s->options.ppc, s->orifice, sums->samples,
          PROFILE_BAND);
  fprintf(csv, "height_m,x_m,x_over_D,areal_density_kg_m3,vy_m_s,flux_kg_m2_"
               "s,filled,volume_ratio,sigma_yy_Pa,sigma_xy_Pa,pressure_Pa,"
               "mobilised,loose\n");
  double area = sums->bin * PROFILE_BAND * fmax(sums->samples, 1.0); /* m^2 */
  for (int k = 0; k < PROFILE_HEIGHTS; k++)
    for (int b = 0; b < PROFILE_BINS && (b + 0.5) * sums->bin < s->half_width;
         b++) {
      double m = sums->mass[k][b], x = (b + 0.5) * sums->bin; /* kg, m */
      double w = m > 0 ? 1.0 / m : 0.0; /* 1/kg: mass-weighted means */
      fprintf(
          csv, "%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g\n", profile_height(s, k),
          x, x / s->orifice, m / area, sums->momentum[k][b] * w,
          sums->momentum[k][b] / area, sums->volume[k][b] / area,
          sums->initial[k][b] > 0 ? sums->volume[k][b] / sums->initial[k][b]
                                  : 0.0,
          sums->syy[k][b] * w, sums->sxy[k][b] * w, sums->pressure[k][b] * w,
          sums->mobilised[k][b] * w, sums->loose[k][b] * w);
    }
  fclose(csv);
  /* The axis column, in PROFILE_axis.csv: by height, the areal density,
   * v_y (mass-weighted), the flux density and the mean pressure. */
  char path[1200];
  snprintf(path, sizeof path, "%s_axis.csv", s->profile);
  csv = fopen(path, "w");
  if (!csv)
    return;
  fprintf(csv, "y_m,y_over_D,areal_density_kg_m3,vy_m_s,flux_kg_m2_s,"
               "pressure_Pa,sigma_yy_Pa,sigma_xy_Pa,next_vy_m_s,next_sigma_"
               "xy_Pa,loose\n");
  double column = s->orifice / 12.0 * AXIS_BIN * fmax(sums->samples, 1.0);
  for (int b = 0; b < AXIS_BINS; b++) {
    double m = sums->axis_mass[b], y = (b + 0.5) * AXIS_BIN; /* kg, m */
    double w = m > 0 ? 1.0 / m : 0.0;                        /* 1/kg */
    double n = sums->next_mass[b] > 0 ? 1.0 / sums->next_mass[b] : 0.0;
    fprintf(csv, "%g,%g,%g,%g,%g,%g,%g,%g,%g,%g,%g\n", y, y / s->orifice,
            m / column, sums->axis_momentum[b] * w,
            sums->axis_momentum[b] / column, sums->axis_pressure[b] * w,
            sums->axis_syy[b] * w, sums->axis_sxy[b] * w,
            sums->next_momentum[b] * n, sums->next_sxy[b] * n,
            sums->axis_loose[b] * w);
  }
  fclose(csv);
}

/* The discharge's samples, filled by sample_discharge. */
typedef struct discharge_record {
  const silo *s;
  wall_loads *loads;
  int sinks[MAX_SINKS];
  int sink_count;
  double centre_sum; /* m/s, v_y of the orifice centre, summed by sample */
  long centre_samples;
  double symmetry;       /* full silo over the model: 2 in plane strain */
  double *time;          /* s, of each sample */
  double *mass;          /* kg, discharged by then (full silo) */
  size_t taken;          /* samples the fit may use */
  FILE *csv;             /* NULL: none */
  profile_sums *profile; /* NULL: none */
  int sliced;            /* 3D: slice.csv and slice.png written */
} discharge_record;

/* The mean vertical velocity (m/s) of the fill's points (material 0,
 * added first) over the orifice's centre: within one cell of the axis,
 * in the cell above the floor (0 <= y < h). */
static gm_status centre_velocity(const gm_domain *domain, const silo *s,
                                 double *velocity) {
  size_t count = gm_domain_point_count(domain), dim = (size_t)s->dim;
  double *fields = malloc((2 * dim + 1) * (count + 1) * sizeof *fields);
  if (!fields)
    return GM_ERR_NO_MEMORY;
  double *x = fields, *v = fields + dim * count, *id = v + dim * count;
  gm_status status =
      gm_domain_get_field(domain, GM_FIELD_POSITION, x, dim * count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_VELOCITY, v, dim * count);
  if (status == GM_OK)
    status = gm_domain_get_field(domain, GM_FIELD_MATERIAL, id, count);
  double h = s->options.cell, sum = 0.0, n = 0.0; /* m, m/s, - */
  for (size_t i = 0; status == GM_OK && i < count; i++) {
    const double *p = x + dim * i;                            /* m */
    double r2 = p[0] * p[0] + (dim == 3 ? p[2] * p[2] : 0.0); /* m^2 */
    if (id[i] == 0.0 && r2 < h * h && p[1] >= 0.0 && p[1] < h) {
      sum += v[dim * i + 1];
      n += 1.0;
    }
  }
  free(fields);
  *velocity = n > 0.0 ? sum / n : 0.0;
  return status;
}

/* example_run_fn: the loads are averaged over each sampling interval. */
static gm_status reset_interval(gm_domain *domain,
                                const example_run_state *state, void *user) {
  (void)domain, (void)state;
  reset_loads(((discharge_record *)user)->loads);
  return GM_OK;
}

/* example_sample_fn: the discharged mass and a CSV row, at the start and
 * after every interval. */
static gm_status sample_discharge(const gm_domain *domain,
                                  const example_run_state *state, void *user) {
  discharge_record *record = user;
  const silo *s = record->s;
  const wall_loads *loads = record->loads;
  size_t taken = (size_t)state->interval;
  double target = state->target; /* s */
  gm_summary summary = gm_summary_default();
  gm_status status = gm_domain_get_summary(domain, &summary);
  if (status != GM_OK)
    return status;
  double *time = record->time, *mass = record->mass;
  time[taken] = target;
  mass[taken] = record->symmetry *
                discharged_mass(domain, record->sinks, record->sink_count);
  double flow = taken > 0 ? (mass[taken] - mass[taken - 1]) / s->sample : 0;
  double total = record->symmetry * s->mass; /* kg, the full fill */
  if (s->geometry != GM_GEOMETRY_PLANE_STRAIN &&
      mass[taken] >= WINDOW_START * total &&
      mass[taken] < s->window_end * total) {
    double velocity = 0.0; /* m/s */
    status = centre_velocity(domain, s, &velocity);
    if (status != GM_OK)
      return status;
    record->centre_sum += velocity;
    record->centre_samples++;
  }
  /* 3D with output: the slice through the axis in mid-window. */
  if (s->dim == 3 && s->options.out[0] && !record->sliced &&
      mass[taken] >= 0.5 * (WINDOW_START + s->window_end) * total) {
    record->sliced = 1;
    status = silo3d_write_slice(domain, s->options.out,
                                s->options.cell / s->options.ppc, s->orifice,
                                target);
    if (status != GM_OK)
      return status;
  }
  if (record->profile && mass[taken] >= WINDOW_START * total &&
      mass[taken] < s->window_end * total) {
    status = add_profile(domain, s, record->profile);
    if (status != GM_OK)
      return status;
  }
  double span = loads->span > 0.0 ? loads->span : 1.0; /* s */
  if (record->csv) {
    fprintf(record->csv, "%g,%g,%g,%g,%zu,%g,%g,%g,%g", target, mass[taken],
            flow, summary.kinetic_energy, gm_domain_point_count(domain),
            wall_load(loads, 0, 0, span), wall_load(loads, 0, 1, span),
            wall_load(loads, 1, 0, span), wall_load(loads, 1, 1, span));
    example_write_states(record->csv, domain);
    fputc('\n', record->csv);
  }
  record->taken = taken + 1;
  return GM_OK;
}

/* example_stop_fn: past t_end and past the steady window. The sample that
 * ends the run is left out of the fit (taken), as it always was. */
static int discharge_done(const gm_domain *domain,
                          const example_run_state *state, void *user) {
  (void)domain;
  discharge_record *record = user;
  size_t last = (size_t)state->interval;
  double t_max = record->s->t_max; /* s */
  if (!(t_max > 0.0 && state->target >= t_max) &&
      !(state->target >= record->s->options.t_end &&
        past_window(record->s, record->time, record->mass, last)))
    return 0;
  record->taken = last;
  return 1;
}

/* Phase 2: discharge; samples the sinks, writes CSV and VTU, and returns
 * the steady rate (full silo: twice the half model's in plane strain, 4
 * times the quarter's in 3D). */
static int discharge(gm_domain *domain, const silo *s, wall_loads *loads,
                     double *rate) {
  discharge_record record = {.s = s, .loads = loads};
  if (s->profile[0]) {
    record.profile = calloc(1, sizeof *record.profile);
    if (!record.profile)
      return example_fail(domain, "calloc", GM_ERR_NO_MEMORY);
    record.profile->bin =
        fmax(s->orifice / 24.0, s->options.cell / s->options.ppc);
  }
  EXAMPLE_CHECK(domain, add_sinks(domain, s, record.sinks, &record.sink_count));
  double symmetry = symmetry_factor(s);
  size_t samples = MAX_SAMPLES;
  double *time = calloc(2 * samples, sizeof *time), *mass = time + samples;
  if (!time)
    return example_fail(domain, "calloc", GM_ERR_NO_MEMORY);
  record.symmetry = symmetry;
  record.time = time;
  record.mass = mass;
  gm_series *series = NULL;
  if (s->options.out[0]) {
    char pvd[1200];
    snprintf(pvd, sizeof pvd, "%s/silo.pvd", s->options.out);
    EXAMPLE_CHECK(NULL, gm_series_create(pvd, &series));
    gm_series_set_domains(series, s->options.shape != GM_SHAPE_LINEAR);
  }
  FILE *csv = example_open_csv(
      &s->options, "discharge.csv",
      "time_s,discharged_kg,flow_rate_kg_s,kinetic_energy_J,points,"
      "wall_normal_N,wall_tangential_N,hopper_normal_N,hopper_tangential_"
      "N," EXAMPLE_STATE_HEADER);
  record.csv = csv;
  EXAMPLE_CHECK(domain,
                gm_domain_set_step_hook(domain, integrate_wall_loads, loads));
  /* Samples at k --sample from 0, a frame every 5, for at least t_end and
   * until the steady window is over (discharge_done) or the sample arrays
   * are full. */
  const example_run_schedule schedule = {.stepping = EXAMPLE_ADVANCE,
                                         .sample_times =
                                             EXAMPLE_SAMPLE_MULTIPLES,
                                         .t_end = INFINITY,
                                         .sample_period = s->sample,
                                         .interval_limit = (long)samples - 1,
                                         .sample_at_start = 1,
                                         .series = series,
                                         .frame_every = 5,
                                         .on_failure = EXAMPLE_FAILURE_STOP,
                                         .progress = &s->options,
                                         .prepare = reset_interval,
                                         .sample = sample_discharge,
                                         .stop = discharge_done,
                                         .user = &record};
  gm_status status = example_run_loop(domain, &schedule, NULL);
  if (csv)
    fclose(csv);
  gm_series_destroy(series);
  if (record.profile)
    write_profile(s, record.profile);
  free(record.profile);
  if (status != GM_OK) {
    free(time);
    return example_fail(domain, "example_run_loop", status);
  }
  size_t taken = record.taken;
  size_t first = 0, last = 0;
  double total = symmetry * s->mass; /* kg, the full silo's fill */
  while (first < taken && mass[first] < WINDOW_START * total)
    first++;
  while (last < taken && mass[last] < s->window_end * total)
    last++;
  printf("steady window: %.3f s to %.3f s (%.0f %% to %.0f %% discharged)\n",
         first < taken ? time[first] : -1.0, last < taken ? time[last] : -1.0,
         100 * WINDOW_START, 100 * s->window_end);
  if (record.centre_samples > 0)
    printf("orifice centre: mean v_y %.4g m/s over the window (%ld samples; "
           "points within one cell of the axis, 0 <= y < h)\n",
           record.centre_sum / (double)record.centre_samples,
           record.centre_samples);
  *rate = last > first + 2 ? fitted_rate(time, mass, first, last) : 0.0;
  /* The catch-all sink under the floor layer counts points that passed
   * through the rigid floor rather than the orifice (docs/3d.md, "The 3D
   * B-spline silo's rate, probed": under 0.4 % of the discharge). */
  gm_flow_totals under = gm_flow_totals_default();
  if (gm_domain_get_sink_totals(domain, record.sinks[record.sink_count - 1],
                                &under) == GM_OK)
    printf("discharged: %g kg, of which %g kg under the floor layer, not "
           "through the orifice\n",
           symmetry * discharged_mass(domain, record.sinks, record.sink_count),
           symmetry * under.mass);
  /* The same fit over parts of the window: a rate that drifts within it
   * (a start-up not over, or the falling head) shows here. */
  printf("rate by window: 10-25 %%: %g, 25-40 %%: %g, 5-45 %%: %g\n",
         window_rate(time, mass, taken, total, 0.10, 0.25),
         window_rate(time, mass, taken, total, 0.25, 0.40),
         window_rate(time, mass, taken, total, 0.05, 0.45));
  if (last >= taken)
    printf("warning: less than %.0f %% discharged (the flow jammed?); the "
           "rate is fitted up to the end of the run\n",
           100 * s->window_end);
  if (last >= taken && first + 2 < taken)
    *rate = fitted_rate(time, mass, first, taken);
  free(time);
  return 0;
}

/* Parses --geometry, --hopper, --orifice and sizes the silo. */
static int configure(silo *s, int argc, char **argv) {
  const char *geometry = "plane", *hopper = "flat", *profile = "";
  const char *dilation = "none", *edge_node = "held";
  s->volumetric = "point";
  s->scheme = "musl";
  s->transfer = "flip";
  double fluid = 0.0;                                  /* Pa */
  double friction = FRICTION_ANGLE;                    /* deg */
  double pic = 0.0;                                    /* - */
  double wall_friction = tan(WALL_ANGLE * PI / 180.0); /* - */
  double orifice = 0.3, sample = 0.01;                 /* m, s */
  double fluidity = 0.0, reference = 0.0;              /* 1/s, Pa */
  double grain = 0.0;                                  /* m */
  double youngs = 0.0;                                 /* Pa, 0: 002's 1 MPa */
  double fill = 2.0;                                   /* full silo widths */
  double t_max = 0.0;                                  /* s, 0: none */
  double window_end = WINDOW_END;                      /* - */
  double cfl = gm_domain_def_default().cfl;            /* - */
  double drop = 0.0;                                   /* m */
  example_extra extras[] = {
      {"orifice", "orifice width (slot) or diameter D, m", &orifice, NULL},
      {"geometry", "plane|axisym|3d (3d: a quarter square silo)", NULL,
       &geometry},
      {"hopper",
       "flat or the hopper wall angle from the vertical, deg (3d: a "
       "pyramidal hopper with a square outlet of side D)",
       NULL, &hopper},
      {"sample", "sampling interval of the discharged mass, s", &sample, NULL},
      {"fluidity",
       "> 0: Perzyna rate term, gamma in 1/s (0: rate-free Drucker-Prager)",
       &fluidity, NULL},
      {"reference-stress",
       "Perzyna normaliser sigma_n = max(m p, this), Pa (with --fluidity)",
       &reference, NULL},
      {"profile",
       "CSV path: steady profiles across the orifice and above it (density, "
       "v_y, flux by x)",
       NULL, &profile},
      {"cfl", "Courant number of the stable time step (library default 0.5)",
       &cfl, NULL},
      {"grain",
       "> 0: mu(I) with this grain diameter, m, on the same cone (0: "
       "Drucker-Prager)",
       &grain, NULL},
      {"dilation",
       "Mohr-Coulomb on the same phi with this dilation angle psi, deg, in "
       "place of Drucker-Prager (none: Drucker-Prager)",
       NULL, &dilation},
      {"pic", "FLIP-PIC blend a in [0, 1] (0: FLIP)", &pic, NULL},
      {"friction", "the fill's friction angle phi, deg (002's 25)", &friction,
       NULL},
      {"fluid",
       "> 0: von Mises with this yield stress, Pa, in place of "
       "Drucker-Prager (a nearly inviscid fluid: Torricelli, sec. 30)",
       &fluid, NULL},
      {"wall-friction",
       "Coulomb mu_w of the silo and hopper walls (002's tan 20 deg)",
       &wall_friction, NULL},
      {"scheme", "usl | musl | usf (001 sec 3)", NULL, &s->scheme},
      {"transfer", "flip | apic (the affine particle-in-cell transfer)", NULL,
       &s->transfer},
      {"youngs",
       "> 0: Young's modulus E, Pa, in place of 002's 1 MPa (the dt "
       "shrinks as 1/sqrt(E))",
       &youngs, NULL},
      {"drop",
       "free fall below the orifice before the sink, m (whole cells; 0: the "
       "sink at the orifice)",
       &drop, NULL},
      {"fill",
       "fill height in full silo widths 2B (default 2; Beverloo's law wants "
       ">= 1.2 at the end of the window)",
       &fill, NULL},
      {"t-max",
       "> 0: stop the discharge here even before the window is over (the "
       "rate is then fitted from the window's start to the end), s",
       &t_max, NULL},
      {"volumetric",
       "point | cell (tr L averaged over each cell's points against "
       "volumetric locking, gm_domain_set_volumetric)",
       NULL, &s->volumetric},
      {"edge-node",
       "held | open: the floor holds the node on the orifice's edge, or "
       "starts a cell beyond it (docs/convergence.md sec. 38)",
       NULL, &edge_node},
      {"window-end",
       "fraction of the fill discharged that ends the rate's window (from "
       "0.1; the run stops 0.05 later; docs/3d.md's Beverloo sweep uses 0.25)",
       &window_end, NULL},
  };
  int parsed =
      example_parse(argc, argv,
                    "Silo discharge through a bottom orifice "
                    "against Beverloo (002 sec 5, 001 sec 5.1.1).",
                    &s->options, extras, sizeof extras / sizeof extras[0]);
  if (parsed != 0)
    return parsed;
  s->geometry = strcmp(geometry, "axisym") == 0 ? GM_GEOMETRY_AXISYMMETRIC
                : strcmp(geometry, "3d") == 0   ? GM_GEOMETRY_3D
                                                : GM_GEOMETRY_PLANE_STRAIN;
  s->dim = s->geometry == GM_GEOMETRY_3D ? 3 : 2;
  if (strcmp(geometry, "plane") != 0 && strcmp(geometry, "axisym") != 0 &&
      strcmp(geometry, "3d") != 0) {
    fprintf(stderr, "--geometry: '%s' is not plane, axisym or 3d\n", geometry);
    return 2;
  }
  if (s->dim == 3 && profile[0]) {
    fprintf(stderr, "--geometry 3d: no --profile\n");
    return 2;
  }
  s->hopper_angle = 0.0;
  if (strcmp(hopper, "flat") != 0) {
    char *end = NULL;
    double degrees = strtod(hopper, &end);
    if (end == hopper || *end || !(degrees > 0.0 && degrees < 80.0)) {
      fprintf(stderr, "--hopper: '%s' is not flat or an angle in (0, 80)\n",
              hopper);
      return 2;
    }
    s->hopper_angle = degrees * PI / 180.0;
  }
  double cell = s->options.cell; /* the orifice edge on a node line */
  s->orifice = 2.0 * cell * fmax(1.0, round(0.5 * orifice / cell));
  if (fabs(s->orifice - orifice) > 1e-9)
    printf("orifice rounded to %g m (its half on a grid line)\n", s->orifice);
  /* 1.5 D (the silo 3 D wide, beyond Mankoc's 2.5 D), up to a node line:
   * the same metres on every cell that divides it (0.45 m for D = 0.3 m on
   * 0.05 m and all its halvings), so --cell refines one scene (it used to
   * be 1.25 D + 1 cell, which narrowed the silo 18 % from 0.05 to
   * 0.00625 m cells). */
  s->half_width = cell * ceil(1.5 * s->orifice / cell - 1e-9);
  if (!(fill >= 0.5 && fill <= 10.0)) {
    fprintf(stderr, "--fill must be in [0.5, 10] widths\n");
    return 2;
  }
  if (s->dim == 3 && 0.5 * s->orifice / cell > MAX_SINKS - 2) {
    fprintf(stderr, "--geometry 3d: at most %d cells across D/2\n",
            MAX_SINKS - 2);
    return 2;
  }
  /* on a node line: the same metres on every cell that divides it */
  s->fill_height = cell * round(2.0 * fill * s->half_width / cell);
  s->sample = sample;
  if (!(fluidity >= 0.0) || !(reference >= 0.0)) {
    fprintf(stderr, "--fluidity and --reference-stress must be >= 0\n");
    return 2;
  }
  if (!(grain >= 0.0) || (grain > 0.0 && fluidity > 0.0)) {
    fprintf(stderr, "--grain must be >= 0 and not combined with --fluidity\n");
    return 2;
  }
  s->fluidity = fluidity;
  s->reference = reference;
  s->grain = grain;
  if (!(youngs >= 0.0 && youngs < 1e12)) {
    fprintf(stderr, "--youngs must be >= 0 (0: 1 MPa) and finite\n");
    return 2;
  }
  s->youngs = youngs;
  s->dilation = -1.0;
  if (!(friction > 0.0 && friction < 90.0)) {
    fprintf(stderr, "--friction must lie in (0, 90) deg\n");
    return 2;
  }
  s->friction = friction * PI / 180.0;
  s->pic = pic;
  s->wall_friction = wall_friction;
  if (!(wall_friction >= 0.0) || !isfinite(wall_friction)) {
    fprintf(stderr, "--wall-friction must be finite and >= 0\n");
    return 2;
  }
  if (!(pic >= 0.0 && pic <= 1.0) ||
      (strcmp(s->scheme, "usl") != 0 && strcmp(s->scheme, "musl") != 0 &&
       strcmp(s->scheme, "usf") != 0)) {
    fprintf(stderr, "--pic must lie in [0, 1], --scheme be usl|musl|usf\n");
    return 2;
  }
  if (strcmp(s->transfer, "flip") != 0 && strcmp(s->transfer, "apic") != 0) {
    fprintf(stderr, "--transfer: '%s' is not flip or apic\n", s->transfer);
    return 2;
  }
  if (strcmp(dilation, "none") != 0) {
    char *end = NULL;
    double degrees = strtod(dilation, &end);
    if (end == dilation || *end || !(degrees >= 0.0 && degrees <= friction)) {
      fprintf(stderr, "--dilation: '%s' is not none or an angle in [0, %g]\n",
              dilation, friction);
      return 2;
    }
    s->dilation = degrees * PI / 180.0;
    if (grain > 0.0 || fluidity > 0.0) {
      fprintf(stderr, "--dilation: not with --grain or --fluidity\n");
      return 2;
    }
  }
  s->fluid = fluid;
  if (!(fluid >= 0.0) || !isfinite(fluid) ||
      (fluid > 0.0 && (grain > 0.0 || fluidity > 0.0 || s->dilation >= 0.0))) {
    fprintf(stderr, "--fluid must be finite, >= 0 and not combined with "
                    "--grain, --fluidity or --dilation\n");
    return 2;
  }
  s->profile = profile;
  if (!(cfl > 0.0 && cfl <= 1.0)) {
    fprintf(stderr, "--cfl must be in (0, 1]\n");
    return 2;
  }
  s->cfl = cfl;
  if (!(drop >= 0.0) || (drop > 0.0 && (s->dim == 3 || s->hopper_angle > 0))) {
    fprintf(stderr, "--drop must be >= 0, in 2D and with a flat floor (a "
                    "hopper's wall plane continues below the orifice)\n");
    return 2;
  }
  s->drop = cell * round(drop / cell); /* y = 0 stays a node line */
  s->t_max = t_max > 0.0 ? t_max : 0.0;
  if (strcmp(s->volumetric, "point") != 0 &&
      strcmp(s->volumetric, "cell") != 0) {
    fprintf(stderr, "--volumetric: '%s' is not point or cell\n", s->volumetric);
    return 2;
  }
  if (!(window_end > WINDOW_START + 0.05 && window_end <= 0.9)) {
    fprintf(stderr, "--window-end must be in (0.15, 0.9]\n");
    return 2;
  }
  s->window_end = window_end;
  if (strcmp(edge_node, "held") != 0 && strcmp(edge_node, "open") != 0) {
    fprintf(stderr, "--edge-node: '%s' is not held or open\n", edge_node);
    return 2;
  }
  s->edge_cells = strcmp(edge_node, "open") == 0;
  if (s->edge_cells && s->hopper_angle > 0.0) {
    fprintf(stderr, "--edge-node open: a flat floor only (the hopper's walls "
                    "pass through the orifice's edges)\n");
    return 2;
  }
  return 0;
}

/* Both phases for one silo: its steady rate (kg/(m s) or kg/s) and the
 * mid-depth wall pressure at rest (Pa, 0 in 3D) at mid_depth (m). */
static int simulate(silo *s, double *rate, double *mid_pressure,
                    double *mid_depth) {
  gm_domain *rest = NULL, *flow = NULL;
  int material = -1, flow_material = -1;
  wall_loads rest_loads = {0}, loads = {0};
  EXAMPLE_CHECK(NULL, create_domain(s, SETTLE_DAMPING, &rest));
  EXAMPLE_CHECK(rest, add_material(rest, s, &material));
  EXAMPLE_CHECK(rest, add_walls(rest, s, &rest_loads));
  EXAMPLE_CHECK(rest,
                add_floor(rest, s, 0.0, s->half_width + 2 * s->options.cell));
  EXAMPLE_CHECK(rest, fill_silo(rest, s, material));
  EXAMPLE_CHECK(rest, settle(rest, s, &rest_loads, mid_pressure));
  *mid_depth =
      s->fill_height -
      s->options.cell * lround(0.5 * s->fill_height / s->options.cell); /* m */

  EXAMPLE_CHECK(NULL, create_domain(s, 0.0, &flow));
  EXAMPLE_CHECK(flow, add_material(flow, s, &flow_material));
  EXAMPLE_CHECK(flow, add_walls(flow, s, &loads));
  if (s->hopper_angle <= 0.0)
    EXAMPLE_CHECK(flow, add_floor(flow, s, floor_edge(s),
                                  s->half_width + 2 * s->options.cell));
  EXAMPLE_CHECK(
      flow, copy_points(rest, material, flow, flow_material, (size_t)s->dim));
  gm_domain_destroy(rest);
  int failed = discharge(flow, s, &loads, rate);
  gm_domain_destroy(flow);
  return failed;
}

/* The open floor nodes of the orifice and the area they open against
 * pi D^2 / 4 (silo_discharge_3d.h). */
static void print_orifice(const silo *s) {
  if (s->hopper_angle > 0.0) { /* the walls cut the opening, not the nodes */
    printf("orifice: %s %g m wide at the hopper's foot\n",
           s->dim == 3 ? "square outlet" : "circular outlet", s->orifice);
    return;
  }
  double h = s->options.cell; /* m */
  long holes = floor_holes(s), nodes = 0;
  double area = silo3d_open_area(s->dim == 3, holes, &nodes) * h * h; /* m^2 */
  printf("orifice: %ld open floor nodes (%s), open area %.4g m^2 = %.3f of "
         "pi D^2/4\n",
         nodes, s->dim == 3 ? "quarter" : "radius", area,
         area / (0.25 * PI * s->orifice * s->orifice));
}

int main(int argc, char **argv) {
  silo s = {0};
  s.options = (example_options){GM_SHAPE_LINEAR,
                                GM_FAMILY_PLAIN,
                                2,
                                0.025,
                                1,
                                "out/silo_discharge",
                                0.5,
                                0};
  int parsed = configure(&s, argc, argv);
  if (parsed != 0)
    return parsed == 1 ? 0 : parsed;
  if (example_make_output(&s.options) != 0)
    return 2;
  printf("%s silo, %s, D = %g m, B = %g m, H = %g m, cell %g m, %s/%s\n",
         s.dim == 3                               ? "3D quarter square"
         : s.geometry == GM_GEOMETRY_AXISYMMETRIC ? "axisymmetric"
                                                  : "planar",
         s.hopper_angle > 0 ? "hopper" : "flat bottom", s.orifice, s.half_width,
         s.fill_height, s.options.cell, example_shape_name(s.options.shape),
         example_family_name(s.options.family));

  if (s.geometry != GM_GEOMETRY_PLANE_STRAIN)
    print_orifice(&s);
  double rate = 0.0, mid_pressure = 0.0, mid_depth = 0.0; /* kg/s, Pa, m */
  int failed = simulate(&s, &rate, &mid_pressure, &mid_depth);
  if (failed)
    return failed;
  double axisym = 0.0; /* kg/s, the axisymmetric silo's rate (3D only) */
  if (s.dim == 3 && s.hopper_angle <= 0.0) {
    silo ring = s; /* the same D, B, H, cell and points, no output */
    ring.geometry = GM_GEOMETRY_AXISYMMETRIC;
    ring.dim = 2;
    ring.options.out = "";
    ring.options.quiet = 1;
    printf("the axisymmetric silo of the same D, B, H and cell:\n");
    print_orifice(&ring);
    double unused[2];
    failed = simulate(&ring, &axisym, &unused[0], &unused[1]);
    if (failed)
      return failed;
  }
  double k = 1.0 - sin(s.friction);
  /* --edge-node open widens the floor's hole by a cell on each side */
  double mesh_grain = MESH_GRAIN - 2.0 * s.edge_cells; /* k d / h */
  printf("Beverloo with d = 0: %g; with the mesh as grain (k d = %g h, see "
         "tests/physics/test_beverloo.c): %g\n",
         beverloo(&s, 0.0), mesh_grain,
         beverloo(&s, mesh_grain * s.options.cell));
  if (s.hopper_angle <= 0.0 && s.dim == 2)
    example_result("wall_pressure_mid_Pa", mid_pressure,
                   janssen_pressure(&s, k, mid_depth));
  example_result(s.geometry == GM_GEOMETRY_PLANE_STRAIN ? "flow_rate_kg_m_s"
                                                        : "flow_rate_kg_s",
                 rate, beverloo(&s, 0.0));
  if (s.dim == 3 && s.hopper_angle <= 0.0)
    example_result("flow_rate_3d_vs_axisym_kg_s", rate, axisym);
  return 0;
}
