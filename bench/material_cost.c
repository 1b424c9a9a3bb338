/*
 * material_cost.c - micro-benchmark of one material update call: the
 * built-in Mohr-Coulomb model (gm_mohr_coulomb_update) against the linear
 * elastic one (gm_elastic_update) on the same batch of points, in ns per
 * point. It isolates the cost of the constitutive update from the rest of
 * the step (granmpm-bench measures the whole step). Not part of make check:
 * speed is measured, never asserted (bench/README.md).
 *
 * Four batches of realistic states, each `--points` points (default 1e5, the
 * size of granmpm-bench's mohr-coulomb-1e5 scene):
 *   plane-elastic  plane strain (yz = zx = 0), a gravity-loaded column at
 *                  rest (K0 = nu/(1-nu)) with a small shear: every trial
 *                  stays inside the Mohr-Coulomb surface (phi 30 deg);
 *   plane-plastic  the same stresses with a deviatoric strain increment
 *                  large enough that every trial is outside the surface;
 *   3d-elastic, 3d-plastic  the same with non-zero yz and zx shear, which
 *                  the general 3D path handles (closed-form principal
 *                  values; eigenvectors only for points that may yield).
 * Each repetition restores the stresses (outside the timed call) and times
 * one call per model, interleaved, with CLOCK_MONOTONIC; the median over the
 * repetitions is printed, as CSV on stdout, and the minimum too: on a
 * machine shared with other jobs the median of the memory-bound elastic
 * call moves by 3x from run to run, the minimum (the call least disturbed)
 * much less.
 *
 * Usage: material-cost [--points N] [--reps R] [--case NAME]
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L
#include "granmpm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct batch_data {
  size_t count;
  double *increment[6]; /* - */
  double *stress0[6];   /* Pa, the stresses restored before each call */
  double *stress[6];    /* Pa, updated in place */
  double *density;      /* kg/m^3 */
  double *plastic;      /* Mohr-Coulomb state */
} batch_data;

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Deterministic uniform numbers in [0, 1). */
static double uniform(unsigned long long *state) {
  *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*state >> 11) * (1.0 / 9007199254740992.0);
}

static void fill(batch_data *b, int plastic, int three_d) {
  unsigned long long seed = 42u + (unsigned)(2 * plastic + three_d);
  double k0 = 0.3 / 0.7;
  for (size_t i = 0; i < b->count; i++) {
    /* Vertical stress of a 5 m column of 2000 kg/m^3 soil. */
    double depth = 0.05 + 4.95 * uniform(&seed); /* m */
    double vertical = -2000.0 * 9.81 * depth;    /* Pa */
    double shear = 0.05 * vertical * (2.0 * uniform(&seed) - 1.0);
    double s[6] = {k0 * vertical, vertical, k0 * vertical, shear, 0.0, 0.0};
    if (three_d) {
      s[GM_YZ] = 0.5 * shear * uniform(&seed);
      s[GM_ZX] = -0.5 * shear * uniform(&seed);
    }
    /* Strain increments of one step (about 1e-7); the plastic batch adds
     * a deviatoric stretch of 1e-3 that takes every trial past yield. */
    double e[6];
    for (int c = 0; c < 6; c++)
      e[c] = 1e-7 * (2.0 * uniform(&seed) - 1.0);
    if (!three_d)
      e[GM_YZ] = e[GM_ZX] = 0.0;
    if (plastic) {
      e[GM_XX] += 1e-3;
      e[GM_YY] -= 1e-3;
    }
    for (int c = 0; c < 6; c++) {
      b->increment[c][i] = e[c];
      b->stress0[c][i] = s[c];
    }
    b->density[i] = 2000.0;
    b->plastic[i] = 0.0;
  }
}

static gm_material_batch make_batch(batch_data *b) {
  gm_material_batch batch;
  memset(&batch, 0, sizeof batch);
  batch.struct_size = sizeof batch;
  batch.count = b->count;
  batch.geometry = GM_GEOMETRY_PLANE_STRAIN;
  batch.dt = 1e-4; /* s */
  for (int c = 0; c < 6; c++) {
    batch.strain_increment[c] = b->increment[c];
    batch.stress[c] = b->stress[c];
  }
  batch.density = b->density;
  batch.state = &b->plastic;
  batch.state_count = 1;
  return batch;
}

static void restore(batch_data *b) {
  for (int c = 0; c < 6; c++)
    memcpy(b->stress[c], b->stress0[c], b->count * sizeof(double));
}

static int compare(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv) {
  size_t points = 100000;
  int reps = 201;
  const char *only = NULL; /* run only this case */
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--points") && i + 1 < argc)
      points = (size_t)strtod(argv[++i], NULL);
    else if (!strcmp(argv[i], "--reps") && i + 1 < argc)
      reps = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--case") && i + 1 < argc)
      only = argv[++i];
    else {
      fprintf(stderr, "usage: %s [--points N] [--reps R] [--case NAME]\n",
              argv[0]);
      return 2;
    }
  }
  if (points < 1 || reps < 1) {
    fprintf(stderr, "material-cost: --points and --reps must be >= 1\n");
    return 2;
  }
  batch_data b;
  b.count = points;
  for (int c = 0; c < 6; c++) {
    b.increment[c] = malloc(points * sizeof(double));
    b.stress0[c] = malloc(points * sizeof(double));
    b.stress[c] = malloc(points * sizeof(double));
    if (!b.increment[c] || !b.stress0[c] || !b.stress[c])
      return 1;
  }
  b.density = malloc(points * sizeof(double));
  b.plastic = malloc(points * sizeof(double));
  double *mc_time = malloc((size_t)reps * sizeof(double));
  double *el_time = malloc((size_t)reps * sizeof(double));
  if (!b.density || !b.plastic || !mc_time || !el_time)
    return 1;

  gm_mohr_coulomb_def mc = gm_mohr_coulomb_def_default();
  mc.youngs_modulus = 1e7; /* Pa, as in granmpm-bench */
  mc.poisson_ratio = 0.3;
  mc.friction_angle = 30.0 * 3.14159265358979323846 / 180.0;
  mc.dilation_angle = 0.0;
  mc.bagnold_viscosity = 0.0;
  gm_elastic_def el = gm_elastic_def_default();
  el.youngs_modulus = mc.youngs_modulus;
  el.poisson_ratio = mc.poisson_ratio;

  static const char *names[4] = {"plane-elastic", "plane-plastic", "3d-elastic",
                                 "3d-plastic"};
  printf("case,points,reps,mohr_coulomb_ns,elastic_ns,ratio,plastic_"
         "fraction,mohr_coulomb_min_ns,elastic_min_ns,min_ratio\n");
  for (int kind = 0; kind < 4; kind++) {
    if (only && strcmp(only, names[kind]))
      continue;
    int plastic = kind % 2, three_d = kind / 2;
    fill(&b, plastic, three_d);
    gm_material_batch batch = make_batch(&b);
    char message[256];
    size_t yielded = 0;
    for (int r = 0; r < reps; r++) {
      restore(&b);
      double t0 = now_s();
      if (gm_mohr_coulomb_update(&batch, &mc, message, sizeof message) != 0) {
        fprintf(stderr, "material-cost: %s\n", message);
        return 1;
      }
      double t1 = now_s();
      if (r == 0) {
        /* Points the model changed against the elastic answer. */
        for (size_t i = 0; i < points; i++)
          yielded += b.plastic[i] > 0.0;
      }
      restore(&b);
      double t2 = now_s();
      gm_elastic_update(&batch, &el, message, sizeof message);
      double t3 = now_s();
      mc_time[r] = t1 - t0;
      el_time[r] = t3 - t2;
    }
    qsort(mc_time, (size_t)reps, sizeof(double), compare);
    qsort(el_time, (size_t)reps, sizeof(double), compare);
    double mc_ns = 1e9 * mc_time[reps / 2] / (double)points;
    double el_ns = 1e9 * el_time[reps / 2] / (double)points;
    double mc_min_ns = 1e9 * mc_time[0] / (double)points;
    double el_min_ns = 1e9 * el_time[0] / (double)points;
    printf("%s,%zu,%d,%.2f,%.2f,%.2f,%.3f,%.2f,%.2f,%.2f\n", names[kind],
           points, reps, mc_ns, el_ns, mc_ns / el_ns,
           (double)yielded / (double)points, mc_min_ns, el_min_ns,
           mc_min_ns / el_min_ns);
  }
  for (int c = 0; c < 6; c++) {
    free(b.increment[c]);
    free(b.stress0[c]);
    free(b.stress[c]);
  }
  free(b.density);
  free(b.plastic);
  free(mc_time);
  free(el_time);
  return 0;
}
