/* Closed meshes and hard-case rays, shared by the robustness test (tests/test_robustness.c) and
 * the accuracy report (benchmarks/bench_accuracy.c). A closed mesh here shares every vertex bit
 * for bit between the triangles around it, so that a ray from its inside must hit something:
 * a miss is a leak. */
#ifndef LT_HARD_CASES_H
#define LT_HARD_CASES_H

#include <stddef.h>
#include <stdint.h>

#include "lazytrace.h"

/* A closed mesh with points strictly inside it to shoot from. */
typedef struct lt_hc_mesh {
  lt_scene *scene;
  float *inside; /* 3 floats per point */
  size_t inside_count;
} lt_hc_mesh;

/* The icosphere generator's sphere:LEVEL (unit radius); inside: the centre and points within
 * half the radius. */
lt_hc_mesh lt_hc_sphere(int level, uint64_t seed);
/* A torus about +y, major radius 1, minor radius 0.35, on an index grid so that the seams
 * close exactly; inside: points of the core circle. */
lt_hc_mesh lt_hc_torus(int major_segments, int minor_segments);
/* The cube [-n/2, n/2]^3 (n even), each face an n x n grid of integer points split into two
 * triangles per square with alternating diagonals, edges shared along the cube's edges;
 * inside: the centre and integer points strictly inside at even indices (axis-aligned rays
 * from them run along the grid lines of the faces they hit), arbitrary points at odd ones. */
lt_hc_mesh lt_hc_cube(int n, uint64_t seed);
/* The mesh scaled about the origin by `scale` and then moved by `offset` (in float, vertex by
 * vertex, so that a closed mesh stays closed), inside points with it. */
lt_hc_mesh lt_hc_transform(const lt_hc_mesh *mesh, float scale, float offset);
void lt_hc_free(lt_hc_mesh *mesh);

/* The distinct vertices of a scene (bitwise), sorted; returns the count, *out is malloc'ed. */
size_t lt_hc_vertices(const lt_scene *scene, float **out);
/* The midpoint of every distinct edge, rounded to float; *out is malloc'ed. */
size_t lt_hc_edge_midpoints(const lt_scene *scene, float **out);

/* count rays, ray i from inside point i % inside_count towards target i % target_count
 * (direction = target - origin, tmin 0, tmax infinity). */
void lt_hc_rays_to_targets(const lt_hc_mesh *mesh, const float *targets, size_t target_count, size_t count,
                           lt_ray *out);
/* count rays from the inside points in uniformly random directions. */
void lt_hc_random_rays(const lt_hc_mesh *mesh, uint64_t seed, size_t count, lt_ray *out);
/* The closed-mesh ray set of the report and the tests: a third at the vertices, a third at
 * the edge midpoints, a third in random directions. */
size_t lt_hc_closed_rays(const lt_hc_mesh *mesh, uint64_t seed, size_t count, lt_ray *out);

/* Rays that miss by definition: a NaN or infinite component, a zero direction, tmin > tmax.
 * Writes at most max rays; returns how many. */
size_t lt_hc_invalid_rays(lt_ray *out, size_t max);

/* Number of rays with no hit. */
size_t lt_hc_count_misses(const lt_hit *hits, size_t n);

#endif
