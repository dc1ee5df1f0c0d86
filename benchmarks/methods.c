/* The methods the benchmarks compare (methods.h). */
#include "benchmarks/methods.h"

const char *const lt_bench_method_names[LT_BENCH_METHODS] = {"full", "requested", "speculative", "lbvh", "embree"};

lt_structure_config lt_bench_method_config(int method) {
  lt_build_mode build = method == LT_BENCH_REQUESTED     ? LT_BUILD_REQUESTED
                        : method == LT_BENCH_SPECULATIVE ? LT_BUILD_SPECULATIVE
                                                         : LT_BUILD_FULL;
  lt_structure_config config = lt_structure_config_default(method == LT_BENCH_LBVH ? LT_STRUCTURE_LBVH : LT_STRUCTURE_BVH);
  config.build = build;
  return config;
}
