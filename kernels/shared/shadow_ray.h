// The exact shadow ray of the Embree reference (tools/reference/tracer.cpp addRays with light_samples.cpp's exact
// rays) and its watertight test against one scene triangle, alpha mask included: what `izb` tests every sample with
// (kernels/izb.cl) and what the map techniques' exact edges (`--exact-edges`, kernels/fvsm.cl) test a pixel near a
// shadow edge with. The origin leaves the surface along its geometric normal, towards the light's centre, by
// SHADOW_RAY_OFFSET times max(|p|_inf, scene radius); the ray ends just short of a spot or point light's point, or
// runs along a directional light's axis. Valid as OpenCL C 1.2 and C++20 (the host sees only the constants).
#ifndef PENUMBRA_KERNELS_SHARED_SHADOW_RAY_H
#define PENUMBRA_KERNELS_SHARED_SHADOW_RAY_H

#include "kernels/shared/alpha.h"
#include "kernels/shared/common.h"
#include "kernels/shared/light_view.h"

// The reference tracer's ShadowTracer::kRayOffset (tools/reference/tracer.h; a test holds them equal).
#define SHADOW_RAY_OFFSET 1e-4f
// Ray end just short of a spot or point light's point, as the reference's (geometry through the light point itself
// does not count).
#define SHADOW_RAY_SPOT_TFAR (1.0f - 1e-6f)

#if !PENUMBRA_HOST
// The same arithmetic on every device: no fused multiply-adds in the ray test or the ray's origin. The pragma holds
// for the rest of the program that includes this header.
#pragma OPENCL FP_CONTRACT OFF

typedef struct {
  float3 origin, direction;
  float tfar;
} ShadowRay;

inline float3 ray_vertex(__global const float* positions, uint v) { return vload3(v, positions); }

// The geometric normal of triangle t (unnormalised), or `fallback` when it is degenerate.
inline float3 ray_geometric_normal(__global const float* positions, __global const uint* triangles, uint t,
                                   float3 fallback) {
  const float3 a = ray_vertex(positions, triangles[3 * t]), b = ray_vertex(positions, triangles[3 * t + 1]);
  const float3 c = ray_vertex(positions, triangles[3 * t + 2]);
  const float3 n = cross(b - a, c - a);
  return dot(n, n) > 0.0f && all(isfinite(n)) ? n : fallback;
}

// The shadow ray from surface point p with geometric normal n0 (unnormalised) towards the light of view lv (its point,
// or against a directional light's axis); sceneRadius is Scene::bounds().radius(), the offset's floor.
inline ShadowRay ray_towards_light(float3 p, float3 n0, __constant const LightViewGpu* lv, float sceneRadius) {
  const bool directional = lv->kind == LIGHT_KIND_DIRECTIONAL;
  const float3 centre = lv->position.xyz, toLight = -lv->axis.xyz;
  float3 towards = toLight;
  if (!directional) {
    const float3 d = centre - p;
    const float len = length(d);
    if (len > 0.0f) towards = d / len;
  }
  float3 n = normalize(n0);
  if (dot(n, towards) < 0.0f) n = -n;
  const float3 q = fabs(p);
  const float extent = fmax(fmax(fmax(q.x, q.y), q.z), sceneRadius);
  ShadowRay ray;
  ray.origin = p + n * (SHADOW_RAY_OFFSET * fmax(extent, FLT_MIN));
  ray.direction = directional ? toLight : centre - ray.origin;
  ray.tfar = directional ? INFINITY : SHADOW_RAY_SPOT_TFAR;
  return ray;
}

// Watertight ray-triangle intersection (Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2013): true
// when the ray meets the triangle at 0 < t < tfar; (u, v) are the barycentric weights of vertices 1 and 2 (Embree's).
inline bool ray_intersect(const ShadowRay* r, float3 v0, float3 v1, float3 v2, float* u, float* v) {
  const float3 ad = fabs(r->direction);
  const int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  const float dir[3] = {r->direction.x, r->direction.y, r->direction.z};
  if (dir[kz] < 0.0f) {
    const int swap = kx;
    kx = ky, ky = swap;
  }
  const float sx = dir[kx] / dir[kz], sy = dir[ky] / dir[kz], sz = 1.0f / dir[kz];
  const float3 a3 = v0 - r->origin, b3 = v1 - r->origin, c3 = v2 - r->origin;
  const float a[3] = {a3.x, a3.y, a3.z}, b[3] = {b3.x, b3.y, b3.z}, c[3] = {c3.x, c3.y, c3.z};
  const float ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  const float bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  const float cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
  const float U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  const float det = U + V + W;
  if (det == 0.0f) return false;
  const float T = U * (sz * a[kz]) + V * (sz * b[kz]) + W * (sz * c[kz]);
  // 0 < T / det < tfar, with det's sign folded in.
  const float sign = det < 0.0f ? -1.0f : 1.0f, adet = fabs(det), st = sign * T;
  if (!(st > 0.0f) || !(st < r->tfar * adet)) return false;
  *u = V / det, *v = W / det;
  return true;
}

// The scene's alpha masks as the ray test reads them (raster::SceneBuffers): alphaIndex holds one entry,
// ALPHA_NO_TRIANGLE, when no triangle of the scene is alpha-tested (alphaTested 0).
typedef struct {
  __global const uint* index;
  __global const AlphaTriangle* triangles;
  __global const AlphaMaterial* materials;
  __global const uchar* texels;
  uint alphaTested;
} RayAlpha;

// Whether triangle t blocks the ray: the intersection, then its alpha test where it has one.
inline bool ray_blocked_by(const ShadowRay* ray, uint t, __global const float* positions,
                           __global const uint* triangles, const RayAlpha* alpha) {
  float u, v;
  if (!ray_intersect(ray, ray_vertex(positions, triangles[3 * t]), ray_vertex(positions, triangles[3 * t + 1]),
                     ray_vertex(positions, triangles[3 * t + 2]), &u, &v))
    return false;
  const uint index = alpha->alphaTested ? alpha->index[t] : ALPHA_NO_TRIANGLE;
  if (index == ALPHA_NO_TRIANGLE) return true;
  __global const AlphaTriangle* a = &alpha->triangles[index];
  // (1 - u - v) uv0 + u uv1 + v uv2, as the reference's filter (tools/reference/alpha_filter.cpp).
  const float w = 1.0f - u - v;
  const float tu = (w * a->uv[0] + u * a->uv[2]) + v * a->uv[4], tv = (w * a->uv[1] + u * a->uv[3]) + v * a->uv[5];
  const AlphaMaterial m = alpha->materials[a->material];
  return alphaPasses(&m, alpha->texels, tu, tv) != 0;
}
#endif

#endif
