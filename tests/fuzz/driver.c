/* A bounded stand-in for libFuzzer, so that the test suite runs every fuzz target with the
 * compiler it is built with: the seed corpus first, then mutations of it (byte flips, inserted
 * and deleted runs, truncations, numbers that break parsers) from a fixed seed, for a given
 * number of seconds. A crash, hang or sanitizer report fails the test like any other; with
 * LT_FUZZ_LAST=FILE, each input is saved to FILE before it runs.
 *   fuzz_TARGET CORPUS_DIR [SECONDS] [SEED] */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "scenes/splitmix.h"
#include "tests/fuzz/fuzz_target.h"

#define MAX_INPUTS 256
#define MAX_SIZE 65536

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Runs one input; with LT_FUZZ_LAST set, the input is first saved there, so that an input that
 * hangs or crashes the target can be found and replayed. */
static void run(const uint8_t *data, size_t size) {
  const char *last = getenv("LT_FUZZ_LAST");
  if (last) {
    FILE *f = fopen(last, "wb");
    if (f) fwrite(data, 1, size, f), fclose(f);
  }
  LLVMFuzzerTestOneInput(data, size);
}

/* Tokens that parsers of numbers, counts and keys trip on. */
static const char *const tokens[] = {"0", "-0", "1e38", "-1e39", "nan", "inf", "-inf", "4294967295", "-2147483649",
                                     "1e-45", "999999999999", "\n", " ", "/", "//", "\"", "{", "}", "[", "]", ",",
                                     ":", "f ", "v ", "element vertex ", "end_header\n", "\"meshes\"", "null"};

static size_t mutate(uint8_t *buf, size_t size, uint64_t *rng) {
  int steps = 1 + (int)(lt__splitmix_next(rng) % 4);
  for (int k = 0; k < steps; k++) {
    size_t at = size ? (size_t)(lt__splitmix_next(rng) % size) : 0;
    switch (lt__splitmix_next(rng) % 6) {
    case 0: /* flip a byte */
      if (size) buf[at] ^= (uint8_t)(1u << (lt__splitmix_next(rng) % 8));
      break;
    case 1: /* a random byte in */
      if (size < MAX_SIZE) memmove(buf + at + 1, buf + at, size - at), buf[at] = (uint8_t)lt__splitmix_next(rng), size++;
      break;
    case 2: { /* a run out */
      size_t n = size - at ? (size_t)(lt__splitmix_next(rng) % (size - at)) + 1 : 0;
      memmove(buf + at, buf + at + n, size - at - n), size -= n;
      break;
    }
    case 3: /* cut short */
      size = at;
      break;
    case 4: { /* a token in */
      const char *t = tokens[lt__splitmix_next(rng) % (sizeof tokens / sizeof tokens[0])];
      size_t n = strlen(t);
      if (size + n <= MAX_SIZE) memmove(buf + at + n, buf + at, size - at), memcpy(buf + at, t, n), size += n;
      break;
    }
    default: { /* a run repeated */
      size_t n = size - at ? (size_t)(lt__splitmix_next(rng) % (size - at)) + 1 : 0;
      if (n && size + n <= MAX_SIZE) memmove(buf + at + n, buf + at, size - at), size += n;
      break;
    }
    }
  }
  return size;
}

int main(int argc, char **argv) {
  if (argc < 2) return fprintf(stderr, "usage: %s CORPUS_DIR [SECONDS] [SEED]\n", argv[0]), 2;
  double seconds = argc > 2 ? atof(argv[2]) : 3.0;
  uint64_t rng = argc > 3 ? strtoull(argv[3], NULL, 10) : 1;

  /* The seed corpus. */
  static uint8_t *inputs[MAX_INPUTS];
  static size_t sizes[MAX_INPUTS];
  int count = 0;
  DIR *dir = opendir(argv[1]);
  if (!dir) return fprintf(stderr, "%s: cannot open the corpus\n", argv[1]), 2;
  for (struct dirent *e; count < MAX_INPUTS && (e = readdir(dir));) {
    if (e->d_name[0] == '.') continue;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", argv[1], e->d_name);
    FILE *f = fopen(path, "rb");
    if (!f) continue;
    inputs[count] = malloc(MAX_SIZE);
    sizes[count] = fread(inputs[count], 1, MAX_SIZE, f);
    fclose(f);
    count++;
  }
  closedir(dir);
  if (!count) return fprintf(stderr, "%s: empty corpus\n", argv[1]), 2;
  for (int i = 0; i < count; i++) run(inputs[i], sizes[i]);

  /* Mutations until the time is up. */
  uint8_t *buf = malloc(MAX_SIZE);
  long runs = count;
  double end = now_s() + seconds;
  while (now_s() < end) {
    int i = (int)(lt__splitmix_next(&rng) % (uint64_t)count);
    memcpy(buf, inputs[i], sizes[i]);
    size_t size = mutate(buf, sizes[i], &rng);
    run(buf, size);
    runs++;
  }
  printf("%s: %ld inputs run (%d seeds) in %.1f s, none failed\n", argv[0], runs, count, seconds);
  free(buf);
  for (int i = 0; i < count; i++) free(inputs[i]);
  return 0;
}
