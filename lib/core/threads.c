/*
 * threads.c - built-in worker pool. Workers spin briefly on a generation
 * counter before sleeping on a condition variable: a step runs about ten
 * short parallel phases, and waking a sleeping thread costs tens of
 * microseconds, which would dominate small scenes.
 */
/* clock_gettime() is POSIX, not C11. */
#define _POSIX_C_SOURCE 200809L

#include "core/core.h"

#include "core/threads.h"

#include <time.h>

enum { SPIN_ROUNDS = 200000 };

typedef struct worker_arg {
  gm_pool *pool;
  int worker;
  unsigned start_generation; /* generation when the pool started */
} worker_arg;

static void run_share(gm_pool *pool, int worker) {
  size_t n = pool->item_count;
  size_t w = (size_t)pool->worker_count;
  size_t begin = n * (size_t)worker / w;
  size_t end = n * ((size_t)worker + 1) / w;
  if (begin < end)
    pool->fn(pool->context, begin, end, worker);
}

static void *worker_main(void *argument) {
  worker_arg *arg = argument;
  gm_pool *pool = arg->pool;
  int worker = arg->worker;
  /* Not the current value: a loop may already have been posted before this
   * thread got to run, and it must not be missed. */
  unsigned seen = arg->start_generation;
  gm_free(arg);
  for (;;) {
    unsigned now = seen;
    for (int spin = 0; spin < SPIN_ROUNDS; spin++) {
      now = atomic_load_explicit(&pool->generation, memory_order_acquire);
      if (now != seen)
        break;
    }
    if (now == seen) {
      pthread_mutex_lock(&pool->mutex);
      while (!atomic_load(&pool->stopping) &&
             (now = atomic_load(&pool->generation)) == seen)
        pthread_cond_wait(&pool->wake, &pool->mutex);
      pthread_mutex_unlock(&pool->mutex);
    }
    if (atomic_load(&pool->stopping))
      return NULL;
    seen = now;
    run_share(pool, worker);
    if (atomic_fetch_sub_explicit(&pool->remaining, 1, memory_order_acq_rel) ==
        1) {
      pthread_mutex_lock(&pool->mutex);
      pthread_cond_signal(&pool->done);
      pthread_mutex_unlock(&pool->mutex);
    }
  }
}

gm_status gm_pool_start(gm_pool *pool, int worker_count,
                        gm_enqueue_task_fn *enqueue_task,
                        gm_finish_task_fn *finish_task, void *task_user) {
  pool->worker_count = worker_count;
  pool->enqueue_task = enqueue_task;
  pool->finish_task = finish_task;
  pool->task_user = task_user;
  pool->threads = NULL;
  atomic_init(&pool->stopping, false);
  pool->started = false;
  atomic_init(&pool->generation, 0);
  atomic_init(&pool->remaining, 0);
  if (enqueue_task || worker_count <= 1)
    return GM_OK;
  if (pthread_mutex_init(&pool->mutex, NULL) != 0)
    return GM_ERR_NO_MEMORY;
  pthread_cond_init(&pool->wake, NULL);
  pthread_cond_init(&pool->done, NULL);
  pool->threads = gm_calloc((size_t)worker_count, sizeof(pthread_t));
  if (!pool->threads)
    return GM_ERR_NO_MEMORY;
  pool->started = true;
  for (int w = 1; w < worker_count; w++) {
    worker_arg *arg = gm_alloc(sizeof *arg);
    if (!arg) {
      pool->worker_count = w;
      gm_pool_stop(pool);
      return GM_ERR_NO_MEMORY;
    }
    arg->pool = pool;
    arg->worker = w;
    arg->start_generation = 0;
    if (pthread_create(&pool->threads[w], NULL, worker_main, arg) != 0) {
      gm_free(arg);
      pool->worker_count = w;
      gm_pool_stop(pool);
      return GM_ERR_NO_MEMORY;
    }
  }
  return GM_OK;
}

void gm_pool_stop(gm_pool *pool) {
  if (!pool->started) {
    gm_free(pool->threads);
    pool->threads = NULL;
    return;
  }
  pthread_mutex_lock(&pool->mutex);
  atomic_store(&pool->stopping, true);
  atomic_fetch_add(&pool->generation, 1);
  pthread_cond_broadcast(&pool->wake);
  pthread_mutex_unlock(&pool->mutex);
  for (int w = 1; w < pool->worker_count; w++)
    pthread_join(pool->threads[w], NULL);
  pthread_cond_destroy(&pool->wake);
  pthread_cond_destroy(&pool->done);
  pthread_mutex_destroy(&pool->mutex);
  gm_free(pool->threads);
  pool->threads = NULL;
  pool->started = false;
}

/* Adapter from the user task system's int ranges to gm_parallel_fn. */
typedef struct task_adapter {
  gm_parallel_fn *fn;
  void *context;
} task_adapter;

static void task_trampoline(int start, int end, int worker, void *context) {
  task_adapter *adapter = context;
  adapter->fn(adapter->context, (size_t)start, (size_t)end, worker);
}

void gm_parallel_for(gm_pool *pool, size_t item_count, gm_parallel_fn *fn,
                     void *context) {
  if (item_count == 0)
    return;
  if (pool->enqueue_task) {
    task_adapter adapter = {fn, context};
    /* Point counts are capped below INT_MAX at insertion. */
    int min_range = item_count > 4096 ? 256 : 1;
    void *handle = pool->enqueue_task(task_trampoline, (int)item_count,
                                      min_range, &adapter, pool->task_user);
    if (handle)
      pool->finish_task(handle, pool->task_user);
    return;
  }
  if (!pool->started || item_count < (size_t)pool->worker_count) {
    fn(context, 0, item_count, 0);
    return;
  }
  pool->fn = fn;
  pool->context = context;
  pool->item_count = item_count;
  atomic_store(&pool->remaining, pool->worker_count - 1);
  pthread_mutex_lock(&pool->mutex);
  atomic_fetch_add_explicit(&pool->generation, 1, memory_order_release);
  pthread_cond_broadcast(&pool->wake);
  pthread_mutex_unlock(&pool->mutex);
  run_share(pool, 0);
  for (int spin = 0; spin < SPIN_ROUNDS; spin++) {
    if (atomic_load_explicit(&pool->remaining, memory_order_acquire) == 0)
      return;
  }
  pthread_mutex_lock(&pool->mutex);
  while (atomic_load(&pool->remaining) != 0)
    pthread_cond_wait(&pool->done, &pool->mutex);
  pthread_mutex_unlock(&pool->mutex);
}

double gm_monotonic_seconds(void) {
  struct timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}
