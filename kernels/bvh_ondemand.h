/* The persistent loop of the on-demand BVH (the on-demand paper, Algorithm 1): every
 * work-group traces rays and, when one of its rays waits for an unbuilt node (or it has no
 * rays left), builds nodes from the task pool; a restart re-checks the waiting rays after each
 * chunk and after each search that found nothing. Barriers sit in straight-line code only (see
 * kernels/lazy_sort.h for why). */
#ifndef LT_KERNEL_BVH_ONDEMAND_H
#define LT_KERNEL_BVH_ONDEMAND_H

#include "traversal/bvh_ondemand.h"

/* Rays a work-item takes at a time: one shared counter update per 64 rays, not per ray. */
#define LT_OD_RAYS_PER_ITEM 64

#ifndef LT_MAX_LOCAL_SIZE
#define LT_MAX_LOCAL_SIZE 256
#endif

typedef struct lt_od_trace_args {
  lt_bvh_build build;
  LT_GLOBAL const float *rays; /* 8 floats a ray */
  LT_GLOBAL lt_hit_record *hits;
  lt_i32 ray_count, any_hit;
  lt_i32 max_idle_polls;
  lt_i32 speculate; /* whether work-groups out of rays build what nobody asked for */
} lt_od_trace_args;

typedef struct lt_od_shared {
  lt_pool_round round;
  lt_i32 pending[LT_MAX_LOCAL_SIZE];
} lt_od_shared;

LT_DEVICE void lt_od_finish_ray(const lt_od_trace_args *a, lt_i32 i, lt_od_ray *q) {
  lt_hit_record hit = q->hit;
  if (hit.prim < 0) hit.t = INFINITY, hit.u = hit.v = 0.0f;
  a->hits[i] = hit;
}

LT_DEVICE void lt_od_run(const lt_od_trace_args *a, LT_LOCAL lt_od_shared *sh) {
  int lid = lt_local_id(), lsize = lt_local_size();
  const lt_bvh_build *b = &a->build;
  const lt_pool *pool = &b->pool;
  lt_od_ray q;
  q.r = lt_ray_prepare(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f);
  q.hit.t = q.hit.u = q.hit.v = 0.0f, q.hit.prim = -1, q.sp = 0, q.cur = -1, q.wait = -1;
  lt_trace_counters c = {0, 0};
  lt_i32 item = -1, next_item = 0, end_item = 0; /* this work-item's rays: item, then next..end */
  int running = 1;
  lt_pool_worker worker = lt_pool_worker_new();
  while (running) {
    /* Trace (or restart) this work-item's rays until one waits or they run out. */
    while (item >= 0 && lt_od_trace(b, &q, a->any_hit, &c)) {
      lt_od_finish_ray(a, item, &q);
      item = -1;
      if (next_item < end_item) {
        item = next_item;
        next_item += lsize;
        lt_od_start(&q, a->rays + 8 * (long)item);
      }
    }
    sh->pending[lid] = item >= 0;
    lt_barrier();

    /* Work-item 0 decides for the group: new rays, building, or quitting. Only speculative and
     * full builds look for work that no ray of the group waits for. */
    if (lid == 0) {
      int waiting = 0;
      for (int l = 0; l < lsize; l++) waiting |= sh->pending[l];
      int build = a->speculate || pool->mode == LT_POOL_FULL;
      sh->round = lt_pool_decide(pool, &worker, waiting, build, lsize * LT_OD_RAYS_PER_ITEM, a->ray_count,
                                 a->max_idle_polls);
    }
    lt_barrier();
    running = !sh->round.quit;
    lt_i32 batch = sh->round.batch, slot = sh->round.slot, chunk = sh->round.chunk;

    /* New rays: every lsize-th of the batch for each work-item, traced at the top of the loop. */
    if (running && batch >= 0) {
      lt_i32 batch_end = batch + lsize * LT_OD_RAYS_PER_ITEM;
      end_item = batch_end < a->ray_count ? batch_end : a->ray_count;
      item = batch + lid < end_item ? batch + lid : -1;
      next_item = batch + lid + lsize;
      if (item >= 0) lt_od_start(&q, a->rays + 8 * (long)item);
    }

    /* Building: the group works the chunk together; work-item 0 finishes it. */
    int building = running && batch < 0 && slot >= 0;
    if (building) lt_bvh_chunk(b, slot, chunk, lid, lsize);
    lt_barrier();
    if (building && lid == 0 && lt_pool_finish_chunk(pool, slot)) lt_bvh_end_phase(b, slot);
    lt_barrier();
  }
  lt_bvh_count(b, LT_BVH_STAT_STEPS, c.traversal_steps);
  lt_bvh_count(b, LT_BVH_STAT_TESTS, c.intersections);
}

#endif
