/* Watertight ray-triangle intersection: Woop, Benthin and Wald, "Watertight Ray/Triangle
 * Intersection", JCGT 2(1), 2013. The ray is sheared so it runs along +z from the origin; the
 * edge functions of the projected triangle then decide the hit, and an edge function that is
 * exactly 0 is recomputed in double so that rays through shared edges and vertices can never
 * slip between two triangles. */
#ifndef LT_INTERSECT_TRIANGLE_H
#define LT_INTERSECT_TRIANGLE_H

#include "kernels/shared_types.h"

/* A ray prepared for the watertight test and the slab test. */
typedef struct lt_ray_setup {
  float org[3];
  float dir[3];
  float inv_dir[3]; /* 1/dir; unused on an axis whose direction component is 0 */
  float tmin, tmax;
  int kx, ky, kz;   /* axes permuted so that kz has the largest |dir| */
  float sx, sy, sz; /* shear constants */
  int valid;        /* 0 for NaN or infinite components, a zero direction or tmin > tmax */
} lt_ray_setup;

LT_DEVICE lt_ray_setup lt_ray_prepare(float ox, float oy, float oz, float tmin, float dx,
                                      float dy, float dz, float tmax) {
  lt_ray_setup r;
  r.org[0] = ox, r.org[1] = oy, r.org[2] = oz;
  r.dir[0] = dx, r.dir[1] = dy, r.dir[2] = dz;
  r.tmin = tmin, r.tmax = tmax;

  /* Reject what has no defined answer; tmax may be +infinity, nothing else may be non-finite. */
  r.valid = lt_isfinite(ox) && lt_isfinite(oy) && lt_isfinite(oz) && lt_isfinite(dx) &&
            lt_isfinite(dy) && lt_isfinite(dz) && lt_isfinite(tmin) && !isnan(tmax) &&
            tmin <= tmax && (dx != 0.0f || dy != 0.0f || dz != 0.0f);
  for (int k = 0; k < 3; k++) r.inv_dir[k] = r.dir[k] != 0.0f ? 1.0f / r.dir[k] : 0.0f;

  /* kz is the dimension where |dir| is largest; swapping kx and ky keeps the winding. */
  float ax = fabs(dx), ay = fabs(dy), az = fabs(dz);
  r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  r.kx = r.kz == 2 ? 0 : r.kz + 1;
  r.ky = r.kx == 2 ? 0 : r.kx + 1;
  if (r.dir[r.kz] < 0.0f) {
    int swap = r.kx;
    r.kx = r.ky;
    r.ky = swap;
  }
  float dkz = r.valid ? r.dir[r.kz] : 1.0f;
  r.sx = r.dir[r.kx] / dkz;
  r.sy = r.dir[r.ky] / dkz;
  r.sz = 1.0f / dkz;
  return r;
}

/* Whether a hit at (t, prim) beats the best so far: closer, or as close with a lower triangle
 * number, so that every structure breaks ties the same way as the brute-force reference. */
LT_DEVICE int lt_hit_better(float t, int prim, float best_t, int best_prim) {
  return best_prim < 0 || t < best_t || (t == best_t && prim < best_prim);
}

/* Tests the triangle (v0, v1, v2) numbered prim; on a better hit in [tmin, tmax] updates hit. */
LT_DEVICE int lt_intersect_triangle(const lt_ray_setup *r, const float *v0, const float *v1,
                                    const float *v2, int prim, lt_hit_record *hit) {
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
  float det = u + v + w;
  if (det == 0.0f) return 0;

  /* Scaled hit distance, then the one division. */
  float az = r->sz * a[r->kz], bz = r->sz * b[r->kz], cz = r->sz * c[r->kz];
  float t_scaled = u * az + v * bz + w * cz;
  float inv_det = 1.0f / det;
  float t = t_scaled * inv_det;
  if (!(t >= r->tmin && t <= r->tmax)) return 0;
  if (!lt_hit_better(t, prim, hit->t, hit->prim)) return 0;
  hit->t = t;
  hit->u = v * inv_det;
  hit->v = w * inv_det;
  hit->prim = prim;
  return 1;
}

#endif
