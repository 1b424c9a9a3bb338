/*
 * triad.c - the machine's memory bandwidth, STREAM-style: the triad
 * a[i] = b[i] + s * c[i] over three arrays much larger than the last-level
 * cache, on 1 and 2 threads (more with --threads), best of N repetitions.
 * It is the yardstick of the memory bound in docs/performance.md: a step
 * that reads and writes B bytes per point cannot take less than
 * B / (triad bandwidth) per point.
 *
 * Bytes are counted as STREAM counts them: 24 per element (two 8-byte
 * reads, one 8-byte write). An ordinary store first reads the line it
 * writes (write-allocate), so the memory bus carries 32 bytes per element;
 * the GB/s printed are the STREAM ones (24 bytes), and the per-point byte
 * counts of docs/performance.md follow the same convention (a written
 * array counts once).
 *
 * Each thread owns a contiguous slice of every array and touches it first
 * (so its pages sit on that thread's memory node); one repetition is a
 * barrier, every thread's slice, a barrier; its time is the slowest
 * thread's. The best repetition is reported, as STREAM does: the others
 * measure what else the machine was doing.
 *
 * Usage: granmpm-triad [--mib M] [--reps N] [--threads "T ..."]
 *   --mib M        MiB per array (default 256: 8x a 32 MiB L3)
 *   --reps N       repetitions per thread count (default 10)
 *   --threads "T"  thread counts (default "1 2")
 * Prints CSV: threads,array_mib,reps,best_seconds,best_gb_per_s,
 * median_gb_per_s (GB = 1e9 bytes).
 *
 * SPDX-License-Identifier: BSD-2-Clause
 */
#define _POSIX_C_SOURCE 200809L

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { MAX_THREADS = 64, MAX_REPS = 1000 };

typedef struct triad_job {
  double *a;
  const double *b;
  const double *c;
  size_t begin, end;
  int reps;
  double *seconds; /* per repetition, written by thread 0 */
} triad_job;

static pthread_barrier_t barrier;

static double now_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *run_slice(void *context) {
  triad_job *job = context;
  double *a = job->a;
  const double *b = job->b, *c = job->c;
  const double scalar = 3.0;
  /* First touch by the owning thread. */
  for (size_t i = job->begin; i < job->end; i++) {
    a[i] = 0.0;
    ((double *)b)[i] = 1.0;
    ((double *)c)[i] = 2.0;
  }
  for (int r = 0; r < job->reps; r++) {
    pthread_barrier_wait(&barrier);
    double start = now_seconds();
    for (size_t i = job->begin; i < job->end; i++)
      a[i] = b[i] + scalar * c[i];
    pthread_barrier_wait(&barrier);
    if (job->seconds) /* thread 0: after the barrier every slice is done */
      job->seconds[r] = now_seconds() - start;
  }
  return NULL;
}

static int compare_doubles(const void *x, const void *y) {
  double l = *(const double *)x, r = *(const double *)y;
  return (l > r) - (l < r);
}

/* Runs reps repetitions on `threads` threads; returns 0 on success. */
static int measure(double *a, double *b, double *c, size_t count, int threads,
                   int reps, double *seconds) {
  pthread_t thread[MAX_THREADS];
  triad_job job[MAX_THREADS];
  if (pthread_barrier_init(&barrier, NULL, (unsigned)threads) != 0)
    return 1;
  for (int t = 0; t < threads; t++) {
    job[t] = (triad_job){a,
                         b,
                         c,
                         count * (size_t)t / (size_t)threads,
                         count * (size_t)(t + 1) / (size_t)threads,
                         reps,
                         t == 0 ? seconds : NULL};
    if (t > 0 && pthread_create(&thread[t], NULL, run_slice, &job[t]) != 0)
      return 1;
  }
  run_slice(&job[0]);
  for (int t = 1; t < threads; t++)
    pthread_join(thread[t], NULL);
  pthread_barrier_destroy(&barrier);
  return 0;
}

int main(int argc, char **argv) {
  size_t mib = 256;
  int reps = 10;
  const char *thread_list = "1 2";
  for (int k = 1; k < argc; k++) {
    if (strcmp(argv[k], "--mib") == 0 && k + 1 < argc)
      mib = (size_t)strtoul(argv[++k], NULL, 10);
    else if (strcmp(argv[k], "--reps") == 0 && k + 1 < argc)
      reps = atoi(argv[++k]);
    else if (strcmp(argv[k], "--threads") == 0 && k + 1 < argc)
      thread_list = argv[++k];
    else {
      fprintf(stderr,
              "usage: granmpm-triad [--mib M] [--reps N] [--threads \"T "
              "...\"]\n");
      return 2;
    }
  }
  if (mib == 0 || reps < 1 || reps > MAX_REPS) {
    fprintf(stderr, "granmpm-triad: --mib must be > 0, --reps 1..%d\n",
            MAX_REPS);
    return 2;
  }
  size_t count = mib * 1024 * 1024 / sizeof(double);
  double *a = malloc(count * sizeof *a), *b = malloc(count * sizeof *b),
         *c = malloc(count * sizeof *c);
  double *seconds = malloc((size_t)reps * sizeof *seconds);
  if (!a || !b || !c || !seconds) {
    fprintf(stderr, "granmpm-triad: out of memory for 3 x %zu MiB\n", mib);
    return 1;
  }
  printf("threads,array_mib,reps,best_seconds,best_gb_per_s,"
         "median_gb_per_s\n");
  const double bytes = 24.0 * (double)count; /* STREAM convention */
  char *list = malloc(strlen(thread_list) + 1);
  if (!list)
    return 1;
  strcpy(list, thread_list);
  int status = 0;
  for (char *token = strtok(list, " ,"); token; token = strtok(NULL, " ,")) {
    int threads = atoi(token);
    if (threads < 1 || threads > MAX_THREADS) {
      fprintf(stderr, "granmpm-triad: thread count '%s' not in 1..%d\n", token,
              MAX_THREADS);
      status = 2;
      break;
    }
    if (measure(a, b, c, count, threads, reps, seconds) != 0) {
      fprintf(stderr, "granmpm-triad: could not start %d threads\n", threads);
      status = 1;
      break;
    }
    qsort(seconds, (size_t)reps, sizeof *seconds, compare_doubles);
    double best = seconds[0], median = seconds[reps / 2];
    printf("%d,%zu,%d,%.6f,%.2f,%.2f\n", threads, mib, reps, best,
           1e-9 * bytes / best, 1e-9 * bytes / median);
    fflush(stdout);
  }
  /* Keeps the stores observable (a compiler may not drop the loops). */
  double check = a[count / 3] + a[count - 1];
  if (status == 0 && check != 2.0 * (1.0 + 3.0 * 2.0))
    fprintf(stderr, "granmpm-triad: unexpected a[] = %g\n", check / 2.0);
  free(list);
  free(seconds);
  free(a);
  free(b);
  free(c);
  return status;
}
