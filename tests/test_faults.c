/* Fault injection that every structure inherits, because the variants come from the registry:
 * the smallest capacities force every overflow-and-retry path and must give the same hits as
 * brute force; an allocation failure at each allocation site of create and trace, device
 * buffers and host memory alike, gives a clean error (under AddressSanitizer, no leak) and a
 * structure created afterwards works.
 *
 * Host memory: this executable is linked with --wrap for malloc, calloc, realloc and
 * aligned_alloc (tests/CMakeLists.txt), so every call the library makes comes here first, and
 * a new structure's allocation sites are covered without naming them. */
#include <setjmp.h>
#include <stdatomic.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "runtime/buffer.h"
#include "runtime/structure_internal.h"
#include "tests/support.h"

#define MAX_VARIANTS (3 * LT_STRUCTURE_COUNT)
#define RAYS 2000

/* Host allocations: while host_fail_after >= 0, the call that finds it at 0 fails. Worker
 * threads allocate too, hence the atomic. */
static atomic_int host_fail_after = -1;

void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t size);
void *__real_aligned_alloc(size_t alignment, size_t size);

static int host_injected_failure(void) {
  int left = atomic_load(&host_fail_after);
  while (left >= 0)
    if (atomic_compare_exchange_weak(&host_fail_after, &left, left - 1)) return left == 0;
  return 0;
}

void *__wrap_malloc(size_t size) { return host_injected_failure() ? NULL : __real_malloc(size); }
void *__wrap_calloc(size_t count, size_t size) { return host_injected_failure() ? NULL : __real_calloc(count, size); }
void *__wrap_realloc(void *p, size_t size) { return host_injected_failure() ? NULL : __real_realloc(p, size); }
void *__wrap_aligned_alloc(size_t alignment, size_t size) {
  return host_injected_failure() ? NULL : __real_aligned_alloc(alignment, size);
}

static lt_context *native_context(void) {
  lt_context *ctx;
  lt_context_config native = {LT_DEVICE_NATIVE, 0, 2, 0, 1};
  assert_int_equal(lt_context_create(&native, &ctx), LT_OK);
  return ctx;
}

static lt_structure_config variant_config(size_t v) {
  lt_structure_kind kinds[MAX_VARIANTS];
  lt_build_mode modes[MAX_VARIANTS];
  lt_structure_variants(kinds, modes, MAX_VARIANTS);
  lt_structure_config c = lt_structure_config_default(kinds[v]);
  c.build = modes[v];
  return c;
}

/* A scene, random rays through it and their brute-force closest hits. */
typedef struct fixture {
  lt_context *ctx;
  lt_scene *scene;
  lt_ray *rays;
  lt_hit *ref, *hits;
} fixture;

static fixture fixture_new(const char *spec, uint64_t seed) {
  fixture f;
  f.ctx = native_context();
  assert_int_equal(lt_scene_load(spec, &f.scene), LT_OK);
  f.rays = malloc(RAYS * sizeof *f.rays);
  f.ref = malloc(RAYS * sizeof *f.ref), f.hits = malloc(RAYS * sizeof *f.hits);
  lt_test_random_rays(f.scene, seed, RAYS, f.rays);
  assert_int_equal(lt_reference_trace(f.scene, f.rays, RAYS, LT_QUERY_CLOSEST, f.ref), LT_OK);
  return f;
}

static void fixture_free(fixture *f) {
  free(f->rays), free(f->ref), free(f->hits);
  lt_scene_destroy(f->scene);
  lt_context_destroy(f->ctx);
}

static void faults_tiny_capacities_retry_to_the_same_hits(void **state) {
  (void)state;
  fixture f = fixture_new("hairball:300", 41);
  lt_context *ctx = f.ctx;
  lt_scene *scene = f.scene;
  lt_ray *rays = f.rays;
  lt_hit *ref = f.ref, *hits = f.hits;
  size_t variants = lt_structure_variants(NULL, NULL, 0);
  lt__structure_tiny_capacities = 1;
  for (size_t v = 0; v < variants; v++) {
    lt_structure_config c = variant_config(v);
    lt_structure *s;
    assert_int_equal(lt_structure_create(ctx, scene, &c, NULL, &s), LT_OK);
    assert_int_equal(lt_structure_trace(s, rays, RAYS, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
    char what[64];
    snprintf(what, sizeof what, "tiny capacities: %s %s", lt_structure_kind_name(c.kind), lt_build_mode_name(c.build));
    assert_int_equal(lt_test_count_mismatches(what, hits, ref, RAYS), 0);
    lt_structure_destroy(s);
  }
  lt__structure_tiny_capacities = 0;
  fixture_free(&f);
}

/* Which allocations a run fails: device buffers (the library's own counter) or host memory. */
typedef enum { FAIL_BUFFER, FAIL_HOST } fail_site;

static void arm(fail_site site, int k) {
  if (site == FAIL_BUFFER) lt__buffer_fail_after = k;
  else atomic_store(&host_fail_after, k);
}

/* Disarms; returns whether the failure was injected (the run reached allocation k). */
static int disarm(fail_site site) {
  int left = site == FAIL_BUFFER ? lt__buffer_fail_after : atomic_exchange(&host_fail_after, -1);
  lt__buffer_fail_after = -1;
  return left < 0;
}

/* For every variant, the k-th allocation of create plus two traces fails, for every k until
 * one run needs fewer: each failure is a clean out-of-memory error, and the first run without
 * a failure gives the reference's hits. */
static void every_allocation_failure_is_a_clean_error(fail_site site, const char *what) {
  fixture f = fixture_new("sphere:2", 43);
  lt_context *ctx = f.ctx;
  lt_scene *scene = f.scene;
  lt_ray *rays = f.rays;
  lt_hit *ref = f.ref, *hits = f.hits;
  size_t variants = lt_structure_variants(NULL, NULL, 0);
  for (size_t v = 0; v < variants; v++) {
    lt_structure_config c = variant_config(v);
    int failures = 0;
    for (int k = 0; k < 400; k++) {
      lt_structure *s = NULL;
      arm(site, k);
      lt_status status = lt_structure_create(ctx, scene, &c, NULL, &s);
      if (!status) status = lt_structure_trace(s, rays, RAYS, LT_QUERY_CLOSEST, hits, NULL);
      if (!status) status = lt_structure_trace(s, rays, RAYS, LT_QUERY_ANY, hits, NULL);
      int injected = disarm(site);
      lt_structure_destroy(s);
      if (!injected) {
        /* This run needed fewer than k + 1 allocations: it must have succeeded. */
        assert_int_equal(status, LT_OK);
        break;
      }
      if (status != LT_ERROR_DEVICE_MEMORY && status != LT_ERROR_OUT_OF_MEMORY)
        fail_msg("%s allocation %d failed: status %d (%s), not an out-of-memory error", what, k, status,
                 lt_last_error());
      failures++;
    }
    assert_true(failures > 0);
    fprintf(stderr, "%s %s: %d %s allocations failed cleanly\n", lt_structure_kind_name(c.kind),
            lt_build_mode_name(c.build), failures, what);

    /* And after all that, the variant still works. */
    lt_structure *s;
    assert_int_equal(lt_structure_create(ctx, scene, &c, NULL, &s), LT_OK);
    assert_int_equal(lt_structure_trace(s, rays, RAYS, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
    assert_int_equal(lt_test_count_mismatches("after injected failures", hits, ref, RAYS), 0);
    lt_structure_destroy(s);
  }
  fixture_free(&f);
}

static void faults_every_buffer_allocation_failure_is_a_clean_error(void **state) {
  (void)state;
  every_allocation_failure_is_a_clean_error(FAIL_BUFFER, "buffer");
}

static void faults_every_host_allocation_failure_is_a_clean_error(void **state) {
  (void)state;
  every_allocation_failure_is_a_clean_error(FAIL_HOST, "host");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(faults_tiny_capacities_retry_to_the_same_hits),
      cmocka_unit_test(faults_every_buffer_allocation_failure_is_a_clean_error),
      cmocka_unit_test(faults_every_host_allocation_failure_is_a_clean_error),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
