/*
 * toe_probe.c - the front of the planar column collapse during the fall,
 * for docs/convergence.md section 18 (issue 13): where and when the front
 * of a finer grid takes its lead.
 *
 * The scene is collapse_scene.c's (examples/column_collapse: a = H/L0,
 * L0 = 0.15 m, rho 1800 kg/m^3, nu 0.3, E 0.5 MPa, Mohr-Coulomb psi = 0
 * unless --dilation,
 * frictionless back wall, floor --floor slip|face), with the built-in
 * material. At t/tau_c = 0.05, 0.1, 0.25, 0.5, 0.75, 1 (tau_c = sqrt(H/g))
 * it prints one FRONT line:
 *   edge      the connected deposit's edge (farthest point centre + half a
 *             point spacing, columns walked from the back wall), m
 *   thick10, thick05  the front of the part of the deposit at least 10 %
 *             or 5 % of L0 thick: the farthest point (+ half a spacing,
 *             connected) whose top (centre + half a spacing) is at least
 *             that high, m (where the surface falls towards the front, the
 *             surface's crossing of that level, on any grid)
 *   u_front   horizontal velocity of the point farthest out, m/s
 *   u_bottom  the same for the farthest point of the bottom row (points
 *             that started within one point spacing of the floor), m/s
 *   x_bottom  that point's position + half a spacing, m
 *   x_upper   the farthest point (+ half a spacing) among those that are
 *             now higher than 0.1 L0 above the floor, m
 *   u_upper   its horizontal velocity, m/s
 * All lengths are printed in L0, velocities in sqrt(g H).
 *
 * Options: --cell m --ppc n --method ugimp|bspline2|linear --family
 * granular|plain --aspect a --friction deg --youngs Pa --cfl C --floor
 * slip|face --dilation deg (psi, default 0) --elastic 1 (an elastic column: the
 * huge-phi limit) --k0 K (the column starts with a geostatic stress sigma_yy =
 * -rho g (H - y), sigma_xx = sigma_zz = K sigma_yy, applied by a wrapping user
 * material on each point's first update; 0 = stress-free, the example's start).
 * Section 19 (the shear bands and a viscoplastic length):
 *   --material mc|dp|perzyna  Mohr-Coulomb (default), rate-free
 *             Drucker-Prager or Perzyna Drucker-Prager (both psi = 0), the
 *             cone matched to --friction's plane-strain flow
 *             (collapse_scene_dp_friction); dp and perzyna print the cone
 *             and Perzyna's length l = c_s t_r, t_r = sigma_n / (3 G gamma)
 *             at the column's mean pressure
 *   --fluidity gamma (1/s, perzyna) --exponent N (default 1)
 *   --reference-stress Pa  sigma_n = max(m p, this) (default 0: m p)
 *   --band PREFIX  writes PREFIX_0.25.csv and PREFIX_0.50.csv: every
 *             point's position and its mean shear rates over the --window W
 *             (in tau_c, default 0.02) before 0.25 and 0.5 tau_c (see
 *             write_band); band_width.py and band_share.py read them.
 * Build after `make` in the worktree:
 *   gcc -std=c11 -O2 -Iinclude -Iexamples bench/convergence/toe_probe.c \
 *     bench/convergence/collapse_scene.c -Lbuild/lib/.libs -lgranmpm -lm \
 *     -o toe_probe
 *   LD_LIBRARY_PATH=build/lib/.libs ./toe_probe --cell 0.0075 --ppc 2 \
 *     --method bspline2 --friction 37 --floor slip
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
static const double DENSITY = COLLAPSE_DENSITY; /* kg/m^3 */

/* The probe's material. */
typedef enum probe_kind {
  PROBE_MOHR_COULOMB,   /* --material mc (default) */
  PROBE_ELASTIC,        /* --elastic 1 */
  PROBE_DRUCKER_PRAGER, /* --material dp: rate-free, psi = 0 */
  PROBE_PERZYNA         /* --material perzyna: viscoplastic DP, psi = 0 */
} probe_kind;

/* The material wrapped as a user material when the geostatic start
 * (--k0) or the shear-rate record (--band) needs it; otherwise the
 * built-in one is registered (the same update, so the same run). */
typedef struct probe_material {
  probe_kind kind;
  gm_mohr_coulomb_def mc;
  gm_elastic_def el;
  gm_drucker_prager_def dp;
  gm_perzyna_def perzyna;
  double k0, height;     /* -, m */
  const double *y_by_id; /* m, initial height of each point id */
  unsigned char *done;   /* per id: initial stress applied */
  /* --band: per point id, the strain increments (tensor components, -)
   * and the plastic strain (the material's state[0]: the accumulated
   * plastic shear strain of Mohr-Coulomb, the equivalent plastic strain
   * of the Drucker-Prager materials) added up since the last reset */
  int record;
  double *sum_xx, *sum_yy, *sum_xy, *sum_plastic;
} probe_material;

static int material_update(const gm_material_batch *batch,
                           const probe_material *s, char *message,
                           size_t message_size) {
  switch (s->kind) {
  case PROBE_ELASTIC:
    return gm_elastic_update(batch, (void *)&s->el, message, message_size);
  case PROBE_DRUCKER_PRAGER:
    return gm_drucker_prager_update(batch, (void *)&s->dp, message,
                                    message_size);
  case PROBE_PERZYNA:
    return gm_perzyna_update(batch, (void *)&s->perzyna, message, message_size);
  default:
    return gm_mohr_coulomb_update(batch, (void *)&s->mc, message, message_size);
  }
}

static int probe_update(const gm_material_batch *batch, void *user,
                        char *message, size_t message_size) {
  probe_material *s = user;
  for (size_t i = 0; s->k0 > 0.0 && i < batch->count; i++) {
    int64_t id = batch->point_id[i];
    if (s->done[id])
      continue;
    s->done[id] = 1;
    /* the weight of the material above, sigma_yy = -rho g (H - y) */
    double syy = -DENSITY * GRAVITY * (s->height - s->y_by_id[id]);
    batch->stress[0][i] += s->k0 * syy;
    batch->stress[1][i] += syy;
    batch->stress[2][i] += s->k0 * syy;
  }
  int plastic = s->record && batch->state_count > 0;
  /* the plastic strain before the update, kept in the sum (subtracted
   * now, the value after added below) */
  for (size_t i = 0; plastic && i < batch->count; i++)
    s->sum_plastic[batch->point_id[i]] -= batch->state[0][i];
  int status = material_update(batch, s, message, message_size);
  if (status != 0 || !s->record)
    return status;
  for (size_t i = 0; i < batch->count; i++) {
    int64_t id = batch->point_id[i];
    s->sum_xx[id] += batch->strain_increment[GM_XX][i];
    s->sum_yy[id] += batch->strain_increment[GM_YY][i];
    s->sum_xy[id] += batch->strain_increment[GM_XY][i];
    if (plastic)
      s->sum_plastic[id] += batch->state[0][i];
  }
  return 0;
}

#define CHECK COLLAPSE_CHECK

/* --band PREFIX: PREFIX_<t/tau>.csv with every point's position (m) and
 * its mean shear rates over the window (1/s): the total one, the largest
 * engineering shear rate in the plane of the grid's rate of deformation
 * D (2 sqrt(((D_xx - D_yy)/2)^2 + D_xy^2), from the strain increments the
 * material received), and the plastic one (the material's plastic strain
 * accrued over the window / its length). */
static int write_band(const char *prefix, double mark, double window,
                      const double *x, const int64_t *ids, size_t count,
                      const probe_material *s) {
  char path[512];
  snprintf(path, sizeof path, "%s_%.2f.csv", prefix, mark);
  FILE *out = fopen(path, "w");
  if (!out) {
    perror(path);
    return 1;
  }
  fprintf(out, "x_m,y_m,shear_rate,plastic_rate\n");
  for (size_t i = 0; i < count; i++) {
    int64_t id = ids[i];
    double half_difference = 0.5 * (s->sum_xx[id] - s->sum_yy[id]);
    double total = 2.0 * sqrt(half_difference * half_difference +
                              s->sum_xy[id] * s->sum_xy[id]);
    fprintf(out, "%.6g,%.6g,%.6g,%.6g\n", x[2 * i], x[2 * i + 1],
            total / window, s->sum_plastic[id] / window);
  }
  return fclose(out) == 0 ? 0 : 1;
}

int main(int argc, char **argv) {
  double cell = 0.0075, aspect = 1.3, friction = 37.0, youngs = 5e5, cfl = 0.0;
  double k0 = 0.0, poisson = 0.3, dilation = 0.0;
  double fluidity = 0.0, exponent = 1.0, reference = 0.0, window = 0.02;
  int ppc = 2, elastic = 0;
  const char *material_name = "mc", *band = NULL;
  gm_shape shape = GM_SHAPE_BSPLINE2;
  gm_family family = GM_FAMILY_GRANULAR;
  const char *floor_kind = "slip";
  for (int k = 1; k + 1 < argc; k += 2) {
    const char *n = argv[k], *v = argv[k + 1];
    if (!strcmp(n, "--cell"))
      cell = atof(v);
    else if (!strcmp(n, "--ppc"))
      ppc = atoi(v);
    else if (!strcmp(n, "--aspect"))
      aspect = atof(v);
    else if (!strcmp(n, "--friction"))
      friction = atof(v);
    else if (!strcmp(n, "--youngs"))
      youngs = atof(v);
    else if (!strcmp(n, "--cfl"))
      cfl = atof(v);
    else if (!strcmp(n, "--dilation"))
      dilation = atof(v);
    else if (!strcmp(n, "--k0"))
      k0 = atof(v);
    else if (!strcmp(n, "--elastic"))
      elastic = atoi(v);
    else if (!strcmp(n, "--floor"))
      floor_kind = v;
    else if (!strcmp(n, "--material"))
      material_name = v;
    else if (!strcmp(n, "--fluidity"))
      fluidity = atof(v);
    else if (!strcmp(n, "--exponent"))
      exponent = atof(v);
    else if (!strcmp(n, "--reference-stress"))
      reference = atof(v);
    else if (!strcmp(n, "--band"))
      band = v;
    else if (!strcmp(n, "--window"))
      window = atof(v);
    else if (!strcmp(n, "--method"))
      shape = !strcmp(v, "ugimp")    ? GM_SHAPE_UGIMP
              : !strcmp(v, "linear") ? GM_SHAPE_LINEAR
                                     : GM_SHAPE_BSPLINE2;
    else if (!strcmp(n, "--family"))
      family = !strcmp(v, "plain") ? GM_FAMILY_PLAIN : GM_FAMILY_GRANULAR;
    else {
      fprintf(stderr, "unknown option %s\n", n);
      return 2;
    }
  }
  probe_kind kind = elastic                             ? PROBE_ELASTIC
                    : !strcmp(material_name, "mc")      ? PROBE_MOHR_COULOMB
                    : !strcmp(material_name, "dp")      ? PROBE_DRUCKER_PRAGER
                    : !strcmp(material_name, "perzyna") ? PROBE_PERZYNA
                                                        : (probe_kind)-1;
  if (cell <= 0.0 || ppc < 1 || ppc > 16 || aspect <= 0.0 || aspect > 1.8 ||
      (int)kind < 0 || (kind == PROBE_PERZYNA && fluidity <= 0.0) ||
      window <= 0.0 || window >= 0.25) {
    fprintf(stderr, "an option is out of range (--material mc|dp|perzyna, "
                    "perzyna needs --fluidity > 0, 0 < --window < 0.25)\n");
    return 2;
  }
  collapse_scene scene = {.cell = cell,
                          .ppc = ppc,
                          .shape = shape,
                          .family = family,
                          .workers = 1,
                          .cfl = cfl,
                          .aspect = aspect,
                          .length = 0.15,
                          .floor =
                              !strcmp(floor_kind, "face") ? "face" : "slip"};
  double height = collapse_scene_height(&scene);
  double tau = collapse_scene_tau(&scene);
  gm_domain_def def = collapse_scene_domain_def(&scene);
  gm_domain *domain = NULL;
  CHECK(NULL, gm_domain_create(&def, &domain));
  static probe_material start;
  start.kind = kind;
  start.k0 = k0;
  start.height = height;
  start.record = band != NULL;
  start.mc = gm_mohr_coulomb_def_default();
  start.mc.youngs_modulus = youngs;
  start.mc.poisson_ratio = poisson;
  start.mc.density = DENSITY;
  start.mc.friction_angle = friction * PI / 180.0;
  start.mc.dilation_angle = dilation * PI / 180.0;
  start.mc.bagnold_viscosity = 0.0;
  start.el = gm_elastic_def_default();
  start.el.youngs_modulus = youngs;
  start.el.poisson_ratio = poisson;
  start.el.density = DENSITY;
  /* the cone that flows in plane strain at Mohr-Coulomb's friction */
  double friction_dp = collapse_scene_dp_friction(friction * PI / 180.0);
  double slope = sqrt(3.0) * sin(friction * PI / 180.0); /* m of the cone */
  start.dp = gm_drucker_prager_def_default();
  start.dp.youngs_modulus = youngs;
  start.dp.poisson_ratio = poisson;
  start.dp.density = DENSITY;
  start.dp.friction_angle = friction_dp;
  start.perzyna = gm_perzyna_def_default();
  start.perzyna.youngs_modulus = youngs;
  start.perzyna.poisson_ratio = poisson;
  start.perzyna.density = DENSITY;
  start.perzyna.friction_angle = friction_dp;
  start.perzyna.fluidity = fluidity > 0.0 ? fluidity : 1.0;
  start.perzyna.exponent = exponent;
  start.perzyna.reference_stress = reference;
  if (kind == PROBE_DRUCKER_PRAGER || kind == PROBE_PERZYNA) {
    /* the viscoplastic length l = c_s t_r, t_r = sigma_n / (3 G gamma)
     * (the overstress relaxation time of eq 18 with N = 1) at the
     * column's mean pressure rho g H / 2 */
    double shear = youngs / (2.0 * (1.0 + poisson));  /* G, Pa */
    double mean_p = 0.5 * DENSITY * GRAVITY * height; /* Pa */
    double sigma_n = fmax(slope * mean_p, reference);
    double t_r = sigma_n / (3.0 * shear * fluidity);
    printf("# drucker-prager phi=%.4f deg (m=%.4f) fluidity=%g 1/s "
           "t_r=%.4g s length=%.4g m (%.3g cells)\n",
           friction_dp * 180.0 / PI, slope, fluidity,
           kind == PROBE_PERZYNA ? t_r : 0.0,
           kind == PROBE_PERZYNA ? sqrt(shear / DENSITY) * t_r : 0.0,
           kind == PROBE_PERZYNA ? sqrt(shear / DENSITY) * t_r / cell : 0.0);
  }
  int material = -1;
  if (k0 > 0.0 || start.record) {
    gm_material_def m = gm_material_def_default();
    m.name = "probe";
    m.update = probe_update;
    m.user = &start;
    m.state_count = kind == PROBE_ELASTIC ? 0 : 1;
    /* the built-in materials' own bound, so the same stable dt */
    m.p_wave_modulus =
        youngs * (1.0 - poisson) / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
    m.density = DENSITY;
    CHECK(domain, gm_domain_add_material(domain, &m, &material));
  } else if (kind == PROBE_ELASTIC)
    CHECK(domain, gm_domain_add_elastic(domain, &start.el, &material));
  else if (kind == PROBE_DRUCKER_PRAGER)
    CHECK(domain, gm_domain_add_drucker_prager(domain, &start.dp, &material));
  else if (kind == PROBE_PERZYNA)
    CHECK(domain, gm_domain_add_perzyna(domain, &start.perzyna, &material));
  else
    CHECK(domain, gm_domain_add_mohr_coulomb(domain, &start.mc, &material));
  CHECK(domain, collapse_scene_set_granular(domain, &scene, material));
  int floor_wall = -1;
  CHECK(domain, collapse_scene_add_walls(domain, &scene, &floor_wall));
  CHECK(domain, collapse_scene_fill(domain, &scene, material));
  size_t count = gm_domain_point_count(domain);
  double *x = malloc(2 * count * sizeof *x), *u = malloc(2 * count * sizeof *u);
  int64_t *ids = malloc(count * sizeof *ids);
  unsigned char *occupied = malloc(collapse_scene_columns(&scene));
  if (!x || !u || !ids || !occupied)
    return 2;
  CHECK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION, x, 2 * count));
  CHECK(domain, gm_domain_get_ids(domain, ids, count));
  int64_t max_id = 0;
  for (size_t i = 0; i < count; i++)
    max_id = ids[i] > max_id ? ids[i] : max_id;
  double *y0 = calloc((size_t)max_id + 1, sizeof *y0);
  start.done = calloc((size_t)max_id + 1, 1);
  if (!y0 || !start.done)
    return 2;
  if (start.record) {
    size_t ids_n = (size_t)max_id + 1;
    start.sum_xx = calloc(ids_n, sizeof(double));
    start.sum_yy = calloc(ids_n, sizeof(double));
    start.sum_xy = calloc(ids_n, sizeof(double));
    start.sum_plastic = calloc(ids_n, sizeof(double));
    if (!start.sum_xx || !start.sum_yy || !start.sum_xy || !start.sum_plastic)
      return 2;
  }
  for (size_t i = 0; i < count; i++)
    y0[ids[i]] = x[2 * i + 1];
  start.y_by_id = y0;
  double spacing = cell / ppc, half = 0.5 * spacing;
  double speed = sqrt(GRAVITY * height);
  printf("# cell=%g ppc=%d points=%zu tau_c=%g s sqrt(gH)=%g m/s\n", cell, ppc,
         count, tau, speed);
  printf("t/tau,edge,thick10,thick05,u_front,u_bottom,x_bottom,x_upper,"
         "u_upper\n");
  static const double marks[] = {0.05, 0.1, 0.25, 0.5, 0.75, 1.0};
  for (int m = 0; m < 6; m++) {
    int band_mark = start.record && (m == 2 || m == 3); /* 0.25, 0.5 tau_c */
    if (band_mark) {
      /* the rates are the means over the window before the mark */
      CHECK(domain, gm_domain_advance(domain, (marks[m] - window) * tau, 0.0,
                                      NULL, NULL));
      size_t ids_n = (size_t)max_id + 1;
      memset(start.sum_xx, 0, ids_n * sizeof(double));
      memset(start.sum_yy, 0, ids_n * sizeof(double));
      memset(start.sum_xy, 0, ids_n * sizeof(double));
      memset(start.sum_plastic, 0, ids_n * sizeof(double));
    }
    CHECK(domain, gm_domain_advance(domain, marks[m] * tau, 0.0, NULL, NULL));
    CHECK(domain, gm_domain_get_field(domain, GM_FIELD_POSITION, x, 2 * count));
    CHECK(domain, gm_domain_get_field(domain, GM_FIELD_VELOCITY, u, 2 * count));
    CHECK(domain, gm_domain_get_ids(domain, ids, count));
    double limit = collapse_scene_connected_limit(&scene, x, count, occupied);
    double edge = 0, u_front = 0, x_bottom = 0, u_bottom = 0;
    double x_upper = 0, u_upper = 0;
    size_t lost = 0; /* points with a non-finite position */
    double thick[2] = {0, 0}, level[2] = {0.10, 0.05};
    for (size_t i = 0; i < count; i++) {
      double px = x[2 * i], py = x[2 * i + 1];
      if (px >= limit)
        continue;
      if (px + half > edge) {
        edge = px + half;
        u_front = u[2 * i];
      }
      if (y0[ids[i]] < spacing && px + half > x_bottom) {
        x_bottom = px + half;
        u_bottom = u[2 * i];
      }
      for (int t = 0; t < 2; t++)
        if (py + half >= level[t] * scene.length)
          thick[t] = fmax(thick[t], px + half);
      if (py > 0.1 * scene.length && px + half > x_upper) {
        x_upper = px + half;
        u_upper = u[2 * i];
      }
    }
    printf("%.2f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n", marks[m],
           edge / scene.length, thick[0] / scene.length,
           thick[1] / scene.length, u_front / speed, u_bottom / speed,
           x_bottom / scene.length, x_upper / scene.length, u_upper / speed);
    if (lost > 0 || edge <= 0.0)
      printf("# t/tau=%.2f: %zu points with a non-finite position, edge "
             "%g m\n",
             marks[m], lost, edge);
    if (band_mark &&
        write_band(band, marks[m], window * tau, x, ids, count, &start) != 0)
      return 2;
    fflush(stdout);
  }
  gm_domain_destroy(domain);
  free(x);
  free(u);
  free(ids);
  free(occupied);
  free(y0);
  free(start.done);
  free(start.sum_xx);
  free(start.sum_yy);
  free(start.sum_xy);
  free(start.sum_plastic);
  return 0;
}
