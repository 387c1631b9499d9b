// Probe of the MSM moment decoding (kernels/shared/moments.h) for tests/moments_test.cpp.
#include "kernels/shared/moments.h"

// Decodes optimized MSM moments back to power moments, as the shading kernels do.
__kernel void moments_msm_decode_test(__global const float4* in, __global float4* out, uint count) {
  uint i = get_global_id(0);
  if (i < count) out[i] = moments_msm_decode(in[i]);
}
