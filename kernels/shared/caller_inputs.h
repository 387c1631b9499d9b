// The caller's images as pn_shade takes them (host/pipeline/caller_shade.h, kernels/caller_inputs.cl): where an
// image's texels lie in the caller's buffer, and how its depth values read as light-eye or camera depths. Shared by
// host and kernels.
#ifndef PENUMBRA_KERNELS_SHARED_CALLER_INPUTS_H
#define PENUMBRA_KERNELS_SHARED_CALLER_INPUTS_H

#include "kernels/shared/common.h"

// Texel (x, y) of an image, y counted from the bottom row as every penumbra buffer is, lies at float
// offset + row * rowPitch + x * channels of the caller's buffer, row = topDown ? height - 1 - y : y.
typedef struct CallerImageGpu {
  uint offset;    // floats before the first row in memory
  uint rowPitch;  // floats from one row in memory to the next
  uint width, height;
  uint channels;  // floats per texel: 1 (depth, visibility) or 4 (positions, normals)
  int topDown;    // 1: the first row in memory is the image's top row (Direct3D, Vulkan); 0: its bottom row
  int pad0, pad1;
} CallerImageGpu;

#define CALLER_DEPTH_LINEAR 0  // the eye depth -z_eye itself
#define CALLER_DEPTH_WINDOW 1  // a depth buffer's window value d in [0, 1], d = z_ndc (ZeroToOne) or z_ndc / 2 + 1/2

// How a depth image's values read. A window value is empty (nothing drawn there: the cleared value) where it lies at
// or beyond the far plane's, (d - farWindow) * farSign >= 0; a linear value where it is not below zFar; any value that
// is not finite (NaN, either infinity).
typedef struct CallerDepthGpu {
  int storage;       // CALLER_DEPTH_*
  int ndcZeroToOne;  // 1: z_ndc = d (Direct3D, Vulkan, reversed Z); 0: z_ndc = 2 d - 1 (OpenGL)
  float farWindow;   // the far plane's window value (1, or 0 with reversed Z)
  float farSign;     // +1 where window values grow towards the far plane, -1 where they shrink (reversed Z)
  // The projection's z and w rows where they depend on z_eye alone (a perspective or orthographic projection):
  // z_ndc = (p22 z_eye + p23) / (p32 z_eye + p33), so z_eye = (p23 - z_ndc p33) / (z_ndc p32 - p22).
  float p22, p23, p32, p33;
  float zFar;  // linear storage: values not below it are empty
  int pad0, pad1, pad2;
} CallerDepthGpu;

#if PENUMBRA_HOST
static_assert(sizeof(CallerImageGpu) == 32, "CallerImageGpu is shared with OpenCL C");
static_assert(sizeof(CallerDepthGpu) == 48 && offsetof(CallerDepthGpu, zFar) == 32,
              "CallerDepthGpu is shared with OpenCL C");
#else
// The float index of texel (x, y)'s first channel in the caller's buffer.
inline uint caller_index(CallerImageGpu image, uint x, uint y) {
  const uint row = image.topDown ? image.height - 1 - y : y;
  return image.offset + row * image.rowPitch + x * image.channels;
}

// A window value's z_ndc.
inline float caller_ndc(CallerDepthGpu depth, float d) { return depth.ndcZeroToOne ? d : 2.0f * d - 1.0f; }

// Whether a depth value is empty (see CallerDepthGpu).
inline int caller_empty(CallerDepthGpu depth, float v) {
  if (!isfinite(v)) return 1;
  return depth.storage == CALLER_DEPTH_LINEAR ? !(v < depth.zFar) : (v - depth.farWindow) * depth.farSign >= 0.0f;
}

// The linear eye depth -z_eye of a value that is not empty; a window value in front of the near plane's (outside
// [0, 1], which no depth buffer holds) reads as the near plane.
inline float caller_eye_depth(CallerDepthGpu depth, float v) {
  if (depth.storage == CALLER_DEPTH_LINEAR) return v;
  const float ndc = caller_ndc(depth, clamp(v, 0.0f, 1.0f));
  return -(depth.p23 - ndc * depth.p33) / (ndc * depth.p32 - depth.p22);
}
#endif

#endif  // PENUMBRA_KERNELS_SHARED_CALLER_INPUTS_H
