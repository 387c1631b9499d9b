// Per-pixel view geometry shared by the fine and G-buffer kernels (OpenCL C only): the eye-space ray through a
// pixel centre and the depth modes, both from the projection terms of RasterViewParams. With z = z_eye and
// v = -z_eye (view depth), a projection of the supported form gives, on the ray through NDC (xn, yn),
//   w_c(v) = P33 - P23 v,   x_eye(v) = (xn w_c(v) + P20 v - P30) / P00   (and y likewise),
// an affine function of v: origin (at v = 0) plus v times a direction whose z component is -1.
#ifndef PENUMBRA_RASTER_DEPTH_H
#define PENUMBRA_RASTER_DEPTH_H

#include "raster/constants.h"
#include "raster/types.h"

// NDC of pixel (x, y)'s centre.
static inline float2 rasterPixelNdc(const RasterViewParams* p, int x, int y) {
  return (float2)((float)(2 * x + 1) / (float)p->width - 1.0f, (float)(2 * y + 1) / (float)p->height - 1.0f);
}

// The eye-space ray through a pixel centre: point(v) = origin + v * direction, direction.z = -1.
static inline void rasterEyeRay(const RasterViewParams* p, float2 ndc, float3* origin, float3* direction) {
  *origin = (float3)((ndc.x * p->p33 - p->p30) / p->p00, (ndc.y * p->p33 - p->p31) / p->p11, 0.0f);
  *direction = (float3)((p->p20 - ndc.x * p->p23) / p->p00, (p->p21 - ndc.y * p->p23) / p->p11, -1.0f);
}

// The stored depth of a covered pixel with view depth v (RASTER_DEPTH_*).
static inline float rasterDepth(const RasterViewParams* p, int x, int y, float v) {
  if (p->depthMode == RASTER_DEPTH_VIEW_Z) return v;
  if (p->depthMode == RASTER_DEPTH_NDC) {
    float zc = p->p32 - p->p22 * v, wc = p->p33 - p->p23 * v;
    return 0.5f * (zc / wc) + 0.5f;
  }
  float3 origin, direction;
  rasterEyeRay(p, rasterPixelNdc(p, x, y), &origin, &direction);
  return length(origin + v * direction);
}

// The inverse: view depth v of a pixel from its stored depth (the G-buffer's fallback for edge-on triangles).
static inline float rasterViewZFromDepth(const RasterViewParams* p, int x, int y, float d) {
  if (p->depthMode == RASTER_DEPTH_VIEW_Z) return d;
  if (p->depthMode == RASTER_DEPTH_NDC) {
    float z = 2.0f * d - 1.0f;
    return (z * p->p33 - p->p32) / (z * p->p23 - p->p22);
  }
  float3 o, r;  // |o + v r| = d, the root in front of the eye
  rasterEyeRay(p, rasterPixelNdc(p, x, y), &o, &r);
  float b = dot(o, r), rr = dot(r, r);
  return (-b + sqrt(max(b * b - rr * (dot(o, o) - d * d), 0.0f))) / rr;
}

#endif
