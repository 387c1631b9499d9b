// G-buffer reconstruction after the fine stage: from each pixel's visible triangle id, the world position where the
// pixel-centre camera ray meets the triangle's world-space plane (exact for the unsnapped triangle, independent of
// snapping and of the interpolated depth), the world shading normal interpolated with the hit's barycentrics and
// normalised, the geometric facing sign, and the object id. One work-item per pixel of the scissor.
// Error: float ray-plane intersection, |p - p_exact| <= about 2^-20 (|eye| + |p|) / |cos(ray, plane normal)|.
#include "raster/constants.h"
#include "raster/depth.h"
#include "raster/types.h"

#ifndef RASTER_WG_GBUFFER
#define RASTER_WG_GBUFFER 64
#endif

static float3 gbufferToWorld(const RasterViewParams* p, float3 v, float w) {  // w = 1: point, 0: direction
  return (float3)(p->invView[0] * v.x + p->invView[3] * v.y + p->invView[6] * v.z + p->invView[9] * w,
                  p->invView[1] * v.x + p->invView[4] * v.y + p->invView[7] * v.z + p->invView[10] * w,
                  p->invView[2] * v.x + p->invView[5] * v.y + p->invView[8] * v.z + p->invView[11] * w);
}

// Barycentric weights of `hit` (on the triangle's plane, normal n) clamped to the triangle, summing to 1.
static float3 gbufferWeights(float3 p0, float3 p1, float3 p2, float3 n, float3 hit) {
  const float nn = dot(n, n);
  float3 w = (float3)(dot(n, cross(p1 - hit, p2 - hit)), dot(n, cross(p2 - hit, p0 - hit)), 0.0f) / nn;
  w.z = 1.0f - w.x - w.y;
  w = max(w, 0.0f);
  const float sum = w.x + w.y + w.z;
  return sum > 0.0f && isfinite(sum) ? w / sum : (float3)(1.0f / 3.0f);
}

__kernel __attribute__((reqd_work_group_size(RASTER_WG_GBUFFER, 1, 1))) void gbuffer_resolve(
    __global const float* positions, __global const float* normals, __global const uint* triangles,
    __global const uint* objectIds, __global const uint* triangleId, __global const float* depth,
    __global float4* position, __global float4* normal, __global uint* objectId, const RasterViewParams p) {
  const int rectWidth = p.rectX1 - p.rectX0;
  const uint i = get_global_id(0);
  if (i >= (uint)(rectWidth * (p.rectY1 - p.rectY0))) return;
  const int x = p.rectX0 + (int)(i % rectWidth), y = p.rectY0 + (int)(i / rectWidth);
  const size_t pixel = (size_t)y * p.width + x;
  const uint id = triangleId[pixel];
  if (id >= p.triangleCount) {  // background
    position[pixel] = (float4)(0.0f);
    normal[pixel] = (float4)(0.0f);
    objectId[pixel] = RASTER_NO_TRIANGLE;
    return;
  }
  const uint3 idx = vload3(id, triangles);
  const float3 p0 = vload3(idx.x, positions), p1 = vload3(idx.y, positions), p2 = vload3(idx.z, positions);
  float3 originEye, directionEye;
  rasterEyeRay(&p, rasterPixelNdc(&p, x, y), &originEye, &directionEye);
  const float3 origin = gbufferToWorld(&p, originEye, 1.0f), direction = gbufferToWorld(&p, directionEye, 0.0f);
  const float3 n = cross(p1 - p0, p2 - p0);
  const float facing = dot(n, direction);
  // t is the view depth of the hit (direction has eye-space z = -1); an edge-on triangle falls back to the
  // rasterized depth along the same ray.
  float t = dot(n, p0 - origin) / facing;
  if (!isfinite(t)) t = rasterViewZFromDepth(&p, x, y, depth[pixel]);
  const float3 hit = origin + t * direction;
  const float3 w = gbufferWeights(p0, p1, p2, n, hit);
  const float3 shading = w.x * vload3(idx.x, normals) + w.y * vload3(idx.y, normals) + w.z * vload3(idx.z, normals);
  const float len = length(shading);
  float3 unit = len > 0.0f && isfinite(len) ? shading / len : normalize(n);
  if (!all(isfinite(unit))) unit = (float3)(0.0f, 0.0f, 1.0f);
  position[pixel] = (float4)(hit, 1.0f);
  normal[pixel] = (float4)(unit, facing < 0.0f ? 1.0f : -1.0f);
  objectId[pixel] = objectIds[id];
}
