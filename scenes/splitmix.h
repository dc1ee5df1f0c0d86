/* splitmix64 (Steele, Lea and Flood, "Fast Splittable Pseudorandom Number Generators", 2014):
 * the one random-number generator of the generators, the ray batches, the renderer and the
 * tests; the same sequence on every machine. */
#ifndef LT_SPLITMIX_H
#define LT_SPLITMIX_H

#include <stdint.h>

static inline uint64_t lt__splitmix_next(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/* A float in [0, 1) from the top 24 bits of the next number. */
static inline float lt__splitmix_unit(uint64_t *state) {
  return (float)(lt__splitmix_next(state) >> 40) * (1.0f / 16777216.0f);
}

#endif
