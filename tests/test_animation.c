/* Animated scenes (scenes/scene_motion.c): instance keyframes move triangles rigidly and
 * interpolate between keys; explode:BASE starts at BASE, keeps every triangle's shape and is
 * the same in every run; every structure, build mode and backend rebuilt over a moved scene
 * returns the brute-force reference's hits on every frame tried, and a frame's image is the
 * brute-force one; bad motion is refused with the file, the line and what was wrong; the
 * statistics keep one record per frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "tests/support.h"
#include "tests/temp_files.h"

/* A sphere swept across a house, turning and growing, and a static sphere beside it. */
static const char keyframed_scene[] =
    "{\"meshes\": [{\"generator\": \"house\"}, {\"generator\": \"sphere:2\"}],\n"
    " \"instances\": [{\"mesh\": 0},\n"
    "   {\"mesh\": 1, \"scale\": 2, \"keyframes\": [{\"time\": 0, \"translate\": [-8, 3, 0]},\n"
    "      {\"time\": 0.5, \"translate\": [0, 3, 0], \"rotate_y\": 90},\n"
    "      {\"time\": 1, \"translate\": [8, 5, 2], \"rotate_y\": 180, \"scale\": 3}]},\n"
    "   {\"mesh\": 1, \"translate\": [0, 0, -6]}]}\n";

/* Two exploding spheres, one of them carried along by keyframes while it bursts. */
static const char exploding_scene[] =
    "{\"meshes\": [{\"generator\": \"explode:sphere:3\"}],\n"
    " \"instances\": [{\"mesh\": 0},\n"
    "   {\"mesh\": 0, \"keyframes\": [{\"time\": 0, \"translate\": [3, 0, 0]},\n"
    "                                  {\"time\": 1, \"translate\": [6, 1, 0]}]}]}\n";

static int setup(void **state) { return lt_test_temp_dir_create(state); }
static int teardown(void **state) { return lt_test_temp_dir_remove(state); }

static float *copy_triangles(const lt_scene *scene) {
  size_t bytes = 9 * sizeof(float) * lt_scene_triangle_count(scene);
  float *copy = malloc(bytes);
  assert_non_null(copy);
  memcpy(copy, lt_scene_triangles(scene), bytes);
  return copy;
}

/* ---- Keyframes ---- */

/* Halfway between two keys, the moving sphere is the sphere scaled, turned and moved by the
 * average of the keys; the static instance and the house never move; time 0 restores the
 * loaded triangles bit for bit. */
static void animation_keyframes_interpolate_rigidly(void **state) {
  (void)state;
  lt_scene *scene = lt_test_load_ok(lt_test_write_file("keys.json", keyframed_scene));
  lt_scene *house = lt_test_load_ok("house"), *sphere = lt_test_load_ok("sphere:2");
  size_t nh = lt_scene_triangle_count(house), ns = lt_scene_triangle_count(sphere);
  assert_int_equal(lt_scene_triangle_count(scene), nh + 2 * ns);
  assert_true(lt_scene_is_animated(scene));
  float *loaded = copy_triangles(scene);

  /* Time 0.25: between the first two keys, a quarter of the way: 45 degrees, (-4, 3, 0). */
  lt_scene_set_time(scene, 0.25);
  const float *t = lt_scene_triangles(scene), *s = lt_scene_triangles(sphere);
  double c = cos(45.0 * 3.14159265358979 / 180.0), sn = sin(45.0 * 3.14159265358979 / 180.0), worst = 0.0;
  for (size_t i = 0; i < 3 * ns; i++) {
    const float *q = s + 3 * i, *p = t + 9 * nh + 3 * i;
    double x = 2.0 * q[0], y = 2.0 * q[1], z = 2.0 * q[2];
    double want[3] = {c * x + sn * z - 4.0, y + 3.0, -sn * x + c * z};
    for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(p[k] - want[k]));
  }
  assert_true(worst < 1e-4);
  assert_memory_equal(t, loaded, 9 * sizeof(float) * nh);
  assert_memory_equal(t + 9 * (nh + ns), loaded + 9 * (nh + ns), 9 * sizeof(float) * ns);

  /* Past the last key the pose holds; time 0 gives back exactly what was loaded. */
  lt_scene_set_time(scene, 1.0);
  float *last = copy_triangles(scene);
  lt_scene_set_time(scene, 7.0);
  assert_memory_equal(lt_scene_triangles(scene), last, 9 * sizeof(float) * lt_scene_triangle_count(scene));
  lt_scene_set_time(scene, 0.0);
  assert_memory_equal(lt_scene_triangles(scene), loaded, 9 * sizeof(float) * lt_scene_triangle_count(scene));

  /* A scene that does not move says so, and time does nothing to it. */
  assert_false(lt_scene_is_animated(house));
  lt_scene_set_time(house, 0.5);
  assert_memory_equal(lt_scene_triangles(house), loaded, 9 * sizeof(float) * nh);
  free(loaded), free(last);
  lt_scene_destroy(scene), lt_scene_destroy(house), lt_scene_destroy(sphere);
}

/* ---- Explosions ---- */

static double edge(const float *t, int a, int b) {
  double d = 0.0;
  for (int k = 0; k < 3; k++) d += (t[3 * a + k] - t[3 * b + k]) * (double)(t[3 * a + k] - t[3 * b + k]);
  return sqrt(d);
}

/* The mean distance of the triangles' centroids from the origin (the sphere's centre). */
static double spread(const lt_scene *scene) {
  const float *t = lt_scene_triangles(scene);
  double sum = 0.0;
  for (size_t i = 0; i < lt_scene_triangle_count(scene); i++) {
    double g[3];
    for (int k = 0; k < 3; k++) g[k] = (t[9 * i + k] + t[9 * i + 3 + k] + t[9 * i + 6 + k]) / 3.0;
    sum += sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  }
  return sum / lt_scene_triangle_count(scene);
}

/* At time 0 the explosion is its base exactly; later, every triangle keeps its edge lengths
 * (each piece moves rigidly), the pieces spread further with time, and two loads agree bit for
 * bit at any time. */
static void animation_explode_starts_at_base_and_repeats(void **state) {
  (void)state;
  lt_scene *a = lt_test_load_ok("explode:sphere:2"), *b = lt_test_load_ok("explode:sphere:2");
  lt_scene *base = lt_test_load_ok("sphere:2");
  size_t n = lt_scene_triangle_count(base);
  assert_int_equal(lt_scene_triangle_count(a), n);
  assert_true(lt_scene_is_animated(a));
  assert_memory_equal(lt_scene_triangles(a), lt_scene_triangles(base), 9 * sizeof(float) * n);

  double last_spread = spread(a);
  for (int f = 1; f <= 4; f++) {
    lt_scene_set_time(a, lt_frame_time(f, 5));
    lt_scene_set_time(b, lt_frame_time(f, 5));
    assert_memory_equal(lt_scene_triangles(a), lt_scene_triangles(b), 9 * sizeof(float) * n);
    for (size_t i = 0; i < n; i++) {
      const float *p = lt_scene_triangles(a) + 9 * i, *q = lt_scene_triangles(base) + 9 * i;
      for (int e = 0; e < 3; e++) assert_true(fabs(edge(p, e, (e + 1) % 3) - edge(q, e, (e + 1) % 3)) < 1e-4);
    }
    double now = spread(a);
    assert_true(now > last_spread);
    last_spread = now;
  }
  lt_scene_destroy(a), lt_scene_destroy(b), lt_scene_destroy(base);
}

/* ---- Every frame against brute force ---- */

/* Turns the rays towards the centroids of triangles spread over the scene's numbering, so that
 * scattered debris is hit too, not only missed. */
static void aim_at_triangles(const lt_scene *scene, lt_ray *rays, size_t n) {
  size_t count = lt_scene_triangle_count(scene);
  for (size_t i = 0; i < n; i++) {
    const float *t = lt_scene_triangles(scene) + 9 * ((i * 7919u) % count);
    for (int k = 0; k < 3; k++) rays[i].dir[k] = (t[k] + t[3 + k] + t[6 + k]) / 3.0f - rays[i].org[k];
    rays[i].tmin = 0.0f, rays[i].tmax = INFINITY;
  }
}

/* Frame f of `frames` of the scene: `side` x `side` camera rays, then `random` rays (half of
 * them aimed at triangles), and the brute-force closest and any hits of them all. */
static void frame_rays(lt_scene *scene, int f, int frames, int side, int random, uint64_t seed, lt_ray *rays,
                       lt_hit *ref, lt_hit *ref_any) {
  size_t n = (size_t)side * side + random;
  lt_scene_set_time(scene, lt_frame_time(f, frames));
  lt_camera camera = lt_scene_camera(scene);
  lt_camera_primary_rays(&camera, side, side, rays);
  lt_test_random_rays(scene, seed, random, rays + side * side);
  aim_at_triangles(scene, rays + side * side, random / 2);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, ref), LT_OK);
  assert_int_equal(lt_reference_trace(scene, rays, n, LT_QUERY_ANY, ref_any), LT_OK);
}

/* Frames 0, 2 and 4 of 5 of the scene: camera and random rays over the moved triangles,
 * through every structure and build mode on every backend, rebuilt for each frame. */
static void check_frames(lt_scene *scene, const char *name) {
  enum { SIDE = 20, RANDOM = 600, MAX_VARIANTS = 64 };
  lt_structure_kind kinds[MAX_VARIANTS];
  lt_build_mode modes[MAX_VARIANTS];
  size_t variants = lt_structure_variants(kinds, modes, MAX_VARIANTS), n = SIDE * SIDE + RANDOM;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *ref = malloc(n * sizeof *ref), *ref_any = malloc(n * sizeof *ref_any);
  assert_true(rays && ref && ref_any);
  for (int f = 0; f < 5; f += 2) {
    frame_rays(scene, f, 5, SIDE, RANDOM, 17 + (uint64_t)f, rays, ref, ref_any);
    size_t hits = 0;
    for (size_t i = 0; i < n; i++) hits += ref[i].prim >= 0;
    if (hits < n / 5) fail_msg("%s frame %d: only %zu of %zu rays hit", name, f, hits, n);
    for (size_t v = 0; v < variants; v++) {
      lt_structure_config sc = lt_structure_config_default(kinds[v]);
      sc.build = modes[v];
      char what[128];
      snprintf(what, sizeof what, "%s frame %d: %s %s", name, f, lt_structure_kind_name(kinds[v]),
               lt_build_mode_name(modes[v]));
      size_t bad = lt_test_backend_mismatches(what, scene, &sc, rays, n, ref, ref_any);
      if (bad) fail_msg("%s: %zu rays differ from brute force", what, bad);
    }
  }
  free(rays), free(ref), free(ref_any);
}

static void animation_keyframed_frames_match_brute_force(void **state) {
  (void)state;
  lt_scene *scene = lt_test_load_ok(lt_test_write_file("keys.json", keyframed_scene));
  check_frames(scene, "keyframes");
  lt_scene_destroy(scene);
}

static void animation_exploding_frames_match_brute_force(void **state) {
  (void)state;
  lt_scene *scene = lt_test_load_ok("explode:house");
  check_frames(scene, "explode:house");
  lt_scene_destroy(scene);
  scene = lt_test_load_ok(lt_test_write_file("burst.json", exploding_scene));
  check_frames(scene, "exploding instances");
  lt_scene_destroy(scene);
}

/* The occluded animation of Table 5 (docs/scenes/town.json: 6x5 houses, 12 agents walking the
 * streets, an exploding ball), frames 0 and 4 of 5: its street camera's rays and rays at its
 * triangles, through the builds a moving scene would use (the on-demand BVH with the SAH and the
 * Morton top, requested and speculative, and the LBVH) on every backend, against brute force.
 * Three million triangles make the reference slow, so only these builds and two frames. */
static void animation_town_frames_match_brute_force(void **state) {
  (void)state;
  enum { SIDE = 16, RANDOM = 200 };
  lt_scene *scene = lt_test_load_ok(LT_TEST_SOURCE_DIR "/docs/scenes/town.json");
  assert_true(lt_scene_is_animated(scene));
  size_t n = SIDE * SIDE + RANDOM;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *ref = malloc(n * sizeof *ref), *ref_any = malloc(n * sizeof *ref_any);
  assert_true(rays && ref && ref_any);
  for (int f = 0; f < 5; f += 4) {
    frame_rays(scene, f, 5, SIDE, RANDOM, 29 + (uint64_t)f, rays, ref, ref_any);
    for (int v = 0; v < 5; v++) {
      lt_structure_config sc = lt_structure_config_default(v < 4 ? LT_STRUCTURE_BVH : LT_STRUCTURE_LBVH);
      if (v < 4) sc.build = v % 2 ? LT_BUILD_SPECULATIVE : LT_BUILD_REQUESTED;
      if (v >= 2 && v < 4) sc.bvh_top = LT_BVH_TOP_MORTON;
      char what[96];
      snprintf(what, sizeof what, "town frame %d: %s %s%s", f, v < 4 ? "bvh" : "lbvh",
               v < 4 ? lt_build_mode_name(sc.build) : "", v >= 2 && v < 4 ? " morton top" : "");
      size_t bad = lt_test_backend_mismatches(what, scene, &sc, rays, n, ref, ref_any);
      if (bad) fail_msg("%s: %zu rays differ from brute force", what, bad);
    }
  }
  free(rays), free(ref), free(ref_any);
  lt_scene_destroy(scene);
}

/* An animation's images, as render --frames draws them: every frame through a structure rebuilt
 * over the moved scene equals the brute-force image of that frame, pixel for pixel, and the
 * frames differ from one another. */
static void animation_frame_images_match_brute_force(void **state) {
  (void)state;
  enum { W = 40, H = 30, FRAMES = 3 };
  lt_scene *scene = lt_test_load_ok(lt_test_write_file("burst.json", exploding_scene));
  lt_context *ctx;
  lt_context_config native = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  assert_int_equal(lt_context_create(&native, &ctx), LT_OK);
  lt_effects effects = {.primary = 1, .ao_samples = 4, .ao_distance = 0.5f, .diffuse_bounces = 1};
  lt_render_config config = {W, H, 1, &effects, 5, 0, 0};
  float *image = malloc(3 * sizeof(float) * W * H), *ref = malloc(3 * sizeof(float) * W * H);
  float *first = malloc(3 * sizeof(float) * W * H);
  assert_true(image && ref && first);
  for (int f = 0; f < FRAMES; f++) {
    lt_scene_set_time(scene, lt_frame_time(f, FRAMES));
    lt_structure *structure = NULL;
    assert_int_equal(lt_structure_create(ctx, scene, NULL, NULL, &structure), LT_OK);
    assert_int_equal(lt_render(structure, scene, &config, image, NULL), LT_OK);
    lt_structure_destroy(structure);
    assert_int_equal(lt_render(NULL, scene, &config, ref, NULL), LT_OK);
    assert_memory_equal(image, ref, 3 * sizeof(float) * W * H);
    if (f == 0) memcpy(first, image, 3 * sizeof(float) * W * H);
    else assert_memory_not_equal(image, first, 3 * sizeof(float) * W * H);
  }
  free(image), free(ref), free(first);
  lt_context_destroy(ctx);
  lt_scene_destroy(scene);
}

/* ---- Bad motion ---- */

static void animation_bad_motion_is_refused(void **state) {
  (void)state;
  static const struct {
    const char *json, *message;
  } cases[] = {
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0,\n \"keyframes\": 3}]}",
       ":3: instances[0].keyframes: expected an array of 1 to 1024 keyframes"},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0, \"keyframes\": []}]}",
       ":2: instances[0].keyframes: expected an array of 1 to 1024 keyframes"},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0, \"keyframes\": [\n"
       "  {\"translate\": [1, 0, 0]}]}]}",
       ":3: instances[0].keyframes[0].time: expected the keyframe's time, a number from 0 to 1, got nothing"},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0, \"keyframes\": [\n"
       "  {\"time\": 0},\n  {\"time\": 1.5}]}]}",
       ":4: instances[0].keyframes[1].time: expected a number from 0 to 1, got the number 1.5"},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0, \"keyframes\": [\n"
       "  {\"time\": 0.5},\n  {\"time\": 0.5}]}]}",
       ":4: instances[0].keyframes[1].time: expected a time after the previous keyframe's (0.5), got the number 0.5"},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0, \"keyframes\": [\n"
       "  {\"time\": 0, \"rotate\": 5}]}]}",
       ":3: instances[0].keyframes[0]: unknown key 'rotate' (expected one of: time, translate, rotate_y, scale)"},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0, \"keyframes\": [\n"
       "  {\"time\": 0},\n  {\"time\": 1,\n   \"translate\": [1, 2]}]}]}",
       ":5: instances[0].keyframes[1].translate: expected an array of 3 finite numbers, got an array of 2"},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"instances\": [{\"mesh\": 0, \"keyframes\": [\n"
       "  {\"time\": 0, \"scale\": 0}]}]}",
       ":3: instances[0].keyframes[0].scale: expected a number from 1e-06 to 1e+06, got the number 0"},
      {"{\"meshes\": [\n {\"generator\": \"explode\"}]}", ":2: meshes[0].generator: explode: expected explode:BASE"},
      {"{\"meshes\": [\n\n {\"generator\": \"explode:explode:sphere:1\"}]}",
       ":3: meshes[0].generator: explode:explode:sphere:1: the base of an explosion cannot explode itself"},
      {"{\"meshes\": [{\"generator\": \"explode:pyramid\"}]}", ":1: meshes[0].generator: unknown generator 'pyramid'"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    const char *message;
    lt_scene *scene;
    lt_status status = lt_test_load_bad(i, cases[i].json, &message, &scene);
    if (status == LT_OK || !message || !strstr(message, cases[i].message))
      fail_msg("case %zu: got %s \"%s\", want an error naming the file with \"%s\"", i, lt_status_name(status),
               lt_last_error(), cases[i].message);
    assert_null(scene);
  }

  /* The generator spec alone, outside a scene file. */
  lt_scene *scene = NULL;
  assert_int_equal(lt_scene_load("explode", &scene), LT_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(lt_last_error(), "expected explode:BASE"));
  assert_int_equal(lt_scene_load("explode:sphere:99", &scene), LT_ERROR_INVALID_ARGUMENT);
  assert_non_null(strstr(lt_last_error(), "sphere:99"));
}

/* ---- Statistics per frame ---- */

/* Frames are recorded in order, survive copying a frame's statistics over the totals, and
 * appear in the JSON as the "frames" array; without frames it is null. */
static void animation_stats_record_frames(void **state) {
  (void)state;
  lt_stats *totals, *frame;
  assert_int_equal(lt_stats_create(&totals), LT_OK);
  assert_int_equal(lt_stats_create(&frame), LT_OK);
  char *text = NULL;
  size_t bytes = 0;
  FILE *f = open_memstream(&text, &bytes);
  assert_int_equal(lt_stats_write_json(totals, f), LT_OK);
  fclose(f);
  assert_non_null(strstr(text, "\"frames\": null"));
  free(text);

  for (int i = 0; i < 3; i++) {
    lt_stats_reset(frame);
    lt_stats_set(frame, "rays", 100 + i);
    lt_stats_set(frame, "build_ms", 1.5 * i);
    lt_stats_set(frame, "trace_ms", 2.0);
    lt_stats_set(frame, "total_ms", 1.5 * i + 2.0);
    lt_stats_set(frame, "nodes_built", 10 * i);
    lt_stats_add_frame(totals, frame);
  }
  lt_stats_copy(totals, frame);
  f = open_memstream(&text, &bytes);
  assert_int_equal(lt_stats_write_json(totals, f), LT_OK);
  fclose(f);
  assert_non_null(strstr(text, "{\"frame\": 0, \"rays\": 100, \"build_ms\": 0.000, \"trace_ms\": 2.000, "
                               "\"total_ms\": 2.000, \"nodes_built\": 0}"));
  assert_non_null(strstr(text, "{\"frame\": 2, \"rays\": 102, \"build_ms\": 3.000, \"trace_ms\": 2.000, "
                               "\"total_ms\": 5.000, \"nodes_built\": 20}"));
  assert_non_null(strstr(text, "\"frames_not_recorded\": 0"));
  free(text);
  lt_stats_destroy(totals), lt_stats_destroy(frame);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(animation_keyframes_interpolate_rigidly),
      cmocka_unit_test(animation_explode_starts_at_base_and_repeats),
      cmocka_unit_test(animation_bad_motion_is_refused),
      cmocka_unit_test(animation_stats_record_frames),
      cmocka_unit_test(animation_frame_images_match_brute_force),
      cmocka_unit_test(animation_keyframed_frames_match_brute_force),
      cmocka_unit_test(animation_exploding_frames_match_brute_force),
      cmocka_unit_test(animation_town_frames_match_brute_force),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
