// Alpha-tested materials (glTF 2.0 sec. 3.9.4 alphaMode MASK; BLEND is drawn as MASK): the material record that the
// rasterizer's fine stage and the Embree reference's filter functions share, and the one function both call to sample
// a base-colour alpha texture (KHR_texture_transform, the sampler's wrap modes and NEAREST/LINEAR filter on the base
// level) times the factor. Valid as OpenCL C 1.2 and C++20: both sides compute the same alpha from the same (u, v).
#ifndef PENUMBRA_KERNELS_SHARED_ALPHA_H
#define PENUMBRA_KERNELS_SHARED_ALPHA_H

#include "kernels/shared/common.h"

// Wrap modes (glTF sampler wrapS / wrapT: 10497 REPEAT, 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT).
#define ALPHA_WRAP_REPEAT 0
#define ALPHA_WRAP_CLAMP 1
#define ALPHA_WRAP_MIRROR 2
// Filters on the base level (glTF magFilter / minFilter 9728 NEAREST, 9729 LINEAR; host/scene/material.h).
#define ALPHA_FILTER_NEAREST 0
#define ALPHA_FILTER_LINEAR 1

// 64 bytes, only 4-byte scalars: both compilers lay it out alike (static_asserts below).
typedef struct {
  float transform[6];  // texture coordinate -> (t0 u + t1 v + t2, t3 u + t4 v + t5): KHR_texture_transform
  float cutoff;        // a fragment whose coverage is below this is discarded
  float factor;        // baseColorFactor's alpha; multiplies the texture's
  uint texelOffset;    // the texture's first texel in the alpha atlas (one byte a texel, rows top to bottom)
  int width, height;   // texels; 0 x 0: no texture, coverage = factor
  int wrapS, wrapT;    // ALPHA_WRAP_*
  int filter;          // ALPHA_FILTER_*
  int pad[2];
} AlphaMaterial;

#define ALPHA_NO_TRIANGLE 0xffffffffu  // a per-triangle alpha index (raster::SceneBuffers::alphaIndex) of opaque ones

// An alpha-tested triangle's texture data, 64 bytes (one cache line): its world-space vertices, their texture
// coordinates and its material; a hit at barycentric weights (u, v) of vertices 1 and 2 has texture coordinate
// (1 - u - v) uv0 + u uv1 + v uv2. The rasterizer's fine stage (raster/alpha.h) and the irregular z-buffer's exact
// test (kernels/izb.cl) read them.
typedef struct {
  float position[9];  // vertices 0, 1, 2 of Scene::triangles, x y z each
  float uv[6];        // their texture coordinates (Scene::uvs), u v each
  uint material;      // index into the AlphaMaterial table
} AlphaTriangle;

#if PENUMBRA_HOST
#include <cmath>
#include <cstddef>
typedef uint8_t alpha_uchar;
#define ALPHA_GLOBAL
#define ALPHA_INLINE inline
#define ALPHA_FLOOR(x) std::floor(x)
#define ALPHA_FINITE(x) std::isfinite(x)
static_assert(sizeof(AlphaMaterial) == 64 && offsetof(AlphaMaterial, cutoff) == 24);
static_assert(offsetof(AlphaMaterial, texelOffset) == 32 && offsetof(AlphaMaterial, filter) == 52);
static_assert(sizeof(AlphaTriangle) == 64 && offsetof(AlphaTriangle, uv) == 36);
#else
typedef uchar alpha_uchar;
#define ALPHA_GLOBAL __global
#define ALPHA_INLINE static inline
#define ALPHA_FLOOR(x) floor(x)
#define ALPHA_FINITE(x) isfinite(x)
#endif

// a + t (b - a) with no fused multiply-add on either side (OpenCL C contracts by default, x86-64 C++ cannot), so the
// kernels and the host round alike.
ALPHA_INLINE float alphaLerp(float a, float b, float t) {
#if !PENUMBRA_HOST
#pragma OPENCL FP_CONTRACT OFF
#endif
  return a + t * (b - a);
}

// One row of the 2x3 transform applied to (u, v, 1), without fused multiply-adds.
ALPHA_INLINE float alphaAffine(float a, float b, float c, float u, float v) {
#if !PENUMBRA_HOST
#pragma OPENCL FP_CONTRACT OFF
#endif
  return (a * u + b * v) + c;
}

// A coordinate reduced to one period of its wrap mode, so texel indices stay small for any finite input: [0, 1] for
// REPEAT, [0, 2] for MIRRORED_REPEAT (1 and 2 only by rounding just below a period), [-1, 2] for CLAMP_TO_EDGE (the
// edge texels cover the rest). NaN and infinite coordinates are defined to be 0.
ALPHA_INLINE float alphaReduce(float c, int wrap) {
  if (!ALPHA_FINITE(c)) return 0.0f;
  if (wrap == ALPHA_WRAP_REPEAT) return c - ALPHA_FLOOR(c);
  if (wrap == ALPHA_WRAP_MIRROR) return c - 2.0f * ALPHA_FLOOR(0.5f * c);
  return c < -1.0f ? -1.0f : (c > 2.0f ? 2.0f : c);
}

// Texel index i of an axis of n texels under the wrap mode, for i within one period of [0, period) (what indices of
// reduced coordinates are: -1 .. n for REPEAT, -1 .. 2n for MIRRORED_REPEAT), so no integer division is needed.
ALPHA_INLINE int alphaWrapIndex(int i, int n, int wrap) {
  if (wrap == ALPHA_WRAP_CLAMP) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  const int period = wrap == ALPHA_WRAP_MIRROR ? 2 * n : n;
  const int k = i < 0 ? i + period : (i >= period ? i - period : i);
  return k < n ? k : period - 1 - k;
}

// Texel (x, y) of the material's texture, 0..255.
ALPHA_INLINE float alphaTexel(const AlphaMaterial* m, ALPHA_GLOBAL const alpha_uchar* texels, int x, int y) {
  return (float)texels[m->texelOffset + (uint)y * (uint)m->width + (uint)x];
}

// The texture's alpha at texture-space point (s, t) in texels (the texture's top-left corner is (0, 0)), 0..255:
// NEAREST reads the texel containing it, LINEAR interpolates the four texel centres around it.
ALPHA_INLINE float alphaFiltered(const AlphaMaterial* m, ALPHA_GLOBAL const alpha_uchar* texels, float s, float t) {
  if (m->filter == ALPHA_FILTER_NEAREST)
    return alphaTexel(m, texels, alphaWrapIndex((int)ALPHA_FLOOR(s), m->width, m->wrapS),
                      alphaWrapIndex((int)ALPHA_FLOOR(t), m->height, m->wrapT));
  const float sc = s - 0.5f, tc = t - 0.5f;
  const float s0 = ALPHA_FLOOR(sc), t0 = ALPHA_FLOOR(tc);
  const int x0 = alphaWrapIndex((int)s0, m->width, m->wrapS), x1 = alphaWrapIndex((int)s0 + 1, m->width, m->wrapS);
  const int y0 = alphaWrapIndex((int)t0, m->height, m->wrapT), y1 = alphaWrapIndex((int)t0 + 1, m->height, m->wrapT);
  const float fs = sc - s0, ft = tc - t0;
  const float top = alphaLerp(alphaTexel(m, texels, x0, y0), alphaTexel(m, texels, x1, y0), fs);
  const float bottom = alphaLerp(alphaTexel(m, texels, x0, y1), alphaTexel(m, texels, x1, y1), fs);
  return alphaLerp(top, bottom, ft);
}

// Alpha coverage at texture coordinate (u, v) of the material's texCoord set (before KHR_texture_transform): the
// texture's alpha (0..1) times the factor, or the factor alone without a texture. One non-finite input makes both
// transformed coordinates NaN (0 x inf, 0 x NaN), so the texture's corner (0, 0) is sampled.
ALPHA_INLINE float alphaCoverage(const AlphaMaterial* m, ALPHA_GLOBAL const alpha_uchar* texels, float u, float v) {
  if (m->width <= 0 || m->height <= 0) return m->factor;
  const float tu = alphaAffine(m->transform[0], m->transform[1], m->transform[2], u, v);
  const float tv = alphaAffine(m->transform[3], m->transform[4], m->transform[5], u, v);
  const float s = alphaReduce(tu, m->wrapS) * (float)m->width, t = alphaReduce(tv, m->wrapT) * (float)m->height;
  return m->factor * (alphaFiltered(m, texels, s, t) * (1.0f / 255.0f));
}

// Whether a fragment at (u, v) is drawn: glTF's MASK rule, opaque when alpha >= alphaCutoff, discarded otherwise.
ALPHA_INLINE int alphaPasses(const AlphaMaterial* m, ALPHA_GLOBAL const alpha_uchar* texels, float u, float v) {
  return alphaCoverage(m, texels, u, v) >= m->cutoff;
}

#endif
