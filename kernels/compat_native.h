/* C11 side of the compat vocabulary (see compat.h): qualifiers vanish, a work-group is one
 * thread with local size 1, barriers are no-ops and atomics are the compiler's builtins. */
#ifndef LT_COMPAT_NATIVE_H
#define LT_COMPAT_NATIVE_H

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#define LT_HAVE_DOUBLE 1

#define LT_GLOBAL
#define LT_LOCAL
#define LT_CONSTANT const
#define LT_DEVICE static inline
#define LT_KERNEL

/* OpenCL's float4 and int4: 16 bytes, 16-byte aligned, components .x .y .z .w. */
typedef struct lt_float4 {
  _Alignas(16) float x;
  float y, z, w;
} lt_float4;
typedef struct lt_int4 {
  _Alignas(16) int32_t x;
  int32_t y, z, w;
} lt_int4;
typedef uint32_t lt_u32;
typedef int32_t lt_i32;

/* The native backend runs one thread per work-group; the runtime sets these per thread. */
extern _Thread_local int lt__native_group_id;
extern _Thread_local int lt__native_num_groups;

#define lt_local_id() 0
#define lt_local_size() 1
#define lt_group_id() lt__native_group_id
#define lt_num_groups() lt__native_num_groups
#define lt_barrier() ((void)0)
#define lt_assert(x) assert(x)

static inline int lt_float_as_int(float x) {
  int32_t i;
  memcpy(&i, &x, sizeof i);
  return i;
}
static inline float lt_int_as_float(int32_t i) {
  float x;
  memcpy(&x, &i, sizeof x);
  return x;
}
#define lt_isfinite(x) isfinite(x)

/* Sequentially consistent, like OpenCL 1.2's atomic_* on global memory used as a fence here. */
#define lt_atomic_add_u32(p, v) __atomic_fetch_add((p), (v), __ATOMIC_SEQ_CST)
static inline lt_u32 lt__atomic_cas_u32(lt_u32 *p, lt_u32 expected, lt_u32 desired) {
  __atomic_compare_exchange_n(p, &expected, desired, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST);
  return expected;
}
#define lt_atomic_cas_u32(p, expected, desired) lt__atomic_cas_u32((lt_u32 *)(p), (expected), (desired))

#endif
