/* Native backend: the kernels compiled as C, one pthread per work-group, local size 1. */
#include <pthread.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "device/compat.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"

/* Fault injection for tests: the thread of this work-group fails to start (-1: none). */
int lt__native_fail_group = -1;
int lt__native_stall_group = -1;

_Thread_local int lt__native_group_id;
_Thread_local int lt__native_num_groups = 1;

/* Work-groups start together: each thread waits at the gate until every one exists, so that
 * when one cannot be created the others return without running a persistent kernel that
 * would wait for it forever. */
typedef struct gate {
  pthread_mutex_t lock;
  pthread_cond_t opened;
  int state; /* 0 closed, 1 open (run), -1 open (return at once) */
} gate;

typedef struct worker {
  pthread_t thread;
  int group;
  int groups;
  void (*fn)(void *arg);
  void *arg;
  gate *gate;
} worker;

static int pass_gate(gate *g) {
  pthread_mutex_lock(&g->lock);
  while (g->state == 0) pthread_cond_wait(&g->opened, &g->lock);
  int state = g->state;
  pthread_mutex_unlock(&g->lock);
  return state;
}

static void open_gate(gate *g, int state) {
  pthread_mutex_lock(&g->lock);
  g->state = state;
  pthread_cond_broadcast(&g->opened);
  pthread_mutex_unlock(&g->lock);
}

static void *worker_main(void *p) {
  worker *w = p;
  if (pass_gate(w->gate) < 0) return NULL;
  lt__native_group_id = w->group;
  lt__native_num_groups = w->groups;
  w->fn(w->arg);
  return NULL;
}

int lt__native_threads(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

/* The watchdog of a persistent launch: a thread that reads the pool's progress counter every
 * 50 ms and, after `seconds` without a change while the work-groups are still running, writes
 * the stall error that every work-group's next decision obeys. It tells a group that stopped
 * (or hangs inside a chunk) from one that is merely slow by time, which polls cannot. */
typedef struct watchdog {
  lt__native_watch watch;
  pthread_mutex_t lock;
  pthread_cond_t finished; /* signalled when every work-group has returned */
  int done;
  pthread_t thread;
} watchdog;

static void *watch_main(void *p) {
  watchdog *d = p;
  int last = __atomic_load_n(d->watch.progress, __ATOMIC_SEQ_CST);
  double still = 0.0;
  pthread_mutex_lock(&d->lock);
  while (!d->done) {
    /* Wait 50 ms, or less when the launch ends (the launch never waits for the watchdog). */
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_nsec += 50000000;
    if (until.tv_nsec >= 1000000000) until.tv_sec++, until.tv_nsec -= 1000000000;
    pthread_cond_timedwait(&d->finished, &d->lock, &until);
    if (d->done) break;
    int now = __atomic_load_n(d->watch.progress, __ATOMIC_SEQ_CST);
    still = now == last ? still + 0.05 : 0.0;
    last = now;
    if (still > d->watch.seconds) {
      int ok = 0;
      __atomic_compare_exchange_n(d->watch.error, &ok, d->watch.stall_error, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST);
      break;
    }
  }
  pthread_mutex_unlock(&d->lock);
  return NULL;
}

lt_status lt__native_run_watched(int groups, void (*fn)(void *arg), void *arg, const lt__native_watch *watch) {
  if (!watch) return lt__native_run(groups, fn, arg);
  watchdog d = {*watch, PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0, 0};
  int watching = pthread_create(&d.thread, NULL, watch_main, &d) == 0;
  lt_status status = lt__native_run(groups, fn, arg);
  pthread_mutex_lock(&d.lock);
  d.done = 1;
  pthread_cond_signal(&d.finished);
  pthread_mutex_unlock(&d.lock);
  if (watching) pthread_join(d.thread, NULL);
  return status;
}

lt_status lt__native_run(int groups, void (*fn)(void *arg), void *arg) {
  if (groups < 1 || groups > LT__MAX_NATIVE_GROUPS)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "native launch of %d work-groups (1 to %d)", groups, LT__MAX_NATIVE_GROUPS);
  worker *workers = calloc(groups, sizeof *workers);
  if (!workers) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %d native work-groups", groups);
  gate g = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0};

  /* Work-group 0 runs on the calling thread; the others get one thread each, and all start
   * only once every thread exists. */
  int started = 1;
  lt_status status = LT_OK;
  for (int gr = 0; gr < groups; gr++) workers[gr] = (worker){0, gr, groups, fn, arg, &g};
  for (int gr = 1; gr < groups; gr++, started++)
    if (gr == lt__native_fail_group || pthread_create(&workers[gr].thread, NULL, worker_main, &workers[gr]) != 0) {
      status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "could not start native work-group %d of %d (thread limit or memory)",
                        gr, groups);
      break;
    }
  open_gate(&g, status == LT_OK ? 1 : -1);
  if (status == LT_OK) worker_main(&workers[0]);
  for (int gr = 1; gr < started; gr++) pthread_join(workers[gr].thread, NULL);
  free(workers);
  return status;
}
