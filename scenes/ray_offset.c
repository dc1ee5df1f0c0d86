/* Where secondary rays start: off the surface by a bound on the hit point's rounding error
 * (ray_offset.h). */
#include "scenes/ray_offset.h"

#include <math.h>

#include "traversal/intersect_triangle.h"

/* gamma(n) = n * eps / (1 - n * eps) with eps = 2^-24, the bound on the relative error of n
 * float operations (Higham; pbrt 3, section 3.9.1). */
static double gamma_n(int n) { return n * 0x1p-24 / (1.0 - n * 0x1p-24); }

/* The origin of a secondary ray from a hit at barycentrics (u, v) of triangle t, with its
 * unit normal n turned to the side the ray leaves by.
 *
 * The hit point p = w0 * v0 + u * v1 + v * v2 with w0 = (1 - u) - v is computed in float:
 *  - w0 takes two roundings, so the weights sum to 1 + e with |e| <= gamma(2) (1 + |u| + |v|);
 *    a combination whose weights do not sum to 1 lies off the plane by e times the point;
 *  - the three products and two sums take gamma(3) of the sum of the absolute terms.
 * So each coordinate is within err_k = (gamma(3) + gamma(2) (1 + |u| + |v|)) * S_k of a point
 * of the triangle's plane, where S_k = |w0 v0_k| + |u v1_k| + |v v2_k|, and p is within
 * d = sum_k |n_k| err_k of the plane along n. Moving p by 2 d along n puts it in front of the
 * plane by at least d; each moved coordinate is then stepped one float further along n, so
 * that rounding the sum cannot give any of the distance back. The bound is computed in
 * double and is relative to the vertices' magnitudes: it grows with coordinates far from the
 * origin (a scene at 1e6) and shrinks with small ones, unlike a fixed epsilon. */
void lt__offset_origin(const float *t, float u, float v, const float n[3], float p[3]) {
  float w0 = 1 - u - v;
  double rel = gamma_n(3) + gamma_n(2) * (1.0 + fabs(u) + fabs(v)), d = 0.0;
  for (int k = 0; k < 3; k++) {
    p[k] = w0 * t[k] + u * t[3 + k] + v * t[6 + k];
    double s = fabs((double)w0 * t[k]) + fabs((double)u * t[3 + k]) + fabs((double)v * t[6 + k]);
    d += fabs(n[k]) * rel * s;
  }
  /* A second bound: the intersection test's own error. A triangle beside this one in the same
   * plane (a quad's other half, a floor of many tiles) meets the ray at a true t just behind
   * the origin, but the watertight test computes t from the vertices relative to the origin,
   * sheared and scaled, with about 10 roundings of terms up to 2 M (M: the largest coordinate
   * of the triangle or the hit point), and the box clamp can carry a tiny negative t to -0.
   * Moving off the plane by twice that error keeps such a neighbour's t negative, for
   * neighbours of this triangle's magnitude. With exact coordinates (a floor at y = 0) the
   * hit point's bound alone would be 0. */
  double m = 0.0;
  for (int k = 0; k < 9; k++) m = fmax(m, fabs((double)t[k]));
  for (int k = 0; k < 3; k++) m = fmax(m, fabs((double)p[k]));
  d = fmax(d, gamma_n(10) * 2.0 * m);
  float offset = (float)(2.0 * d * (1.0 + gamma_n(4)));
  for (int k = 0; k < 3; k++) {
    float moved = p[k] + offset * n[k];
    if (n[k] > 0.0f) moved = nextafterf(moved, INFINITY);
    if (n[k] < 0.0f) moved = nextafterf(moved, -INFINITY);
    p[k] = moved;
  }
}

float lt__secondary_tmin(const float *t, int prim, const float org[3], const float dir[3], float tmax) {
  /* The origin is in front of the plane and the ray leaves it, so the plane is crossed behind
   * the origin. Only a ray running almost inside the plane can still get a computed t >= 0 on
   * the triangle it starts from (its weights are then poorly conditioned): every backend
   * computes that t bit for bit like the host, so the host runs the same test and starts such
   * a ray just past it. */
  lt_ray_setup setup = lt_ray_prepare(org[0], org[1], org[2], 0.0f, dir[0], dir[1], dir[2], tmax);
  lt_hit_record self = {INFINITY, 0.0f, 0.0f, -1};
  if (lt_intersect_triangle(&setup, t, t + 3, t + 6, prim, &self)) return nextafterf(self.t, INFINITY);
  return nextafterf(0.0f, INFINITY); /* never t = 0 or -0: the origin is off every surface */
}
