// Pyramid stage: mip chains of moment images (exact area averages; odd sizes keep the mean) and the
// min-max depth pyramid of a hierarchical shadow map (VSSM). One launch per level. Kernels:
// kernels/pyramid.cl; layout: kernels/shared/pyramid.h.
#pragma once

#include <CL/opencl.hpp>
#include <cstdint>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/stages/image_shape.h"
#include "kernels/shared/pyramid.h"

namespace penumbra {

// Levels `firstLevel`.. down to 1x1 of a width x height base: levels[i] is level firstLevel + i, with
// offsets (in texels) into one buffer of `texels` texels.
struct PyramidLayout {
  uint32_t firstLevel = 0;
  std::vector<PyramidLevel> levels;
  size_t texels = 0;
};
PyramidLayout pyramidLayout(uint32_t width, uint32_t height, uint32_t firstLevel);

// Mip levels 1.. of `base` (shape.count() floats, level 0) into `mips` (pyramidLayout(w, h, 1).texels *
// channels floats). Launches "pyramid/pyramid_downsample", one per level.
std::vector<cl::Event> computeMomentMips(Context& ctx, const Buffer<float>& base, const ImageShape& shape,
                                         Buffer<float>& mips);

// Levels 0.. of the min-max pyramid of `depth` (width*height light depths) into `out`
// (pyramidLayout(w, h, 0).texels float2 (min, max)). Background and NaN texels are the empty interval
// (+INFINITY, -INFINITY), so they never widen a range. Launches "pyramid/pyramid_minmax_*".
std::vector<cl::Event> computeMinMaxPyramid(Context& ctx, const Buffer<float>& depth, uint32_t width, uint32_t height,
                                            Buffer<cl_float2>& out);

}  // namespace penumbra
