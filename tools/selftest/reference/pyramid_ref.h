// Double-precision reference of the pyramids: each level the exact area average (or the min and max over
// every texel with positive overlap) of the previous level's footprint [x s/d, (x+1) s/d].
#pragma once

#include <utility>
#include <vector>

#include "host/stages/image_shape.h"

namespace penumbra::ref {

// Levels 1.. down to 1x1 (level l+1 is max(1, floor(size_l / 2)) per axis), each shape.channels wide.
std::vector<std::vector<double>> momentMips(const std::vector<double>& base, const ImageShape& shape);

// Levels 0.. of (min, max) with non-finite depths excluded (+inf, -inf for an empty footprint).
std::vector<std::vector<std::pair<float, float>>> minMaxPyramid(const std::vector<float>& depth, uint32_t width,
                                                                uint32_t height);

}  // namespace penumbra::ref
