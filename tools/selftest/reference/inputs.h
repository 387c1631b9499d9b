// The inputs the kernel checks run on, random and adversarial (background, NaN, infinities, huge ranges), made the
// same way for the test suite and `penumbra selftest`: the same seed gives the same input on every machine
// (std::mt19937 and the distributions below are specified to the bit for the integer draws the adversarial choices
// use; the real-valued draws are libstdc++'s, the same on every build of penumbra).
#pragma once

#include <CL/cl_platform.h>

#include <cstdint>
#include <vector>

#include "host/stages/image_shape.h"

namespace penumbra::ref {

// A value no kernel writes by accident: outputs are filled with it before a launch, so that an element left unwritten
// shows up as a mismatch instead of a stale correct value.
inline constexpr float kPoison = -1234567.0f;
// Its half-storage counterpart: -65504, the most negative finite half, which no stage writes.
inline constexpr cl_half kHalfPoison = 0xFBFF;

// IEEE binary16 values (half moments as a stage stores them) as floats.
std::vector<float> fromHalf(const std::vector<cl_half>& bits);

// `count` floats uniform in [0, 1).
std::vector<float> randomUnitImage(size_t count, uint32_t seed);

// width x height light depths: 1 texel in 5 background (+INF), 1 in 29 NaN, the rest uniform in [1, 50]; every texel
// background when `empty`.
std::vector<float> randomDepthMap(uint32_t width, uint32_t height, uint32_t seed, bool empty = false);

// Light depths over [near - 1, far + 1] with background, NaN, -inf and a few +-3e38 mixed in (1 in 16 each): what
// the moments stage must normalise.
std::vector<float> momentsDepth(size_t count, uint32_t seed, float depthNear, float depthFar);

// Light depths over [1.5, 9.5] (the moments' range in these cases is [2, 9]) with texels 3, 14, 25, ... background
// (+inf) and texels 5, 22, 39, ... NaN.
std::vector<float> depthWithHoles(uint32_t width, uint32_t height, uint32_t seed);

// SAT inputs: uniform [0, 1); constant 0.75; uniform with a quarter scaled by 1e30 (both signs); uniform with 1 in 97
// non-finite.
enum class SatInput { Random, Constant, HugeRange, NonFinite };
std::vector<float> satImage(const ImageShape& shape, SatInput kind, uint32_t seed);

// Blur inputs (as doubles, each exactly a float): uniform [0, 1); constant 0.625; positive values 1e20..1e30.
enum class BlurInput { Random, Constant, HugeRange };
std::vector<double> blurImage(const ImageShape& shape, BlurInput kind, uint32_t seed);

// Lloyd samples and weights: 1 in 50 NaN x, 1 in 50 infinite x, zero, negative and NaN weights; `clusters - 1`
// boundaries evenly spaced in (0, 1).
struct LloydInputs {
  std::vector<float> x, w, boundaries;
};
LloydInputs lloydInputs(uint32_t count, uint32_t clusters);

}  // namespace penumbra::ref
