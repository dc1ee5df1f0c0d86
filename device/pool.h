/* The task pool: a scheduler that lives in global memory and is driven by persistent
 * work-groups (Vinkler et al. 2013; on-demand paper, sections 3.2 and 4).
 *
 * A task subdivides one node. It runs its phases in order; each phase is cut into work chunks
 * that work-groups take in parallel; the work-group that finishes the last chunk of a phase
 * switches the phase, or retires the task. A task's header says what may be done with it:
 *
 *   > 0                 unlocked: the number of chunks of the current phase still to take
 *   0                   locked: being initialised, switching phase, or all chunks handed out
 *   WAITING | node      inserted, waiting for a ray to unlock it (unique per node, so a
 *                       compare-and-swap can never unlock another task)
 *   EMPTY (most neg.)   a free slot
 *
 * Publishing order: task data first, a fence, then the header store that makes it takeable. */
#ifndef LT_DEVICE_POOL_H
#define LT_DEVICE_POOL_H

#include "device/compat.h"

#define LT_POOL_EMPTY ((lt_i32)(-2147483647 - 1))
#define LT_POOL_WAITING_BASE ((lt_i32)(-1073741824)) /* 0xC0000000: WAITING | node */
#define LT_POOL_MAX_NODE 0x3fffffff
#define LT_POOL_WAITING(node) (LT_POOL_WAITING_BASE + (node))
#define LT_POOL_IS_WAITING(h) ((h) >= LT_POOL_WAITING_BASE && (h) < 0)

/* Build modes, as the pool sees them (the same numbers as lt_build_mode). */
#define LT_POOL_FULL 0
#define LT_POOL_REQUESTED 1
#define LT_POOL_SPECULATIVE 2
/* The level-by-level baseline: children wait, and the host unlocks each level between
 * launches; a launch ends when no unlocked task is left. */
#define LT_POOL_LEVELS 3

/* Errors a kernel reports through the control block; the host turns them into lt_status. */
#define LT_POOL_OK 0
#define LT_POOL_ERROR_FULL 1  /* no empty slot for a new task */
#define LT_POOL_ERROR_HEAP 2  /* a device heap (nodes, references, cells) is full */
#define LT_POOL_ERROR_STALL 3 /* a work-group polled past its cap with no progress anywhere */
#define LT_POOL_ERROR_STACK 4 /* a traversal stack would overflow */
#define LT_POOL_ERROR_KIND 5  /* a task of a kind the running workload has no hooks for */

/* Task flags. */
#define LT_TASK_REQUESTED 1

/* One task: 96 bytes of plain ints, so that single fields can be used atomically. A task's
 * kind says which hooks run its chunks and phase ends (kernels/persistent_loop.h); kinds are
 * numbered by the workload that runs them, so one pool can hold tasks of several kinds. */
typedef struct lt_task {
  lt_i32 kind;       /* 4 bytes: which task hooks run it (the workload's numbering) */
  lt_i32 begin, end; /* 8 bytes: the range of elements (primitives) the node holds */
  lt_i32 node;       /* 4 bytes: the node this task builds; its waiting value is WAITING | node */
  lt_i32 phase;      /* 4 bytes: the current phase, from 0 */
  lt_i32 chunks;     /* 4 bytes: chunks in the current phase */
  lt_i32 done;       /* 4 bytes: chunks of the current phase finished (atomic) */
  lt_i32 flags;      /* 4 bytes: LT_TASK_REQUESTED once a ray asked for it */
  lt_i32 depth;      /* 4 bytes: depth of the node */
  lt_i32 work[15];   /* 60 bytes: the task kind's own data and scratch */
} lt_task;

/* The pool's global counters. */
typedef struct lt_pool_control {
  lt_i32 termination; /* work-groups that still have rays (own work) */
  lt_i32 outstanding; /* tasks inserted and not yet retired */
  lt_i32 error;       /* LT_POOL_ERROR_*, first one wins */
  lt_i32 progress;    /* bumped by every finished chunk and every batch of own work taken */
  lt_i32 empty_put;   /* write counter of the empty-task cache ring */
  lt_i32 priority_put; /* write counter of the prioritisation cache ring */
  lt_i32 high_water;  /* one past the highest slot ever used: scans stop there */
  lt_i32 work_next;   /* next item of own work (ray, query) to hand out */
  lt_i32 order_next;  /* next entry of the order log */
  lt_i32 waiting;     /* tasks published waiting in LT_POOL_LEVELS mode */
  lt_i32 scan_hint;   /* where a scan last found work */
  lt_i32 groups;      /* work-groups of this launch */
  lt_i32 idle_groups; /* work-groups in an idle streak, or gone (lt_pool_decide) */
  lt_i32 pad[3];
} lt_pool_control;

/* Per-work-group counters, written by work-item 0 of that group only. */
#define LT_POOL_STAT_LIST(X)                                                   \
  X(LT_POOL_STAT_TASKS, "tasks") /* tasks retired */                           \
  X(LT_POOL_STAT_REQUESTED, "requested") /* tasks unlocked by a request */     \
  X(LT_POOL_STAT_SPECULATIVE, "speculative") /* retired, never requested */    \
  X(LT_POOL_STAT_STALLS, "stalls") /* own work suspended on an unbuilt node */ \
  X(LT_POOL_STAT_CACHE_HITS, "cache_hits") /* chunks from the priority cache */ \
  X(LT_POOL_STAT_CACHE_MISSES, "cache_misses") /* chunk searches it missed */  \
  X(LT_POOL_STAT_SCANS, "scans") /* scans of the whole pool */                  \
  X(LT_POOL_STAT_EMPTY_HITS, "empty_cache_hits") /* inserts served by it */     \
  X(LT_POOL_STAT_CHUNKS, "chunks") /* work chunks processed */                  \
  X(LT_POOL_STAT_IDLE, "idle_polls") /* searches that found nothing */

enum {
#define LT_POOL_STAT_ENUM(id, name) id,
  LT_POOL_STAT_LIST(LT_POOL_STAT_ENUM)
#undef LT_POOL_STAT_ENUM
      LT_POOL_STAT_COUNT
};

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_task) == 96, "lt_task is 96 bytes on both sides");
_Static_assert(sizeof(lt_pool_control) == 64, "lt_pool_control is 64 bytes on both sides");
#endif

/* Where the pool lives; a private struct of global pointers handed to every operation. */
typedef struct lt_pool {
  LT_GLOBAL lt_i32 *headers;
  LT_GLOBAL lt_task *tasks;
  LT_GLOBAL lt_i32 *empty_cache;    /* ring of recently emptied slots */
  LT_GLOBAL lt_i32 *priority_cache; /* ring of slots unlocked by requests */
  LT_GLOBAL lt_pool_control *control;
  LT_GLOBAL lt_u32 *stats;          /* LT_POOL_STAT_COUNT per work-group */
  LT_GLOBAL lt_i32 *order;          /* log of nodes in the order their tasks were first taken */
  lt_i32 capacity, empty_size, priority_size, order_size;
  lt_i32 mode;                      /* LT_POOL_FULL, _REQUESTED or _SPECULATIVE */
} lt_pool;

/* The pool's kernel arguments, for a workload's argument list (device/kernel_args.h): V is
 * the path of the workload's lt_pool inside its view struct. */
#define LT_POOL_ARGS(X, V)                                   \
  X(BUF, lt_i32, V.headers, pool_headers)                    \
  X(BUF, lt_task, V.tasks, pool_tasks)                       \
  X(BUF, lt_i32, V.empty_cache, pool_empty_cache)            \
  X(BUF, lt_i32, V.priority_cache, pool_priority_cache)      \
  X(BUF, lt_pool_control, V.control, pool_control)           \
  X(BUF, lt_u32, V.stats, pool_stats)                        \
  X(BUF, lt_i32, V.order, pool_order)                        \
  X(VAL, lt_i32, V.capacity, pool_capacity)                  \
  X(VAL, lt_i32, V.empty_size, pool_empty_size)              \
  X(VAL, lt_i32, V.priority_size, pool_priority_size)        \
  X(VAL, lt_i32, V.order_size, pool_order_size)              \
  X(VAL, lt_i32, V.mode, pool_mode)

/* Entries of the empty-task cache an insert looks at before it scans the headers. */
#define LT_POOL_EMPTY_TRIES 32

/* Counters are per work-group but any work-item may count, hence the atomic. */
LT_DEVICE void lt_pool_count(const lt_pool *pool, int stat, lt_u32 n) {
  lt_atomic_add_u32(&pool->stats[lt_group_id() * LT_POOL_STAT_COUNT + stat], n);
}

LT_DEVICE void lt_pool_fail(const lt_pool *pool, lt_i32 error) {
  lt_atomic_cas_i32(&pool->control->error, LT_POOL_OK, error);
}

/* Claims an empty slot (header EMPTY -> 0, locked): the empty-task cache first, then a scan.
 * Returns the slot, or -1 when the pool is full. */
LT_DEVICE lt_i32 lt_pool_claim(const lt_pool *pool) {
  /* The newest few recently emptied slots. An entry is cleared once its slot is claimed; one
   * whose slot was taken another way is stale and only read (no compare-and-swap on a header
   * that is not empty): when most tasks wait for requests that never come, slots rarely empty
   * and a long walk over stale entries would cost every insert. */
  lt_i32 put = lt_atomic_load_i32(&pool->control->empty_put);
  lt_i32 tries = put < pool->empty_size ? put : pool->empty_size;
  if (tries > LT_POOL_EMPTY_TRIES) tries = LT_POOL_EMPTY_TRIES;
  for (lt_i32 k = 1; k <= tries; k++) {
    LT_GLOBAL lt_i32 *entry = &pool->empty_cache[(lt_u32)(put - k) % (lt_u32)pool->empty_size];
    lt_i32 slot = lt_atomic_load_i32(entry);
    if (slot >= 0 && lt_atomic_load_i32(&pool->headers[slot]) == LT_POOL_EMPTY &&
        lt_atomic_cas_i32(&pool->headers[slot], LT_POOL_EMPTY, 0) == LT_POOL_EMPTY) {
      lt_atomic_cas_i32(entry, slot, -1);
      lt_pool_count(pool, LT_POOL_STAT_EMPTY_HITS, 1);
      return slot;
    }
  }

  /* A full scan, starting where slots were last handed out. */
  lt_i32 start = lt_atomic_load_i32(&pool->control->high_water);
  for (lt_i32 i = 0; i < pool->capacity; i++) {
    lt_i32 slot = (start + i) % pool->capacity;
    if (lt_atomic_load_i32(&pool->headers[slot]) == LT_POOL_EMPTY &&
        lt_atomic_cas_i32(&pool->headers[slot], LT_POOL_EMPTY, 0) == LT_POOL_EMPTY) {
      lt_atomic_max_i32(&pool->control->high_water, slot + 1);
      return slot;
    }
  }
  return -1;
}

/* Inserts a task for `node` over [begin, end) whose first phase has `chunks` chunks, still
 * locked: the caller links it into its structure and then calls lt_pool_publish, so that no
 * work-group can finish the task before the link to it exists. Returns the slot, or -1 (and
 * the error is set) if the pool is full. */
LT_DEVICE lt_i32 lt_pool_insert(const lt_pool *pool, lt_i32 kind, lt_i32 node, lt_i32 begin, lt_i32 end,
                                lt_i32 depth, lt_i32 chunks) {
  lt_i32 slot = lt_pool_claim(pool);
  if (slot < 0) {
    lt_pool_fail(pool, LT_POOL_ERROR_FULL);
    return -1;
  }

  /* Task data, then the outstanding count, then the header that publishes it. */
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  task->kind = kind, task->begin = begin, task->end = end, task->depth = depth, task->phase = 0;
  lt_atomic_store_i32(&task->node, node);
  lt_atomic_store_i32(&task->chunks, chunks);
  lt_atomic_store_i32(&task->flags, 0);
  lt_atomic_store_i32(&task->done, 0);
  for (int k = 0; k < 15; k++) task->work[k] = 0; /* published with the header, like the rest */
  lt_atomic_add_i32(&pool->control->outstanding, 1);
  return slot;
}

/* Makes an inserted task visible: waiting in requested mode, unlocked otherwise. */
LT_DEVICE void lt_pool_publish(const lt_pool *pool, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  int wait = pool->mode == LT_POOL_REQUESTED || pool->mode == LT_POOL_LEVELS;
  lt_i32 header = wait ? LT_POOL_WAITING(lt_atomic_load_i32(&task->node)) : lt_atomic_load_i32(&task->chunks);
  if (pool->mode == LT_POOL_LEVELS) lt_atomic_add_i32(&pool->control->waiting, 1);
  lt_fence();
  lt_atomic_store_i32(&pool->headers[slot], header);
}

/* A request from traversal for the task in `slot` building `node`: unlock it if it waits and,
 * the first time it is requested, put it in the prioritisation cache unless it is already
 * finished. Returns 1 if this call unlocked it. */
LT_DEVICE int lt_pool_request(const lt_pool *pool, lt_i32 slot, lt_i32 node) {
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  lt_i32 waiting = LT_POOL_WAITING(node);
  lt_i32 old = lt_atomic_cas_i32(&pool->headers[slot], waiting, lt_atomic_load_i32(&task->chunks));
  int unlocked = old == waiting;

  /* Live and ours (unlocked now, or already unlocked or locked in speculative mode)? */
  if (unlocked || (old >= 0 && lt_atomic_load_i32(&task->node) == node)) {
    if (!(lt_atomic_max_i32(&task->flags, LT_TASK_REQUESTED) & LT_TASK_REQUESTED)) {
      lt_pool_count(pool, LT_POOL_STAT_REQUESTED, 1);
      lt_i32 k = lt_atomic_add_i32(&pool->control->priority_put, 1);
      lt_atomic_store_i32(&pool->priority_cache[(lt_u32)k % (lt_u32)pool->priority_size], slot);
    }
  }
  return unlocked;
}

/* Takes one chunk of an unlocked task in `slot`: header h > 0 becomes h - 1. Returns the
 * chunk index (h - 1) or -1 if there was nothing to take. */
LT_DEVICE lt_i32 lt_pool_take_from(const lt_pool *pool, lt_i32 slot) {
  lt_i32 h = lt_atomic_load_i32(&pool->headers[slot]);
  while (h > 0) {
    lt_i32 seen = lt_atomic_cas_i32(&pool->headers[slot], h, h - 1);
    if (seen == h) return h - 1;
    h = seen;
  }
  return -1;
}

/* Finds a chunk in the prioritisation cache only (requested tasks). Returns the slot and
 * sets *chunk, or returns -1. */
LT_DEVICE lt_i32 lt_pool_take_requested(const lt_pool *pool, lt_i32 *chunk) {
  lt_i32 put = lt_atomic_load_i32(&pool->control->priority_put);
  lt_i32 tries = put < pool->priority_size ? put : pool->priority_size;
  for (lt_i32 k = 1; k <= tries; k++) {
    lt_i32 slot = lt_atomic_load_i32(&pool->priority_cache[(lt_u32)(put - k) % (lt_u32)pool->priority_size]);
    /* A cached slot may since have been retired and reused by a task nobody asked for. */
    if (slot < 0 || !(lt_atomic_load_i32(&pool->tasks[slot].flags) & LT_TASK_REQUESTED)) continue;
    lt_i32 c = lt_pool_take_from(pool, slot);
    if (c >= 0) {
      lt_pool_count(pool, LT_POOL_STAT_CACHE_HITS, 1);
      *chunk = c;
      return slot;
    }
  }
  return -1;
}

/* Finds a chunk: the prioritisation cache first (requested tasks before speculative ones),
 * then a scan of the pool from where work was last found. Returns the slot and sets *chunk,
 * or returns -1. */
LT_DEVICE lt_i32 lt_pool_take(const lt_pool *pool, lt_i32 *chunk) {
  /* Requested tasks, newest first. */
  lt_i32 slot = lt_pool_take_requested(pool, chunk);
  if (slot >= 0) return slot;
  lt_pool_count(pool, LT_POOL_STAT_CACHE_MISSES, 1);

  /* Any unlocked task, starting where work was last found: tasks inserted together sit
   * together, so this finds the next one in a few steps instead of a scan of everything. */
  lt_i32 used = lt_atomic_load_i32(&pool->control->high_water);
  lt_pool_count(pool, LT_POOL_STAT_SCANS, 1);
  lt_i32 start = lt_atomic_load_i32(&pool->control->scan_hint);
  start = start >= 0 && start < used ? start : 0;
  for (lt_i32 i = 0; i < used; i++) {
    lt_i32 slot = start + i < used ? start + i : start + i - used;
    lt_i32 c = lt_pool_take_from(pool, slot);
    if (c >= 0) {
      if (slot != start) lt_atomic_store_i32(&pool->control->scan_hint, slot);
      *chunk = c;
      return slot;
    }
  }
  return -1;
}

/* Records that a task's first chunk was taken, for tests of the scheduling order. */
LT_DEVICE void lt_pool_log_start(const lt_pool *pool, lt_i32 slot, lt_i32 chunk) {
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  if (pool->order_size <= 0 || task->phase != 0 || chunk != lt_atomic_load_i32(&task->chunks) - 1) return;
  lt_i32 k = lt_atomic_add_i32(&pool->control->order_next, 1);
  if (k < pool->order_size) pool->order[k] = task->node;
}

/* Marks one chunk of the current phase done; returns 1 for the work-group that finished the
 * last one, which must then call lt_pool_next_phase or lt_pool_retire. */
LT_DEVICE int lt_pool_finish_chunk(const lt_pool *pool, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  lt_atomic_add_i32(&pool->control->progress, 1);
  lt_pool_count(pool, LT_POOL_STAT_CHUNKS, 1);

  /* The phase's chunk count is read before the increment: once this chunk counts as done,
   * another work-group may switch the phase, or retire the task and see its slot reused, and
   * a count read afterwards would be someone else's (two "last" finishers). */
  lt_i32 chunks = lt_atomic_load_i32(&task->chunks);
  return lt_atomic_add_i32(&task->done, 1) + 1 == chunks;
}

/* Switches the task (locked: header 0, all chunks done) to `phase`, of `chunks` chunks. */
LT_DEVICE void lt_pool_next_phase(const lt_pool *pool, lt_i32 slot, lt_i32 phase, lt_i32 chunks) {
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  task->phase = phase;
  lt_atomic_store_i32(&task->chunks, chunks);
  lt_atomic_store_i32(&task->done, 0);
  lt_fence();
  lt_atomic_store_i32(&pool->headers[slot], chunks);
}

/* Turns a task whose phase is done (locked, all chunks done) into the task of the next step of
 * its structure, of another kind: the same slot, node and flags, so whatever points at the slot
 * (a top map, a ray's request, the prioritisation cache) follows it; a new kind and range, from
 * phase 0 with `chunks` chunks. The caller writes the new kind's work words first. */
LT_DEVICE void lt_pool_next_kind(const lt_pool *pool, lt_i32 slot, lt_i32 kind, lt_i32 begin, lt_i32 end,
                                 lt_i32 chunks) {
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  task->kind = kind, task->begin = begin, task->end = end;
  lt_pool_next_phase(pool, slot, 0, chunks);
}
/* Retires a finished task: its slot becomes empty and goes to the empty-task cache. */
LT_DEVICE void lt_pool_retire(const lt_pool *pool, lt_i32 slot) {
  LT_GLOBAL lt_task *task = &pool->tasks[slot];
  lt_pool_count(pool, LT_POOL_STAT_TASKS, 1);
  if (!(lt_atomic_load_i32(&task->flags) & LT_TASK_REQUESTED)) lt_pool_count(pool, LT_POOL_STAT_SPECULATIVE, 1);
  lt_fence();
  lt_atomic_store_i32(&pool->headers[slot], LT_POOL_EMPTY);
  lt_i32 k = lt_atomic_add_i32(&pool->control->empty_put, 1);
  lt_atomic_store_i32(&pool->empty_cache[(lt_u32)k % (lt_u32)pool->empty_size], slot);
  lt_atomic_add_i32(&pool->control->outstanding, -1);
}

/* Whether a work-group that has given up its own work may quit: every work-group is out of
 * own work, and in a full build every task is done too (in the level baseline every task of
 * this level); or an error stopped everything. */
LT_DEVICE int lt_pool_may_quit(const lt_pool *pool) {
  if (lt_atomic_load_i32(&pool->control->error) != LT_POOL_OK) return 1;
  if (lt_atomic_load_i32(&pool->control->termination) > 0) return 0;
  lt_i32 outstanding = lt_atomic_load_i32(&pool->control->outstanding);
  if (pool->mode == LT_POOL_LEVELS) return outstanding - lt_atomic_load_i32(&pool->control->waiting) == 0;
  return pool->mode != LT_POOL_FULL || outstanding == 0;
}

/* One round of a work-group's persistent loop, decided by its work-item 0 and shared with the
 * others: a new batch of its own work (items batch...), a chunk of a task (slot, chunk), or
 * quitting; all -1 and 0 when the group found nothing this round. */
typedef struct lt_pool_round {
  lt_i32 batch, slot, chunk, quit;
} lt_pool_round;

/* What work-item 0 remembers between rounds. */
typedef struct lt_pool_worker {
  int gave_up;                /* out of own work: the termination counter has been decremented */
  int idle;                   /* in an idle streak: counted in control->idle_groups */
  lt_i32 polls, last_progress; /* the stall cap's count of polls without progress */
} lt_pool_worker;

LT_DEVICE lt_pool_worker lt_pool_worker_new(void) {
  lt_pool_worker w;
  w.gave_up = 0, w.idle = 0, w.polls = 0, w.last_progress = -1;
  return w;
}

/* Counts the work-group in control->idle_groups, once per idle streak. */
LT_DEVICE void lt_pool_mark_idle(const lt_pool *pool, lt_pool_worker *w) {
  if (!w->idle) {
    w->idle = 1;
    lt_atomic_add_i32(&pool->control->idle_groups, 1);
  }
}

/* The stall cap. A round that found nothing is an idle poll; it counts towards the cap only
 * while every work-group of the launch is idle (or gone) and the global progress counter has
 * not moved. A work-group that is tracing a long batch, or whose thread the operating system
 * has set aside, is not idle, so the others wait for it however long that takes; when all
 * poll and nothing moves, nothing can (a true hang), and the cap turns it into an error. */
LT_DEVICE void lt_pool_idle(const lt_pool *pool, lt_pool_worker *w, lt_i32 max_idle_polls) {
  lt_pool_count(pool, LT_POOL_STAT_IDLE, 1);
  lt_pool_mark_idle(pool, w);
  lt_i32 progress = lt_atomic_load_i32(&pool->control->progress);
  int all_idle = lt_atomic_load_i32(&pool->control->idle_groups) >= lt_atomic_load_i32(&pool->control->groups);
  w->polls = progress == w->last_progress && all_idle ? w->polls + 1 : 0;
  w->last_progress = progress;
  if (w->polls > max_idle_polls) lt_pool_fail(pool, LT_POOL_ERROR_STALL);
}

/* A round that found work ends the idle streak. */
LT_DEVICE void lt_pool_busy(const lt_pool *pool, lt_pool_worker *w) {
  if (w->idle) {
    w->idle = 0;
    lt_atomic_add_i32(&pool->control->idle_groups, -1);
  }
  w->polls = 0;
}

/* A work-group that quits stays counted as idle: the others' stall cap must not wait for it. */
LT_DEVICE void lt_pool_leave(const lt_pool *pool, lt_pool_worker *w) { lt_pool_mark_idle(pool, w); }

/* The round's decision: when none of the group's items waits, a new batch of batch_size out of
 * item_count (or, out of items, giving up); otherwise, or then, a chunk of work when an item
 * waits for one or `build` says to look anyway; quitting once lt_pool_may_quit allows it or an
 * error stopped the pool. */
LT_DEVICE lt_pool_round lt_pool_decide(const lt_pool *pool, lt_pool_worker *w, int waiting, int build,
                                       lt_i32 batch_size, lt_i32 item_count, lt_i32 max_idle_polls) {
  lt_pool_round r;
  r.batch = -1, r.slot = -1, r.chunk = -1, r.quit = 0;
  if (!waiting && !w->gave_up) {
    lt_i32 first = lt_atomic_add_i32(&pool->control->work_next, batch_size);
    if (first < item_count) {
      r.batch = first;
      lt_atomic_add_i32(&pool->control->progress, 1);
    } else {
      w->gave_up = 1;
      lt_atomic_add_i32(&pool->control->termination, -1);
    }
  }
  if (r.batch < 0) {
    if (w->gave_up && lt_pool_may_quit(pool)) r.quit = 1;
    else if (waiting || build) r.slot = lt_pool_take(pool, &r.chunk);
  }
  if (r.batch >= 0 || r.slot >= 0) lt_pool_busy(pool, w);
  else if (!r.quit) lt_pool_idle(pool, w, max_idle_polls);
  if (lt_atomic_load_i32(&pool->control->error) != LT_POOL_OK) r.quit = 1;
  if (r.quit) lt_pool_leave(pool, w);
  return r;
}

#endif
