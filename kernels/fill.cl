// Fills a buffer with a constant: the smallest kernel, used by the runtime's own tests and the device
// bandwidth probe of `penumbra bench`.
#include "kernels/shared/common.h"

__kernel void fill_float(__global float* out, uint count, float value) {
  uint i = get_global_id(0);
  if (i < count) out[i] = value;
}

__kernel void copy_float4(__global const float4* in, __global float4* out, uint count) {
  uint i = get_global_id(0);
  if (i < count) out[i] = in[i];
}
