/*
 * slide_probe.c - an elastic block (E, nu, 2000 kg/m^3) on a frictional
 * planar wall, 2D plane strain or 3D, for docs/3d.md ("The sliding block
 * under refinement", issue 16 item 3): the slide against the rigid block's
 * 1/2 g (sin th - mu cos th) t^2 (plus v0 t), the wall's friction impulse
 * along the slide and across it over the normal impulse, and the spread
 * of the block's velocities about its mean over time windows. The scene
 * is tests/physics/test_walls_3d.c's (block W x W x H, W = 0.3 m,
 * H = 0.15 m, 2D: W x H; the uniaxial stress of its weight; the plane's
 * normal (0.25, 0.35, 1)/|.| when `oblique` in 3D, 20 deg off y in 2D,
 * along z / y when `axis`), USL, 1 worker, the stable dt.
 *
 * usage: slide_probe DIM CELL NU E CFL oblique|axis OFFSET PPC DURATION
 *                    DEGREES MU AZIMUTH_DEG [WINDOWS [W [H]]]
 *   OFFSET: cells off a node row along z (3D) or y (2D); AZIMUTH: the
 *   slide direction's turn about the normal (3D). Environment: PIC=f
 *   (pic_fraction), MUSL=1, SHAPE=k (gm_shape), V0=v (initial velocity
 *   along the slide, m/s).
 * Per window: the end time (s), the block's velocity along the slide
 * (m/s), -J_d/J_n and -J_e/J_n of the wall's impulses in the window, the
 * rms of the bottom layer's velocity about the block's mean along e, d
 * and n (m/s, time-averaged), mean |v_e| / v_d; then the number of sign
 * changes of the bottom layer's mean d velocity (as a frequency, Hz)
 * against v/h, that mean's rms and the correlation of cell means along d
 * one and two cells apart (one = smooth), and the rms about the mean of
 * every point (m/s) and of the bottom layer's e velocity linear in e.
 * Build and run from the worktree after `make`:
 *   gcc -std=c11 -O2 -Iinclude bench/convergence/slide_probe.c \
 *     build/lib/.libs/libgranmpm.a -lm -lpthread -o slide_probe
 *   ./slide_probe 3 0.025 0.3 2e7 0.5 oblique 0.3 2 0.3 30 0.4 30 10
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#include <granmpm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846, G = 9.81, RHO = 2000.0;

static void normalise(double *v, int n) {
  double l = 0;
  for (int k = 0; k < n; k++)
    l += v[k] * v[k];
  l = sqrt(l);
  for (int k = 0; k < n; k++)
    v[k] /= l;
}
static void cross(const double a[3], const double b[3], double o[3]) {
  o[0] = a[1] * b[2] - a[2] * b[1];
  o[1] = a[2] * b[0] - a[0] * b[2];
  o[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
#define OK(x)                                                                  \
  do {                                                                         \
    gm_status s_ = (x);                                                        \
    if (s_ != GM_OK) {                                                         \
      fprintf(stderr, "%s: %s\n", #x, gm_domain_last_error(domain));           \
      exit(1);                                                                 \
    }                                                                          \
  } while (0)

int main(int argc, char **argv) {
  if (argc < 13) {
    fprintf(stderr, "usage\n");
    return 2;
  }
  int dim = atoi(argv[1]);
  double cell = atof(argv[2]), nu = atof(argv[3]), E = atof(argv[4]);
  double cfl = atof(argv[5]);
  int oblique = strcmp(argv[6], "oblique") == 0;
  double offset = atof(argv[7]);
  int ppc = atoi(argv[8]);
  double duration = atof(argv[9]), theta = atof(argv[10]) * PI / 180;
  double mu = atof(argv[11]), azimuth = atof(argv[12]) * PI / 180;
  int windows = argc > 13 ? atoi(argv[13]) : 10;
  double W = argc > 14 ? atof(argv[14]) : 0.3,
         H = argc > 15 ? atof(argv[15]) : 0.15;
  double n[3] = {0, 0, 0}, d[3] = {0, 0, 0}, e[3] = {0, 0, 0};
  if (dim == 3) {
    if (oblique) {
      n[0] = 0.25, n[1] = 0.35, n[2] = 1.0;
    } else
      n[2] = 1.0;
    normalise(n, 3);
    double a[3] = {1, 0, 0}, b[3];
    for (int k = 0; k < 3; k++)
      a[k] -= n[0] * n[k];
    normalise(a, 3);
    cross(n, a, b);
    for (int k = 0; k < 3; k++)
      d[k] = cos(azimuth) * a[k] + sin(azimuth) * b[k];
    cross(n, d, e);
  } else {
    if (oblique) { /* tilted plane, normal at 20 deg off y */
      n[0] = -sin(20 * PI / 180), n[1] = cos(20 * PI / 180);
    } else
      n[1] = 1.0;
    d[0] = n[1], d[1] = -n[0];
  }
  gm_domain_def def = gm_domain_def_default();
  def.geometry = dim == 3 ? GM_GEOMETRY_3D : GM_GEOMETRY_PLANE_STRAIN;
  def.scheme = GM_SCHEME_USL;
  def.worker_count = 1;
  def.cell_size = cell;
  def.cfl = cfl;
  if (getenv("PIC"))
    def.pic_fraction = atof(getenv("PIC"));
  if (getenv("MUSL"))
    def.scheme = GM_SCHEME_MUSL;
  if (getenv("SHAPE"))
    def.shape = (gm_shape)atoi(getenv("SHAPE"));
  double extent = dim == 3 ? 1.0 : 1.6;
  for (int k = 0; k < dim; k++) {
    def.extent[k] = extent;
    def.gravity[k] = G * (-cos(theta) * n[k] + sin(theta) * d[k]);
  }
  gm_domain *domain = NULL;
  if (gm_domain_create(&def, &domain) != GM_OK) {
    fprintf(stderr, "create failed\n");
    return 1;
  }
  double point[3] = {round(0.4 / cell) * cell, round(0.4 / cell) * cell, 0};
  if (dim == 3)
    point[2] = (round(0.3 / cell) + offset) * cell;
  else
    point[1] += offset * cell;
  gm_wall_def wall = gm_wall_def_default();
  for (int k = 0; k < 3; k++)
    wall.point[k] = point[k], wall.normal[k] = n[k];
  wall.friction_static = wall.friction_kinetic = mu;
  int wall_id = -1;
  OK(gm_domain_add_wall(domain, &wall, &wall_id));
  gm_elastic_def el = gm_elastic_def_default();
  el.youngs_modulus = E;
  el.poisson_ratio = nu;
  el.density = RHO;
  int material = -1;
  OK(gm_domain_add_elastic(domain, &el, &material));
  int along = (int)lround(W / cell) * ppc, up = (int)lround(H / cell) * ppc;
  int across = dim == 3 ? along : 1;
  size_t count = (size_t)along * across * up;
  double sp = cell / ppc;
  double *pos = malloc(count * 3 * sizeof(double));
  double *vol = malloc(count * sizeof(double));
  double *str = calloc(count * 6, sizeof(double));
  size_t p = 0;
  double ws = RHO * G * cos(theta);
  for (int k = 0; k < up; k++)
    for (int j = 0; j < across; j++)
      for (int i = 0; i < along; i++, p++) {
        double s = -0.25 * W + (i + 0.5) * sp;
        double r = dim == 3 ? -0.5 * W + (j + 0.5) * sp : 0;
        double h = (k + 0.5) * sp;
        for (int c = 0; c < 3; c++)
          pos[3 * p + c] = point[c] + s * d[c] + r * e[c] + h * n[c];
        vol[p] = dim == 3 ? sp * sp * sp : sp * sp;
        double sg = -ws * (H - h);
        if (dim == 3) {
          str[6 * p + GM_XX] = sg * n[0] * n[0];
          str[6 * p + GM_YY] = sg * n[1] * n[1];
          str[6 * p + GM_ZZ] = sg * n[2] * n[2];
          str[6 * p + GM_XY] = sg * n[0] * n[1];
          str[6 * p + GM_YZ] = sg * n[1] * n[2];
          str[6 * p + GM_ZX] = sg * n[2] * n[0];
        } else { /* plane strain: sigma_zz = nu (s_xx + s_yy) */
          str[6 * p + GM_XX] = sg * n[0] * n[0];
          str[6 * p + GM_YY] = sg * n[1] * n[1];
          str[6 * p + GM_XY] = sg * n[0] * n[1];
          str[6 * p + GM_ZZ] = nu * sg;
        }
      }
  if (dim == 2)
    for (p = 0; p < count; p++)
      pos[2 * p] = pos[3 * p], pos[2 * p + 1] = pos[3 * p + 1];
  double v0 = getenv("V0") ? atof(getenv("V0")) : 0.0;
  double *vel = calloc(count * 3, sizeof(double));
  for (p = 0; p < count; p++)
    for (int c = 0; c < dim; c++)
      vel[dim * p + c] = v0 * d[c];
  gm_points_def pd = gm_points_def_default();
  pd.velocity = vel;
  pd.count = count;
  pd.material = material;
  pd.position = pos;
  pd.volume = vol;
  pd.stress = str;
  OK(gm_domain_add_points(domain, &pd, NULL));
  gm_summary sum = gm_summary_default();
  OK(gm_domain_get_summary(domain, &sum));
  double mass = sum.mass, start = dot(sum.centre_of_mass, d);
  double *x = malloc(count * 3 * sizeof(double)),
         *v = malloc(count * 3 * sizeof(double));
  double time = 0, wstart = 0;
  double Jn = 0, Jd = 0, Je = 0; /* window impulses */
  double Jn_all = 0, Jd_all = 0, Je_all = 0;
  double acc_e2 = 0, acc_dd2 = 0, acc_n2 = 0, acc_w = 0; /* bottom layer */
  double acc_bd2 = 0, acc_c0 = 0, acc_c1 = 0, acc_c2 = 0;
  double acc_abs_e = 0, acc_fit = 0, acc_ke = 0, last_bd = 0;
  int crossings = 0;
  int next = 1;
  printf("# dim %d cell %g nu %g E %g cfl %g %s offset %g ppc %d T %g th %g mu "
         "%g az %g W %g H %g points %zu\n",
         dim, cell, nu, E, cfl, argv[6], offset, ppc, duration,
         theta * 180 / PI, mu, azimuth * 180 / PI, W, H, count);
  printf("# t_end  v_d  mu_d(window) mu_e(window) rms_e_bottom rms_dd_bottom "
         "rms_n_bottom mean|v_e|/v_d\n");
  long steps = 0;
  while (time < duration - 1e-12) {
    double dt = 0;
    OK(gm_domain_stable_dt(domain, &dt));
    if (time + dt > duration)
      dt = duration - time;
    OK(gm_domain_step(domain, dt));
    time += dt;
    steps++;
    gm_wall_force f = gm_wall_force_default();
    OK(gm_domain_get_wall_force(domain, wall_id, &f));
    Jn += dot(f.impulse, n), Jd += dot(f.impulse, d), Je += dot(f.impulse, e);
    Jn_all += dot(f.impulse, n), Jd_all += dot(f.impulse, d),
        Je_all += dot(f.impulse, e);
    if (steps % 4 == 0 || time >= duration - 1e-12) {
      OK(gm_domain_get_field(domain, GM_FIELD_POSITION, x,
                             (size_t)dim * count));
      OK(gm_domain_get_field(domain, GM_FIELD_VELOCITY, v,
                             (size_t)dim * count));
      OK(gm_domain_get_summary(domain, &sum));
      double vm[3] = {sum.momentum[0] / mass, sum.momentum[1] / mass,
                      sum.momentum[2] / mass};
      double se = 0, sd = 0, sn = 0, ae = 0, srr = 0, sre = 0, ke = 0;
      int nb = 0;
      double bd = 0;
      for (p = 0; p < count; p++) {
        double xp[3] = {0, 0, 0}, vp[3] = {0, 0, 0};
        for (int c = 0; c < dim; c++)
          xp[c] = x[dim * p + c] - point[c], vp[c] = v[dim * p + c] - vm[c];
        ke += dot(vp, vp);
        if (dot(xp, n) > sp)
          continue;
        {
          double cm[3];
          for (int c = 0; c < 3; c++)
            cm[c] = sum.centre_of_mass[c] - point[c];
          double r = dot(xp, e) - dot(cm, e);
          srr += r * r;
          sre += r * dot(vp, e);
        }
        nb++;
        bd += dot(vp, d);
        se += dot(vp, e) * dot(vp, e), sd += dot(vp, d) * dot(vp, d),
            sn += dot(vp, n) * dot(vp, n);
        ae += fabs(dot(vp, e));
      }
      double vd = dot(vm, d);
      acc_e2 += se / nb * dt, acc_dd2 += sd / nb * dt, acc_n2 += sn / nb * dt,
          acc_w += dt;
      bd /= nb;
      acc_bd2 += bd * bd * dt;
      { /* bins one cell long along d */
        enum { NB = 512 };
        static double bin[NB];
        static int bc[NB];
        int nbin = (int)(W / cell) + 4;
        for (int q = 0; q < nbin; q++)
          bin[q] = 0, bc[q] = 0;
        double cm[3];
        for (int c = 0; c < 3; c++)
          cm[c] = sum.centre_of_mass[c] - point[c];
        for (size_t pp = 0; pp < count; pp++) {
          double xq[3] = {0, 0, 0}, vq[3] = {0, 0, 0};
          for (int c = 0; c < dim; c++)
            xq[c] = x[dim * pp + c] - point[c], vq[c] = v[dim * pp + c] - vm[c];
          if (dot(xq, n) > sp)
            continue;
          int q = (int)floor((dot(xq, d) - dot(cm, d)) / cell + 0.5 * nbin);
          if (q < 0 || q >= nbin)
            continue;
          bin[q] += dot(vq, d) - bd;
          bc[q]++;
        }
        double c0 = 0, c1 = 0, c2 = 0;
        for (int q = 0; q < nbin; q++)
          if (bc[q])
            bin[q] /= bc[q];
        for (int q = 0; q + 2 < nbin; q++)
          if (bc[q] && bc[q + 1] && bc[q + 2]) {
            c0 += bin[q] * bin[q];
            c1 += bin[q] * bin[q + 1];
            c2 += bin[q] * bin[q + 2];
          }
        acc_c0 += c0 * dt;
        acc_c1 += c1 * dt;
        acc_c2 += c2 * dt;
      }
      if (last_bd * bd < 0)
        crossings++;
      last_bd = bd;
      acc_abs_e += (vd > 0 ? ae / nb / vd : 0) * dt;
      double slope = srr > 0 ? sre / srr : 0; /* 1/s */
      acc_fit += slope * slope * srr / nb * dt;
      acc_ke += ke / count * dt;
    }
    if (time >= next * duration / windows - 1e-12) {
      OK(gm_domain_get_summary(domain, &sum));
      double vd = dot(sum.momentum, d) / mass;
      printf("%.4f %.5f %.5f %+.5f %.3e %.3e %.3e %.4f\n", time, vd, -Jd / Jn,
             -Je / Jn, sqrt(acc_e2 / acc_w), sqrt(acc_dd2 / acc_w),
             sqrt(acc_n2 / acc_w), acc_abs_e / acc_w);
      printf("   crossing_freq_Hz %.1f v/h_Hz %.1f\n",
             crossings / (2.0 * (duration / windows)), vd / cell);
      crossings = 0;
      printf("   rms_bottom_mean_dd %.3e  lag1 %.3f lag2 %.3f\n",
             sqrt(acc_bd2 / acc_w), acc_c1 / acc_c0, acc_c2 / acc_c0);
      acc_bd2 = acc_c0 = acc_c1 = acc_c2 = 0;
      printf("   rms_fluct_all %.3e  rms_e_bottom_linear_mode %.3e\n",
             sqrt(acc_ke / acc_w), sqrt(acc_fit / acc_w));
      Jn = Jd = Je = 0;
      acc_e2 = acc_dd2 = acc_n2 = acc_w = acc_abs_e = acc_fit = acc_ke = 0;
      wstart = time;
      next++;
    }
  }
  (void)wstart;
  OK(gm_domain_get_summary(domain, &sum));
  double slide = dot(sum.centre_of_mass, d) - start;
  double a = G * (sin(theta) - mu * cos(theta));
  double expect =
      (a > 0 || v0 > 0 ? 0.5 * a * duration * duration : 0) + v0 * duration;
  double fl = 0.5 * G * sin(theta) * duration * duration;
  printf(
      "RESULT dim %d cell %g nu %g E %g cfl %g %s az %g steps %ld slide %.6f "
      "expected %.6f err %+.3f %% (of frictionless %+.4f %%) mu_d_all %.5f "
      "mu_e_all %+.5f Jn/(mg cos T) %.5f\n",
      dim, cell, nu, E, cfl, argv[6], azimuth * 180 / PI, steps, slide, expect,
      expect > 0 ? 100 * (slide - expect) / expect : 0,
      100 * (slide - expect) / fl, -Jd_all / Jn_all, -Je_all / Jn_all,
      Jn_all / (mass * G * cos(theta) * duration));
  gm_domain_destroy(domain);
  return 0;
}
