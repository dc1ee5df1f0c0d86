/* Mesh files in and out: the OBJ and PLY readers' triangle numbering and errors, the OBJ
 * writer's exact round trip, and the assimp path for other formats. */
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
#include <time.h>
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

/* A binary PLY body under construction, in either byte order. */
typedef struct ply_body {
  unsigned char bytes[512];
  size_t size;
  int big_endian;
} ply_body;

static void put_bits(ply_body *b, uint64_t bits, int size) {
  for (int i = 0; i < size; i++) b->bytes[b->size++] = (unsigned char)(bits >> 8 * (b->big_endian ? size - 1 - i : i));
}

static void put_int(ply_body *b, int64_t value, int size) { put_bits(b, (uint64_t)value, size); }

static void put_float(ply_body *b, float x) {
  uint32_t bits;
  memcpy(&bits, &x, sizeof bits);
  put_bits(b, bits, 4);
}

static void put_double(ply_body *b, double x) {
  uint64_t bits;
  memcpy(&bits, &x, sizeof bits);
  put_bits(b, bits, 8);
}

static const char *write_ply(const char *name, const char *header, const ply_body *body) {
  const char *path = lt_test_temp_path(name);
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  fputs(header, f);
  fwrite(body->bytes, 1, body->size, f);
  assert_int_equal(fclose(f), 0);
  return path;
}

/* The geometry every PLY test writes: coordinates whose bits a careless reader would change
 * (0.1 and -2.5 as floats, integers in z so that integer types can carry them), a quad and a
 * triangle. The quad is fanned from its first vertex: triangles (0 1 2), (0 2 3), then (4 1 0). */
static const float ply_verts[] = {0.1f, -2.5f, -3, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 2};
static const int ply_faces[] = {4, 0, 1, 2, 3, 3, 4, 1, 0};

static void assert_ply_geometry(const char *path) {
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 3);
  assert_int_equal(lt_scene_skipped_triangles(scene), 0);
  assert_triangle(scene, 0, ply_verts, 0, 1, 2);
  assert_triangle(scene, 1, ply_verts, 0, 2, 3);
  assert_triangle(scene, 2, ply_verts, 4, 1, 0);
  lt_scene_destroy(scene);
}

/* CRLF line endings, comments, normals and colours beside the positions, and an extra element
 * with a list property both before and after the faces. */
static void scenes_io_ply_ascii_skips_other_properties_and_elements(void **state) {
  (void)state;
  const char *path = lt_test_write_file("ascii.ply",
                                "ply\r\n"
                                "format ascii 1.0\r\n"
                                "comment written by test_scenes_io.c\r\n"
                                "obj_info nothing to see\r\n"
                                "element vertex 5\r\n"
                                "property float x\r\nproperty float y\r\nproperty float z\r\n"
                                "property float nx\r\nproperty float ny\r\nproperty float nz\r\n"
                                "property uchar red\r\nproperty uchar green\r\nproperty uchar blue\r\n"
                                "element material 2\r\n"
                                "property list uchar float values\r\n"
                                "element face 2\r\n"
                                "property list uchar int vertex_indices\r\n"
                                "element edge 1\r\n"
                                "property list int int vertices\r\n"
                                "end_header\r\n"
                                "0.1 -2.5 -3 0 0 1 255 128 0\r\n"
                                "1 0 0 0 0 1 255 128 0\r\n"
                                "1 1 0 0 0 1 255 128 0\r\n"
                                "0 1 0 0 0 1 255 128 0\r\n"
                                "0.5 0.5 2 0 0 1 255 128 0\r\n"
                                "3 0.5 0.25 1\r\n"
                                "0\r\n"
                                "4 0 1 2 3\r\n"
                                "3 4 1 0\r\n"
                                "2 0 1\r\n");
  assert_ply_geometry(path);
}

/* Little endian, float positions with normals and colours, a flag and a tag around the index
 * list, an element with a list before the faces and one after them. */
static void scenes_io_ply_binary_little_endian_reads_positions_and_fans_quad(void **state) {
  (void)state;
  ply_body b = {.big_endian = 0};
  for (int v = 0; v < 5; v++) {
    for (int k = 0; k < 3; k++) put_float(&b, ply_verts[3 * v + k]);
    put_float(&b, 0), put_float(&b, 0), put_float(&b, 1);
    put_int(&b, 255, 1), put_int(&b, 128, 1), put_int(&b, 0, 1);
  }
  put_int(&b, 2, 1), put_float(&b, 0.5f), put_float(&b, 0.25f); /* material 0 */
  put_int(&b, 0, 1);                                            /* material 1: an empty list */
  for (int i = 0; i < 9; i += ply_faces[i] + 1) {
    put_int(&b, 7, 1); /* flags */
    put_int(&b, ply_faces[i], 1);
    for (int k = 1; k <= ply_faces[i]; k++) put_int(&b, ply_faces[i + k], 4);
    put_int(&b, -1, 4); /* tag */
  }
  put_int(&b, 2, 4), put_int(&b, 0, 2), put_int(&b, 1, 2); /* edge 0 */
  put_int(&b, 2, 4), put_int(&b, 3, 2), put_int(&b, 4, 2); /* edge 1 */
  const char *path = write_ply("little.ply",
                               "ply\n"
                               "format binary_little_endian 1.0\n"
                               "comment written by test_scenes_io.c\n"
                               "element vertex 5\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "property float nx\nproperty float ny\nproperty float nz\n"
                               "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                               "element material 2\n"
                               "property list uchar float values\n"
                               "element face 2\n"
                               "property uchar flags\n"
                               "property list uchar int vertex_indices\n"
                               "property int tag\n"
                               "element edge 2\n"
                               "property list int ushort vertices\n"
                               "end_header\n",
                               &b);
  assert_ply_geometry(path);
}

/* Big endian with positions of three types (double, float, short), the type aliases, the
 * vertex_index spelling and a short count of unsigned indices. */
static void scenes_io_ply_binary_big_endian_reads_any_scalar_type(void **state) {
  (void)state;
  ply_body b = {.big_endian = 1};
  for (int v = 0; v < 5; v++) {
    put_double(&b, ply_verts[3 * v]);
    put_float(&b, ply_verts[3 * v + 1]);
    put_int(&b, (int64_t)ply_verts[3 * v + 2], 2);
    put_int(&b, 200, 1);    /* alpha */
    put_double(&b, 0.75);   /* confidence */
  }
  put_int(&b, 1, 1), put_int(&b, -7, 2); /* material 0 */
  for (int i = 0; i < 9; i += ply_faces[i] + 1) {
    put_int(&b, ply_faces[i], 2);
    for (int k = 1; k <= ply_faces[i]; k++) put_int(&b, ply_faces[i + k], 4);
  }
  put_int(&b, 3, 1), put_int(&b, 0, 4), put_int(&b, 1, 4), put_int(&b, 2, 4); /* edge 0 */
  const char *path = write_ply("big.ply",
                               "ply\n"
                               "format binary_big_endian 1.0\n"
                               "element vertex 5\n"
                               "property float64 x\nproperty float32 y\nproperty int16 z\n"
                               "property uint8 alpha\nproperty double confidence\n"
                               "element material 1\n"
                               "property list int8 short ids\n"
                               "element face 2\n"
                               "property list uint16 uint32 vertex_index\n"
                               "element edge 1\n"
                               "property list char int vertices\n"
                               "end_header\n",
                               &b);
  assert_ply_geometry(path);
}

/* NaN and doubles beyond float's range: their triangles are skipped and counted. */
static void scenes_io_ply_non_finite_vertices_skip_triangles(void **state) {
  (void)state;
  ply_body b = {.big_endian = 0};
  const double v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1e300, 0, 0, 0, NAN, 0};
  for (int i = 0; i < 15; i++) put_double(&b, v[i]);
  const int faces[] = {0, 1, 2, 0, 1, 3, 4, 0, 1};
  for (int f = 0; f < 3; f++) {
    put_int(&b, 3, 1);
    for (int k = 0; k < 3; k++) put_int(&b, faces[3 * f + k], 4);
  }
  const char *path = write_ply("non_finite.ply",
                               "ply\nformat binary_little_endian 1.0\nelement vertex 5\n"
                               "property double x\nproperty double y\nproperty double z\n"
                               "element face 3\nproperty list uchar int vertex_indices\nend_header\n",
                               &b);
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 1);
  assert_int_equal(lt_scene_skipped_triangles(scene), 2);
  lt_scene_destroy(scene);
}

/* The test that used to go through assimp: a triangle and a quad. */
static void scenes_io_ply_tiny_ascii_loads(void **state) {
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

#define PLY_XYZ "property float x\nproperty float y\nproperty float z\n"
#define PLY_TRIANGLE_HEADER "ply\nformat ascii 1.0\nelement vertex 3\n" PLY_XYZ "element face 1\n"
#define PLY_TRIANGLE_BODY "end_header\n0 0 0\n1 0 0\n0 1 0\n"

/* Header and ascii body errors: each names the file and the line, and what is wrong. */
static void scenes_io_ply_errors_name_file_and_line(void **state) {
  (void)state;
  static const struct {
    const char *text, *message;
  } cases[] = {
      {"plyx\nformat ascii 1.0\nend_header\n", "%s:1: not a PLY file (the first line is not \"ply\")"},
      {"", "%s:1: not a PLY file (the first line is not \"ply\")"},
      {"ply\nformat ascii 1.0\nelement vertex 1\n" PLY_XYZ, "%s:7: the header ends without an end_header line"},
      {"ply\nformat binary_middle_endian 1.0\nend_header\n", "%s:2: unknown format 'binary_middle_endian'"},
      {"ply\nformat ascii 2.0\nend_header\n", "%s:2: unknown PLY version '2.0'"},
      {"ply\nelement vertex 0\n" PLY_XYZ "end_header\n", "%s:6: the header has no format line"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\n", "%s:4: unknown type 'real'"},
      {"ply\nformat ascii 1.0\nelemnt vertex 3\n",
       "%s:3: not a PLY header line (format, comment, obj_info, element, property or end_header)"},
      {"ply\nformat ascii 1.0\nproperty float x\n", "%s:3: a property before any element"},
      {"ply\nformat ascii 1.0\nelement vertex -3\n", "%s:3: element count '-3' is not a whole number from 0"},
      {"ply\nformat ascii 1.0\nelement vertex three\n", "%s:3: element count 'three' is not a whole number from 0"},
      {"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n",
       "%s:3: element count '99999999999999999999999' is not a whole number from 0"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
       "%s:3: the vertex element has no property z"},
      {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n",
       "%s:3: the face element comes before the vertex element"},
      {PLY_TRIANGLE_HEADER "property list uchar int corners\n" PLY_TRIANGLE_BODY "3 0 1 2\n",
       "%s:7: the face element has no vertex_indices list"},
      {PLY_TRIANGLE_HEADER "property list float int vertex_indices\n",
       "%s:8: a list count of type 'float' (an integer type is needed)"},
      {PLY_TRIANGLE_HEADER "property list uchar double vertex_indices\n",
       "%s:8: vertex indices of type 'double' (an integer type is needed)"},
      {PLY_TRIANGLE_HEADER "property list uchar int vertex_indices\n" PLY_TRIANGLE_BODY "3 0 1 3\n",
       "%s:13: face 0: vertex index 3 out of range (3 vertices)"},
      {PLY_TRIANGLE_HEADER "property list uchar int vertex_indices\n" PLY_TRIANGLE_BODY "3 0 -1 2\n",
       "%s:13: face 0: vertex index -1 out of range (3 vertices)"},
      {PLY_TRIANGLE_HEADER "property list uchar int vertex_indices\n" PLY_TRIANGLE_BODY "2 0 1\n",
       "%s:13: face 0: face with fewer than 3 vertices (2)"},
      {PLY_TRIANGLE_HEADER "property list uchar int vertex_indices\n" PLY_TRIANGLE_BODY "3 0 1 2.5\n",
       "%s:13: face 0: property 'vertex_indices': '2.5' is not an integer"},
      {PLY_TRIANGLE_HEADER "property list char int vertex_indices\n" PLY_TRIANGLE_BODY "-1 0 1 2\n",
       "%s:13: face 0: list 'vertex_indices' has a negative count -1"},
      {PLY_TRIANGLE_HEADER "property list uint int vertex_indices\n" PLY_TRIANGLE_BODY "1000 0 1 2\n",
       "%s:13: face 0: list 'vertex_indices' has a count 1000, more than the 7 bytes left can hold"},
      {PLY_TRIANGLE_HEADER "property list uchar int vertex_indices\n" PLY_TRIANGLE_BODY "3 0 1      \n\n",
       "%s:15: face 0: the file ends before property 'vertex_indices'"},
      {PLY_TRIANGLE_HEADER "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n",
       "%s:12: vertex 2: property 'z': 'zero' is not a number"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    char name[32];
    snprintf(name, sizeof name, "error%zu.ply", i);
    const char *path = lt_test_write_file(name, cases[i].text);
    assert_error_is(load_fails(path, LT_ERROR_PARSE), cases[i].message, path);
  }
}

#define PLY_BINARY_TRIANGLE_HEADER "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" PLY_XYZ "element face 1\n"

/* Binary body errors name the element, the item and the byte offset. */
static void scenes_io_ply_binary_errors_name_item_and_byte(void **state) {
  (void)state;
  const char *header = PLY_BINARY_TRIANGLE_HEADER "property list char uint vertex_indices\nend_header\n";
  size_t face_at = strlen(header) + 36;
  char expected[160];

  /* 3 vertices and a face declared, 12 bytes of body: refused before the body is read. */
  ply_body b = {.size = 12};
  const char *path = write_ply("short_body.ply", header, &b);
  assert_error_is(load_fails(path, LT_ERROR_PARSE),
                  "%s: the header declares 3 vertex elements (line 3) of at least 12 bytes each, more than the 12 "
                  "bytes left for them can hold",
                  path);

  /* A face whose last property, after a whole index list, is cut off. */
  b = (ply_body){.size = 36};
  put_int(&b, 3, 1), put_int(&b, 0, 4), put_int(&b, 1, 4), put_int(&b, 2, 4);
  path = write_ply("short_face.ply",
                   PLY_BINARY_TRIANGLE_HEADER "property list char uint vertex_indices\nproperty int tag\nend_header\n",
                   &b);
  size_t tag_at = face_at + strlen("property int tag\n") + 1 + 12; /* after the count and 3 indices */
  snprintf(expected, sizeof expected, "%%s: face 0 at byte %zu: the file ends before the 4 bytes of property 'tag'",
           tag_at);
  assert_error_is(load_fails(path, LT_ERROR_PARSE), expected, path);

  /* An index beyond the vertices, as unsigned as it gets. */
  b = (ply_body){.size = 36};
  put_int(&b, 3, 1), put_int(&b, 0, 4), put_int(&b, 1, 4), put_int(&b, 4294967295u, 4);
  path = write_ply("range.ply", header, &b);
  snprintf(expected, sizeof expected, "%%s: face 0 at byte %zu: vertex index 4294967295 out of range (3 vertices)",
           face_at + 9);
  assert_error_is(load_fails(path, LT_ERROR_PARSE), expected, path);

  /* Negative and absurd list counts. */
  b = (ply_body){.size = 36};
  put_int(&b, -1, 1), put_int(&b, 0, 4), put_int(&b, 1, 4), put_int(&b, 2, 4);
  path = write_ply("negative_list.ply", header, &b);
  snprintf(expected, sizeof expected, "%%s: face 0 at byte %zu: list 'vertex_indices' has a negative count -1",
           face_at);
  assert_error_is(load_fails(path, LT_ERROR_PARSE), expected, path);

  header = PLY_BINARY_TRIANGLE_HEADER "property list int uint vertex_indices\nend_header\n";
  face_at = strlen(header) + 36;
  b = (ply_body){.size = 36};
  put_int(&b, 1000000000, 4), put_int(&b, 0, 4), put_int(&b, 1, 4), put_int(&b, 2, 4);
  path = write_ply("huge_list.ply", header, &b);
  snprintf(expected, sizeof expected, "%%s: face 0 at byte %zu: list 'vertex_indices' has a count 1000000000, more "
           "than the 12 bytes left can hold", face_at);
  assert_error_is(load_fails(path, LT_ERROR_PARSE), expected, path);
}

/* A 200-byte file that declares 10^9 vertices fails at once, before any allocation for them. */
static void scenes_io_ply_huge_count_in_small_file_fails_fast(void **state) {
  (void)state;
  const char *headers[] = {"ply\nformat ascii 1.0\nelement vertex 1000000000\n" PLY_XYZ "end_header\n",
                           "ply\nformat binary_big_endian 1.0\nelement vertex 1000000000\n" PLY_XYZ "end_header\n"};
  for (int i = 0; i < 2; i++) {
    ply_body b = {.size = 200 - strlen(headers[i])};
    memset(b.bytes, '0', b.size);
    const char *path = write_ply(i ? "huge_binary.ply" : "huge_ascii.ply", headers[i], &b);
    char expected[200];
    snprintf(expected, sizeof expected, "%%s: the header declares 1000000000 vertex elements (line 3) of at least %d "
             "bytes each, more than the %zu bytes left for them can hold", i ? 12 : 6, b.size);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    assert_error_is(load_fails(path, LT_ERROR_PARSE), expected, path);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    assert_true(t1.tv_sec - t0.tv_sec < 2);
  }
}

/* Other formats still go through assimp, whose errors are prefixed with the file. */
static void scenes_io_assimp_reads_off_and_names_file_on_error(void **state) {
  (void)state;
  const char *path = lt_test_write_file("triangle.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  lt_scene *scene = lt_test_load_ok(path);
  assert_int_equal(lt_scene_triangle_count(scene), 1);
  lt_scene_destroy(scene);

  path = lt_test_write_file("garbage.off", "OFF\nthree one zero\n");
  const char *message = load_fails(path, LT_ERROR_PARSE);
  assert_true(strncmp(message, path, strlen(path)) == 0);
  assert_true(strlen(message) > strlen(path) + 2);
}

static void scenes_io_ply_garbage_count_is_parse_error(void **state) {
  (void)state;
  const char *path = lt_test_write_file("garbage.ply", "ply\nformat ascii 1.0\nelement vertex nonsense\nend_header\n");
  assert_error_is(load_fails(path, LT_ERROR_PARSE), "%s:3: element count 'nonsense' is not a whole number from 0",
                  path);
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
      cmocka_unit_test(scenes_io_ply_ascii_skips_other_properties_and_elements),
      cmocka_unit_test(scenes_io_ply_binary_little_endian_reads_positions_and_fans_quad),
      cmocka_unit_test(scenes_io_ply_binary_big_endian_reads_any_scalar_type),
      cmocka_unit_test(scenes_io_ply_non_finite_vertices_skip_triangles),
      cmocka_unit_test(scenes_io_ply_tiny_ascii_loads),
      cmocka_unit_test(scenes_io_ply_errors_name_file_and_line),
      cmocka_unit_test(scenes_io_ply_binary_errors_name_item_and_byte),
      cmocka_unit_test(scenes_io_ply_huge_count_in_small_file_fails_fast),
      cmocka_unit_test(scenes_io_ply_garbage_count_is_parse_error),
      cmocka_unit_test(scenes_io_assimp_reads_off_and_names_file_on_error),
      cmocka_unit_test(scenes_io_generators_round_trip_through_obj),
      cmocka_unit_test(scenes_io_generators_are_deterministic),
  };
  return cmocka_run_group_tests(tests, lt_test_temp_dir_create, lt_test_temp_dir_remove);
}
