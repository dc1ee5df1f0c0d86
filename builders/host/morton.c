/* Morton order and block boxes for the on-demand BVH's top (builders/host/morton.h): 30-bit codes
 * of the triangles' box centres, an LSD radix sort in chunks (each chunk counts its digits, prefix
 * sums over (digit, chunk), each chunk scatters its keys in order), and a pyramid of boxes over
 * blocks of the sorted order. */
#include "builders/host/morton.h"
#include "builders/host/radix_sort.h"

#include <stdlib.h>
#include <string.h>

#define AXIS_BITS  10
/* The top 20 of the code's 30 bits are sorted (two passes): the Morton top only splits nodes of
 * thousands of triangles, which never need the last 10 bits, and a node whose triangles share
 * all 20 is left to the SAH (builders/bvh_morton.h). */
#define SORT_BITS    20
#define RADIX_PASSES (SORT_BITS / LT_RADIX_BITS)
#define BUCKETS      LT_RADIX_BUCKETS
/* Triangles per work item: a fixed size, so that the order is the same for any worker count. */
#define CHUNK (1 << 14)

typedef struct sort_job {
  const float *boxes;
  int n, chunks;
  float lo[3], scale[3];
  uint64_t *keys;   /* code << 32 | triangle (sorted in `sort`) */
  uint32_t *digits; /* the first radix pass's counts, per chunk */
  uint32_t *codes;
  int32_t *index;
  lt_v4 *blocks;
} sort_job;

static int chunk_end(const sort_job *j, int chunk) {
  long long end = (long long)(chunk + 1) * CHUNK;
  return end < j->n ? (int)end : j->n;
}

/* Moves the low 10 bits of v to every third bit of 30, so that three axes interleave. */
static uint32_t spread_bits(uint32_t v) {
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  v = (v * 0x00000005u) & 0x49249249u;
  return v;
}

/* Each lane as one of 1024 cells: (p - lo) * scale truncated, NaN and below 0 in cell 0, from
 * 1023 on in cell 1023 (max and min as comparisons, which send NaN to their second operand). */
static inline uint32_t code4(lt_v4 p, lt_v4 lo, lt_v4 scale) {
  lt_v4 t = lt_v4_min(lt_v4_max((p - lo) * scale, lt_v4_splat(0.0f)), lt_v4_splat(1023.0f));
  lt_vi4 q = lt_v4_to_int(t);
  return spread_bits((uint32_t)q[0]) << 2 | spread_bits((uint32_t)q[1]) << 1 | spread_bits((uint32_t)q[2]);
}

uint32_t lt__morton_code(const float p[3], const float lo[3], const float scale[3]) {
  return code4(lt_v4_make(p[0], p[1], p[2], 0.0f), lt_v4_make(lo[0], lo[1], lo[2], 0.0f),
               lt_v4_make(scale[0], scale[1], scale[2], 0.0f));
}

static void codes_chunk(void *job, int chunk) {
  sort_job *j = job;
  uint32_t *count = j->digits + (size_t)chunk * BUCKETS;
  memset(count, 0, BUCKETS * sizeof *count);
  const lt_v4 *boxes = (const lt_v4 *)j->boxes;
  lt_v4 lo = lt_v4_make(j->lo[0], j->lo[1], j->lo[2], 0.0f),
        scale = lt_v4_make(j->scale[0], j->scale[1], j->scale[2], 0.0f);
  for (int i = chunk * CHUNK, end = chunk_end(j, chunk); i < end; i++) {
    uint32_t code = code4((boxes[2 * (size_t)i] + boxes[2 * (size_t)i + 1]) * 0.5f, lo, scale) >> (30 - SORT_BITS);
    j->keys[i] = (uint64_t)code << 32 | (uint32_t)i;
    count[code & (BUCKETS - 1)]++;
  }
}

/* Sorted codes and triangle numbers out of the keys, and the bottom level's block boxes (a
 * chunk is a whole number of blocks). */
static void unpack_chunk(void *job, int chunk) {
  sort_job *j = job;
  const lt_v4 *boxes = (const lt_v4 *)j->boxes;
  for (int i = chunk * CHUNK; i < chunk_end(j, chunk); i += LT_BVH_MORTON_BLOCK) {
    /* The boxes are gathered in code order: ask for a block ahead. */
    for (int p = i + 4 * LT_BVH_MORTON_BLOCK; p < i + 5 * LT_BVH_MORTON_BLOCK && p < j->n; p++)
      __builtin_prefetch(&boxes[2 * (size_t)(uint32_t)j->keys[p]]);
    int end = i + LT_BVH_MORTON_BLOCK < j->n ? i + LT_BVH_MORTON_BLOCK : j->n;
    lt_v4 lo = lt_v4_splat(INFINITY), hi = lt_v4_splat(-INFINITY);
    for (int p = i; p < end; p++) {
      uint32_t t = (uint32_t)j->keys[p];
      j->codes[p] = (uint32_t)(j->keys[p] >> 32), j->index[p] = (int32_t)t;
      lo = lt_v4_min(boxes[2 * (size_t)t], lo), hi = lt_v4_max(boxes[2 * (size_t)t + 1], hi);
    }
    j->blocks[2 * (i / LT_BVH_MORTON_BLOCK)] = lo, j->blocks[2 * (i / LT_BVH_MORTON_BLOCK) + 1] = hi;
  }
}

size_t lt__morton_block_count(size_t n) {
  size_t total = 0;
  for (size_t count = (n + LT_BVH_MORTON_BLOCK - 1) / LT_BVH_MORTON_BLOCK; count > 0; count = (count + 1) / 2) {
    total += count;
    if (count == 1) break;
  }
  return total;
}

size_t lt__morton_work_bytes(size_t n) {
  return 2 * n * sizeof(uint64_t) + (n + CHUNK - 1) / CHUNK * BUCKETS * sizeof(uint32_t);
}

lt_status lt__morton_order(const float *boxes, size_t n, const lt_box *bounds, const lt__executor *executor, void *work,
                           uint32_t *codes, int32_t *index, float *block_boxes, double *sort_ops) {
  if (!boxes || !bounds || !codes || !index || !block_boxes || n == 0 || n > INT32_MAX / 2)
    return LT_ERROR_INVALID_ARGUMENT;
  sort_job j = {.boxes = boxes, .n = (int)n, .chunks = (int)((n + CHUNK - 1) / CHUNK)};
  j.codes = codes, j.index = index, j.blocks = (lt_v4 *)block_boxes;
  for (int k = 0; k < 3; k++) {
    float extent = bounds->hi[k] - bounds->lo[k];
    j.lo[k] = bounds->lo[k], j.scale[k] = extent > 0.0f ? (float)(1 << AXIS_BITS) / extent : 0.0f;
  }
  void *own = work ? NULL : malloc(lt__morton_work_bytes(n));
  uint64_t *keys = work ? work : own, *tmp = keys ? keys + n : NULL;
  j.digits = tmp ? (uint32_t *)(tmp + n) : NULL;
  lt_status status = keys ? LT_OK : LT_ERROR_OUT_OF_MEMORY;
  if (!status) {
    /* Fewer than two chunks are done on the caller: starting threads would cost more. */
    const lt__executor *ex = j.chunks > 1 ? executor : NULL;
    j.keys = keys;
    lt__executor_for(ex, j.chunks, codes_chunk, &j);
    lt__radix_sort sort = {keys, tmp, j.digits, j.n, CHUNK, 0};
    lt__radix_sort_keys(&sort, RADIX_PASSES, 1, ex);
    *sort_ops += (double)RADIX_PASSES * j.n;
    j.keys = sort.keys;
    lt__executor_for(ex, j.chunks, unpack_chunk, &j);

    /* The levels above the bottom: box i of a level bounds boxes 2i and 2i + 1 below. */
    lt_v4 *level = j.blocks;
    for (size_t count = (n + LT_BVH_MORTON_BLOCK - 1) / LT_BVH_MORTON_BLOCK; count > 1; count = (count + 1) / 2) {
      lt_v4 *up = level + 2 * count;
      for (size_t i = 0; 2 * i < count; i++) {
        lt_v4 lo = level[4 * i], hi = level[4 * i + 1];
        if (2 * i + 1 < count) lo = lt_v4_min(level[4 * i + 2], lo), hi = lt_v4_max(level[4 * i + 3], hi);
        up[2 * i] = lo, up[2 * i + 1] = hi;
      }
      level = up;
    }
  }
  free(own);
  return status;
}
