// The caller's light depth map and camera G-buffer (pn_shade, host/pipeline/caller_shade.h) in the layouts the
// techniques read, and their visibility back into the caller's image: a shadow map of linear light depth, +INFINITY
// where empty; G-buffer positions (w = 1 covered, 0 background) and unit normals, rows from the bottom; and plain
// copies between layouts. Each kernel finds the caller's texels where kernels/shared/caller_inputs.h says they lie
// (offset, row pitch, row order).
#include "kernels/shared/caller_inputs.h"

// One light-map texel per work-item: linear light depth, +INFINITY where the caller's map is empty.
__kernel void caller_light_depth(__global const float* src, CallerImageGpu image, CallerDepthGpu depth,
                                 __global float* map) {
  const uint i = get_global_id(0);
  if (i >= image.width * image.height) return;
  const uint x = i % image.width, y = i / image.width;
  const float v = src[caller_index(image, x, y)];
  map[i] = caller_empty(depth, v) ? INFINITY : caller_eye_depth(depth, v);
}

// Whether x, y and z are finite.
inline int caller_finite3(float3 p) { return isfinite(p.x) && isfinite(p.y) && isfinite(p.z); }

// Row-major 4x4 matrix (rows) times (x, y, z, 1), divided by w. Scalars in, not vectors assembled from smaller ones:
// Oclgrind's uninitialised-value check crashes on those shuffles.
inline float3 caller_unproject(float4 r0, float4 r1, float4 r2, float4 r3, float x, float y, float z) {
  const float4 p = (float4)(x, y, z, 1.0f);
  const float w = dot(r3, p);
  return (float3)(dot(r0, p) / w, dot(r1, p) / w, dot(r2, p) / w);
}

// G-buffer positions from the caller's camera depth and inverse view-projection (rows r0..r3): the point at the
// pixel's centre, background (w = 0) where the depth is empty.
__kernel void caller_positions_from_depth(__global const float* src, CallerImageGpu image, CallerDepthGpu depth,
                                          float4 r0, float4 r1, float4 r2, float4 r3, __global float4* position) {
  const uint i = get_global_id(0);
  if (i >= image.width * image.height) return;
  const uint x = i % image.width, y = i / image.width;
  const float d = src[caller_index(image, x, y)];
  if (caller_empty(depth, d)) {
    position[i] = (float4)(0.0f);
    return;
  }
  const float ndcX = ((float)x + 0.5f) / (float)image.width * 2.0f - 1.0f;
  const float ndcY = ((float)y + 0.5f) / (float)image.height * 2.0f - 1.0f;
  const float3 p = caller_unproject(r0, r1, r2, r3, ndcX, ndcY, caller_ndc(depth, d));
  position[i] = caller_finite3(p) ? (float4)(p.x, p.y, p.z, 1.0f) : (float4)(0.0f);
}

// G-buffer positions from the caller's world positions (xyz; w = 0 marks background, as penumbra's own G-buffer).
__kernel void caller_positions(__global const float* src, CallerImageGpu image, __global float4* position) {
  const uint i = get_global_id(0);
  if (i >= image.width * image.height) return;
  const float4 p = vload4(0, src + caller_index(image, i % image.width, i / image.width));
  position[i] = p.w != 0.0f && caller_finite3(p.xyz) ? (float4)(p.xyz, 1.0f) : (float4)(0.0f);
}

// The step from pixel (x, y)'s position to a covered neighbour's along one axis (dx, dy): the shorter of the two
// sides, so a depth edge takes the surface's own side. Zero when neither neighbour is covered.
inline float3 caller_step(__global const float4* position, uint width, uint height, int x, int y, int dx, int dy) {
  const float3 p = position[y * (int)width + x].xyz;
  float3 best = (float3)(0.0f);
  float bestLength = INFINITY;
  for (int s = -1; s <= 1; s += 2) {
    const int xx = x + s * dx, yy = y + s * dy;
    if (xx < 0 || yy < 0 || xx >= (int)width || yy >= (int)height) continue;
    const float4 q = position[yy * (int)width + xx];
    if (q.w == 0.0f) continue;
    const float3 step = (q.xyz - p) * (float)s;
    const float length2 = dot(step, step);
    if (length2 > 0.0f && length2 < bestLength) best = step, bestLength = length2;
  }
  return best;
}

// The surface's geometric normal from the positions of the neighbouring pixels (the cross product of the shorter
// steps along x and y), unoriented: the shading kernels compare a receiver's normal with the direction to the light
// and flip one that faces away (kernels/shared/shadow_common.h sc_receiver). Where a pixel has no covered neighbour
// along an axis (an isolated pixel or a one-pixel line), it is +y: such a pixel has no surface for the bias to follow.
inline float3 caller_fallback_normal(__global const float4* position, uint width, uint height, uint x, uint y) {
  const float3 n = cross(caller_step(position, width, height, (int)x, (int)y, 1, 0),
                         caller_step(position, width, height, (int)x, (int)y, 0, 1));
  const float length2 = dot(n, n);
  return length2 > 0.0f && isfinite(length2) ? n * rsqrt(length2) : (float3)(0.0f, 1.0f, 0.0f);
}

// G-buffer normals where the caller gives none.
__kernel void caller_derived_normals(__global const float4* position, uint width, uint height,
                                     __global float4* normal) {
  const uint i = get_global_id(0);
  if (i >= width * height) return;
  normal[i] = (float4)(caller_fallback_normal(position, width, height, i % width, i / width), 1.0f);
}

// G-buffer normals from the caller's (xyz, normalised; w = 1), or where a zero or non-finite one is given, as below.
__kernel void caller_normals(__global const float* src, CallerImageGpu image, __global const float4* position,
                             __global float4* normal) {
  const uint i = get_global_id(0);
  if (i >= image.width * image.height) return;
  const uint x = i % image.width, y = i / image.width;
  const float3 n = vload4(0, src + caller_index(image, x, y)).xyz;
  const float length2 = dot(n, n);
  normal[i] = (float4)(length2 > 0.0f && isfinite(length2) ? n * rsqrt(length2)
                                                           : caller_fallback_normal(position, image.width,
                                                                                    image.height, x, y),
                       1.0f);
}

// Texels from one layout into another (the same width, height and channels): a stage's input packed from the caller's
// layout, a result unpacked into it (host/stages/image_layout.h copyImage).
__kernel void caller_copy(__global const float* src, CallerImageGpu from, __global float* dst, CallerImageGpu to) {
  const uint i = get_global_id(0);
  if (i >= from.width * from.height) return;
  const uint x = i % from.width, y = i / from.width;
  const uint a = caller_index(from, x, y), b = caller_index(to, x, y);
  for (uint c = 0; c < from.channels; ++c) dst[b + c] = src[a + c];
}
