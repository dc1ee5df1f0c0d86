/* How a host builder runs its parallel loops (the executor of madmann91/bvh): the caller says how
 * many workers and how to start them, so that the same builder runs serially in a test and on
 * every work-group's thread in production. Builders include this; runtime/ fills it in. */
#ifndef LT_EXECUTOR_H
#define LT_EXECUTOR_H

#include "lazytrace.h"

typedef struct lt__executor {
  int workers; /* how many threads run fn at once; 1 or less runs everything on the caller */
  /* Runs fn(arg) on `workers` threads at once and returns when all have returned; nonzero if
   * they could not be started, in which case fn ran on none of them. */
  lt_status (*run)(int workers, void (*fn)(void *arg), void *arg);
} lt__executor;

/* Items claimed one at a time from a shared counter by every worker of the executor. */
typedef struct lt__executor_loop {
  void (*body)(void *ctx, int item);
  void *ctx;
  int items;
  int next; /* the next item to claim */
} lt__executor_loop;

static inline void lt__executor_loop_worker(void *p) {
  lt__executor_loop *l = p;
  for (int i; (i = __atomic_fetch_add(&l->next, 1, __ATOMIC_RELAXED)) < l->items;) l->body(l->ctx, i);
}

/* Runs body(ctx, i) for every i in [0, items), on the executor's workers when there are several
 * (or on the caller alone when they cannot be started; ex NULL: the caller). Starting and joining
 * the threads orders their writes before what follows. */
static inline void lt__executor_for(const lt__executor *ex, int items, void (*body)(void *ctx, int item), void *ctx) {
  lt__executor_loop l = {body, ctx, items, 0};
  int workers = ex && ex->run ? (ex->workers < items ? ex->workers : items) : 1;
  if (workers > 1 && ex->run(workers, lt__executor_loop_worker, &l) == LT_OK) return;
  lt__executor_loop_worker(&l);
}

#endif
