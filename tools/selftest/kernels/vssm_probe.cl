// Probe of VSSM's per-pixel algorithm (kernels/vssm.cl) for tests/vssm_test.cpp, with receivers given directly.
// Built with the maps' -DSAT_MODE=... -DSAT_CHANNELS=2 (VssmMaps::buildOptions).
#include "kernels/vssm.cl"

// Receivers given directly as (u, v, depth, bias) and bias slope, so the per-pixel algorithm can be
// checked against tests/reference/vssm_ref.cpp on arbitrary maps.
__kernel void vssm_visibility_receivers(__global const float4* receivers, __global const float* slopes, uint count,
                                        __global const float* depth, __constant const LightViewGpu* lv,
                                        __global const SAT_T* sat, SatTableDesc desc, __global const float* satOffset,
                                        __global const float2* hsm, __constant const PyramidLevel* levels,
                                        __constant const VssmNode* nodes, __constant const float* strips,
                                        VssmParams params, __global float4* debug, __global float* visibility) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  const float4 q = receivers[i];
  const VssmMaps m = {sat, satOffset, depth, hsm, levels, nodes, strips, lv, desc, params};
  vssm_store(vssm_pixel(&m, vssm_receiver(&m, q.xy, q.z, q.w, slopes[i], i)), i, debug, visibility);
}
