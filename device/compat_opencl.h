/* OpenCL C 1.2 side of the compat vocabulary (see compat.h). */
#ifndef LT_COMPAT_OPENCL_H
#define LT_COMPAT_OPENCL_H

/* Both backends must produce bit-identical hits: no fused multiply-adds anywhere. */
#pragma OPENCL FP_CONTRACT OFF

#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define LT_HAVE_DOUBLE 1
#endif

#define LT_GLOBAL __global
#define LT_LOCAL __local
#define LT_CONSTANT __constant
#define LT_DEVICE static inline
#define LT_KERNEL __kernel

typedef float4 lt_float4;
typedef int4 lt_int4;
typedef uint lt_u32;
typedef ushort lt_u16;
typedef uchar lt_u8;
typedef int lt_i32;

/* Four floats (and ints) as one SIMD value (see compat_native.h). */
typedef float4 lt_v4;
typedef int4 lt_vi4;
#define lt_v4_lane(v, i) ((i) == 0 ? (v).x : (i) == 1 ? (v).y : (i) == 2 ? (v).z : (v).w)
#define lt_v4_make(a, b, c, d) ((float4)((a), (b), (c), (d)))
#define lt_v4_splat(a) ((float4)(a))
#define lt_v4_to_int(v) convert_int4_rtz(v)
#define lt_prefetch(p) prefetch((p), 1)
#define lt_low_bit(m) (31 - (int)clz((m) & (0u - (m)))) /* see compat_native.h */
#define lt_high_bit(m) (31 - (int)clz(m))
#define LT_UNROLL_2 _Pragma("unroll 2") /* see compat_native.h */
#define LT_DEVICE_OUTLINE LT_DEVICE /* PoCL inlines everything into the work-group function */
/* a < b ? a : b and a > b ? a : b per lane, as the scalar code writes them. */
LT_DEVICE float4 lt_v4_min(float4 a, float4 b) { return select(b, a, a < b); }
LT_DEVICE float4 lt_v4_max(float4 a, float4 b) { return select(b, a, a > b); }
/* Whether a >= b in any lane. */
LT_DEVICE int lt_v4_any_ge(float4 a, float4 b) { return any(a >= b); }

#define lt_make_int4(a, b, c, d) ((int4)((a), (b), (c), (d)))
#define lt_make_float4(a, b, c, d) ((float4)((a), (b), (c), (d)))

#define lt_global_id() ((int)get_global_id(0))
#define lt_global_size() ((int)get_global_size(0))
#define lt_local_id() ((int)get_local_id(0))
#define lt_local_size() ((int)get_local_size(0))
#define lt_group_id() ((int)get_group_id(0))
#define lt_num_groups() ((int)get_num_groups(0))
#define lt_barrier() barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE)
#define lt_assert(x) ((void)0)

#define lt_float_as_int(x) as_int(x)
#define lt_int_as_float(x) as_float(x)
#define lt_isfinite(x) isfinite(x)
#define lt_fabsf(x) fabs(x)

/* The pool's protocol is written for sequentially consistent atomics and fences that order
 * global memory across the whole device (compat_native.h). OpenCL 1.2 promises neither: its
 * atomic_* functions order nothing and mem_fence is only defined within a work-group. PoCL on
 * a CPU gives both anyway. NVIDIA's compiler does not: mem_fence orders only within the SM and
 * the atomics are relaxed, so work-groups on other SMs saw flags before the data they publish
 * (wrong trees, early termination). Where the host says the device is NVIDIA's
 * (LT_FENCE_PTX, runtime/opencl.c), the fence is PTX's device-wide membar.gl, and every atomic
 * operation sits between two of them, which makes it sequentially consistent as on the native
 * backend; LT_FENCE_CL20 does the same with OpenCL 2.0's scoped fence, for devices that have
 * it (-cl-std=CL2.0 or later). */
#if defined(LT_FENCE_PTX)
#define lt_fence() __asm__ __volatile__("membar.gl;" ::: "memory")
#elif defined(LT_FENCE_CL20)
#define lt_fence() atomic_work_item_fence(CLK_GLOBAL_MEM_FENCE, memory_order_seq_cst, memory_scope_device)
#else
#define lt_fence() mem_fence(CLK_GLOBAL_MEM_FENCE)
#endif

#if defined(LT_FENCE_PTX) || defined(LT_FENCE_CL20)
/* lt__fenced_NAME(p, args): OP(p, args) between two fences. */
#define LT__FENCED(T, NAME, PARAMS, CALL) \
  inline T lt__fenced_##NAME PARAMS {     \
    lt_fence();                           \
    T old = CALL;                         \
    lt_fence();                           \
    return old;                           \
  }
LT__FENCED(uint, add_u32, (volatile LT_GLOBAL uint *p, uint v), atomic_add(p, v))
LT__FENCED(uint, cas_u32, (volatile LT_GLOBAL uint *p, uint e, uint d), atomic_cmpxchg(p, e, d))
LT__FENCED(int, add_i32, (volatile LT_GLOBAL int *p, int v), atomic_add(p, v))
LT__FENCED(int, cas_i32, (volatile LT_GLOBAL int *p, int e, int d), atomic_cmpxchg(p, e, d))
LT__FENCED(int, min_i32, (volatile LT_GLOBAL int *p, int v), atomic_min(p, v))
LT__FENCED(int, max_i32, (volatile LT_GLOBAL int *p, int v), atomic_max(p, v))
LT__FENCED(int, load_i32, (volatile LT_GLOBAL const int *p), *p)
LT__FENCED(int, xchg_i32, (volatile LT_GLOBAL int *p, int v), atomic_xchg(p, v))
#define lt_atomic_add_u32(p, v) lt__fenced_add_u32((volatile LT_GLOBAL uint *)(p), (v))
#define lt_atomic_cas_u32(p, e, d) lt__fenced_cas_u32((volatile LT_GLOBAL uint *)(p), (e), (d))
#define lt_atomic_add_i32(p, v) lt__fenced_add_i32((volatile LT_GLOBAL int *)(p), (v))
#define lt_atomic_cas_i32(p, e, d) lt__fenced_cas_i32((volatile LT_GLOBAL int *)(p), (e), (d))
#define lt_atomic_load_i32(p) lt__fenced_load_i32((volatile LT_GLOBAL const int *)(p))
#define lt_atomic_store_i32(p, v) ((void)lt__fenced_xchg_i32((volatile LT_GLOBAL int *)(p), (v)))
#define lt_atomic_min_i32(p, v) lt__fenced_min_i32((volatile LT_GLOBAL int *)(p), (v))
#define lt_atomic_max_i32(p, v) lt__fenced_max_i32((volatile LT_GLOBAL int *)(p), (v))
#else
#define lt_atomic_add_u32(p, v) atomic_add((volatile LT_GLOBAL uint *)(p), (v))
#define lt_atomic_cas_u32(p, expected, desired) \
  atomic_cmpxchg((volatile LT_GLOBAL uint *)(p), (expected), (desired))

/* Signed 32-bit atomics on global memory. A load is a volatile read, so that a polling loop
 * cannot be hoisted; a store is an exchange, so that it is one indivisible write; both sit
 * behind a fence where they publish or consume data (see lt_fence). */
#define lt_atomic_add_i32(p, v) atomic_add((volatile LT_GLOBAL int *)(p), (v))
#define lt_atomic_cas_i32(p, expected, desired) \
  atomic_cmpxchg((volatile LT_GLOBAL int *)(p), (expected), (desired))
#define lt_atomic_load_i32(p) (*(volatile LT_GLOBAL int *)(p))
#define lt_atomic_store_i32(p, v) ((void)atomic_xchg((volatile LT_GLOBAL int *)(p), (v)))
#define lt_atomic_min_i32(p, v) atomic_min((volatile LT_GLOBAL int *)(p), (v))
#define lt_atomic_max_i32(p, v) atomic_max((volatile LT_GLOBAL int *)(p), (v))
#endif
/* A load that later reads cannot overtake (a consumer's side of a publication). On NVIDIA,
 * LT_PTX_ACQUIRE (an experiment, through LT_OPENCL_OPTIONS) makes it PTX's acquire load instead
 * of a load and a device-wide fence. */
#if defined(LT_FENCE_PTX) && defined(LT_PTX_ACQUIRE)
inline int lt__load_acquire_i32(volatile LT_GLOBAL const int *p) {
  int v;
  __asm__ __volatile__("ld.acquire.gpu.global.b32 %0, [%1];" : "=r"(v) : "l"(p) : "memory");
  return v;
}
#else
inline int lt__load_acquire_i32(volatile LT_GLOBAL const int *p) {
  int v = *p;
  lt_fence();
  return v;
}
#endif
/* A load that orders nothing: for a value an acquire load before it already publishes. */
#define lt_atomic_load_relaxed_i32(p) (*(volatile LT_GLOBAL const int *)(p))
#define lt_atomic_load_acquire_i32(p) lt__load_acquire_i32((volatile LT_GLOBAL const int *)(p))

#endif
