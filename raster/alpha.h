// The fine stage's alpha test (OpenCL C only): an alpha-tested triangle's barycentrics at a pixel centre, its texture
// coordinate there and its material's MASK test (kernels/shared/alpha.h, the same function the Embree reference
// calls). The barycentrics come from the clip coordinates q_k = (x_k, y_k, w_k) of the triangle's own, unclipped
// vertices (2D homogeneous rasterization: Olano & Greer, "Triangle Scan Conversion using 2D Homogeneous Coordinates",
// HWWS 1997): the point of the triangle's plane seen through NDC (xn, yn) has weights b with sum(b_k X_k) = 0 and
// sum(b_k Y_k) = 0 for X_k = x_k - xn w_k, Y_k = y_k - yn w_k, so b = X x Y normalised. That is the perspective-
// correct interpolation at the pixel centre for any projective view, whatever clipping made of the triangle (the
// record's own vertices may be a clipped fan's). The weights are clamped to the triangle, as the G-buffer's are.
#ifndef PENUMBRA_RASTER_ALPHA_H
#define PENUMBRA_RASTER_ALPHA_H

#include "kernels/shared/alpha.h"
#include "raster/types.h"

// What an alpha-tested triangle's fragments share: its vertices in clip space, texture coordinates and material.
typedef struct {
  float3 x, y, w;       // clip coordinates x_c, y_c, w_c of vertices 0, 1, 2
  float2 uv0, uv1, uv2;
  AlphaMaterial material;
} RasterAlphaFragment;

static inline float rasterClipRow(const RasterViewParams* p, int row, float3 v) {
  return ((p->clip[row] * v.x + p->clip[4 + row] * v.y) + p->clip[8 + row] * v.z) + p->clip[12 + row];
}

// Loads triangle `index` of the alpha table and moves its vertices into the view's clip space.
static inline RasterAlphaFragment rasterAlphaFragment(const RasterViewParams* p,
                                                      __global const AlphaTriangle* triangles,
                                                      __global const AlphaMaterial* materials, uint index) {
  __global const AlphaTriangle* t = &triangles[index];
  RasterAlphaFragment f;
  const float3 v0 = vload3(0, t->position), v1 = vload3(1, t->position), v2 = vload3(2, t->position);
  f.x = (float3)(rasterClipRow(p, 0, v0), rasterClipRow(p, 0, v1), rasterClipRow(p, 0, v2));
  f.y = (float3)(rasterClipRow(p, 1, v0), rasterClipRow(p, 1, v1), rasterClipRow(p, 1, v2));
  f.w = (float3)(rasterClipRow(p, 3, v0), rasterClipRow(p, 3, v1), rasterClipRow(p, 3, v2));
  f.uv0 = vload2(0, t->uv), f.uv1 = vload2(1, t->uv), f.uv2 = vload2(2, t->uv);
  f.material = materials[t->material];
  return f;
}

// The texture coordinate (u, v) at NDC (xn, yn), as one function for a pixel (TYPE float) and for a row of 8 pixels
// (float8: the same operations lane by lane, so both layouts of the fine stage compute the same values).
#define RASTER_ALPHA_UV(TYPE, NAME)                                                                                \
  static inline void NAME(const RasterAlphaFragment* f, TYPE xn, float yn, TYPE* u, TYPE* v) {                    \
    const TYPE X0 = f->x.x - xn * f->w.x, X1 = f->x.y - xn * f->w.y, X2 = f->x.z - xn * f->w.z;                \
    const float Y0 = f->y.x - yn * f->w.x, Y1 = f->y.y - yn * f->w.y, Y2 = f->y.z - yn * f->w.z;                \
    const TYPE b0 = X1 * Y2 - X2 * Y1, b1 = X2 * Y0 - X0 * Y2, b2 = X0 * Y1 - X1 * Y0;                          \
    const TYPE s = b0 + b1 + b2; /* 0 (seen edge-on) gives NaN weights, replaced below */                      \
    const TYPE w0 = max(b0 / s, 0.0f), w1 = max(b1 / s, 0.0f), w2 = max(b2 / s, 0.0f);                          \
    const TYPE sum = w0 + w1 + w2;                                                                               \
    const TYPE r = 1.0f / sum, third = 1.0f / 3.0f;                                                             \
    const TYPE c0 = select(third, w0 * r, sum > 0.0f && isfinite(sum));                                         \
    const TYPE c1 = select(third, w1 * r, sum > 0.0f && isfinite(sum));                                         \
    const TYPE c2 = select(third, w2 * r, sum > 0.0f && isfinite(sum));                                         \
    *u = c0 * f->uv0.x + c1 * f->uv1.x + c2 * f->uv2.x;                                                          \
    *v = c0 * f->uv0.y + c1 * f->uv1.y + c2 * f->uv2.y;                                                          \
  }
RASTER_ALPHA_UV(float, rasterAlphaUv)
RASTER_ALPHA_UV(float8, rasterAlphaUv8)

// NDC of pixel column x and row y's centres, as rasterPixelNdc computes them.
static inline float rasterNdcX(const RasterViewParams* p, int x) { return (float)(2 * x + 1) / (float)p->width - 1.0f; }
static inline float rasterNdcY(const RasterViewParams* p, int y) { return (float)(2 * y + 1) / (float)p->height - 1.0f; }

// Whether the triangle's fragment at pixel (px, py) survives its material's alpha test.
static inline bool rasterAlphaPasses(const RasterViewParams* p, const RasterAlphaFragment* f,
                                     __global const uchar* texels, int px, int py) {
  float u, v;
  rasterAlphaUv(f, rasterNdcX(p, px), rasterNdcY(p, py), &u, &v);
  return alphaPasses(&f->material, texels, u, v) != 0;
}

// The lanes of `keep` (pixels x0 .. x0 + 7 of row y) whose alpha test passes: the coordinates for the row at once,
// then the texture per kept lane (a gather each).
static inline int8 rasterAlphaPassesRow(const RasterViewParams* p, const RasterAlphaFragment* f,
                                        __global const uchar* texels, int8 keep, int x0, int y) {
  const float8 xn = convert_float8(2 * (x0 + (int8)(0, 1, 2, 3, 4, 5, 6, 7)) + 1) / (float)p->width - 1.0f;
  float8 u8, v8;
  rasterAlphaUv8(f, xn, rasterNdcY(p, y), &u8, &v8);
  float u[8], v[8];
  int lanes[8];
  vstore8(u8, 0, u), vstore8(v8, 0, v), vstore8(keep, 0, lanes);
  for (int i = 0; i < 8; ++i)
    if (lanes[i] != 0 && !alphaPasses(&f->material, texels, u[i], v[i])) lanes[i] = 0;
  return vload8(0, lanes);
}

#endif
