/* Ray-triangle intersection. The default is the watertight test of Woop, Benthin and Wald,
 * "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013: the ray is sheared so that it runs
 * along +z from the origin, the edge functions of the projected triangle decide the hit, and
 * an edge function that is exactly 0 is recomputed in double, so that rays through shared edges
 * and vertices can never slip between two triangles. The fast option is the test of Moller and
 * Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection", JGT 2(1), 1997: fewer
 * operations, but a ray through an edge or a vertex may miss every triangle around it. */
#ifndef LT_INTERSECT_TRIANGLE_H
#define LT_INTERSECT_TRIANGLE_H

#include "traversal/ray.h"

/* Whether a hit at (t, prim) beats the best so far: closer, or as close with a lower triangle
 * number, so that every structure breaks ties the same way as the brute-force reference. */
LT_DEVICE int lt_hit_better(float t, int prim, float best_t, int best_prim) {
  return best_prim < 0 || t < best_t || (t == best_t && prim < best_prim);
}

/* The hit distance, kept inside the interval where the ray's line crosses the triangle's own
 * bounding box; NaN when the line misses that box.
 *
 * Why: the watertight test computes t as a weighted mean of the vertices' depths, and for a
 * ray that grazes the triangle's plane the weights are poorly conditioned, so t can land
 * outside the stretch of the ray that lies in the triangle's box. A node holding the triangle
 * has a wider slab interval, bit for bit (see lt_ray_slabs), so after this clamp a node is
 * culled against the best hit or against [tmin, tmax] only when none of its triangles could
 * have won or tied: every structure then returns exactly the brute-force answer. The clamp
 * only ever moves t towards the true hit, which lies in that interval. */
LT_DEVICE float lt_clamp_to_box(const lt_ray_setup *r, const float *v0, const float *v1, const float *v2, float t) {
  float lo[3], hi[3];
  for (int k = 0; k < 3; k++) {
    float a = v0[k], b = v1[k], c = v2[k];
    float l = a < b ? a : b, h = a > b ? a : b;
    lo[k] = c < l ? c : l;
    hi[k] = c > h ? c : h;
  }
  float t_near, t_far;
  if (!lt_ray_slabs(r, lo, hi, 1, &t_near, &t_far) || !(t_near <= t_far)) return NAN;
  return t < t_near ? t_near : t > t_far ? t_far : t;
}

/* Whether the triangle has no area: its edges' cross product is exactly zero (collinear or
 * repeated vertices). Such a triangle is never hit. The edge functions of a ray that starts on
 * one, or runs along its line, are zero in exact arithmetic but not always after the shear's
 * rounding, which made it report hits at t = 0; tested only once a hit is found, so that the
 * cost is paid per hit, not per test. In double where the device has it: the differences of
 * floats are then exact, and the products nearly so.
 *
 * The distance of such a hit, from the triangle's plane in double where the device has it.
 * Which triangle is hit is the watertight test's decision; its own distance t, a weighted mean
 * of the sheared vertices' depths, loses digits on long slivers (weights from edge functions
 * that nearly cancel): 3% off on 60-by-0.02 triangles, where the plane's distance in double is
 * within a rounding of the true one. A ray in the plane, or a device without double, keeps the
 * test's own distance.
 *
 * Both in one: the plane's normal is the cross product the degeneracy test looks at, computed
 * once. Returns 0 for a triangle without area, else 1 with the distance in *dist. */
LT_DEVICE int lt_hit_distance_checked(const lt_ray_setup *r, const float *v0, const float *v1, const float *v2,
                                      float t, float *dist) {
#ifdef LT_HAVE_DOUBLE
  double e1[3], e2[3], n[3], num = 0.0, den = 0.0;
  for (int k = 0; k < 3; k++) e1[k] = (double)v1[k] - (double)v0[k], e2[k] = (double)v2[k] - (double)v0[k];
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  if (n[0] == 0 && n[1] == 0 && n[2] == 0) return 0;
  for (int k = 0; k < 3; k++) num += n[k] * ((double)v0[k] - (double)r->org[k]), den += n[k] * (double)r->dir[k];
  double plane = num / den;
  *dist = den != 0.0 && plane == plane && plane < 3.0e38 && plane > -3.0e38 ? (float)plane : t;
#else
  float e1[3], e2[3];
  for (int k = 0; k < 3; k++) e1[k] = v1[k] - v0[k], e2[k] = v2[k] - v0[k];
  if (e1[1] * e2[2] - e1[2] * e2[1] == 0 && e1[2] * e2[0] - e1[0] * e2[2] == 0 && e1[0] * e2[1] - e1[1] * e2[0] == 0)
    return 0;
  *dist = t;
#endif
  return 1;
}

/* Records a hit in [tmin, tmax] that beats the one in hit. */
LT_DEVICE int lt_record_hit(const lt_ray_setup *r, float t, float u, float v, int prim, lt_hit_record *hit) {
  if (!(t >= r->tmin && t <= r->tmax)) return 0;
  if (!lt_hit_better(t, prim, hit->t, hit->prim)) return 0;
  hit->t = t;
  hit->u = u;
  hit->v = v;
  hit->prim = prim;
  return 1;
}

/* The watertight test's last steps, for a triangle whose edge functions u, v, w (recomputed
 * in double where one was 0) are of one sign, with the scaled distance t_scaled = u * az +
 * v * bz + w * cz: the one division, the area and distance checks, the clamp and the record.
 * Shared by the one-triangle test and the native 8-wide path's four-triangle one, which
 * computes the same floats lane by lane. */
LT_DEVICE int lt_watertight_finish(const lt_ray_setup *r, const float *v0, const float *v1, const float *v2, float u,
                                   float v, float w, float t_scaled, int prim, lt_hit_record *hit) {
  float det = u + v + w, t;
  if (det == 0.0f) return 0;
  float inv_det = 1.0f / det;
  if (!lt_hit_distance_checked(r, v0, v1, v2, t_scaled * inv_det, &t)) return 0;
  return lt_record_hit(r, lt_clamp_to_box(r, v0, v1, v2, t), v * inv_det, w * inv_det, prim, hit);
}

/* The watertight test of the triangle (v0, v1, v2) numbered prim. */
LT_DEVICE int lt_intersect_watertight(const lt_ray_setup *r, const float *v0, const float *v1, const float *v2,
                                      int prim, lt_hit_record *hit) {
  /* Vertices relative to the origin, sheared and scaled into ray space. */
  float a[3], b[3], c[3];
  for (int k = 0; k < 3; k++) {
    a[k] = v0[k] - r->org[k];
    b[k] = v1[k] - r->org[k];
    c[k] = v2[k] - r->org[k];
  }
  float ax = a[r->kx] - r->sx * a[r->kz], ay = a[r->ky] - r->sy * a[r->kz];
  float bx = b[r->kx] - r->sx * b[r->kz], by = b[r->ky] - r->sy * b[r->kz];
  float cx = c[r->kx] - r->sx * c[r->kz], cy = c[r->ky] - r->sy * c[r->kz];

  /* Scaled barycentric coordinates: the edge functions. */
  float u = cx * by - cy * bx;
  float v = ax * cy - ay * cx;
  float w = bx * ay - by * ax;

#ifdef LT_HAVE_DOUBLE
  /* An edge function of exactly 0 may have lost its sign: recompute all three exactly. */
  if (u == 0.0f || v == 0.0f || w == 0.0f) {
    u = (float)((double)cx * (double)by - (double)cy * (double)bx);
    v = (float)((double)ax * (double)cy - (double)ay * (double)cx);
    w = (float)((double)bx * (double)ay - (double)by * (double)ax);
  }
#endif

  /* The ray passes outside an edge: mixed signs. Both windings are hit. */
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return 0;

  /* Scaled hit distance. */
  float az = r->sz * a[r->kz], bz = r->sz * b[r->kz], cz = r->sz * c[r->kz];
  float t_scaled = u * az + v * bz + w * cz;
  return lt_watertight_finish(r, v0, v1, v2, u, v, w, t_scaled, prim, hit);
}

/* The Moller-Trumbore test: barycentrics from two cross products, edges included. */
LT_DEVICE int lt_intersect_fast(const lt_ray_setup *r, const float *v0, const float *v1, const float *v2, int prim,
                                lt_hit_record *hit) {
  float e1[3], e2[3], s[3], p[3], q[3];
  for (int k = 0; k < 3; k++) e1[k] = v1[k] - v0[k], e2[k] = v2[k] - v0[k], s[k] = r->org[k] - v0[k];
  p[0] = r->dir[1] * e2[2] - r->dir[2] * e2[1];
  p[1] = r->dir[2] * e2[0] - r->dir[0] * e2[2];
  p[2] = r->dir[0] * e2[1] - r->dir[1] * e2[0];
  float det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
  if (det == 0.0f) return 0;
  float inv_det = 1.0f / det;

  /* The weight of v1, then of v2; each must be in [0, 1] and their sum at most 1. */
  float u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv_det;
  if (!(u >= 0.0f && u <= 1.0f)) return 0;
  q[0] = s[1] * e1[2] - s[2] * e1[1];
  q[1] = s[2] * e1[0] - s[0] * e1[2];
  q[2] = s[0] * e1[1] - s[1] * e1[0];
  float v = (r->dir[0] * q[0] + r->dir[1] * q[1] + r->dir[2] * q[2]) * inv_det;
  if (!(v >= 0.0f && u + v <= 1.0f)) return 0;
  float t;
  if (!lt_hit_distance_checked(r, v0, v1, v2, (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv_det, &t)) return 0;
  return lt_record_hit(r, lt_clamp_to_box(r, v0, v1, v2, t), u, v, prim, hit);
}

/* Tests the triangle (v0, v1, v2) numbered prim with the ray's test; on a better hit in
 * [tmin, tmax] updates hit and returns 1. */
LT_DEVICE int lt_intersect_triangle(const lt_ray_setup *r, const float *v0, const float *v1, const float *v2,
                                    int prim, lt_hit_record *hit) {
  if (r->flags & LT_QUERY_FLAG_FAST_TRIANGLES) return lt_intersect_fast(r, v0, v1, v2, prim, hit);
  return lt_intersect_watertight(r, v0, v1, v2, prim, hit);
}

#endif
