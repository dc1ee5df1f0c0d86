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

#endif
