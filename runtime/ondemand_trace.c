/* Tracing through a structure built on demand (see ondemand_trace.h). */
#include "runtime/ondemand_trace.h"

#include "runtime/stats_internal.h"

lt_status lt__ondemand_trace(lt_structure *s, const lt__ondemand_ops *ops, const lt_ray *rays, int count, int flags,
                             lt_hit *hits, lt_stats *stats) {
  int speculate = s->config.build == LT_BUILD_SPECULATIVE;
  double begin = lt_now_ms();
  lt_status status = ops->launch(s, rays, count, flags, hits, speculate, stats);
  while (status == LT_ERROR_CAPACITY && ops->may_grow(s)) {
    status = ops->retry(s, stats, status);
    begin = lt_now_ms();
    if (!status) status = ops->launch(s, rays, count, flags, hits, speculate, stats);
  }
  double total = lt_now_ms() - begin;
  if (status || !stats) return status;
  lt_stats *again;
  if ((status = lt_stats_create(&again))) return status;
  if (ops->retracing) ops->retracing(s, 1);
  double retrace_start = lt_now_ms();
  status = ops->launch(s, rays, count, flags, hits, 0, again);
  double retrace = lt_now_ms() - retrace_start;
  if (ops->retracing) ops->retracing(s, 0);
  lt_stats_destroy(again);
  lt__stats_add(stats, LT_STAT_TRACE_MS, retrace);
  lt__stats_add(stats, LT_STAT_BUILD_MS, total > retrace ? total - retrace : 0.0);
  return status;
}
