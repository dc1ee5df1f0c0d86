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
typedef uint16_t lt_u16;
typedef uint8_t lt_u8;

/* Four floats (and ints) as one SIMD value, for the builders' box arithmetic: the GCC/Clang
 * vector extension here, float4 and int4 in OpenCL. Lanes are read with lt_v4_lane. */
typedef float lt_v4 __attribute__((vector_size(16)));
typedef int32_t lt_vi4 __attribute__((vector_size(16)));
#define lt_v4_lane(v, i) ((v)[i])
#define lt_v4_make(a, b, c, d) ((lt_v4){(a), (b), (c), (d)})
#define lt_v4_splat(a) ((lt_v4){(a), (a), (a), (a)})
#define lt_v4_to_int(v) __builtin_convertvector((v), lt_vi4) /* toward zero, like (int) */
/* Unroll the next loop twice (loops over a node's two children, where the arrays indexed by
 * the side should become registers). */
#define LT_UNROLL_2 _Pragma("GCC unroll 2")
/* Keep a function out of line (a leaf's triangle loop, called from two places of a loop that
 * is unrolled, was slower inlined into both). */
#define LT_DEVICE_OUTLINE static __attribute__((noinline, unused))
/* A hint that *p is read soon (the builders gather primitive boxes through the index). */
#define lt_prefetch(p) __builtin_prefetch(p)
/* The lowest and the highest set bit of a nonzero 32-bit mask. */
#define lt_low_bit(m) __builtin_ctz(m)
#define lt_high_bit(m) (31 - __builtin_clz(m))
#if defined(__SSE__)
#include <xmmintrin.h>
/* a < b ? a : b and a > b ? a : b per lane, as the scalar code writes them. */
static inline lt_v4 lt_v4_min(lt_v4 a, lt_v4 b) { return (lt_v4)_mm_min_ps((__m128)a, (__m128)b); }
static inline lt_v4 lt_v4_max(lt_v4 a, lt_v4 b) { return (lt_v4)_mm_max_ps((__m128)a, (__m128)b); }
/* Whether a >= b in any lane. */
static inline int lt_v4_any_ge(lt_v4 a, lt_v4 b) { return _mm_movemask_ps(_mm_cmpge_ps((__m128)a, (__m128)b)) != 0; }
#else
static inline int lt_v4_any_ge(lt_v4 a, lt_v4 b) {
  lt_vi4 m = a >= b;
  return (m[0] | m[1] | m[2] | m[3]) != 0;
}
static inline lt_v4 lt_v4_min(lt_v4 a, lt_v4 b) {
  lt_vi4 m = a < b;
  return (lt_v4)((m & (lt_vi4)a) | (~m & (lt_vi4)b));
}
static inline lt_v4 lt_v4_max(lt_v4 a, lt_v4 b) {
  lt_vi4 m = a > b;
  return (lt_v4)((m & (lt_vi4)a) | (~m & (lt_vi4)b));
}
#endif
#define lt_make_int4(a, b, c, d) ((lt_int4){(a), (b), (c), (d)})
#define lt_make_float4(a, b, c, d) ((lt_float4){(a), (b), (c), (d)})
typedef int32_t lt_i32;

/* The native backend runs one thread per work-group; the runtime sets these per thread. */
extern _Thread_local int lt__native_group_id;
extern _Thread_local int lt__native_num_groups;
/* Fault injection for tests: this work-group stops at once inside a persistent launch, without
 * leaving the pool (-1: none). */
extern int lt__native_stall_group;

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
/* The magnitude of a float as a float: C's fabs would take every operation after it into double. */
#define lt_fabsf(x) fabsf(x)

/* Sequentially consistent, like OpenCL 1.2's atomic_* on global memory used as a fence here. */
#define lt_atomic_add_u32(p, v) __atomic_fetch_add((p), (v), __ATOMIC_SEQ_CST)
static inline lt_u32 lt__atomic_cas_u32(lt_u32 *p, lt_u32 expected, lt_u32 desired) {
  __atomic_compare_exchange_n(p, &expected, desired, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST);
  return expected;
}
#define lt_atomic_cas_u32(p, expected, desired) lt__atomic_cas_u32((lt_u32 *)(p), (expected), (desired))

static inline lt_i32 lt__atomic_cas_i32(lt_i32 *p, lt_i32 expected, lt_i32 desired) {
  __atomic_compare_exchange_n(p, &expected, desired, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST);
  return expected;
}
#define lt_atomic_add_i32(p, v) __atomic_fetch_add((lt_i32 *)(p), (v), __ATOMIC_SEQ_CST)
#define lt_atomic_cas_i32(p, expected, desired) lt__atomic_cas_i32((lt_i32 *)(p), (expected), (desired))
#define lt_atomic_load_i32(p) __atomic_load_n((lt_i32 *)(p), __ATOMIC_SEQ_CST)
#define lt_atomic_store_i32(p, v) __atomic_store_n((lt_i32 *)(p), (v), __ATOMIC_SEQ_CST)
/* GCC 12 has no __atomic_fetch_min: a compare-and-swap loop, returning the old value. */
static inline lt_i32 lt__atomic_min_i32(lt_i32 *p, lt_i32 v) {
  lt_i32 old = __atomic_load_n(p, __ATOMIC_SEQ_CST);
  while (v < old && !__atomic_compare_exchange_n(p, &old, v, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) {
  }
  return old;
}
static inline lt_i32 lt__atomic_max_i32(lt_i32 *p, lt_i32 v) {
  lt_i32 old = __atomic_load_n(p, __ATOMIC_SEQ_CST);
  while (v > old && !__atomic_compare_exchange_n(p, &old, v, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) {
  }
  return old;
}
#define lt_atomic_min_i32(p, v) lt__atomic_min_i32((lt_i32 *)(p), (v))
#define lt_atomic_max_i32(p, v) lt__atomic_max_i32((lt_i32 *)(p), (v))
#define lt_fence() __atomic_thread_fence(__ATOMIC_SEQ_CST)
/* A load that later reads cannot overtake (a consumer's side of a publication): on x86 a plain
 * load, where lt_atomic_load_i32 followed by lt_fence costs a full fence per read. */
#define lt_atomic_load_acquire_i32(p) __atomic_load_n((lt_i32 *)(p), __ATOMIC_ACQUIRE)
/* A load that orders nothing: for a value an acquire load before it already publishes. */
#define lt_atomic_load_relaxed_i32(p) __atomic_load_n((lt_i32 *)(p), __ATOMIC_RELAXED)

#endif
