/* How a structure built through the task pool traces a batch: one launch builds what the
 * rays need while tracing them (time to image); a full pool or heap starts the structure again
 * with more room and traces again; with statistics asked for, a second launch traces the same
 * rays on the tree as built, which is the trace time, and build time is the difference (the
 * paper's convention). The BVH and the kd-tree share it; each says how it launches and grows. */
#ifndef LT_ONDEMAND_TRACE_H
#define LT_ONDEMAND_TRACE_H

#include "runtime/structure_internal.h"

typedef struct lt__ondemand_ops {
  /* One launch over the batch; speculate: work-groups out of rays build unrequested nodes. */
  lt_status (*launch)(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, int speculate,
                      lt_stats *stats);
  /* Whether what filled up may still grow. */
  int (*may_grow)(const lt_structure *s);
  /* Starts the structure again with more room after `status` (LT_ERROR_CAPACITY). */
  lt_status (*retry)(lt_structure *s, lt_stats *stats, lt_status status);
  /* Optional: told before (1) and after (0) the re-trace for statistics, which must not
   * change the structure in a way the next batch's time would then miss. */
  void (*retracing)(lt_structure *s, int on);
} lt__ondemand_ops;

/* Traces a batch on demand (requested or speculative build), as said above. */
lt_status lt__ondemand_trace(lt_structure *s, const lt__ondemand_ops *ops, const lt_ray *rays, int count, int flags,
                             lt_hit *hits, lt_stats *stats);

#endif
