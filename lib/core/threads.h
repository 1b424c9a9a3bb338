/*
 * threads.h - the built-in worker pool and the parallel-for used by every
 * step phase. A phase's result never depends on how its items are split
 * between workers, so a user task system may split them any way it likes.
 */
#ifndef GM_THREADS_H
#define GM_THREADS_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>

#include "granmpm.h"

/* Runs items [begin, end) on worker `worker` (0 .. worker_count-1). */
typedef void gm_parallel_fn(void *context, size_t begin, size_t end,
                            int worker);

typedef struct gm_pool {
  int worker_count;
  pthread_t *threads;
  pthread_mutex_t mutex;
  pthread_cond_t wake;
  pthread_cond_t done;
  atomic_uint generation; /* bumped once per parallel loop */
  atomic_int remaining;   /* workers still busy in this loop */
  atomic_bool stopping;
  bool started;
  /* The loop being run. */
  gm_parallel_fn *fn;
  void *context;
  size_t item_count;
  /* A user task system replaces the threads when set. */
  gm_enqueue_task_fn *enqueue_task;
  gm_finish_task_fn *finish_task;
  void *task_user;
} gm_pool;

/* Starts worker_count-1 threads (the caller is worker 0). */
gm_status gm_pool_start(gm_pool *pool, int worker_count,
                        gm_enqueue_task_fn *enqueue_task,
                        gm_finish_task_fn *finish_task, void *task_user);
void gm_pool_stop(gm_pool *pool);
/* Runs fn over [0, item_count) split in contiguous ranges, one per worker,
 * and returns when all are done. */
void gm_parallel_for(gm_pool *pool, size_t item_count, gm_parallel_fn *fn,
                     void *context);

/* Seconds on the monotonic clock (for the profiling summaries). */
double gm_monotonic_seconds(void);

#endif
