/* Helpers shared by the tests: deterministic random rays and hit comparisons. */
#ifndef LT_TEST_SUPPORT_H
#define LT_TEST_SUPPORT_H

#include <stdint.h>

#include "lazytrace.h"

/* The library's deterministic generator (lt__splitmix_next, lt__splitmix_unit), so that every
 * failure reproduces from its seed. */
#include "scenes/splitmix.h"

/* n rays between random points of the scene's bounds grown by 10%: many start inside. */
void lt_test_random_rays(const lt_scene *scene, uint64_t seed, size_t n, lt_ray *out);
/* Camera rays of the scene's named camera, width x height. */
void lt_test_camera_rays(const lt_scene *scene, const char *camera, int width, int height, lt_ray *out);

/* Whether an OpenCL device can be used (and LT_TEST_NATIVE_ONLY is not set). */
int lt_test_opencl_available(void);
/* Number of rays whose closest hits differ in prim or t (bitwise); prints the first few. */
size_t lt_test_count_mismatches(const char *what, const lt_hit *a, const lt_hit *b, size_t n);
/* Number of rays on which a and b disagree about being occluded. */
size_t lt_test_count_occlusion_mismatches(const lt_hit *a, const lt_hit *b, size_t n);
/* A context of this device and launch shape (0: the default) for lt_test_trace_with. */
typedef struct lt_test_launch {
  lt_device_kind device;
  int work_groups, local_size;
} lt_test_launch;
/* Creates a context with launch shape l and a structure with config sc over the scene, traces
 * the rays (query: LT_QUERY_*), destroys both and returns the malloc'ed hits; NULL (and says
 * why on stderr) when anything fails. Statistics go to stats (may be NULL). */
lt_hit *lt_test_trace_with(const lt_scene *scene, const lt_test_launch *l, const lt_structure_config *sc,
                           const lt_ray *rays, size_t n, int query, lt_stats *stats);
/* Traces the rays through a structure of config sc on every backend (native, and OpenCL where
 * there is one), closest hit and any hit, against ref and ref_any (the reference's answers to
 * the same rays): the mismatches over all of them, (size_t)-1 when a create or trace fails. */
size_t lt_test_backend_mismatches(const char *what, const lt_scene *scene, const lt_structure_config *sc,
                                  const lt_ray *rays, size_t n, const lt_hit *ref, const lt_hit *ref_any);
/* The rays of the generator tests: side x side from the outer camera, as many from the close
 * one, then `random` random rays of the given seed; *n says how many in all. */
lt_ray *lt_test_generator_rays(const lt_scene *scene, int side, size_t random, uint64_t seed, size_t *n);
/* Ambient-occlusion rays in pixel order: the close camera's side x side primary rays (into
 * primary, side * side of them), then 8 rays from each brute-force hit, as long as a tenth of the
 * sum of the scene's extents; returns them (*n of them), or NULL when they are not more than
 * the primary rays or something failed. */
lt_ray *lt_test_ao_rays(const lt_scene *scene, int side, lt_ray *primary, size_t *n);
/* A structure of `kind` started with a pool of 2 slots, which fills at once, in every build
 * mode it has, on 500 random rays over sphere:5: the closest hits that differ from brute
 * force's after its retries, summed over the modes; (size_t)-1 when a create or trace fails. */
size_t lt_test_small_pool_mismatches(lt_structure_kind kind);

#endif
