// The kernel checks' cases, listed once: the test suite instantiates its stage tests from these lists and
// `penumbra selftest --full` runs every one of them on the user's device (--quick the cases marked quick). Sizes are
// awkward on purpose (1x1, primes, thin strips, non-powers of two); inputs come from inputs.h.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/stages/blur.h"
#include "host/stages/moments.h"
#include "host/stages/sat.h"
#include "tools/selftest/reference/inputs.h"

namespace penumbra::ref {

const char* momentKindName(MomentKind kind);  // "Vsm", "Evsm2", ...

// The moments stage: every encoding on random depth with background, NaN, -inf and out-of-range texels.
struct MomentsCase {
  MomentKind kind;
  uint32_t width, height;
  bool constant;  // every texel 5 instead of momentsDepth
  bool quick;
  std::string name() const;
};
std::vector<MomentsCase> momentsCases();
inline constexpr float kMomentsCaseNear = 2.0f, kMomentsCaseFar = 10.0f;
// The configuration the moments cases run with: near 2, far 10, EVSM exponents 100 (clamped to the storage's bound)
// and 7.5, three overlapping LVSM layers.
MomentsConfig momentsCaseConfig(MomentKind kind);

// computeMomentsReduced: block means of every linear encoding, blocks that tile the map and blocks past its edge.
struct MomentsReducedCase {
  MomentKind kind;
  uint32_t width, height, factor;
  bool quick;
  std::string name() const;
};
std::vector<MomentsReducedCase> momentsReducedCases();

// Blur settings: a Gaussian of standard deviation `sigma` (times `scale`), a box of 2 `radius` + 1 taps.
BlurConfig gaussianBlur(float sigma, float scale = 1.0f, BlurMethod method = BlurMethod::Auto);
BlurConfig boxBlur(int radius, BlurMethod method = BlurMethod::Auto);

// The blur stage: Gaussian and box, direct and running sums, 1/2/4 channels, radii beyond the image.
struct BlurCase {
  std::string name;
  uint32_t width, height, channels;
  BlurConfig config;
  BlurInput input = BlurInput::Random;
  bool quick = false;
};
std::vector<BlurCase> blurCases();

// The SAT stage: every storage mode and algorithm on awkward sizes, and the adversarial inputs.
struct SatCase {
  std::string name;
  uint32_t width, height, channels, mode;
  SatAlgorithm algorithm = SatAlgorithm::Tiled;
  SatInput input = SatInput::Random;
  bool zeroMean = true;
  bool quick = false;
};
std::vector<SatCase> satCases();

// The pyramids: moment mips (channels 1, 2, 4) and min-max pyramids (channels 0: an all-background map).
struct PyramidCase {
  uint32_t width, height, channels;
  bool quick;
  std::string name() const;
};
std::vector<PyramidCase> momentMipCases();
std::vector<PyramidCase> minMaxCases();
// ESM's log-space mips (channels 1) at the linear limit c = 0, the paper's 80 and 600.
std::vector<PyramidCase> logMipCases();
inline constexpr float kLogMipExponents[] = {0.0f, 80.0f, 600.0f};

// The Lloyd reduction: 1 to 16 clusters over counts that are not multiples of a work-group.
struct ReduceCase {
  uint32_t count, clusters;
  bool quick;
  std::string name() const;
};
std::vector<ReduceCase> reduceCases();

}  // namespace penumbra::ref
