// Definitions shared by every kernel and by the host: fixed-width types, vector types and the
// PENUMBRA_HOST switch. Valid as OpenCL C 1.2 and as C++20; layout-carrying structs live in their own
// headers with static_asserts on the host side.
#ifndef PENUMBRA_KERNELS_SHARED_COMMON_H
#define PENUMBRA_KERNELS_SHARED_COMMON_H

#ifdef __OPENCL_C_VERSION__
#define PENUMBRA_HOST 0
typedef float4 pn_float4;
typedef uint4 pn_uint4;

// Vector types by channel count, for kernels built for 1, 2 or 4 interleaved channels with a -D option:
// PN_VEC(float, 2) is float2, PN_VEC(float, 1) is float; PN_CONVERT(float, 2) is convert_float2.
#define PN_CAT_(a, b) a##b
#define PN_CAT(a, b) PN_CAT_(a, b)
#define PN_VEC_1(t) t
#define PN_VEC_2(t) t##2
#define PN_VEC_4(t) t##4
#define PN_VEC(t, n) PN_CAT(PN_VEC_, n)(t)
#define PN_CONVERT(t, n) PN_CAT(convert_, PN_VEC(t, n))

// floor(), with the same value for every input (beyond 2^31 in magnitude, infinities and NaN are their own floor and
// are returned as they are), from a saturating conversion and a correction: a few instructions where a device library's
// floor is generic code (PoCL 3.1's, in the bilinear comparisons alone, cost 7 % of pcss's shading on default.json,
// 2026-12-07). For texel addressing, whose floors run per tap.
inline float pn_floor(float x) {
  const float t = convert_float(convert_int_sat(x));
  return fabs(x) < 2147483648.0f ? (t > x ? t - 1.0f : t) : x;
}
inline float2 pn_floor2(float2 x) { return (float2)(pn_floor(x.x), pn_floor(x.y)); }

// Software prefetch on CPU devices (PENUMBRA_CPU_LAYOUTS, a build option the host passes where the CPU layouts apply,
// Oclgrind aside): clang's builtin through an integer, a CPU device having one flat address space; nothing elsewhere.
// Shading kernels ask for what the pixel PN_PREFETCH_AHEAD work-items on reads: PoCL runs a work-group's items one
// after another, so by the time that pixel runs its lines have arrived (docs/performance.md, "Prefetching").
#if defined(__clang__) && defined(PENUMBRA_CPU_LAYOUTS)
#define PN_PREFETCH(address) __builtin_prefetch((const void*)(size_t)(address))
#define PN_PREFETCHES 1
#else
#define PN_PREFETCH(address) ((void)0)
#define PN_PREFETCHES 0
#endif
#define PN_PREFETCH_AHEAD 4
#else
#define PENUMBRA_HOST 1
#include <CL/cl_platform.h>

#include <cstddef>
#include <cstdint>
typedef uint32_t uint;
typedef cl_float4 pn_float4;
typedef cl_uint4 pn_uint4;
#endif

#endif
