// Percentage-closer filtering (Reeves et al., "Rendering Antialiased Shadows with Depth Maps", SIGGRAPH
// 1987): the fraction of bilinear-weighted depth comparisons that pass over a kernel around the receiver.
// - Taps: a (2r+1)^2 grid, or `poissonTaps` points of a Poisson disk (Mitchell's best candidate, host side)
//   rotated per pixel by interleaved gradient noise (Jimenez, "Next Generation Post Processing in Call of
//   Duty: Advanced Warfare", SIGGRAPH 2014 course) so the banding of a fixed pattern becomes fine noise.
// - Adaptive size: the kernel's half-width grows to half the pixel's footprint in the map (from neighbouring
//   G-buffer pixels: OpenCL has no ddx/ddy), so minified shadows are filtered over what the pixel covers;
//   the tap count stays fixed, their spacing grows.
// - Bias: receiver-plane depth bias (Isidoro, GDC 2006; sc_receiver_plane) where the receiver's plane is
//   known from its neighbours, else the slope-scaled bias growing with the tap offset.
// - A grid at unit spacing (the kernel no wider than its taps) against the receiver's plane compares each texel once
//   for all the taps that read it (sc_grid_plane_sum), the same sum to rounding.
// - ID buffer (Luksch sec. 9.1, kernels/shared/id_buffer.h): each tap's four-neighbour id test instead of (or, in
//   combined mode, between objects beside) its depth comparison, so the filter averages id tests.
#include "kernels/shared/id_buffer.h"
#include "kernels/shared/rotation.h"
#include "kernels/shared/shade.h"
#include "kernels/shared/shadow_common.h"

__kernel void pcf_visibility(__global const float4* position, __global const float4* normal, __global const float* map,
                             __constant const LightViewGpu* lv, ShadeFrame f, __global const uint* mapIds,
                             __global const uint* objectIds, __global const uint* pixelTriangle,
                             __global const uint* pixelObject, PcfShade s, __global const float2* poisson,
                             __global float* filterOut, __global float* visibility) {
  const uint width = f.width, height = f.height;
  const float biasConstant = f.biasConstant;
  const int idMode = f.idMode, radius = s.radius, poissonTaps = s.poissonTaps;
  uint i = get_global_id(0);
  if (i >= width * height) return;
  sc_prefetch_texels(position, lv, map, sizeof(float), radius + 1, i + PN_PREFETCH_AHEAD, width * height);
  float4 p = position[i];
  visibility[i] = 1.0f;
  filterOut[i] = 0.0f;
  if (p.w == 0.0f) return;
  ShadowBias bias = {f.biasConstant, f.biasSlope, f.normalOffset};
  float3 n = normal[i].xyz;
  Receiver r = sc_receiver_unsloped(lv, p.xyz, n, bias);
  if (!r.valid) return;
  // The footprint serves the receiver plane and the adaptive size: measured only when one of them is on.
  Footprint fp = {(float3)(0.0f), (float3)(0.0f)};
  if (f.receiverPlane || s.adaptive) fp = sc_footprint(position, lv, width, height, i, p.xyz, n);
  ReceiverPlane rp = sc_receiver_plane(fp, r.texel);
  if (!f.receiverPlane) rp.valid = 0;
  if (!rp.valid) r = sc_receiver_sloped(lv, r, p.xyz, n, bias);  // the taps' slope-scaled bias (sc_tap)
  const float planeBias = biasConstant * r.texel;
  const uint ownTriangle = id_pixel(pixelTriangle, i, idMode), ownObject = id_pixel(pixelObject, i, idMode);
  const float2 idUv = id_uv(lv, p.xyz, idMode);
  // Half-width of the kernel in texels.
  float reach = s.width;
  if (s.adaptive) reach = min(max(reach, 0.5f * sc_footprint_texels(fp)), s.maxRadius);
  filterOut[i] = reach;
  float sum = 0.0f;
  int taps = 0;
  if (poissonTaps > 0) {
    float angle = rot_angle(i % width, i / width);
    float2 cs = (float2)(cos(angle), sin(angle));
    const int sparse = sc_sparse_taps((float)poissonTaps, M_PI_F * reach * reach);
    for (int k = 0; k < poissonTaps; ++k) {
      float2 offset = reach * rot_apply(cs, poisson[k]);
      sum += id_visibility(
          mapIds, objectIds, lv->width, lv->height, idUv + offset, ownTriangle, ownObject, idMode,
          sparse ? sc_tap_texel(map, lv, r, rp, planeBias, offset) : sc_tap(map, lv, r, rp, planeBias, offset));
    }
    taps = poissonTaps;
  } else if (rp.valid && idMode == ID_BUFFER_OFF && reach == (float)radius) {
    // A unit grid against the receiver's plane shares its texels between taps: each compared once (box: 4x faster).
    sum = sc_grid_plane_sum(map, lv->width, lv->height, r.uv, radius, r.depth - planeBias, rp.gradient);
    taps = (2 * radius + 1) * (2 * radius + 1);
  } else {
    float step = radius > 0 ? reach / (float)radius : 0.0f;
    const int sparse = sc_sparse_taps(1.0f, step * step);  // each tap of the grid stands for step^2 texels
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx) {
        float2 offset = step * (float2)(dx, dy);
        sum += id_visibility(
            mapIds, objectIds, lv->width, lv->height, idUv + offset, ownTriangle, ownObject, idMode,
            sparse ? sc_tap_texel(map, lv, r, rp, planeBias, offset) : sc_tap(map, lv, r, rp, planeBias, offset));
      }
    taps = (2 * radius + 1) * (2 * radius + 1);
  }
  visibility[i] = sum / (float)taps;
}
