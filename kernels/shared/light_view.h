// The light's view as the shading kernels see it: world -> light eye -> clip, the map size, and what the
// filters need to turn world sizes into texels (light size, texel footprint). Shared by host and kernels.
#ifndef PENUMBRA_KERNELS_SHARED_LIGHT_VIEW_H
#define PENUMBRA_KERNELS_SHARED_LIGHT_VIEW_H

#include "kernels/shared/common.h"

#define LIGHT_KIND_SPOT 0         // perspective projection from a point / disk
#define LIGHT_KIND_DIRECTIONAL 1  // orthographic projection (or, with LIGHT_WARP_PERSPECTIVE, LiSPSM's warp)
#define LIGHT_KIND_POINT 2        // every way from a point (its position alone): the preview's only, kernels/shade.cl
                                  // (a point light's maps are six LIGHT_KIND_SPOT faces: kernels/shared/cube.h)

#define LIGHT_WARP_NONE 0         // texels uniform in light-eye x/y (directional) or in tangents (spot)
#define LIGHT_WARP_PERSPECTIVE 1  // LiSPSM (host/views/lispsm.h): texels vary over the map; a general projective
                                  // matrix (spot: the warp times the light's perspective) whose texel is constant
                                  // along the light's rays, so its footprint is the 2x2 Jacobian's across the light

typedef struct LightViewGpu {
  pn_float4 view[4];        // rows of the world -> light-eye matrix
  pn_float4 projection[4];  // rows of the light-eye -> clip matrix
  pn_float4 position;       // xyz: light position (spot) ; w unused
  pn_float4 axis;           // xyz: unit direction the light travels along its axis
  float zNear, zFar;        // light-eye depth range of the map (linear, world units)
  float texelScale;         // spot: texel width / depth (2 tan(fov/2) / size); dir: texel width in world units
                            // (warped: the geometric mean over the body, in the same unit)
  float lightSize;          // spot: disk radius in world units; dir: tan(angular radius)
  float frustumWidth;       // spot: 2 tan(fov/2) (width of the frustum per unit depth); dir: world width
                            // (warped: the uniform map's the warp was built on; position, axis, lightSize too)
  int kind;                 // LIGHT_KIND_*
  int width, height;        // shadow-map size in texels
  int warp;                 // LIGHT_WARP_*
  int pad0, pad1, pad2;
} LightViewGpu;

#if PENUMBRA_HOST
static_assert(sizeof(LightViewGpu) == 4 * 16 * 2 + 2 * 16 + 12 * 4, "LightViewGpu layout must match OpenCL C");
static_assert(offsetof(LightViewGpu, zNear) == 160, "LightViewGpu layout must match OpenCL C");
static_assert(offsetof(LightViewGpu, warp) == 192, "LightViewGpu layout must match OpenCL C");
#else
// Row-major matrix times column vector.
inline float4 lv_transform(__constant const float4* rows, float4 p) {
  return (float4)(dot(rows[0], p), dot(rows[1], p), dot(rows[2], p), dot(rows[3], p));
}

// World position -> (shadow-map texel x, texel y, linear light depth). Texel row 0 is the bottom row. A warped map's
// w_c can be negative in front of the light (beyond the warp's centre, outside the body): no texel there (NaN).
inline float3 lv_project(__constant const LightViewGpu* lv, float3 world) {
  float4 eye = lv_transform(lv->view, (float4)(world, 1.0f));
  float4 clip = lv_transform(lv->projection, eye);
  float2 ndc = lv->warp != LIGHT_WARP_NONE && !(clip.w > 0.0f) ? (float2)(NAN) : clip.xy / clip.w;
  return (float3)((ndc.x * 0.5f + 0.5f) * lv->width, (ndc.y * 0.5f + 0.5f) * lv->height, -eye.z);
}

// World-space width of one texel at light depth `depth`.
inline float lv_texel_world(__constant const LightViewGpu* lv, float depth) {
  return lv->kind == LIGHT_KIND_SPOT ? lv->texelScale * depth : lv->texelScale;
}

// World-space width of one texel at world point `world` (light depth `depth`): lv_texel_world for uniform maps;
// for a warped map the longer side of the texel's footprint across the light (in the plane z_eye = const, as the
// uniform spot's texelScale * depth), from the Jacobian J = d(texel x, y) / d(light-eye x, y) at fixed z_eye
// = (size / 2) (P_r.xy - ndc_r P_3.xy) / w_c, which holds for any projective P (z_eye enters through ndc and w_c
// only): the columns of J^-1 are the world steps of one texel, of lengths |J row| / |det J|.
inline float lv_texel_world_at(__constant const LightViewGpu* lv, float3 world, float depth) {
  if (lv->warp == LIGHT_WARP_NONE) return lv_texel_world(lv, depth);
  float4 clip = lv_transform(lv->projection, lv_transform(lv->view, (float4)(world, 1.0f)));
  float2 ndc = clip.xy / clip.w;
  float2 gu = (lv->projection[0].xy - ndc.x * lv->projection[3].xy) * (0.5f * (float)lv->width / clip.w);
  float2 gv = (lv->projection[1].xy - ndc.y * lv->projection[3].xy) * (0.5f * (float)lv->height / clip.w);
  float texel = max(length(gu), length(gv)) / fabs(gu.x * gv.y - gu.y * gv.x);
  return isfinite(texel) && texel > 0.0f ? texel : lv_texel_world(lv, depth);  // behind the warp's centre: typical
}

// Texels (at the receiver's depth) covered by the half-width of the penumbra that an occluder at light
// depth `occluder` casts on a receiver at light depth `receiver`, by similar triangles (Fernando 2005):
// spot disk of radius R: R (z_r - z_o) / z_o in world units at the receiver; sun disk: (z_r - z_o) tan(alpha).
inline float lv_penumbra_texels(__constant const LightViewGpu* lv, float receiver, float occluder) {
  float world = lv->kind == LIGHT_KIND_SPOT ? lv->lightSize * (receiver - occluder) / max(occluder, 1e-20f)
                                            : lv->lightSize * (receiver - occluder);
  return max(world, 0.0f) / lv_texel_world(lv, receiver);
}

// The map texel under G-buffer pixel `pixel` of `count` (its position projected): 0 for a pixel past the end,
// background (w = 0) or a point off the map (or behind a warp's centre: NaN). What the shading kernels' prefetches ask
// about.
inline int lv_pixel_texel(__global const float4* position, __constant const LightViewGpu* lv, uint pixel, uint count,
                          int2* texel) {
  if (pixel >= count) return 0;
  const float4 q = position[pixel];
  if (q.w == 0.0f) return 0;
  const float2 uv = lv_project(lv, q.xyz).xy;
  if (!(uv.x >= 0.0f && uv.y >= 0.0f && uv.x < (float)lv->width && uv.y < (float)lv->height)) return 0;
  *texel = convert_int2(uv);
  return 1;
}

// Unit vector from a world point towards the light (spot and point: its position; directional: against its axis).
inline float3 lv_to_light(__constant const LightViewGpu* lv, float3 world) {
  return lv->kind == LIGHT_KIND_DIRECTIONAL ? -lv->axis.xyz : normalize(lv->position.xyz - world);
}
#endif

#endif
