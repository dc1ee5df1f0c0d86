/* The median of a benchmark's runs (median.h). */
#include "benchmarks/median.h"

#include <stdlib.h>
#include <string.h>

static int compare_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

double lt_bench_median(const double *v, int n) {
  if (n <= 0) return 0.0;
  double *s = malloc((size_t)n * sizeof *s);
  if (!s) abort();
  memcpy(s, v, (size_t)n * sizeof *s);
  qsort(s, (size_t)n, sizeof *s, compare_double);
  double m = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
  free(s);
  return m;
}
