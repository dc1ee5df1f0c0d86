/* Fault injection that every structure inherits, because the variants come from the registry:
 * the smallest capacities force every overflow-and-retry path and must give the same hits as
 * brute force; an allocation failure at each allocation site of create and trace gives a clean
 * error (under AddressSanitizer, no leak) and a structure created afterwards works. */
#include <setjmp.h>
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

static void faults_tiny_capacities_retry_to_the_same_hits(void **state) {
  (void)state;
  lt_context *ctx = native_context();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("hairball:300", &scene), LT_OK);
  lt_ray *rays = malloc(RAYS * sizeof *rays);
  lt_hit *ref = malloc(RAYS * sizeof *ref), *hits = malloc(RAYS * sizeof *hits);
  lt_test_random_rays(scene, 41, RAYS, rays);
  assert_int_equal(lt_reference_trace(scene, rays, RAYS, LT_QUERY_CLOSEST, ref), LT_OK);
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
  free(rays), free(ref), free(hits);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
}

/* For every variant, the k-th buffer allocation of create plus two traces fails, for every k
 * until one run needs fewer: each failure is a clean out-of-memory error, and the first run
 * without a failure gives the reference's hits. */
static void faults_every_allocation_failure_is_a_clean_error(void **state) {
  (void)state;
  lt_context *ctx = native_context();
  lt_scene *scene;
  assert_int_equal(lt_scene_load("sphere:2", &scene), LT_OK);
  lt_ray *rays = malloc(RAYS * sizeof *rays);
  lt_hit *ref = malloc(RAYS * sizeof *ref), *hits = malloc(RAYS * sizeof *hits);
  lt_test_random_rays(scene, 43, RAYS, rays);
  assert_int_equal(lt_reference_trace(scene, rays, RAYS, LT_QUERY_CLOSEST, ref), LT_OK);
  size_t variants = lt_structure_variants(NULL, NULL, 0);
  for (size_t v = 0; v < variants; v++) {
    lt_structure_config c = variant_config(v);
    int failures = 0;
    for (int k = 0; k < 200; k++) {
      lt_structure *s = NULL;
      lt__buffer_fail_after = k;
      lt_status status = lt_structure_create(ctx, scene, &c, NULL, &s);
      if (!status) status = lt_structure_trace(s, rays, RAYS, LT_QUERY_CLOSEST, hits, NULL);
      if (!status) status = lt_structure_trace(s, rays, RAYS, LT_QUERY_ANY, hits, NULL);
      int injected = lt__buffer_fail_after < 0;
      lt__buffer_fail_after = -1;
      lt_structure_destroy(s);
      if (!injected) {
        /* This run needed fewer than k + 1 allocations: it must have succeeded. */
        assert_int_equal(status, LT_OK);
        break;
      }
      assert_int_equal(status, LT_ERROR_DEVICE_MEMORY);
      failures++;
    }
    assert_true(failures > 0);
    fprintf(stderr, "%s %s: %d allocation sites failed cleanly\n", lt_structure_kind_name(c.kind),
            lt_build_mode_name(c.build), failures);

    /* And after all that, the variant still works. */
    lt_structure *s;
    assert_int_equal(lt_structure_create(ctx, scene, &c, NULL, &s), LT_OK);
    assert_int_equal(lt_structure_trace(s, rays, RAYS, LT_QUERY_CLOSEST, hits, NULL), LT_OK);
    assert_int_equal(lt_test_count_mismatches("after injected failures", hits, ref, RAYS), 0);
    lt_structure_destroy(s);
  }
  free(rays), free(ref), free(hits);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(faults_tiny_capacities_retry_to_the_same_hits),
      cmocka_unit_test(faults_every_allocation_failure_is_a_clean_error),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
