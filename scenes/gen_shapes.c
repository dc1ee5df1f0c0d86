/* The generators of single shapes and classic test scenes: a subdivided icosphere, a hairball,
 * the "teapot in a stadium" and the Cornell box. */
#include <math.h>
#include <stdlib.h>

#include "runtime/error.h"
#include "gen_geometry.h"

/* ---- sphere:LEVEL ---- */

/* Edge midpoints of one subdivision level, keyed on the sorted vertex pair, so that the two
 * triangles on an edge get the same new vertex and the sphere stays watertight bit for bit. */
typedef struct edge_map {
  uint64_t *keys; /* (lo << 32 | hi) + 1; 0 marks an empty slot */
  uint32_t *values;
  size_t mask;
} edge_map;

static uint32_t midpoint(edge_map *map, float *verts, uint32_t *vert_count, uint32_t a, uint32_t b) {
  uint64_t key = ((uint64_t)(a < b ? a : b) << 32 | (a < b ? b : a)) + 1;
  size_t slot = (size_t)((key * 0x9e3779b97f4a7c15ull) >> 20) & map->mask;
  for (; map->keys[slot]; slot = (slot + 1) & map->mask)
    if (map->keys[slot] == key) return map->values[slot];

  /* A new vertex: the chord's midpoint pushed out to the unit sphere, in double, then rounded. */
  double m[3], len = 0.0;
  for (int k = 0; k < 3; k++) m[k] = (double)verts[3 * a + k] + (double)verts[3 * b + k], len += m[k] * m[k];
  uint32_t v = (*vert_count)++;
  for (int k = 0; k < 3; k++) verts[3 * v + k] = (float)(m[k] / sqrt(len));
  map->keys[slot] = key;
  map->values[slot] = v;
  return v;
}

/* Splits every triangle into four; the last level appends to the scene instead of storing. */
static void subdivide(edge_map *map, float *verts, uint32_t *vert_count, const uint32_t *tris, size_t count,
                      uint32_t *out, lt__gen *g) {
  for (size_t i = 0; i < count; i++) {
    const uint32_t *t = tris + 3 * i;
    uint32_t ab = midpoint(map, verts, vert_count, t[0], t[1]);
    uint32_t bc = midpoint(map, verts, vert_count, t[1], t[2]);
    uint32_t ca = midpoint(map, verts, vert_count, t[2], t[0]);
    const uint32_t kids[12] = {t[0], ab, ca, ab, t[1], bc, ca, bc, t[2], ab, bc, ca};
    for (int j = 0; j < 12; j++)
      if (out) out[12 * i + j] = kids[j];
    for (int j = 0; !out && j < 12; j += 3)
      lt__gen_tri(g, verts + 3 * kids[j], verts + 3 * kids[j + 1], verts + 3 * kids[j + 2]);
  }
}

/* The icosahedron: cyclic permutations of (0, +-1, +-phi), normalized, with its 20 faces wound
 * counter-clockwise seen from outside. */
static void icosahedron(float *verts, uint32_t *tris) {
  static const uint32_t faces[60] = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                     4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                                     6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  static const signed char corners[12][3] = {{-1, 2, 0},  {1, 2, 0},  {-1, -2, 0}, {1, -2, 0}, {0, -1, 2},  {0, 1, 2},
                                             {0, -1, -2}, {0, 1, -2}, {2, 0, -1},  {2, 0, 1},  {-2, 0, -1}, {-2, 0, 1}};
  double phi = 0.5 * (1.0 + sqrt(5.0)), norm = sqrt(1.0 + phi * phi);
  for (int i = 0; i < 12; i++)
    for (int k = 0; k < 3; k++) {
      int c = corners[i][k];
      verts[3 * i + k] = (float)((c == 2 || c == -2 ? phi * (c / 2) : (double)c) / norm);
    }
  for (int i = 0; i < 60; i++) tris[i] = faces[i];
}

lt_status lt__gen_sphere(lt_scene *scene, int level) {
  lt__gen g;
  lt__gen_init(&g, scene);
  const float outer_eye[3] = {0.0f, 0.8f, -2.9f}, close_eye[3] = {0.0f, 0.4f, -1.45f}, origin[3] = {0, 0, 0};
  lt__gen_camera(&g, "outer", outer_eye, origin, 50.0f);
  lt__gen_camera(&g, "close", close_eye, origin, 60.0f);

  /* A level-L sphere has 10 * 4^L + 2 vertices and 20 * 4^L triangles. */
  size_t final_tris = (size_t)20 << (2 * level), max_verts = ((size_t)10 << (2 * level)) + 2;
  float *verts = malloc(max_verts * 3 * sizeof *verts);
  uint32_t *tris = malloc(60 * sizeof *tris), vert_count = 12;
  edge_map map = {NULL, NULL, 0};
  if (!verts || !tris) goto out_of_memory;
  icosahedron(verts, tris);
  for (int i = 0; level == 0 && i < 20; i++)
    lt__gen_tri(&g, verts + 3 * tris[3 * i], verts + 3 * tris[3 * i + 1], verts + 3 * tris[3 * i + 2]);

  /* Each level gets a fresh midpoint table, at most half full. */
  for (int l = 0; l < level && !g.status; l++) {
    size_t count = (size_t)20 << (2 * l), slots = 1;
    while (slots < 3 * count) slots <<= 1;
    uint32_t *next = l + 1 == level ? NULL : malloc(4 * count * 3 * sizeof *next);
    map.keys = calloc(slots, sizeof *map.keys);
    map.values = malloc(slots * sizeof *map.values);
    map.mask = slots - 1;
    if ((l + 1 < level && !next) || !map.keys || !map.values) {
      free(next);
      goto out_of_memory;
    }
    subdivide(&map, verts, &vert_count, tris, count, next, &g);
    free(map.keys), free(map.values), free(tris);
    map.keys = NULL, map.values = NULL, tris = next;
  }
  free(verts), free(tris);
  return g.status;

out_of_memory:
  free(map.keys), free(map.values), free(verts), free(tris);
  return lt__fail(LT_ERROR_OUT_OF_MEMORY, "sphere:%d: out of memory for %zu triangles", level, final_tris);
}

/* ---- hairball:N ---- */

/* A uniform random point in the ball of radius r, by rejection from the cube. */
static void random_in_ball(lt__rng *rng, float r, float p[3]) {
  do
    for (int k = 0; k < 3; k++) p[k] = lt__rng_range(rng, -r, r);
  while (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] > r * r || p[0] * p[0] + p[1] * p[1] + p[2] * p[2] < 1e-6f * r * r);
}

static void set_length(float v[3], float length) {
  float s = length / sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; k++) v[k] *= s;
}

lt_status lt__gen_hairball(lt_scene *scene, int strands) {
  enum { POINTS = 7 };
  const float step = 0.1f, bend = 0.6f;
  lt__rng rng = {0x6861697262616c6cull};
  lt__gen g;
  lt__gen_init(&g, scene);
  const float outer_eye[3] = {0.0f, 0.6f, -2.8f}, close_eye[3] = {0.15f, 0.2f, -1.3f}, origin[3] = {0, 0, 0};
  lt__gen_camera(&g, "outer", outer_eye, origin, 50.0f);
  lt__gen_camera(&g, "close", close_eye, origin, 60.0f);

  /* Thinner strands when there are more, so that the ball is about equally opaque at any N
   * and N scales the triangle count; within limits that keep the tubes sound in float. */
  float radius = (float)(0.02 * sqrt(1000.0 / strands));
  radius = fminf(0.03f, fmaxf(0.0005f, radius));
  for (int s = 0; s < strands && !g.status; s++) {
    float path[POINTS][3], dir[3], kick[3];
    random_in_ball(&rng, 0.9f, path[0]);
    random_in_ball(&rng, 1.0f, dir);
    set_length(dir, step);

    /* A random walk that bends a little each step and turns back at the ball's surface. */
    for (int i = 1; i < POINTS; i++) {
      random_in_ball(&rng, 1.0f, kick);
      set_length(kick, bend * step);
      for (int k = 0; k < 3; k++) dir[k] += kick[k];
      set_length(dir, step);
      const float *p = path[i - 1];
      float out = p[0] * dir[0] + p[1] * dir[1] + p[2] * dir[2], r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
      if (r2 > 0.81f && out > 0.0f)
        for (int k = 0; k < 3; k++) dir[k] -= 2.0f * out / r2 * p[k];
      for (int k = 0; k < 3; k++) path[i][k] = p[k] + dir[k];
    }
    lt__gen_tube(&g, (const float(*)[3])path, POINTS, radius, 3 + (int)(lt__rng_next(&rng) % 3), 0);
  }
  return g.status;
}

/* ---- teapot-stadium ---- */

/* A teapot of about 3.7k triangles, 0.2 m high, at the origin: body and lid as surfaces of
 * revolution meeting on one ring, the spout and handle as tubes sunk into the body. It stands
 * half a millimetre above the field so that its base and the field never coincide. */
static void teapot(lt__gen *g) {
  enum { BODY = 20, SLICES = 48, SPOUT = 12, HANDLE = 24 };
  static const float lid[9][2] = {{0, 1.0f},     {0.8f, 1.0f},  {0.7f, 1.08f},  {0.4f, 1.15f}, {0.15f, 1.18f},
                                  {0.1f, 1.22f}, {0.16f, 1.3f}, {0.12f, 1.36f}, {0, 1.37f}};
  float body[BODY + 3][2], spout[SPOUT][3], handle[HANDLE][3];
  lt__xform size = lt__xform_scale(0.15f, 0.15f, 0.15f);
  size.m[1][3] = 0.0005f;
  lt__xform saved = lt__gen_push(g, size);
  body[0][0] = 0.0f, body[0][1] = 0.0f;
  for (int i = 0; i <= BODY; i++) {
    float y = (float)i / BODY, c, s;
    lt__sincos(LT_GEN_PI * (0.85 * y + 0.05), &c, &s);
    body[i + 1][0] = 0.72f + 0.4f * s, body[i + 1][1] = y;
  }
  body[BODY + 2][0] = 0.8f, body[BODY + 2][1] = 1.0f;
  lt__gen_lathe(g, (const float(*)[2])body, BODY + 3, SLICES);
  lt__gen_lathe(g, lid, 9, SLICES);

  /* The spout follows a quadratic Bezier curve out and up; the handle a half ellipse. */
  for (int i = 0; i < SPOUT; i++) {
    float t = (float)i / (SPOUT - 1), u = 1.0f - t;
    spout[i][0] = u * u * 0.85f + 2.0f * u * t * 1.5f + t * t * 1.75f;
    spout[i][1] = u * u * 0.3f + 2.0f * u * t * 0.35f + t * t * 0.95f;
    spout[i][2] = 0.0f;
  }
  for (int i = 0; i < HANDLE; i++) {
    float c, s;
    lt__sincos(LT_GEN_PI * ((double)i / (HANDLE - 1) - 0.5), &c, &s);
    handle[i][0] = -0.9f - 0.5f * c, handle[i][1] = 0.52f + 0.3f * s, handle[i][2] = 0.0f;
  }
  lt__gen_tube(g, (const float(*)[3])spout, SPOUT, 0.12f, 16, 1);
  lt__gen_tube(g, (const float(*)[3])handle, HANDLE, 0.07f, 12, 0);
  g->xf = saved;
}

/* A stadium of about 330k triangles around the origin, elliptical with semi-axes 62 m by 48 m at
 * the field's edge: the field, a bowl of 30 rows of seats, and a roof ring on columns. The
 * bowl's profile is in units of those semi-axes, scaled to the ellipse by the placement. */
static void stadium(lt__gen *g) {
  enum { ROWS = 30, SLICES = 512 };
  const float A = 62.0f, B = 48.0f, rise = 0.45f, ds = 0.015f, front = 2.5f;
  static const float roof[5][2] = {{1.5f, 23.5f}, {1.5f, 24.0f}, {1.15f, 25.0f}, {1.15f, 24.7f}, {1.5f, 23.5f}};
  float bowl[2 * ROWS + 5][2];
  int n = 0;

  /* The field: 2 m squares wherever they reach inside the ellipse; their outer parts are hidden
   * under the stands. A disc of fan triangles would crowd slivers under the teapot instead. */
  for (int i = -32; i < 32; i++)
    for (int j = -25; j < 25; j++) {
      float x = 2.0f * (i < 0 ? i + 1 : i), z = 2.0f * (j < 0 ? j + 1 : j);
      if ((x / A) * (x / A) + (z / B) * (z / B) < 1.0f)
        lt__gen_rect(g, 1, 0.0f, 2.0f * j, 2.0f * i, 2.0f * j + 2.0f, 2.0f * i + 2.0f, 1);
    }
  lt__xform saved = lt__gen_push(g, lt__xform_scale(A, 1.0f, B));

  /* The bowl from its outer foot over the top walkway, down the rows to the field barrier. */
  float s_top = 1.0f + ROWS * ds, y_top = front + ROWS * rise;
  bowl[n][0] = s_top + 0.02f, bowl[n++][1] = 0.0f;
  bowl[n][0] = s_top + 0.02f, bowl[n++][1] = y_top;
  bowl[n][0] = s_top, bowl[n++][1] = y_top;
  for (int k = ROWS; k > 0; k--) {
    bowl[n][0] = 1.0f + k * ds, bowl[n++][1] = front + (k - 1) * rise;
    bowl[n][0] = 1.0f + (k - 1) * ds, bowl[n++][1] = front + (k - 1) * rise;
  }
  bowl[n][0] = 1.0f, bowl[n++][1] = 0.0f;
  lt__gen_lathe(g, (const float(*)[2])bowl, n, SLICES);
  lt__gen_lathe(g, roof, 5, SLICES);
  g->xf = saved;

  /* Seats on every row, about 0.6 m apart, each turned to face the field. */
  for (int k = 0; k < ROWS; k++) {
    float s = 1.0f + (k + 0.5f) * ds, y = front + k * rise;
    int seats = (int)(2.0 * LT_GEN_PI * s * sqrt(0.5 * (A * A + B * B)) / 0.6);
    for (int j = 0; j < seats; j++) {
      float c, sn;
      lt__sincos(2.0 * LT_GEN_PI * j / seats, &c, &sn);
      double facing = atan2(c / A, sn / B) * 180.0 / LT_GEN_PI;
      lt__xform seat = lt__gen_push(g, lt__xform_place(A * s * c, y, B * s * sn, (float)facing));
      lt__gen_box(g, -0.22f, 0.0f, -0.2f, 0.22f, 0.45f, 0.2f);
      g->xf = seat;
    }
  }

  /* Columns under the outer edge of the roof. */
  for (int j = 0; j < 48; j++) {
    float c, sn;
    lt__sincos(2.0 * LT_GEN_PI * j / 48, &c, &sn);
    lt__xform column = lt__gen_push(g, lt__xform_place(A * 1.49f * c, 0.0f, B * 1.49f * sn, 0.0f));
    lt__gen_cylinder(g, 0.4f, 0.0f, 23.6f, 16);
    g->xf = column;
  }
}

lt_status lt__gen_teapot_stadium(lt_scene *scene) {
  lt__gen g;
  lt__gen_init(&g, scene);
  const float outer_eye[3] = {0.0f, 38.0f, -62.0f}, outer_look[3] = {0.0f, 0.0f, 0.0f};
  const float close_eye[3] = {0.25f, 0.25f, -0.55f}, close_look[3] = {0.0f, 0.08f, 0.0f};
  lt__gen_camera(&g, "outer", outer_eye, outer_look, 60.0f);
  lt__gen_camera(&g, "close", close_eye, close_look, 45.0f);
  teapot(&g);
  stadium(&g);
  return g.status;
}

/* ---- cornell ---- */

/* The Cornell box as measured (www.graphics.cornell.edu/online/box/data.html), in millimetres,
 * open towards -z. The light hangs 0.5 mm below the ceiling so that no two faces coincide. */
lt_status lt__gen_cornell(lt_scene *scene) {
  static const float quads[][4][3] = {
      {{552.8f, 0, 0}, {0, 0, 0}, {0, 0, 559.2f}, {549.6f, 0, 559.2f}},                     /* floor */
      {{556.0f, 548.8f, 0}, {556.0f, 548.8f, 559.2f}, {0, 548.8f, 559.2f}, {0, 548.8f, 0}}, /* ceiling */
      {{343.0f, 548.3f, 227.0f}, {343.0f, 548.3f, 332.0f}, {213.0f, 548.3f, 332.0f}, {213.0f, 548.3f, 227.0f}},
      {{549.6f, 0, 559.2f}, {0, 0, 559.2f}, {0, 548.8f, 559.2f}, {556.0f, 548.8f, 559.2f}}, /* back */
      {{0, 0, 559.2f}, {0, 0, 0}, {0, 548.8f, 0}, {0, 548.8f, 559.2f}},                     /* green */
      {{552.8f, 0, 0}, {549.6f, 0, 559.2f}, {556.0f, 548.8f, 559.2f}, {556.0f, 548.8f, 0}}, /* red */
      {{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}},                   /* short */
      {{290, 0, 114}, {290, 165, 114}, {240, 165, 272}, {240, 0, 272}},
      {{130, 0, 65}, {130, 165, 65}, {290, 165, 114}, {290, 0, 114}},
      {{82, 0, 225}, {82, 165, 225}, {130, 165, 65}, {130, 0, 65}},
      {{240, 0, 272}, {240, 165, 272}, {82, 165, 225}, {82, 0, 225}},
      {{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}}, /* tall */
      {{423, 0, 247}, {423, 330, 247}, {472, 330, 406}, {472, 0, 406}},
      {{472, 0, 406}, {472, 330, 406}, {314, 330, 456}, {314, 0, 456}},
      {{314, 0, 456}, {314, 330, 456}, {265, 330, 296}, {265, 0, 296}},
      {{265, 0, 296}, {265, 330, 296}, {423, 330, 247}, {423, 0, 247}}};
  lt__gen g;
  lt__gen_init(&g, scene);

  /* The measured camera: 35 mm focal length on a 25 mm film, a vertical field of 39.3 degrees. */
  const float outer_eye[3] = {278.0f, 273.0f, -800.0f}, outer_look[3] = {278.0f, 273.0f, 0.0f};
  const float close_eye[3] = {278.0f, 420.0f, 10.0f}, close_look[3] = {278.0f, 60.0f, 240.0f};
  lt__gen_camera(&g, "outer", outer_eye, outer_look, 39.3f);
  lt__gen_camera(&g, "close", close_eye, close_look, 70.0f);
  for (size_t i = 0; i < sizeof quads / sizeof quads[0]; i++)
    lt__gen_quad(&g, quads[i][0], quads[i][1], quads[i][2], quads[i][3]);
  return g.status;
}
