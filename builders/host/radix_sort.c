/* The host builders' parallel radix sort (radix_sort.h). */
#include "builders/host/radix_sort.h"

#include <string.h>

static int chunk_end(const lt__radix_sort *s, int c) {
  long long end = (long long)(c + 1) * s->chunk;
  return end < s->n ? (int)end : s->n;
}

void lt__radix_count_chunk(void *sort, int c) {
  lt__radix_sort *s = sort;
  uint32_t *count = s->digits + (size_t)c * LT_RADIX_BUCKETS;
  memset(count, 0, LT_RADIX_BUCKETS * sizeof *count);
  for (int i = c * s->chunk, end = chunk_end(s, c); i < end; i++)
    count[(s->keys[i] >> s->shift) & (LT_RADIX_BUCKETS - 1)]++;
}

static void scatter_chunk(void *sort, int c) {
  lt__radix_sort *s = sort;
  uint32_t *slot = s->digits + (size_t)c * LT_RADIX_BUCKETS;
  for (int i = c * s->chunk, end = chunk_end(s, c); i < end; i++)
    s->tmp[slot[(s->keys[i] >> s->shift) & (LT_RADIX_BUCKETS - 1)]++] = s->keys[i];
}

int lt__radix_sort_keys(lt__radix_sort *s, int passes, int first_counted, const lt__executor *ex) {
  int chunks = lt__radix_chunks(s), moved = 0;
  for (int p = 0; p < passes; p++) {
    s->shift = 32 + p * LT_RADIX_BITS;
    if (p > 0 || !first_counted) lt__executor_for(ex, chunks, lt__radix_count_chunk, s);

    /* A digit that is the same in every key would only copy the array. */
    uint32_t first = (uint32_t)(s->keys[0] >> s->shift) & (LT_RADIX_BUCKETS - 1), same = 0;
    for (int c = 0; c < chunks; c++) same += s->digits[(size_t)c * LT_RADIX_BUCKETS + first];
    if ((int)same == s->n) continue;

    /* Exclusive prefix sums, digit by digit and within a digit chunk by chunk, give each chunk's
     * first slot for each digit. */
    uint32_t sum = 0;
    for (int d = 0; d < LT_RADIX_BUCKETS; d++)
      for (int c = 0; c < chunks; c++) {
        uint32_t *v = &s->digits[(size_t)c * LT_RADIX_BUCKETS + d], count = *v;
        *v = sum, sum += count;
      }
    lt__executor_for(ex, chunks, scatter_chunk, s);
    uint64_t *swap = s->keys;
    s->keys = s->tmp, s->tmp = swap;
    moved++;
  }
  return moved;
}
