// Receiver set-up and depth comparison shared by the shadow-map techniques (sm, pcf, pcss): normal offset,
// constant and slope-scaled bias in units of the local texel footprint (so defaults work at any scene
// scale), and bilinear-weighted depth comparisons. OpenCL C only.
#ifndef PENUMBRA_KERNELS_SHARED_SHADOW_COMMON_H
#define PENUMBRA_KERNELS_SHARED_SHADOW_COMMON_H

#include "kernels/shared/light_view.h"

// Biases in texel footprints (world width of one shadow-map texel at the receiver's light depth).
typedef struct ShadowBias {
  float base;          // added to every comparison
  float slope;         // times tan(angle between normal and light direction), clamped
  float normalOffset;  // receiver moved along its geometric normal before projection
} ShadowBias;

#define SHADOW_MAX_SLOPE 10.0f  // tan of ~84 degrees: beyond this the surface is nearly edge-on

// A receiver projected into the map: texel coordinates, its light depth and the bias per texel of
// filter offset (grows with the filter footprint so tilted planar receivers do not self-shadow).
typedef struct Receiver {
  float2 uv;       // continuous texel coordinates (row 0 at the bottom)
  float depth;     // linear light depth of the receiver
  float bias;      // depth bias at the centre tap
  float biasSlope; // extra bias per texel of tap offset
  int valid;       // 0 when the point is behind the light or not a surface
} Receiver;

inline Receiver sc_receiver(__constant const LightViewGpu* lv, float3 position, float3 normal, ShadowBias bias) {
  Receiver r;
  float3 toLight = lv_to_light(lv, position);
  float cosTheta = dot(normal, toLight);
  if (cosTheta < 0.0f) {  // back-facing to the light: compare with the flipped normal (thin, two-sided)
    normal = -normal;
    cosTheta = -cosTheta;
  }
  float3 first = lv_project(lv, position);
  float texel = lv_texel_world(lv, max(first.z, lv->zNear));
  float3 moved = position + normal * (bias.normalOffset * texel);
  float3 p = lv_project(lv, moved);
  float tanTheta = min(sqrt(max(1.0f - cosTheta * cosTheta, 0.0f)) / max(cosTheta, 1e-4f), SHADOW_MAX_SLOPE);
  r.uv = p.xy;
  r.depth = p.z;
  r.bias = texel * (bias.base + bias.slope * tanTheta);
  r.biasSlope = texel * tanTheta;
  r.valid = p.z > 0.0f && all(isfinite(p));
  return r;
}

// Map depth at an integer texel; texels outside the map hold no occluder (+INFINITY).
inline float sc_fetch(__global const float* depth, int width, int height, int x, int y) {
  if (x < 0 || y < 0 || x >= width || y >= height) return INFINITY;
  return depth[y * width + x];
}

// 1 when the receiver at `depth` is lit by the occluder depth `occluder` (NaN and background lit).
inline float sc_lit(float occluder, float depth) { return occluder < depth ? 0.0f : 1.0f; }

// Bilinear-weighted comparison of the four texels around continuous texel coordinate `uv`.
inline float sc_compare_bilinear(__global const float* map, int width, int height, float2 uv, float depth) {
  float2 t = uv - 0.5f;
  float2 base = floor(t);
  float2 f = t - base;
  int x = (int)base.x, y = (int)base.y;
  float s00 = sc_lit(sc_fetch(map, width, height, x, y), depth);
  float s10 = sc_lit(sc_fetch(map, width, height, x + 1, y), depth);
  float s01 = sc_lit(sc_fetch(map, width, height, x, y + 1), depth);
  float s11 = sc_lit(sc_fetch(map, width, height, x + 1, y + 1), depth);
  return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

#endif
