/* Rendering by effects: only the batches the effects call for are traced (no shadow rays
 * without lights, no mirror rays without mirrors, only primary rays for primary alone); enabling
 * an effect changes the rays traced and the nodes built as it should; the estimators give exact
 * values where the answer is known; and an image through the structure matches the one traced
 * by brute force. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lazytrace.h"
#include "tests/temp_files.h"

/* The bound on the mean absolute difference, in 8-bit sRGB levels, between the image through
 * the structure and the brute-force one: both trace the same rays with the same intersection
 * test and tie rule, so they should agree exactly; the bound leaves room for a rare tie. */
#define REFERENCE_MAE_BOUND 0.5

static lt_context *ctx;

static int setup(void **state) {
  lt_context_config config = {LT_DEVICE_NATIVE, 0, 0, 0, 1};
  return lt_test_temp_dir_create(state) == 0 && lt_context_create(&config, &ctx) == LT_OK ? 0 : -1;
}

static int teardown(void **state) {
  lt_context_destroy(ctx);
  return lt_test_temp_dir_remove(state);
}

static lt_scene *scene_from_text(const char *name, const char *text) {
  return lt_test_load_ok(lt_test_write_file(name, text));
}

/* A render through a fresh structure in the given build mode (or brute force with mode < 0);
 * returns the linear image, statistics in stats. */
static float *render(const lt_scene *scene, int mode, const lt_effects *effects, int width, int height,
                     lt_stats *stats) {
  lt_render_config config = {width, height, 1, effects, 7, 0, 0};
  float *image = malloc(3 * sizeof(float) * width * height);
  lt_structure *structure = NULL;
  if (mode >= 0) {
    lt_structure_config sc = lt_structure_config_default(LT_STRUCTURE_BVH);
    sc.build = (lt_build_mode)mode;
    if (lt_structure_create(ctx, scene, &sc, stats, &structure)) fail_msg("structure: %s", lt_last_error());
  }
  if (lt_render(structure, scene, &config, image, stats)) fail_msg("render: %s", lt_last_error());
  lt_structure_destroy(structure);
  return image;
}

static double rays_of(const lt_stats *stats, const char *effect) {
  char key[64];
  snprintf(key, sizeof key, "rays_by_effect.%s", effect);
  return lt_stats_get(stats, key);
}

/* A Cornell box (in millimetres) with a mirror sphere in it; lights as the test needs. */
static const char box_scene[] =
    "{\"meshes\": [{\"generator\": \"cornell\"}, {\"generator\": \"sphere:2\"}],\n"
    " \"instances\": [{\"mesh\": 0}, {\"mesh\": 1, \"translate\": [170, 280, 250], \"scale\": 90, \"material\": 1}],\n"
    " \"materials\": [{\"diffuse\": [0.7, 0.6, 0.5]}, {\"diffuse\": [0.9, 0.9, 0.9], \"mirror\": 0.7}],\n"
    " \"lights\": [LIGHTS],\n"
    " \"effects\": {\"primary\": true, \"shadows\": true, \"ao\": {\"samples\": 3, \"distance\": 80},\n"
    "             \"diffuse\": {\"samples\": 2, \"bounces\": 2}, \"mirror\": {\"depth\": 2},\n"
    "             \"collision\": {\"agents\": 5, \"rays\": 4, \"frames\": 3}}}\n";

/* The box scene with the light list replaced. */
static lt_scene *box_with_lights(const char *name, const char *lights) {
  char text[2048];
  const char *at = strstr(box_scene, "LIGHTS");
  snprintf(text, sizeof text, "%.*s%s%s", (int)(at - box_scene), box_scene, lights, at + 6);
  return scene_from_text(name, text);
}

static void render_without_lights_traces_no_shadow_rays(void **state) {
  (void)state;
  lt_scene *scene = box_with_lights("dark.json", "");
  lt_stats *stats;
  lt_stats_create(&stats);
  free(render(scene, LT_BUILD_SPECULATIVE, NULL, 24, 24, stats));
  assert_true(lt_scene_effects(scene).shadows);
  assert_true(rays_of(stats, "shadows") == 0);
  assert_true(rays_of(stats, "primary") == 24 * 24 && rays_of(stats, "ao") > 0 && rays_of(stats, "diffuse") > 0);
  assert_true(rays_of(stats, "collision") == 5 * 4 * 3);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);

  /* The same scene with a light: shadow rays, at most one per shaded point and light. */
  scene = box_with_lights("lit.json", "{\"point\": [278, 500, 280], \"intensity\": [1e5, 1e5, 1e5]}");
  lt_stats_create(&stats);
  free(render(scene, LT_BUILD_SPECULATIVE, NULL, 24, 24, stats));
  assert_true(rays_of(stats, "shadows") > 0);
  assert_true(rays_of(stats, "shadows") <= rays_of(stats, "primary") + rays_of(stats, "diffuse") + rays_of(stats, "mirror"));
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
}

static void render_without_mirrors_traces_no_mirror_rays(void **state) {
  (void)state;
  lt_scene *scene = scene_from_text("matte.json", "{\"meshes\": [{\"generator\": \"cornell\"}],\n"
                                                  " \"effects\": {\"mirror\": {\"depth\": 3}}}");
  lt_stats *stats;
  lt_stats_create(&stats);
  free(render(scene, LT_BUILD_SPECULATIVE, NULL, 24, 24, stats));
  assert_true(rays_of(stats, "mirror") == 0 && rays_of(stats, "primary") == 24 * 24);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);

  /* With a mirror sphere, mirror rays from the pixels that see it, and no more than depth
   * reflections per pixel. */
  scene = box_with_lights("mirror.json", "");
  lt_effects fx = {.primary = 1, .mirror_depth = 2};
  lt_stats_create(&stats);
  free(render(scene, LT_BUILD_SPECULATIVE, &fx, 24, 24, stats));
  assert_true(rays_of(stats, "mirror") > 0 && rays_of(stats, "mirror") <= 2 * 24 * 24);
  assert_true(rays_of(stats, "shadows") == 0 && rays_of(stats, "ao") == 0 && rays_of(stats, "diffuse") == 0);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
}

static void render_primary_only_traces_only_primary_rays(void **state) {
  (void)state;
  lt_scene *scene = box_with_lights("primary.json", "{\"point\": [278, 500, 280], \"intensity\": [1e5, 1e5, 1e5]}");
  lt_effects fx = {.primary = 1, .shadows = 0};
  lt_stats *stats;
  lt_stats_create(&stats);
  free(render(scene, LT_BUILD_SPECULATIVE, &fx, 32, 16, stats));
  assert_true(rays_of(stats, "primary") == 32 * 16);
  assert_true(lt_stats_get(stats, "rays") == 32 * 16);
  static const char *const others[] = {"shadows", "ao", "diffuse", "mirror", "collision"};
  for (int e = 0; e < 5; e++) assert_true(rays_of(stats, others[e]) == 0);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
}

/* AO rays: exactly the samples per primary hit. Collision: agents x rays x frames. */
static void render_effect_counts_follow_parameters(void **state) {
  (void)state;
  lt_scene *scene = box_with_lights("counts.json", "");
  lt_effects fx = {.primary = 1, .ao_samples = 5, .ao_distance = 50.0f, .collision_agents = 7, .collision_rays = 3,
                   .collision_frames = 2};
  lt_stats *stats;
  lt_stats_create(&stats);
  free(render(scene, LT_BUILD_SPECULATIVE, &fx, 20, 20, stats));

  /* The Cornell box is open at the front: count the primary rays that hit. */
  lt_ray rays[400];
  lt_hit hits[400];
  lt_camera cam = lt_scene_camera(scene);
  lt_camera_primary_rays(&cam, 20, 20, rays);
  assert_int_equal(lt_reference_trace(scene, rays, 400, LT_QUERY_CLOSEST, hits), LT_OK);
  int hit = 0;
  for (int i = 0; i < 400; i++) hit += hits[i].prim >= 0;
  assert_true(rays_of(stats, "ao") == 5.0 * hit);
  assert_true(rays_of(stats, "collision") == 7 * 3 * 2);
  assert_true(lt_stats_get(stats, "rays") == 400 + 5.0 * hit + 42);
  lt_stats_destroy(stats);
  lt_scene_destroy(scene);
}

/* On a house seen from outside, requested mode: AO rays a few centimetres long build few nodes
 * beyond the primary rays', diffuse rays (through windows, onto furniture) many more. */
static void render_short_ao_builds_fewer_nodes_than_diffuse(void **state) {
  (void)state;
  lt_scene *scene;
  assert_int_equal(lt_scene_load("house", &scene), LT_OK);
  lt_effects primary = {.primary = 1};
  lt_effects ao = {.primary = 1, .ao_samples = 4, .ao_distance = 0.05f};
  lt_effects diffuse = {.primary = 1, .diffuse_samples = 4, .diffuse_bounces = 1};
  double nodes[3], rays[3];
  const lt_effects *fx[3] = {&primary, &ao, &diffuse};
  for (int i = 0; i < 3; i++) {
    lt_stats *stats;
    lt_stats_create(&stats);
    free(render(scene, LT_BUILD_REQUESTED, fx[i], 48, 48, stats));
    nodes[i] = lt_stats_get(stats, "nodes_built");
    rays[i] = lt_stats_get(stats, "rays");
    lt_stats_destroy(stats);
  }
  fprintf(stderr, "nodes built: primary %.0f, + AO %.0f, + diffuse %.0f (rays %.0f, %.0f, %.0f)\n", nodes[0], nodes[1],
          nodes[2], rays[0], rays[1], rays[2]);
  assert_true(nodes[0] <= nodes[1] && nodes[1] < nodes[2]);
  assert_true(rays[1] == rays[2]);
  lt_scene_destroy(scene);
}

/* Every effect at once through the structure (speculative and full) against brute force. */
static void render_matches_brute_force_reference(void **state) {
  (void)state;
  lt_scene *scene = box_with_lights("reference.json", "{\"point\": [278, 500, 280], \"intensity\": [8e4, 8e4, 8e4]}, "
                                                      "{\"direction\": [0.3, -1, 0.5], \"intensity\": [0.5, 0.5, 0.5]}");
  const int w = 32, h = 24;
  float *ref = render(scene, -1, NULL, w, h, NULL);
  unsigned char *a = malloc(3 * w * h), *b = malloc(3 * w * h);
  lt_image_to_srgb8(ref, (size_t)w * h, a);
  const int modes[2] = {LT_BUILD_SPECULATIVE, LT_BUILD_FULL};
  for (int m = 0; m < 2; m++) {
    float *img = render(scene, modes[m], NULL, w, h, NULL);
    lt_image_to_srgb8(img, (size_t)w * h, b);
    double mae = 0;
    for (int i = 0; i < 3 * w * h; i++) mae += abs((int)a[i] - (int)b[i]);
    mae /= 3.0 * w * h;
    fprintf(stderr, "%s: mean absolute error against brute force %.4f levels of 255\n",
            lt_build_mode_name((lt_build_mode)modes[m]), mae);
    assert_true(mae < REFERENCE_MAE_BOUND);
    free(img);
  }

  /* The image is not trivially dark or flat. */
  double sum = 0;
  for (int i = 0; i < 3 * w * h; i++) sum += a[i];
  assert_true(sum / (3.0 * w * h) > 20);
  free(ref), free(a), free(b);
  lt_scene_destroy(scene);
}

/* A square floor under a point light, seen from above, black background: every pixel is the
 * Lambertian direct light albedo * I * cos / (pi d^2) at the point the pixel sees. */
static void render_direct_light_is_lambertian(void **state) {
  (void)state;
  static const char floor_obj[] = "v -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\nf 1 4 3 2\n";
  lt_test_write_file("floor.obj", floor_obj);
  lt_scene *scene = scene_from_text("lambert.json",
                          "{\"meshes\": [{\"file\": \"floor.obj\"}], \"background\": [0, 0, 0],\n"
                          " \"materials\": [{\"diffuse\": [0.5, 0.25, 1]}],\n"
                          " \"lights\": [{\"point\": [0.5, 2, 0.25], \"intensity\": [3, 3, 3]}],\n"
                          " \"camera\": {\"eye\": [0, 3, 0], \"look\": [0, 0, 0], \"up\": [0, 0, 1], \"fov\": 60},\n"
                          " \"effects\": {\"shadows\": true}}");
  const int w = 16, h = 16;
  float *img = render(scene, LT_BUILD_SPECULATIVE, NULL, w, h, NULL);
  lt_ray rays[16 * 16];
  lt_camera cam = lt_scene_camera(scene);
  lt_camera_primary_rays(&cam, w, h, rays);
  const float albedo[3] = {0.5f, 0.25f, 1.0f}, q[3] = {0.5f, 2, 0.25f};
  for (int i = 0; i < w * h; i++) {
    float t = -rays[i].org[1] / rays[i].dir[1], p[3], d2 = 0;
    for (int k = 0; k < 3; k++) p[k] = rays[i].org[k] + t * rays[i].dir[k], d2 += (q[k] - p[k]) * (q[k] - p[k]);
    float irradiance = 3.0f * (q[1] / sqrtf(d2)) / d2;
    for (int k = 0; k < 3; k++) {
      float want = albedo[k] * irradiance / 3.14159265f;
      if (fabsf(img[3 * i + k] - want) > 1e-4f * want) fail_msg("pixel %d: %g, want %g", i, img[3 * i + k], want);
    }
  }
  free(img);
  lt_scene_destroy(scene);
}

/* Inside a closed sphere: ambient occlusion sees nothing unoccluded (black); in an emitting
 * sphere of albedo a, diffuse rays with B bounces give E (1 + a + ... + a^B) exactly, since
 * every ray hits the same emission. */
static void render_ao_and_diffuse_estimators_are_exact_in_a_closed_sphere(void **state) {
  (void)state;
  lt_scene *scene = scene_from_text(
      "inside.json",
      "{\"meshes\": [{\"generator\": \"sphere:2\"}], \"materials\": [{\"diffuse\": [0.5, 0.5, 0.5], "
      "\"emission\": [0.2, 0.1, 0.4]}],\n"
      " \"camera\": {\"eye\": [0, 0, 0], \"look\": [0, 0, 1], \"fov\": 90}}");
  const int w = 8, h = 8;
  lt_effects ao = {.primary = 1, .ao_samples = 6, .ao_distance = 10.0f};
  float *img = render(scene, LT_BUILD_SPECULATIVE, &ao, w, h, NULL);
  for (int i = 0; i < 3 * w * h; i++) assert_true(fabsf(img[i] - (i % 3 == 0 ? 0.2f : i % 3 == 1 ? 0.1f : 0.4f)) < 1e-6f);
  free(img);

  lt_effects diffuse = {.primary = 1, .diffuse_samples = 3, .diffuse_bounces = 2};
  img = render(scene, LT_BUILD_SPECULATIVE, &diffuse, w, h, NULL);
  const float e[3] = {0.2f, 0.1f, 0.4f};
  for (int i = 0; i < w * h; i++)
    for (int k = 0; k < 3; k++) assert_true(fabsf(img[3 * i + k] - e[k] * 1.75f) < 1e-5f);
  free(img);
  lt_scene_destroy(scene);
}

/* A structure built over one scene cannot render another: refused, not traced. */
static void render_refuses_a_structure_of_another_scene(void **state) {
  (void)state;
  lt_scene *a, *b;
  assert_int_equal(lt_scene_load("sphere:1", &a), LT_OK);
  assert_int_equal(lt_scene_load("cornell", &b), LT_OK);
  lt_structure *s;
  assert_int_equal(lt_structure_create(ctx, a, NULL, NULL, &s), LT_OK);
  lt_render_config config = {8, 8, 1, NULL, 1, 0, 0};
  float rgb[8 * 8 * 3];
  assert_int_equal(lt_render(s, b, &config, rgb, NULL), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt_render(s, a, &config, rgb, NULL), LT_OK);
  lt_structure_destroy(s);
  lt_scene_destroy(a), lt_scene_destroy(b);
}

/* An image rendered in parts (as MPI ranks do: bands of rows, or every third pixel), each part
 * through its own structure, has exactly the whole render's bits; parts beyond the image are
 * refused. */
static void render_parts_equal_the_whole(void **state) {
  (void)state;
  lt_scene *scene = scene_from_text("parts.json", "{\"meshes\": [{\"generator\": \"cornell\"}],"
                                                 " \"lights\": [{\"point\": [278, 500, 280], \"intensity\": [9e4, 9e4, 9e4]}],"
                                                 " \"effects\": {\"primary\": true, \"shadows\": true,"
                                                 " \"ao\": {\"samples\": 2, \"distance\": 100}}}");
  enum { W = 24, H = 17, P = W * H };
  lt_render_config config = {W, H, 2, NULL, 5, 0, 0};
  float *whole = malloc(3 * sizeof(float) * P), *parts = malloc(3 * sizeof(float) * P);
  lt_structure *one;
  assert_int_equal(lt_structure_create(ctx, scene, NULL, NULL, &one), LT_OK);
  assert_int_equal(lt_render(one, scene, &config, whole, NULL), LT_OK);
  lt_structure_destroy(one);
  for (int interleaved = 0; interleaved < 2; interleaved++) {
    memset(parts, 0xff, 3 * sizeof(float) * P);
    for (size_t part = 0; part < 3; part++) {
      lt_structure *structure;
      assert_int_equal(lt_structure_create(ctx, scene, NULL, NULL, &structure), LT_OK);
      size_t first = interleaved ? part : part * 6 * W, count = interleaved ? (P - part + 2) / 3 : (part < 2 ? 6 * W : P - 12 * W);
      assert_int_equal(lt_render_part(structure, scene, &config, first, count, interleaved ? 3 : 1, parts, NULL), LT_OK);
      lt_structure_destroy(structure);
    }
    assert_memory_equal(whole, parts, 3 * sizeof(float) * P);
  }
  assert_int_equal(lt_render_part(NULL, scene, &config, P - 1, 2, 1, parts, NULL), LT_ERROR_INVALID_ARGUMENT);
  assert_int_equal(lt_render_part(NULL, scene, &config, 0, 1, 0, parts, NULL), LT_ERROR_INVALID_ARGUMENT);
  free(whole), free(parts);
  lt_scene_destroy(scene);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(render_refuses_a_structure_of_another_scene),
      cmocka_unit_test(render_parts_equal_the_whole),
      cmocka_unit_test(render_without_lights_traces_no_shadow_rays),
      cmocka_unit_test(render_without_mirrors_traces_no_mirror_rays),
      cmocka_unit_test(render_primary_only_traces_only_primary_rays),
      cmocka_unit_test(render_effect_counts_follow_parameters),
      cmocka_unit_test(render_short_ao_builds_fewer_nodes_than_diffuse),
      cmocka_unit_test(render_matches_brute_force_reference),
      cmocka_unit_test(render_direct_light_is_lambertian),
      cmocka_unit_test(render_ao_and_diffuse_estimators_are_exact_in_a_closed_sphere),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
