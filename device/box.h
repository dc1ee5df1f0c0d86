/* Axis-aligned boxes and the vector helpers every builder and traversal shares: a box as 6
 * floats or as two 4-lane vectors, a triangle's box, surface area, and an order-preserving int
 * encoding of floats so that atomic integer min and max can grow boxes in global memory. */
#ifndef LT_DEVICE_BOX_H
#define LT_DEVICE_BOX_H

#include "device/compat.h"

/* An int whose order is the float's order (for every non-NaN float). */
LT_DEVICE lt_i32 lt_ordered(float f) {
  lt_i32 b = lt_float_as_int(f);
  return b >= 0 ? b : b ^ 0x7fffffff;
}
LT_DEVICE float lt_unordered(lt_i32 o) { return lt_int_as_float(o >= 0 ? o : o ^ 0x7fffffff); }

/* An axis-aligned box as 6 floats: lo xyz, hi xyz. */
typedef struct lt_box {
  float lo[3], hi[3];
} lt_box;

LT_DEVICE lt_box lt_box_empty(void) {
  lt_box b;
  for (int k = 0; k < 3; k++) b.lo[k] = INFINITY, b.hi[k] = -INFINITY;
  return b;
}

LT_DEVICE void lt_box_grow(lt_box *b, const lt_box *o) {
  for (int k = 0; k < 3; k++) {
    b->lo[k] = o->lo[k] < b->lo[k] ? o->lo[k] : b->lo[k];
    b->hi[k] = o->hi[k] > b->hi[k] ? o->hi[k] : b->hi[k];
  }
}

LT_DEVICE float lt_box_area(const lt_box *b) {
  float d[3];
  for (int k = 0; k < 3; k++) d[k] = b->hi[k] > b->lo[k] ? b->hi[k] - b->lo[k] : 0.0f;
  return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

/* A box as two vectors (lanes x y z, w unused) and back. */
LT_DEVICE lt_v4 lt_box_lo4(const lt_box *b) { return lt_v4_make(b->lo[0], b->lo[1], b->lo[2], 0.0f); }
LT_DEVICE lt_v4 lt_box_hi4(const lt_box *b) { return lt_v4_make(b->hi[0], b->hi[1], b->hi[2], 0.0f); }
LT_DEVICE lt_box lt_box_of4(lt_v4 lo, lt_v4 hi) {
  lt_box b;
  for (int k = 0; k < 3; k++) b.lo[k] = lt_v4_lane(lo, k), b.hi[k] = lt_v4_lane(hi, k);
  return b;
}

/* The box of a triangle given as 9 floats, as two vectors (w 0). */
LT_DEVICE void lt_tri_box4(const float *v, lt_v4 *lo, lt_v4 *hi) {
  lt_v4 a = lt_v4_make(v[0], v[1], v[2], 0.0f), b = lt_v4_make(v[3], v[4], v[5], 0.0f);
  lt_v4 c = lt_v4_make(v[6], v[7], v[8], 0.0f);
  *lo = lt_v4_min(c, lt_v4_min(a, b)), *hi = lt_v4_max(c, lt_v4_max(a, b));
}

/* The box and centroid of a triangle given as 9 floats. */
LT_DEVICE void lt_tri_bounds(const float *v, lt_box *box, float centroid[3]) {
  lt_v4 lo, hi;
  lt_tri_box4(v, &lo, &hi);
  *box = lt_box_of4(lo, hi);
  for (int k = 0; k < 3; k++) centroid[k] = 0.5f * (box->lo[k] + box->hi[k]);
}

/* Surface area of a box given as two vectors; the same float as lt_box_area (an extent is
 * hi - lo where hi > lo, else 0, and max(hi - lo, 0) is that, empty boxes included). */
LT_DEVICE float lt_area4(lt_v4 lo, lt_v4 hi) {
  lt_v4 d = lt_v4_max(hi - lo, lt_v4_splat(0.0f));
  float x = lt_v4_lane(d, 0), y = lt_v4_lane(d, 1), z = lt_v4_lane(d, 2);
  return 2.0f * (x * y + y * z + z * x);
}

#endif
