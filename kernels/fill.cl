// Fills a buffer with a constant: the smallest kernel, used by the runtime's own tests and the device
// bandwidth probe of `penumbra bench`.
#include "kernels/shared/common.h"

__kernel void fill_float(__global float* out, uint count, float value) {
  uint i = get_global_id(0);
  if (i < count) out[i] = value;
}

// in[0, count) to out[offset, offset + count) in elements of 4 and 2 bytes: copyInto's copy on a simulator
// (host/techniques/split_maps.cpp), whose copies Oclgrind's uninitialised-value check tracks only in kernels.
__kernel void copy_into_u32(__global const uint* in, __global uint* out, uint offset, uint count) {
  uint i = get_global_id(0);
  if (i < count) out[offset + i] = in[i];
}

__kernel void copy_into_u16(__global const ushort* in, __global ushort* out, uint offset, uint count) {
  uint i = get_global_id(0);
  if (i < count) out[offset + i] = in[i];
}

__kernel void copy_float4(__global const float4* in, __global float4* out, uint count) {
  uint i = get_global_id(0);
  if (i < count) out[i] = in[i];
}
