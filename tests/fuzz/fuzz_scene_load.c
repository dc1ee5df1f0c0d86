/* Fuzz targets of the readers lt_scene_load picks by extension: built once per extension
 * (LT_FUZZ_SUFFIX: ".obj" and ".ply" for lazytrace's own OBJ and PLY readers, ".json" for
 * scene files; tests/CMakeLists.txt). */
#include <unistd.h>

#include "lazytrace.h"
#include "tests/fuzz/fuzz_target.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = lt_fuzz_file(data, size, LT_FUZZ_SUFFIX);
  if (!path) return 0;
  lt_scene *scene = NULL;
  if (lt_scene_load(path, &scene) == LT_OK) {
    /* Whatever loaded is a usable scene: bounds and triangles can be read. */
    float lo[3], hi[3];
    lt_scene_bounds(scene, lo, hi);
    volatile float sink = lt_scene_triangle_count(scene) ? lt_scene_triangles(scene)[0] : 0.0f;
    (void)sink;
    lt_scene_destroy(scene);
  }
  unlink(path);
  return 0;
}
