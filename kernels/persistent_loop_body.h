/* The persistent loop's body, instantiated by include: see kernels/persistent_loop.h for the
 * hooks a workload defines first. No include guard, on purpose. */
#include "kernels/persistent_loop.h"

#define LT_LOOP_CHUNK_CASE(kind, chunk_fn, end_fn, context) \
  case kind:                                                \
    chunk_fn(context, slot, chunk, lid, lsize);             \
    break;
#define LT_LOOP_END_CASE(kind, chunk_fn, end_fn, context) \
  case kind:                                              \
    end_fn(context, slot);                                \
    break;

LT_DEVICE void LT_LOOP_NAME(const LT_LOOP_ARGS *a, LT_LOCAL lt_loop_shared *sh) {
  int lid = lt_local_id(), lsize = lt_local_size();
  const lt_pool *pool = LT_LOOP_POOL(a);
  lt_i32 count = LT_LOOP_ITEM_COUNT(a);
  LT_LOOP_ITEM q = {0};
  lt_trace_counters c = {0, 0};
  lt_i32 item = -1, next_item = 0, end_item = 0; /* this work-item's items: item, then next..end */
  int running = 1;
  lt_pool_worker worker = lt_pool_worker_new();
#ifndef __OPENCL_VERSION__
  if (lt_group_id() == lt__native_stall_group) return; /* fault injection: a group that stops */
#endif
  while (running) {
    /* Advance (or restart) this work-item's items until one waits or they run out. */
    while (item >= 0 && LT_LOOP_ADVANCE(a, &q, &c)) {
      LT_LOOP_FINISH(a, item, &q);
      item = -1;
      if (next_item < end_item) {
        item = next_item;
        next_item += lsize;
        LT_LOOP_START(a, &q, item, &c);
      }
    }
    sh->pending[lid] = item >= 0;
    lt_barrier();

    /* Work-item 0 decides for the group: new items, building, or quitting. */
    if (lid == 0) {
      int waiting = 0;
      for (int l = 0; l < lsize; l++) waiting |= sh->pending[l];
      lt_pool_round r = lt_pool_decide(pool, &worker, waiting, LT_LOOP_BUILD(a),
                                       lsize * LT_LOOP_ITEMS_PER_WORK_ITEM, count, LT_LOOP_MAX_IDLE(a));
      if (r.slot >= 0) lt_pool_log_start(pool, r.slot, r.chunk);
      sh->round = r;
    }
    lt_barrier();
    running = !sh->round.quit;
    lt_i32 batch = sh->round.batch, slot = sh->round.slot, chunk = sh->round.chunk;

    /* New items: every lsize-th of the batch for each work-item, started at the top. */
    if (running && batch >= 0) {
      lt_i32 batch_end = batch + lsize * LT_LOOP_ITEMS_PER_WORK_ITEM;
      end_item = batch_end < count ? batch_end : count;
      item = batch + lid < end_item ? batch + lid : -1;
      next_item = batch + lid + lsize;
      if (item >= 0) LT_LOOP_START(a, &q, item, &c);
    }

    /* Building: the group works the chunk together; work-item 0 ends the phase. */
    int building = running && batch < 0 && slot >= 0;
    lt_i32 kind = building ? pool->tasks[slot].kind : -1;
    if (building) {
      switch (kind) { LT_LOOP_TASK_KINDS(LT_LOOP_CHUNK_CASE) default: lt_pool_fail(pool, LT_POOL_ERROR_KIND); }
    }
    lt_barrier();
    if (building && lid == 0 && lt_pool_finish_chunk(pool, slot)) {
      switch (kind) { LT_LOOP_TASK_KINDS(LT_LOOP_END_CASE) default: lt_pool_fail(pool, LT_POOL_ERROR_KIND); }
    }
    lt_barrier();
  }
  LT_LOOP_FLUSH(a, &c);
}

#undef LT_LOOP_CHUNK_CASE
#undef LT_LOOP_END_CASE
#undef LT_LOOP_NAME
#undef LT_LOOP_ARGS
#undef LT_LOOP_POOL
#undef LT_LOOP_ITEM
#undef LT_LOOP_ITEMS_PER_WORK_ITEM
#undef LT_LOOP_ITEM_COUNT
#undef LT_LOOP_START
#undef LT_LOOP_ADVANCE
#undef LT_LOOP_FINISH
#undef LT_LOOP_BUILD
#undef LT_LOOP_MAX_IDLE
#undef LT_LOOP_FLUSH
#undef LT_LOOP_TASK_KINDS
