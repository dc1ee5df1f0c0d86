/* Mesh files in and out: the OBJ reader's triangle numbering and errors, the OBJ writer's exact
 * round trip, and the assimp path for other formats. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <dirent.h>
#include <unistd.h>

#include "runtime/output_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lazytrace.h"
#include "tests/support.h"
#include "tests/temp_files.h"

/* Loads a file that must fail with status and returns the error message. */
static const char *load_fails(const char *path, lt_status expected) {
  lt_scene *scene = NULL;
  assert_int_equal(lt_scene_load(path, &scene), expected);
  assert_null(scene);
  return lt_last_error();
}

static void assert_error_is(const char *message, const char *format, const char *path) {
  char expected[640];
  snprintf(expected, sizeof expected, format, path);
  assert_string_equal(message, expected);
}

/* Triangle t of the scene must have corners at the given vertices of verts (3 floats each). */
static void assert_triangle(const lt_scene *scene, size_t t, const float *verts, int a, int b, int c) {
  const float *tri = lt_scene_triangles(scene) + 9 * t;
  int corners[3] = {a, b, c};
  for (int k = 0; k < 3; k++)
    for (int j = 0; j < 3; j++) assert_true(tri[3 * k + j] == verts[3 * corners[k] + j]);
}

/* xorshift32: deterministic bit patterns for the round trip. */
static uint32_t next_random(uint32_t *s) {
  *s ^= *s << 13;
  *s ^= *s >> 17;
  *s ^= *s << 5;
  return *s;
}

static float random_finite_float(uint32_t *s) {
  for (;;) {
    uint32_t bits = next_random(s);
    float x;
    memcpy(&x, &bits, sizeof x);
    if (isfinite(x)) return x;
  }
}

/* A write that fails at the end (a full disk) leaves the existing file as it was and no
 * temporary file beside it. */
static void scenes_io_failed_write_leaves_the_old_file(void **state) {
  (void)state;
  char dir[] = "/tmp/lt_atomic_XXXXXX";
  assert_non_null(mkdtemp(dir));
  char path[64];
  snprintf(path, sizeof path, "%s/out.hits", dir);
  lt_hit first[2] = {{1.0f, 0.0f, 0.0f, 3}, {INFINITY, 0.0f, 0.0f, -1}}, second[3] = {{2.0f, 0.5f, 0.25f, 7}};
  assert_int_equal(lt_hits_write(path, first, 2), LT_OK);
  lt__output_fail_next_commit = 1;
  assert_int_equal(lt_hits_write(path, second, 3), LT_ERROR_IO);
  lt_hit *back;
  size_t n;
  assert_int_equal(lt_hits_read(path, &back, &n), LT_OK);
  assert_int_equal(n, 2);
  assert_memory_equal(back, first, sizeof first);
  free(back);

  /* Nothing but the file itself is left in the directory. */
  DIR *d = opendir(dir);
  int entries = 0;
  for (struct dirent *e; (e = readdir(d));) entries += e->d_name[0] != '.';
  closedir(d);
  assert_int_equal(entries, 1);
  assert_int_equal(lt_hits_write(path, second, 3), LT_OK);
  assert_int_equal(lt_hits_read(path, &back, &n), LT_OK);
  assert_int_equal(n, 3);
  free(back);
  unlink(path);
  rmdir(dir);
}

/* The accessors answer NULL with "nothing" instead of crashing. */
static void scenes_io_accessors_of_null_scene(void **state) {
  (void)state;
  assert_int_equal(lt_scene_triangle_count(NULL), 0);
  assert_null(lt_scene_triangles(NULL));
  assert_int_equal(lt_scene_skipped_triangles(NULL), 0);
}

static void scenes_io_obj_round_trip_is_bit_identical(void **state) {
  (void)state;
  enum { N = 200 };
  float tris[9 * N];
  uint32_t seed = 12345;
  for (int i = 0; i < 9 * N; i++) tris[i] = random_finite_float(&seed);

  /* Values that printing tends to get wrong: signed zero, subnormals, the extremes, thirds. */
  const float hard[9] = {-0.0f, 1.4e-45f,  3.4028235e38f, -1.17549435e-38f, 1.0f / 3.0f,
                         0.1f,  1e-7f,     -2.5e6f,       16777217.0f};
  memcpy(tris, hard, sizeof hard);

  lt_scene *scene = NULL;
  assert_int_equal(lt_scene_from_triangles(tris, N, &scene), LT_OK);
  const char *path = lt_test_temp_path("round_trip.obj");
  assert_int_equal(lt_scene_write_obj(scene, path), LT_OK);
  lt_scene_destroy(scene);

  scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), N);
  assert_int_equal(lt_scene_skipped_triangles(scene), 0);
  assert_memory_equal(lt_scene_triangles(scene), tris, sizeof tris);
  lt_scene_destroy(scene);
}

static void scenes_io_obj_fans_quad_and_pentagon_from_first_vertex(void **state) {
  (void)state;
  const char *path = lt_test_write_file("fan.obj",
                                "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                "v 0 0 1\nv 1 0 1\nv 2 1 1\nv 1 2 1\nv 0 1 1\n"
                                "f 1 2 3 4\n"
                                "f 5 6 7 8 9\n");
  const float v[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 2, 1, 1, 1, 2, 1, 0, 1, 1};
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 2 + 3);
  assert_triangle(scene, 0, v, 0, 1, 2);
  assert_triangle(scene, 1, v, 0, 2, 3);
  assert_triangle(scene, 2, v, 4, 5, 6);
  assert_triangle(scene, 3, v, 4, 6, 7);
  assert_triangle(scene, 4, v, 4, 7, 8);
  lt_scene_destroy(scene);
}

static void scenes_io_obj_negative_indices_count_back_from_last_vertex(void **state) {
  (void)state;
  const char *path = lt_test_write_file("negative.obj",
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                "f -3 -2 -1\n"
                                "v 5 5 5\n"
                                "f -1 -4 -2\n");
  const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 2);
  assert_triangle(scene, 0, v, 0, 1, 2);
  assert_triangle(scene, 1, v, 3, 0, 2);
  lt_scene_destroy(scene);
}

static void scenes_io_obj_reads_slash_forms(void **state) {
  (void)state;
  const char *path = lt_test_write_file("slashes.obj",
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                                "f 1/1 2/2 3/3\n"
                                "f 2//1 4//1 3//1\n"
                                "f 1/1/1 2/2/1 4/3/1\n"
                                "f -4/-3/-1 -3//-1 -2/1\n");
  const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 4);
  assert_triangle(scene, 0, v, 0, 1, 2);
  assert_triangle(scene, 1, v, 1, 3, 2);
  assert_triangle(scene, 2, v, 0, 1, 3);
  assert_triangle(scene, 3, v, 0, 1, 2);
  lt_scene_destroy(scene);
}

static void scenes_io_obj_skips_other_statements_crlf_and_indentation(void **state) {
  (void)state;
  const char *path = lt_test_write_file("noise.obj",
                                "# a comment\r\n"
                                "mtllib scene.mtl\r\n"
                                "\r\n"
                                "o thing\r\ng group\r\ns 1\r\nusemtl red\r\n"
                                "  v 0 0 0\r\n"
                                "\tv 1 0 0 1.0\r\n"
                                "v 0 1 0 # trailing comment\r\n"
                                "vn 0 0 1\r\nvt 0 0\r\nvp 0.5\r\n"
                                "l 1 2\r\np 1\r\n"
                                "   f 1 2 3   \r\n");
  const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 1);
  assert_triangle(scene, 0, v, 0, 1, 2);
  lt_scene_destroy(scene);
}

/* A 5000-gon on one line of about 25 kB: no line buffer may cut it short. */
static void scenes_io_obj_reads_lines_of_any_length(void **state) {
  (void)state;
  enum { N = 5000 };
  const char *path = lt_test_temp_path("long.obj");
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  for (int i = 0; i < N; i++) fprintf(f, "v %d %d 0\n", i, i * i % 7);
  fputs("f", f);
  for (int i = 1; i <= N; i++) fprintf(f, " %d", i);
  fputs("\n", f);
  assert_int_equal(fclose(f), 0);

  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), N - 2);
  const float *last = lt_scene_triangles(scene) + 9 * (N - 3);
  assert_true(last[0] == 0.0f && last[3] == (float)(N - 2) && last[6] == (float)(N - 1));
  lt_scene_destroy(scene);
}

static void scenes_io_obj_malformed_face_names_file_and_line(void **state) {
  (void)state;
  const char *path = lt_test_write_file("bad_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 oops 3\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:5: face vertex 'oops' is not an index", path);

  path = lt_test_write_file("bad_number.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.5\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:4: face vertex '3.5' is not an index", path);
}

static void scenes_io_obj_face_with_two_vertices_fails(void **state) {
  (void)state;
  const char *path = lt_test_write_file("short_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:4: face with fewer than 3 vertices", path);
}

static void scenes_io_obj_vertex_with_too_few_coordinates_fails(void **state) {
  (void)state;
  const char *path = lt_test_write_file("short_vertex.obj", "v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:3: vertex needs 3 coordinates", path);

  path = lt_test_write_file("garbage_vertex.obj", "v 0 0 0\nv 1.0x 0 0\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:2: vertex coordinate '1.0x' is not a number", path);
}

static void scenes_io_obj_index_out_of_range_fails(void **state) {
  (void)state;
  const char *path = lt_test_write_file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:4: face index 4 out of range (3 vertices so far)", path);

  path = lt_test_write_file("range_negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:4: face index -4 out of range (3 vertices so far)", path);

  /* Faces may only use vertices defined above them. */
  path = lt_test_write_file("forward.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:3: face index 3 out of range (2 vertices so far)", path);
}

static void scenes_io_missing_file_is_io_error(void **state) {
  (void)state;
  const char *obj = lt_test_temp_path("missing.obj");
  assert_error_is(load_fails(obj, LT_ERROR_IO), "%s: cannot open: No such file or directory", obj);
  const char *ply = lt_test_temp_path("missing.ply");
  assert_error_is(load_fails(ply, LT_ERROR_IO), "%s: cannot open: No such file or directory", ply);
}

static void scenes_io_obj_nan_vertex_skips_and_counts_triangle(void **state) {
  (void)state;
  const char *path = lt_test_write_file("nan.obj",
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nv 0 inf 0\n"
                                "f 1 2 3\nf 1 2 4\nf 5 1 2\nf 3 2 1\n");
  const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 2);
  assert_int_equal(lt_scene_skipped_triangles(scene), 2);
  assert_triangle(scene, 0, v, 0, 1, 2);
  assert_triangle(scene, 1, v, 2, 1, 0);
  lt_scene_destroy(scene);
}

static void scenes_io_ply_loads_through_assimp(void **state) {
  (void)state;
  const char *path = lt_test_write_file("tiny.ply",
                                "ply\n"
                                "format ascii 1.0\n"
                                "element vertex 5\n"
                                "property float x\nproperty float y\nproperty float z\n"
                                "element face 2\n"
                                "property list uchar int vertex_indices\n"
                                "end_header\n"
                                "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 2\n"
                                "3 0 1 4\n"
                                "4 0 1 2 3\n");
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 1 + 2);
  float lo[3], hi[3];
  lt_scene_bounds(scene, lo, hi);
  assert_true(lo[0] == 0.0f && lo[1] == 0.0f && lo[2] == 0.0f);
  assert_true(hi[0] == 1.0f && hi[1] == 1.0f && hi[2] == 2.0f);
  lt_scene_destroy(scene);
}

static void scenes_io_assimp_garbage_is_parse_error(void **state) {
  (void)state;
  const char *path = lt_test_write_file("garbage.ply", "ply\nformat ascii 1.0\nelement vertex nonsense\nend_header\n");
  const char *message = load_fails(path, LT_ERROR_PARSE);
  assert_true(strncmp(message, path, strlen(path)) == 0);
  assert_true(strlen(message) > strlen(path) + 2);
}

/* What `lazytrace scene GEN -o f.obj` writes is exactly what trace numbers for GEN: every
 * generator's triangles survive the OBJ round trip bit for bit and in order. */
static void scenes_io_generators_round_trip_through_obj(void **state) {
  (void)state;
  const char *specs[] = {"house", "house-row:2", "house-grid:2x1", "hairball:50", "teapot-stadium", "sphere:3", "cornell"};
  for (size_t i = 0; i < sizeof specs / sizeof specs[0]; i++) {
    lt_scene *generated = lt_test_load_ok(specs[i]);
    char name[32];
    snprintf(name, sizeof name, "gen%zu.obj", i);
    const char *path = lt_test_temp_path(name);
    assert_int_equal(lt_scene_write_obj(generated, path), LT_OK);
    lt_scene *loaded = lt_test_load_ok(path);
    size_t n = lt_scene_triangle_count(generated);
    assert_int_equal(lt_scene_triangle_count(loaded), n);
    assert_memory_equal(lt_scene_triangles(loaded), lt_scene_triangles(generated), n * 9 * sizeof(float));
    lt_scene_destroy(generated);
    lt_scene_destroy(loaded);
  }
}

/* Generators are deterministic: the same spec gives the same bytes. */
static void scenes_io_generators_are_deterministic(void **state) {
  (void)state;
  lt_scene *a = lt_test_load_ok("house-grid:2x2"), *b = lt_test_load_ok("house-grid:2x2");
  assert_int_equal(lt_scene_triangle_count(a), lt_scene_triangle_count(b));
  assert_memory_equal(lt_scene_triangles(a), lt_scene_triangles(b), lt_scene_triangle_count(a) * 9 * sizeof(float));
  lt_scene_destroy(a);
  lt_scene_destroy(b);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(scenes_io_accessors_of_null_scene),
      cmocka_unit_test(scenes_io_failed_write_leaves_the_old_file),
      cmocka_unit_test(scenes_io_obj_round_trip_is_bit_identical),
      cmocka_unit_test(scenes_io_obj_fans_quad_and_pentagon_from_first_vertex),
      cmocka_unit_test(scenes_io_obj_negative_indices_count_back_from_last_vertex),
      cmocka_unit_test(scenes_io_obj_reads_slash_forms),
      cmocka_unit_test(scenes_io_obj_skips_other_statements_crlf_and_indentation),
      cmocka_unit_test(scenes_io_obj_reads_lines_of_any_length),
      cmocka_unit_test(scenes_io_obj_malformed_face_names_file_and_line),
      cmocka_unit_test(scenes_io_obj_face_with_two_vertices_fails),
      cmocka_unit_test(scenes_io_obj_vertex_with_too_few_coordinates_fails),
      cmocka_unit_test(scenes_io_obj_index_out_of_range_fails),
      cmocka_unit_test(scenes_io_missing_file_is_io_error),
      cmocka_unit_test(scenes_io_obj_nan_vertex_skips_and_counts_triangle),
      cmocka_unit_test(scenes_io_ply_loads_through_assimp),
      cmocka_unit_test(scenes_io_assimp_garbage_is_parse_error),
      cmocka_unit_test(scenes_io_generators_round_trip_through_obj),
      cmocka_unit_test(scenes_io_generators_are_deterministic),
  };
  return cmocka_run_group_tests(tests, lt_test_temp_dir_create, lt_test_temp_dir_remove);
}
