// Mip-chain layout shared by the pyramid kernels and their host wrapper: each level halves the previous
// one (floor, at least 1) down to 1x1; levels are stored one after another in one buffer.
#ifndef PENUMBRA_KERNELS_SHARED_PYRAMID_H
#define PENUMBRA_KERNELS_SHARED_PYRAMID_H

#include "kernels/shared/common.h"

#define PYRAMID_MAX_LEVELS 16  // 2^15 = the largest supported image side, plus the base level

typedef struct PyramidLevel {
  uint offset;         // first texel of the level in its buffer
  uint width, height;  // texels
  uint pad0;
} PyramidLevel;

#if PENUMBRA_HOST
static_assert(sizeof(PyramidLevel) == 16, "PyramidLevel layout is shared with OpenCL C");
#else

// Taps of destination texel `x` along one axis when a source of `src` texels shrinks to `dst`: an exact
// area average (the footprint [x src/dst, (x+1) src/dst] covers 1, 2 or 3 texels; odd sizes weight the
// outer two by their coverage, as in NVIDIA's non-power-of-two mipmapping note). Returns the tap count.
inline int pyramid_taps(uint x, uint src, uint dst, int* first, float* w) {
  *first = 2 * x;
  if (src == 1) {
    *first = 0, w[0] = 1.0f;
    return 1;
  }
  if (src % 2 == 0) {
    w[0] = w[1] = 0.5f;
    return 2;
  }
  const float norm = 1.0f / (float)(2 * dst + 1);
  w[0] = (float)(dst - x) * norm, w[1] = (float)dst * norm, w[2] = (float)(x + 1) * norm;
  return 3;
}

#endif
#endif
