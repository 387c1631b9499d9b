// Temporal stability of a sequence (shimmer): between consecutive frames, how much a technique's visibility changes
// at the pixels seen in both frames where the reference's does not, so that every change counted is the technique's
// own (shadow-map texels crawling as the light's fit follows the camera, filter kernels snapping). Plain C++.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace penumbra {

// A pixel's reference is stable when it changes by at most this between the frames: 256-spp area-light references
// carry a standard error near 0.01 in penumbrae (hard lights' are exactly 0 or 1), so two independent estimates of
// the same value differ by less than 0.02 most of the time.
inline constexpr double kStableReference = 0.02;
// A stable pixel shimmers when ours changes by more than this (about one step of a 4x4 PCF kernel, 1/16).
inline constexpr double kShimmerStep = 0.0625;

struct ShimmerMetrics {
  size_t pixels = 0;    // stable pixels counted (covered in both frames, both references finite and stable)
  double mean = 0;      // mean |ours_b - ours_a| over them (0 when there are none)
  double fraction = 0;  // fraction of them changing by more than kShimmerStep
  double maxAbs = 0;    // the largest change
};

// One pair of consecutive frames. Every span holds one value per pixel (rows as stored); a coverage span may be empty
// (every pixel counts), else a pixel counts where both frames' coverage is > 0. NaN in ours counts as a change of 1.
// Throws std::invalid_argument when the sizes differ.
ShimmerMetrics frameShimmer(std::span<const float> oursA, std::span<const float> oursB,
                            std::span<const float> referenceA, std::span<const float> referenceB,
                            std::span<const float> coverageA = {}, std::span<const float> coverageB = {});

// Several pairs as one: the pixel-weighted mean and fraction, the largest change.
ShimmerMetrics combineShimmer(const std::vector<ShimmerMetrics>& pairs);

}  // namespace penumbra
