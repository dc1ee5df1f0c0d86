/* The median of a benchmark's runs. */
#ifndef LT_BENCH_MEDIAN_H
#define LT_BENCH_MEDIAN_H

/* The median of v[0..n) (the mean of the middle two for even n); v is left as it was. */
double lt_bench_median(const double *v, int n);

#endif
