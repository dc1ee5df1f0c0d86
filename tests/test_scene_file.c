/* Scene files: the issue's example parses with every key, instances place meshes where their
 * transforms say with their materials, missing sections take their defaults, generators get a
 * default description, and each bad file fails with a message naming the file, the key and
 * what was expected. */
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
#include "tests/support.h"
#include "tests/temp_files.h"

static const char one_triangle_obj[] = "v 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n";

static void scene_file_issue_example_parses_every_key(void **state) {
  (void)state;
  lt_test_write_file("chair.obj", one_triangle_obj);
  const char *path = lt_test_write_file(
      "example.json",
      "{\"meshes\": [{\"generator\": \"sphere:1\"}, {\"file\": \"chair.obj\"}],\n"
      " \"instances\": [{\"mesh\": 0, \"translate\": [0, 0, 0], \"rotate_y\": 0, \"scale\": 1, \"material\": 0},\n"
      "               {\"mesh\": 1, \"translate\": [3, 0, 0], \"material\": 1}],\n"
      " \"materials\": [{\"diffuse\": [0.8, 0.8, 0.8], \"mirror\": 0.0, \"emission\": [0, 0, 0]},\n"
      "               {\"diffuse\": [0.1, 0.2, 0.3], \"mirror\": 0.5, \"emission\": [1, 2, 3]}],\n"
      " \"lights\": [{\"point\": [0, 5, 0], \"intensity\": [10, 10, 10]}, {\"direction\": [1, -1, 0], \"intensity\": [1, 1, 1]}],\n"
      " \"camera\": {\"eye\": [0, 2, -10], \"look\": [0, 1, 0], \"up\": [0, 1, 0], \"fov\": 60},\n"
      " \"image\": {\"width\": 64, \"height\": 32, \"spp\": 3},\n"
      " \"background\": [0.1, 0.2, 0.3],\n"
      " \"effects\": {\"primary\": true, \"shadows\": true, \"ao\": {\"samples\": 8, \"distance\": 2.0},\n"
      "             \"diffuse\": {\"samples\": 4, \"bounces\": 1}, \"mirror\": {\"depth\": 2},\n"
      "             \"collision\": {\"agents\": 100, \"rays\": 8, \"frames\": 20}}}\n");
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 80 + 1);
  assert_int_equal(lt_scene_material_count(scene), 2);
  assert_true(lt_scene_materials(scene)[1].mirror == 0.5f && lt_scene_materials(scene)[1].emission[2] == 3.0f);
  assert_int_equal(lt_scene_triangle_material(scene, 0), 0);
  assert_int_equal(lt_scene_triangle_material(scene, 80), 1);
  assert_int_equal(lt_scene_light_count(scene), 2);
  assert_int_equal(lt_scene_lights(scene)[0].kind, LT_LIGHT_POINT);
  assert_int_equal(lt_scene_lights(scene)[1].kind, LT_LIGHT_DIRECTIONAL);
  assert_true(lt_scene_lights(scene)[0].vector[1] == 5.0f && lt_scene_lights(scene)[0].intensity[0] == 10.0f);
  lt_camera cam = lt_scene_camera(scene);
  assert_true(cam.eye[2] == -10.0f && cam.look[1] == 1.0f && cam.fov_deg == 60.0f);
  int w, h, spp;
  lt_scene_image(scene, &w, &h, &spp);
  assert_int_equal(w, 64), assert_int_equal(h, 32), assert_int_equal(spp, 3);
  float bg[3];
  lt_scene_background(scene, bg);
  assert_true(bg[2] == 0.3f);
  lt_effects fx = lt_scene_effects(scene);
  assert_true(fx.primary && fx.shadows);
  assert_int_equal(fx.ao_samples, 8), assert_true(fx.ao_distance == 2.0f);
  assert_int_equal(fx.diffuse_samples, 4), assert_int_equal(fx.diffuse_bounces, 1);
  assert_int_equal(fx.mirror_depth, 2);
  assert_int_equal(fx.collision_agents, 100), assert_int_equal(fx.collision_rays, 8);
  assert_int_equal(fx.collision_frames, 20);
  lt_scene_destroy(scene);
}

/* One triangle placed twice: scaled by 2, turned 90 degrees about y, moved; each instance's
 * triangles carry its material. */
static void scene_file_instances_transform_and_material(void **state) {
  (void)state;
  lt_test_write_file("tri.obj", one_triangle_obj);
  const char *path = lt_test_write_file("instances.json",
                                "{\"meshes\": [{\"file\": \"tri.obj\"}],\n"
                                " \"materials\": [{}, {\"diffuse\": [1, 0, 0]}],\n"
                                " \"instances\": [{\"mesh\": 0},\n"
                                "   {\"mesh\": 0, \"scale\": 2, \"rotate_y\": 90, \"translate\": [10, 20, 30], "
                                "\"material\": 1}]}");
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 2);
  const float *t = lt_scene_triangles(scene);
  /* The first instance is the mesh as it is. */
  static const float first[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int k = 0; k < 9; k++) assert_true(t[k] == first[k]);
  /* Turning +90 degrees about y takes x to -z and z to x. */
  static const float second[9] = {10, 20, 28, 10, 22, 30, 12, 20, 30};
  for (int k = 0; k < 9; k++) assert_true(fabsf(t[9 + k] - second[k]) < 1e-5f);
  assert_int_equal(lt_scene_triangle_material(scene, 0), 0);
  assert_int_equal(lt_scene_triangle_material(scene, 1), 1);
  /* An empty material object takes every default. */
  assert_true(lt_scene_materials(scene)[0].diffuse[1] == 0.8f && lt_scene_materials(scene)[0].mirror == 0.0f);
  lt_scene_destroy(scene);
}

/* A PLY mesh goes to lazytrace's own reader, as it does outside scene files: its triangle
 * arrives as the file has it, and its errors keep their line. */
static void scene_file_ply_mesh_is_read_by_lazytrace(void **state) {
  (void)state;
  static const char header[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                               "1 0 0\n0 1 0\n0 0 1\n";
  char text[sizeof header + 16];
  snprintf(text, sizeof text, "%s3 0 1 2\n", header);
  lt_test_write_file("tri.ply", text);
  lt_scene *scene = lt_test_load_ok(lt_test_write_file("ply.json", "{\"meshes\": [{\"file\": \"tri.ply\"}]}"));
  assert_int_equal(lt_scene_triangle_count(scene), 1);
  static const float expected[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int k = 0; k < 9; k++) assert_true(lt_scene_triangles(scene)[k] == expected[k]);
  lt_scene_destroy(scene);

  snprintf(text, sizeof text, "%s3 0 1 3\n", header);
  lt_test_write_file("bad.ply", text);
  const char *path = lt_test_write_file("bad_ply.json", "{\"meshes\": [{\"file\": \"bad.ply\"}]}");
  assert_int_equal(lt_scene_load(path, &scene), LT_ERROR_PARSE);
  assert_non_null(strstr(lt_last_error(), "meshes[0].file: "));
  assert_non_null(strstr(lt_last_error(), "bad.ply:13: face 0: vertex index 3 out of range (3 vertices)"));
}

/* Without instances every mesh is placed once; without materials one grey diffuse material;
 * without a camera the generator's outer camera; without effects primary rays only. */
static void scene_file_missing_sections_take_defaults(void **state) {
  (void)state;
  const char *path = lt_test_write_file("bare.json", "{\"meshes\": [{\"generator\": \"sphere:1\"}, {\"generator\": \"sphere:0\"}]}");
  lt_scene *scene = lt_test_load_ok(path), *sphere = lt_test_load_ok("sphere:1");
  assert_int_equal(lt_scene_triangle_count(scene), 80 + 20);
  assert_int_equal(lt_scene_material_count(scene), 1);
  assert_true(lt_scene_materials(scene)[0].diffuse[0] == 0.8f);
  assert_int_equal(lt_scene_light_count(scene), 0);
  lt_camera a = lt_scene_camera(scene), b;
  assert_int_equal(lt_scene_named_camera(sphere, "outer", &b), LT_OK);
  assert_memory_equal(&a, &b, sizeof a);
  lt_effects fx = lt_scene_effects(scene);
  assert_true(fx.primary && !fx.shadows && !fx.ao_samples && !fx.diffuse_samples && !fx.mirror_depth &&
              !fx.collision_agents);
  int w, h, spp;
  lt_scene_image(scene, &w, &h, &spp);
  assert_int_equal(w, 0), assert_int_equal(spp, 0);
  lt_scene_destroy(scene);
  lt_scene_destroy(sphere);
}

/* Generators and mesh files get the default description, so that they render as before. */
static void scene_file_generators_have_default_description(void **state) {
  (void)state;
  lt_scene *scene = lt_test_load_ok("house-grid:1x2");
  assert_int_equal(lt_scene_material_count(scene), 1);
  assert_int_equal(lt_scene_light_count(scene), 0);
  assert_int_equal(lt_scene_triangle_material(scene, 5), 0);
  lt_effects fx = lt_scene_effects(scene);
  assert_true(fx.primary && !fx.shadows && !fx.ao_samples && !fx.diffuse_samples && !fx.mirror_depth);
  lt_scene_destroy(scene);
}

/* Effects written as true take their defaults; false is off. */
static void scene_file_effects_true_and_false(void **state) {
  (void)state;
  const char *path = lt_test_write_file("fx.json", "{\"meshes\": [{\"generator\": \"sphere:0\"}], \"effects\": {\"shadows\": "
                                           "false, \"ao\": true, \"diffuse\": true, \"mirror\": false}}");
  lt_scene *scene = lt_test_load_ok(path);
  lt_effects fx = lt_scene_effects(scene);
  assert_true(fx.primary && !fx.shadows && !fx.mirror_depth);
  assert_int_equal(fx.ao_samples, 8), assert_int_equal(fx.diffuse_samples, 4), assert_int_equal(fx.diffuse_bounces, 1);
  lt_scene_destroy(scene);
}

/* Each bad file: the message starts with the file's path and contains the key and what was
 * expected. */
static void scene_file_errors_name_file_key_and_expectation(void **state) {
  (void)state;
  static const struct {
    const char *json, *message;
    lt_status status;
  } cases[] = {
      {"{\"meshes\": []}", "meshes: expected an array of at least one mesh", LT_ERROR_PARSE},
      {"{\"instances\": []}", "meshes: expected an array of at least one mesh", LT_ERROR_PARSE},
      {"{\"meshes\": {\"generator\": \"house\"}}", "meshes: expected an array of objects, got an object", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"lihgts\": []}", "unknown key 'lihgts' (expected one of: meshes",
       LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"instances\": [{\"mesh\": 3}]}",
       "instances[0].mesh: expected a whole number from 0 to 0, got the number 3", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"instances\": [{\"translate\": [0, 0, 0]}]}",
       "instances[0].mesh: expected the index of a mesh (0 to 0), got nothing", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"instances\": [{\"mesh\": 0, \"translate\": [0, \"x\", 0]}]}",
       "instances[0].translate: expected an array of 3 finite numbers", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"instances\": [{\"mesh\": 0, \"material\": 1}]}",
       "instances[0].material: expected a whole number from 0 to 0, got the number 1", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"materials\": [{\"diffuse\": [1, 2]}]}",
       "materials[0].diffuse: expected an array of 3 numbers from 0 to 1, got an array of 2", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"materials\": [{\"mirror\": 2}]}",
       "materials[0].mirror: expected a number from 0 to 1, got the number 2", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"lights\": [{\"point\": [0, 1, 0], \"direction\": [0, 1, 0]}]}",
       "lights[0]: expected an object with either \"point\" or \"direction\"", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"lights\": [{\"direction\": [0, 0, 0]}]}",
       "lights[0].direction: expected a direction that is not zero", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"camera\": {\"eye\": [0, 0, -5], \"look\": [0, 0, 0], "
       "\"up\": [0, 0, 2]}}",
       "camera.up: expected a direction that is not zero and not along the view", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"camera\": {\"eye\": [0, 0, -5], \"look\": [0, 0, 0], "
       "\"up\": [0, 0, 0]}}",
       "camera.up: expected a direction that is not zero and not along the view", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"instances\": [{\"mesh\": 0, \"scale\": 1e30}]}",
       "instances[0].scale: expected a number from 1e-06 to 1e+06", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"camera\": {\"look\": [0, 0, 0]}}",
       "camera.eye: expected an array of 3 finite numbers, got nothing", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"image\": {\"width\": -4}}",
       "image.width: expected a whole number from 1 to 16384, got the number -4", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"effects\": {\"ao\": {\"samples\": 0}}}",
       "effects.ao.samples: expected a whole number from 1 to 4096, got the number 0", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"effects\": {\"mirror\": {\"deep\": 2}}}",
       "effects.mirror: unknown key 'deep' (expected one of: depth)", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"effects\": {\"shadows\": 3}}",
       "effects.shadows: expected true or false, got the number 3", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}], \"effects\": {\"primary\": false, \"ao\": true}}",
       "effects.ao: expected effects.primary to be on", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"pyramid:3\"}]}", "meshes[0].generator: unknown generator 'pyramid'",
       LT_ERROR_UNKNOWN_GENERATOR},
      {"{\"meshes\": [{\"generator\": \"sphere:1@close\"}]}", "meshes[0].generator: expected a generator spec",
       LT_ERROR_PARSE},
      {"{\"meshes\": [{\"file\": \"no-such.obj\"}]}", "meshes[0].file:", LT_ERROR_IO},
      {"{\"meshes\": [{\"file\": \"a.obj\", \"generator\": \"house\"}]}",
       "meshes[0]: expected an object with either \"generator\" or \"file\"", LT_ERROR_PARSE},
      {"{\"meshes\": [{\"generator\": \"sphere:1\"}],\n \"lights\": [}", ":2:13: malformed JSON near '}'",
       LT_ERROR_PARSE},
      {"[1, 2]", "the top level: expected an object, got an array of 2", LT_ERROR_PARSE},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    const char *message;
    lt_scene *scene;
    lt_status status = lt_test_load_bad(i, cases[i].json, &message, &scene);
    if (status != cases[i].status || !message || !strstr(message, cases[i].message))
      fail_msg("case %zu: got %s \"%s\", want %s naming the file with \"%s\"", i, lt_status_name(status),
               lt_last_error(), lt_status_name(cases[i].status), cases[i].message);
    assert_null(scene);
  }
  /* A missing scene file is an I/O error that names it. */
  lt_scene *scene = NULL;
  assert_int_equal(lt_scene_load("/nonexistent/scene.json", &scene), LT_ERROR_IO);
  assert_non_null(strstr(lt_last_error(), "/nonexistent/scene.json"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(scene_file_issue_example_parses_every_key),
      cmocka_unit_test(scene_file_instances_transform_and_material),
      cmocka_unit_test(scene_file_ply_mesh_is_read_by_lazytrace),
      cmocka_unit_test(scene_file_missing_sections_take_defaults),
      cmocka_unit_test(scene_file_generators_have_default_description),
      cmocka_unit_test(scene_file_effects_true_and_false),
      cmocka_unit_test(scene_file_errors_name_file_key_and_expectation),
  };
  return cmocka_run_group_tests(tests, lt_test_temp_dir_create, lt_test_temp_dir_remove);
}
