/* Structs shared by the host and the kernels, laid out the same on both sides: float4/int4
 * fields, sizes checked on the host with _Static_assert. */
#ifndef LT_DEVICE_TYPES_H
#define LT_DEVICE_TYPES_H

#include "device/compat.h"

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
_Static_assert(sizeof(lt_tri) == 48, "lt_tri is 48 bytes on both sides");
_Static_assert(sizeof(lt_hit_record) == 16, "lt_hit_record is 16 bytes, as in the hit file");
#endif

#endif
