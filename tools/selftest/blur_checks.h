// The blur's checks on moments, the production path of every moment technique (blurMoments: the moments made in the
// row pass): ESM's filtered depth in log space and linearly, and every other encoding's blurred moments, against the
// references. tests/blur_test.cpp runs the ESM cases; `penumbra selftest` runs both.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/stages/blur.h"
#include "host/stages/moments.h"
#include "tools/selftest/reference/tolerance.h"

namespace penumbra::selftest {

// MomentKind::Esm's filtered depth D (e^(c D) the blurred e^(c d)) at the linear limit c = 0, in log space
// (kernels/shared/moments.h moments_log_mix: c = 0.5, 81, fp32's largest 1000, where e^(c d) itself would overflow even
// double) and as the linear blur of e^(c (d - 1)) (c = 20, 80: the fused direct and running-sum plans), on depth with
// background, NaN and out-of-range texels, 1x1 and thin maps. Log-space exponents take direct plans only.
struct EsmBlurCase {
  uint32_t width, height;
  float exponent;
  BlurConfig config;
  bool quick = false;
  std::string name() const;
};
std::vector<EsmBlurCase> esmBlurCases();
ref::Comparison esmBlur(Context& ctx, const EsmBlurCase& c);  // within ref::kLogBlurTol, in normalised depth

// VSM, EVSM2/4 and MSM blurred as they are made, in fp32 and half storage and both direct layouts, against the
// reference moments blurred by the reference plan (ref::blurredMomentsTolerance; half: plus half a half-ulp).
struct MomentBlurCase {
  uint32_t width, height;
  MomentKind kind;
  BlurConfig config;  // its layout included
  MomentStorage storage = MomentStorage::Float32;
  bool quick = false;
  std::string name() const;
};
std::vector<MomentBlurCase> momentBlurCases();
ref::Comparison momentBlur(Context& ctx, const MomentBlurCase& c);

}  // namespace penumbra::selftest
