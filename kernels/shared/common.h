// Definitions shared by every kernel and by the host: fixed-width types and the PENUMBRA_HOST switch.
// Valid as OpenCL C 1.2 and as C++20; layout-carrying structs live in their own headers with
// static_asserts on the host side.
#ifndef PENUMBRA_KERNELS_SHARED_COMMON_H
#define PENUMBRA_KERNELS_SHARED_COMMON_H

#ifdef __OPENCL_C_VERSION__
#define PENUMBRA_HOST 0
#else
#define PENUMBRA_HOST 1
#include <cstdint>
typedef uint32_t uint;
#endif

#endif
