/* The host builders' parallel sort of 64-bit keys (a 32-bit code above a 32-bit triangle
 * number): an LSD radix sort in chunks of keys, each chunk counting its digits, prefix sums over
 * (digit, chunk), each chunk scattering its keys in order; stable, so keys of equal code keep
 * their order, and the same whatever the number of workers. Used by the LBVH and by the Morton
 * order of the on-demand BVH's top. */
#ifndef LT_RADIX_SORT_H
#define LT_RADIX_SORT_H

#include <stdint.h>

#include "builders/host/executor.h"

#define LT_RADIX_BITS    10
#define LT_RADIX_BUCKETS (1 << LT_RADIX_BITS)

/* A sort's arrays: n keys in *keys, as many in *tmp (scratch), and `digits`, chunks *
 * LT_RADIX_BUCKETS counts for chunks of `chunk` keys. */
typedef struct lt__radix_sort {
  uint64_t *keys, *tmp;
  uint32_t *digits;
  int n, chunk, shift;
} lt__radix_sort;

/* The number of chunks of the sort. */
static inline int lt__radix_chunks(const lt__radix_sort *s) { return (s->n + s->chunk - 1) / s->chunk; }

/* Counts chunk c's digits of the pass whose lowest bit is s->shift. */
void lt__radix_count_chunk(void *sort, int c);

/* Sorts the keys by `passes` digits of LT_RADIX_BITS from bit 32 up; the result ends in s->keys
 * (keys and tmp are swapped as passes move them). first_counted: digits already hold the first
 * pass's counts. A pass whose digit is the same in every key moves nothing and is skipped.
 * Returns the passes that moved the keys. */
int lt__radix_sort_keys(lt__radix_sort *s, int passes, int first_counted, const lt__executor *ex);

#endif
