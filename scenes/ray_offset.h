/* Where secondary rays (shadow, AO, diffuse, mirror) start: off the surface by a bound
 * derived from the hit point's floating-point error, not a fixed epsilon (issue 5). */
#ifndef LT_SCENES_RAY_OFFSET_H
#define LT_SCENES_RAY_OFFSET_H

/* The origin of a secondary ray from a hit at barycentrics (u, v) of triangle t (9 floats),
 * with its unit normal n turned to the side the ray leaves by: the hit point moved along n
 * past its rounding bound and the intersection test's error for triangles of its magnitude
 * (the derivations are in ray_offset.c). */
void lt__offset_origin(const float *t, float u, float v, const float n[3], float p[3]);

/* The tmin of a secondary ray from origin org (lt__offset_origin) leaving triangle prim: the
 * smallest positive float, or just past the triangle for a ray that runs almost inside its plane and would still meet
 * it in front of the origin. */
float lt__secondary_tmin(const float *t, int prim, const float org[3], const float dir[3], float tmax);

#endif
