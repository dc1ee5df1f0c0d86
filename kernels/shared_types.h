/* Structs shared by the host and the kernels, laid out the same on both sides: float4/int4
 * fields, sizes checked on the host with _Static_assert. */
#ifndef LT_SHARED_TYPES_H
#define LT_SHARED_TYPES_H

#include "kernels/compat.h"

/* The deepest a BVH may be, so that a traversal stack of this many entries never overflows:
 * the builder makes a leaf at this depth whatever its size. */
#define LT_BVH_MAX_DEPTH 64
#define LT_BVH_STACK_SIZE LT_BVH_MAX_DEPTH

/* A binary BVH node holds the boxes of both children, so a visit tests two boxes with one
 * fetch (Aila and Laine 2009). A child link is an inner node index when its count is 0 and
 * the link is >= 0, a leaf of `count` triangles starting at `link` when count > 0, and an
 * empty child when count is 0 and the link is negative. */
typedef struct lt_bvh_node {
  lt_float4 left_xy;   /* 16 bytes: left child lo.x, hi.x, lo.y, hi.y */
  lt_float4 right_xy;  /* 16 bytes: right child lo.x, hi.x, lo.y, hi.y */
  lt_float4 lr_z;      /* 16 bytes: left lo.z, hi.z, right lo.z, hi.z */
  lt_i32 link[4];      /* 16 bytes: left link, right link, left count, right count (an array,
                          not an int4, so that single fields can be used atomically) */
} lt_bvh_node;

/* A triangle in leaf order: its three vertices, and its number in the scene in v0.w. */
typedef struct lt_tri {
  lt_float4 v0; /* 16 bytes: x, y, z, prim (int bits) */
  lt_float4 v1; /* 16 bytes: x, y, z, unused */
  lt_float4 v2; /* 16 bytes: x, y, z, unused */
} lt_tri;

/* A hit record, the same 16 bytes as the public lt_hit and the hit file. */
typedef struct lt_hit_record {
  float t;    /* 4 bytes */
  float u;    /* 4 bytes: weight of v1 */
  float v;    /* 4 bytes: weight of v2 */
  lt_i32 prim; /* 4 bytes: -1 on a miss */
} lt_hit_record;

/* Per-work-group counters, summed by the host. */
typedef struct lt_trace_counters {
  lt_u32 traversal_steps; /* 4 bytes: node visits */
  lt_u32 intersections;   /* 4 bytes: ray-triangle tests */
} lt_trace_counters;

#ifndef __OPENCL_VERSION__
_Static_assert(sizeof(lt_bvh_node) == 64, "lt_bvh_node is 64 bytes on both sides");
_Static_assert(sizeof(lt_tri) == 48, "lt_tri is 48 bytes on both sides");
_Static_assert(sizeof(lt_hit_record) == 16, "lt_hit_record is 16 bytes, as in the hit file");
#endif

#endif
