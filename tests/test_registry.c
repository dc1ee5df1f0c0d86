/* The host registry of structures: every entry is complete and consistent, its kernels exist
 * in the program, its options parse, and names, help and variant lists all come from it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "runtime/context_internal.h"
#include "runtime/registry.h"
#include "tests/support.h"

static void registry_entries_are_complete_and_consistent(void **state) {
  (void)state;
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++) {
    const lt__structure_class *c = lt__structure_class_of((lt_structure_kind)k);
    assert_non_null(c);
    assert_true(c->name && *c->name && c->summary && *c->summary);
    assert_true(c->create && c->trace && c->put_stats && c->release && c->kernels && c->kernels[0]);
    assert_int_equal(c->defaults.kind, k);
    assert_true(c->modes & (1u << c->defaults.build)); /* its default mode is one it has */
    assert_int_equal(c->modes & (1u << LT_BUILD_DEFAULT), 0);

    /* The name parses back to the kind, and differs from every other entry's. */
    lt_structure_kind back;
    assert_int_equal(lt_structure_kind_parse(c->name, &back), LT_OK);
    assert_int_equal(back, k);
    for (int o = 0; o < k; o++) assert_string_not_equal(c->name, lt__structure_class_of((lt_structure_kind)o)->name);
  }
  assert_null(lt__structure_class_of(LT_STRUCTURE_COUNT));
}

static void registry_planned_names_are_refused_and_unknown_ones_named(void **state) {
  (void)state;
  lt_structure_kind kind;
  /* Each planned name (the list may be empty) is refused as not implemented yet. */
  char names[256];
  snprintf(names, sizeof names, "%s", lt_structure_planned());
  for (char *name = strtok(names, ", "); name; name = strtok(NULL, ", ")) {
    assert_int_equal(lt_structure_kind_parse(name, &kind), LT_ERROR_UNSUPPORTED);
    assert_non_null(strstr(lt_last_error(), "not implemented yet"));
  }
  /* The escape-index BVH, planned until issue 16, is a structure now. */
  assert_int_equal(lt_structure_kind_parse("escape-bvh", &kind), LT_OK);
  assert_int_equal(kind, LT_STRUCTURE_ESCAPE_BVH);
  assert_int_equal(lt_structure_kind_parse("octree", &kind), LT_ERROR_INVALID_ARGUMENT);
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++) assert_non_null(strstr(lt_last_error(), lt_structure_kind_name(k)));
  /* No implemented name is still listed as planned. */
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++) {
    const char *planned = lt_structure_planned(), *name = lt_structure_kind_name((lt_structure_kind)k);
    const char *at = strstr(planned, name);
    int listed = at && (at == planned || at[-1] == ' ') && (at[strlen(name)] == ',' || at[strlen(name)] == '\0');
    assert_false(listed);
  }
}

static void registry_variants_cover_every_mode_of_every_entry(void **state) {
  (void)state;
  lt_structure_kind kinds[3 * LT_STRUCTURE_COUNT];
  lt_build_mode modes[3 * LT_STRUCTURE_COUNT];
  size_t n = lt_structure_variants(kinds, modes, 3 * LT_STRUCTURE_COUNT);
  size_t expected = 0;
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++)
    for (int m = LT_BUILD_FULL; m <= LT_BUILD_SPECULATIVE; m++) expected += (lt_structure_modes(k) >> m) & 1;
  assert_int_equal(n, expected);
  for (size_t i = 0; i < n; i++) assert_true(lt_structure_modes(kinds[i]) & (1u << modes[i]));
}

static void registry_options_parse_into_the_config(void **state) {
  (void)state;
  lt_structure_config c;
  memset(&c, 0, sizeof c);
  assert_int_equal(lt_structure_option(&c, "--leaf-size", "4"), LT_OK);
  assert_int_equal(lt_structure_option(&c, "--bins", "8"), LT_OK);
  assert_int_equal(lt_structure_option(&c, "--grid-density", "1.5"), LT_OK);
  assert_int_equal(c.max_leaf_size, 4);
  assert_int_equal(c.sah_bins, 8);
  assert_true(c.grid_density == 1.5f);
  assert_int_equal(lt_structure_option(&c, "--bins", "33"), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt_structure_option(&c, "--bins", "2.5"), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt_structure_option(&c, "--grid-density", "nan"), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt_structure_option(&c, "--frobnicate", "1"), LT_ERROR_UNSUPPORTED);
  assert_int_equal(c.sah_bins, 8); /* a refused value changes nothing */
  /* Help names every option of every structure, each with its default (none cut off). */
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++) {
    const char *text = lt_structure_parameters((lt_structure_kind)k);
    assert_non_null(text);
    int options = 0, defaults = 0;
    for (const lt__param *p = lt__structure_class_of((lt_structure_kind)k)->params; p && p->option; p++, options++)
      assert_non_null(strstr(text, p->option));
    for (const char *at = text; (at = strstr(at, "(default ")) != NULL; at++) defaults++;
    assert_int_equal(defaults, options);
  }
}

/* Every kernel an entry names is an entry point of the program (OpenCL, where there is one). */
static void registry_kernels_exist_in_the_program(void **state) {
  (void)state;
  lt_context *ctx;
  lt_context_config opencl = {LT_DEVICE_OPENCL, 0, 0, 0, 1};
  if (getenv("LT_TEST_NATIVE_ONLY") || lt_context_create(&opencl, &ctx) != LT_OK) {
    fprintf(stderr, "no OpenCL device: kernels not checked\n");
    return;
  }
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++)
    for (const char *const *name = lt__structure_class_of((lt_structure_kind)k)->kernels; *name; name++) {
      lt__kernel *kernel;
      assert_int_equal(lt__opencl_kernel(ctx, *name, &kernel), LT_OK);
    }
  lt_context_destroy(ctx);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(registry_entries_are_complete_and_consistent),
      cmocka_unit_test(registry_planned_names_are_refused_and_unknown_ones_named),
      cmocka_unit_test(registry_variants_cover_every_mode_of_every_entry),
      cmocka_unit_test(registry_options_parse_into_the_config),
      cmocka_unit_test(registry_kernels_exist_in_the_program),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
