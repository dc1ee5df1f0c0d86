/* Fuzz target: the ray file reader (runtime/rays_io.c), and the rays it reads traced through
 * the reference and the default structure on the native backend, which must agree. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lazytrace.h"
#include "tests/fuzz/fuzz_target.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static lt_context *ctx;
  static lt_scene *scene;
  if (!ctx) {
    lt_context_config native = {LT_DEVICE_NATIVE, 0, 1, 0, 1};
    if (lt_context_create(&native, &ctx) != LT_OK || lt_scene_load("sphere:1", &scene) != LT_OK) abort();
  }
  const char *path = lt_fuzz_file(data, size, ".rays");
  if (!path) return 0;
  lt_ray *rays = NULL;
  size_t n = 0;
  lt_status status = lt_rays_read(path, &rays, &n);
  unlink(path);
  if (status || n == 0 || n > 4096) {
    free(rays);
    return 0;
  }

  /* Any bytes are some rays: NaN, infinities, zero directions included. Hits must agree. */
  lt_hit *ref = malloc(n * sizeof *ref), *hits = malloc(n * sizeof *hits);
  lt_structure *s;
  if (ref && hits && lt_structure_create(ctx, scene, NULL, NULL, &s) == LT_OK) {
    if (lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref) != LT_OK ||
        lt_structure_trace(s, rays, n, LT_QUERY_CLOSEST, hits, NULL) != LT_OK)
      abort();
    for (size_t i = 0; i < n; i++)
      if (hits[i].prim != ref[i].prim || memcmp(&hits[i].t, &ref[i].t, sizeof(float)) != 0) abort();
    lt_structure_destroy(s);
  }
  free(ref), free(hits), free(rays);
  return 0;
}
