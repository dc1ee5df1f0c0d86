/* Shared pieces of the procedural scene generators: a deterministic random stream, affine
 * placements, tessellated primitives appended through the current placement, and the entry
 * points of the generators that generators.c dispatches to. */
#ifndef LT_GEN_GEOMETRY_H
#define LT_GEN_GEOMETRY_H

#include <stdint.h>

#include "scene_internal.h"

/* Every generator stays below this many triangles, so that a scene fits in a few GiB. */
#define LT_GEN_MAX_TRIANGLES 50000000.0
/* The most segments around a surface of revolution, and the most points on its profile. */
#define LT_GEN_MAX_SLICES  2048
#define LT_GEN_MAX_PROFILE 256
#define LT_GEN_PI          3.14159265358979323846

/* splitmix64: the same seed gives the same stream on every machine, which rand() does not. */
typedef struct lt__rng {
  uint64_t state;
} lt__rng;

uint64_t lt__rng_next(lt__rng *rng);
/* Uniform in [lo, hi), from the top 24 bits so that the step to a float is exact. */
float lt__rng_range(lt__rng *rng, float lo, float hi);

/* An affine map: out[i] = m[i][0] * x + m[i][1] * y + m[i][2] * z + m[i][3]. */
typedef struct lt__xform {
  float m[3][4];
} lt__xform;

lt__xform lt__xform_identity(void);
/* A rotation about +y by degrees (exact at quarter turns), then a move to (x, y, z). */
lt__xform lt__xform_place(float x, float y, float z, float degrees);
lt__xform lt__xform_scale(float sx, float sy, float sz);
/* The map that applies b first, then a. */
lt__xform lt__xform_mul(const lt__xform *a, const lt__xform *b);
/* cos and sin of an angle, computed in double and rounded, so that libm differences between
 * machines almost never reach the float result. */
void lt__sincos(double radians, float *c, float *s);

/* A generator's output: the scene, the placement applied to every vertex, and the first
 * failure, after which appends do nothing, so that shape code need not check every call. */
typedef struct lt__gen {
  lt_scene *scene;
  lt__xform xf;
  lt_status status;
} lt__gen;

void lt__gen_init(lt__gen *gen, lt_scene *scene);
/* Adds a camera with +y up, in world coordinates (the placement does not apply). */
void lt__gen_camera(lt__gen *gen, const char *name, const float eye[3], const float look[3], float fov_deg);
/* Composes local onto the current placement; returns the previous one, for restoring. */
lt__xform lt__gen_push(lt__gen *gen, lt__xform local);
void lt__gen_tri(lt__gen *gen, const float a[3], const float b[3], const float c[3]);
void lt__gen_quad(lt__gen *gen, const float a[3], const float b[3], const float c[3], const float d[3]);
/* An axis-aligned rectangle at coordinate `at` on axis (0 x, 1 y, 2 z), spanning the next two
 * axes in cyclic order (u, v) from (u0, v0) to (u1, v1), facing +axis if positive, else -axis. */
void lt__gen_rect(lt__gen *gen, int axis, float at, float u0, float v0, float u1, float v1, int positive);
/* A closed axis-aligned box, 12 triangles. */
void lt__gen_box(lt__gen *gen, float x0, float y0, float z0, float x1, float y1, float z1);
/* A surface of revolution about +y: profile points (radius, height), listed so that the
 * outside is on the right when walking along them in the (radius, height) plane, as on a
 * vase's outer wall from the bottom up; triangles then face outward. A zero radius
 * closes the surface with a fan; a profile whose last point equals its first is a closed ring. */
void lt__gen_lathe(lt__gen *gen, const float (*profile)[2], int points, int slices);
/* A closed cylinder about +y from height y0 to y1. */
void lt__gen_cylinder(lt__gen *gen, float radius, float y0, float y1, int sides);
void lt__gen_uv_sphere(lt__gen *gen, float cx, float cy, float cz, float radius, int stacks, int slices);
/* A torus about +y in the plane y = 0. */
void lt__gen_torus(lt__gen *gen, float major, float minor, int major_segments, int minor_segments);
/* A tube of the given radius along a polyline, with parallel-transported cross sections of
 * `sides` corners; the ends are closed with fans when capped is nonzero. */
void lt__gen_tube(lt__gen *gen, const float (*path)[3], int points, float radius, int sides, int capped);

/* The generators. Houses: rows one behind the other along +z, columns along x; style picks
 * the outer camera (LT_HOUSES_ROW: level, straight along +z; LT_HOUSES_GRID: raised). */
enum { LT_HOUSES_ROW = 0, LT_HOUSES_GRID = 1 };
#define LT_HOUSES_MAX 480 /* about 100k triangles each */
lt_status lt__gen_houses(lt_scene *scene, int rows, int columns, int style);
lt_status lt__gen_sphere(lt_scene *scene, int level);
lt_status lt__gen_hairball(lt_scene *scene, int strands);
lt_status lt__gen_teapot_stadium(lt_scene *scene);
lt_status lt__gen_cornell(lt_scene *scene);

#endif
