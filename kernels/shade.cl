// The shaded preview: a grey Lambertian surface lit by the shadowing light (visibility x cos x spot cone x range
// window; point lights shine every way, without a cone; no light falls off with distance otherwise) plus a dim
// hemispherical ambient term so shadowed regions keep their shape. Linear RGB, A = coverage.
#include "kernels/shared/light_view.h"

#define SHADE_ALBEDO 0.75f
#define SHADE_AMBIENT 0.12f  // sky irradiance relative to the light

// The light's terms: terms.x: cos of a spot's outer half angle; terms.y: cos of the inner one, or below -1 for a light
// without one; terms.z: glTF's range (0: unlimited); terms.w: cos of 90% of the outer half angle (computed once on
// the host, not per pixel).
//
// Spot cone.
// With an inner cone (glTF's KHR_lights_punctual), the extension's falloff: ((c - cos outer) / (cos inner - cos
// outer))^2, clamped to [0, 1]. Without, full inside 90% of the half angle, falling linearly to zero at its edge.
// Directional and point lights: 1.
inline float shade_cone(__constant const LightViewGpu* lv, float3 toLight, float4 cone) {
  if (lv->kind != LIGHT_KIND_SPOT) return 1.0f;
  float c = dot(-toLight, lv->axis.xyz);
  if (cone.y >= -1.0f) {
    float t = clamp((c - cone.x) / max(cone.y - cone.x, 1e-3f), 0.0f, 1.0f);
    return t * t;
  }
  return clamp((c - cone.x) / max(cone.w - cone.x, 1e-6f), 0.0f, 1.0f);
}

// The side of the surface the camera sees. eye.w == 0: an orthographic camera, eye.xyz the direction to it.
inline float3 shade_facing_normal(float4 p, float3 n, float4 eye) {
  float3 toEye = eye.w != 0.0f ? eye.xyz - p.xyz : eye.xyz;
  return dot(n, toEye) < 0.0f ? -n : n;
}

// KHR_lights_punctual's range window for a spot or point light at distance d: clamp(1 - (d / range)^4, 0, 1), the
// extension's recommended falloff to zero at `range` (without its 1 / d^2, which the preview leaves out for every
// light). 1 for an unlimited light or a directional one.
inline float shade_range(__constant const LightViewGpu* lv, float3 p, float range) {
  if (range <= 0.0f || lv->kind == LIGHT_KIND_DIRECTIONAL) return 1.0f;
  float r = length(lv->position.xyz - p) / range;
  return clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
}

// One light's direct term at p with facing normal n.
inline float shade_direct(__constant const LightViewGpu* lv, float3 p, float3 n, float4 terms, float visibility) {
  float3 toLight = lv_to_light(lv, p);
  return max(dot(n, toLight), 0.0f) * shade_cone(lv, toLight, terms) * shade_range(lv, p, terms.z) * visibility;
}

// The grey surface under `direct` (the lights' terms summed) and the sky.
inline float4 shade_rgba(float3 n, float direct) {
  float sky = 0.5f + 0.5f * n.y;
  float value = SHADE_ALBEDO * (direct + SHADE_AMBIENT * sky);
  return (float4)(value, value, value, 1.0f);
}

__kernel void shade_preview(__global const float4* position, __global const float4* normal,
                            __global const float* visibility, uint count, __constant const LightViewGpu* lv, float4 eye,
                            float4 terms, __global float4* rgba) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float4 p = position[i];
  if (p.w == 0.0f) {
    rgba[i] = (float4)(0.0f);
    return;
  }
  float3 n = shade_facing_normal(p, normal[i].xyz, eye);  // two-sided
  rgba[i] = shade_rgba(n, shade_direct(lv, p.xyz, n, terms, visibility[i]));
}

// Several lights: shade_add_direct adds one light's direct term to `direct` (zeroed first), once per light, then
// shade_finish shades the sum as shade_preview shades one light's term.
__kernel void shade_add_direct(__global const float4* position, __global const float4* normal,
                               __global const float* visibility, uint count, __constant const LightViewGpu* lv,
                               float4 eye, float4 terms, __global float* direct) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float4 p = position[i];
  if (p.w == 0.0f) return;
  float3 n = shade_facing_normal(p, normal[i].xyz, eye);
  direct[i] += shade_direct(lv, p.xyz, n, terms, visibility[i]);
}

__kernel void shade_finish(__global const float4* position, __global const float4* normal,
                           __global const float* direct, uint count, float4 eye, __global float4* rgba) {
  uint i = get_global_id(0);
  if (i >= count) return;
  float4 p = position[i];
  if (p.w == 0.0f) {
    rgba[i] = (float4)(0.0f);
    return;
  }
  rgba[i] = shade_rgba(shade_facing_normal(p, normal[i].xyz, eye), direct[i]);
}
