/* Native backend: the kernels compiled as C, one pthread per work-group, local size 1. */
#include <pthread.h>
#include <stdlib.h>
#include <unistd.h>

#include "device/compat.h"
#include "runtime/context_internal.h"
#include "runtime/error.h"

_Thread_local int lt__native_group_id;
_Thread_local int lt__native_num_groups = 1;

typedef struct worker {
  pthread_t thread;
  int group;
  int groups;
  void (*fn)(void *arg);
  void *arg;
} worker;

static void *worker_main(void *p) {
  worker *w = p;
  lt__native_group_id = w->group;
  lt__native_num_groups = w->groups;
  w->fn(w->arg);
  return NULL;
}

int lt__native_threads(void) {
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (int)n : 1;
}

lt_status lt__native_run(int groups, void (*fn)(void *arg), void *arg) {
  if (groups < 1) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "native launch of %d work-groups", groups);
  worker *workers = calloc(groups, sizeof *workers);
  if (!workers) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for %d native work-groups", groups);

  /* Work-group 0 runs on the calling thread; the others get one thread each. */
  int started = 1;
  lt_status status = LT_OK;
  for (int g = 0; g < groups; g++) workers[g] = (worker){0, g, groups, fn, arg};
  for (int g = 1; g < groups; g++, started++)
    if (pthread_create(&workers[g].thread, NULL, worker_main, &workers[g]) != 0) {
      status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "could not start native work-group %d", g);
      break;
    }
  if (status == LT_OK) worker_main(&workers[0]);
  for (int g = 1; g < started; g++) pthread_join(workers[g].thread, NULL);
  free(workers);
  return status;
}
