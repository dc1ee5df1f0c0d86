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

/* For every variant, the k-th buffer allocation of create plus two traces fails, for every k
 * until one run needs fewer: each failure is a clean out-of-memory error, and the first run
 * without a failure gives the reference's hits. */
static void faults_every_allocation_failure_is_a_clean_error(void **state) {
  (void)state;
  fixture f = fixture_new("sphere:2", 43);
  lt_context *ctx = f.ctx;
  lt_scene *scene = f.scene;
  lt_ray *rays = f.rays;
  lt_hit *ref = f.ref, *hits = f.hits;
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
  fixture_free(&f);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(faults_tiny_capacities_retry_to_the_same_hits),
      cmocka_unit_test(faults_every_allocation_failure_is_a_clean_error),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
