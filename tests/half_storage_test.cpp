// Half (fp16) moment storage through every stage that writes or reads it: the moments kernels, the blur's
// column pass (and the running-sum plans' pack) and the mip chain. The stages compute in fp32 exactly as with
// fp32 storage and round once when they store, so each half result is checked bit for bit against the fp32
// result rounded to nearest even (Imath::half, OpenEXR's IEEE binary16), and each mip level against the double
// area average of the stored level above within half a half-ulp plus fp32 error. Inputs: depth with background,
// NaN and out-of-range texels; 1x1, prime and thin sizes; exponents beyond the half clamp.
#include <Imath/half.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "host/cl/buffer.h"
#include "host/stages/blur.h"
#include "host/stages/moments.h"
#include "host/stages/pyramid.h"
#include "tests/support/cl_test.h"
#include "tests/support/random_images.h"
#include "tools/selftest/reference/pyramid_ref.h"

namespace penumbra {
namespace half_storage_test {
using test::kPoison;

using ref::kHalfPoison;

// The IEEE binary16 bits of `v` rounded to nearest even, as vstore_half_rte writes them.
cl_half toHalf(float v) { return Imath::half(v).bits(); }

float fromHalf(cl_half bits) {
  Imath::half h;
  h.setBits(bits);
  return float(h);
}

std::vector<cl_half> rounded(const std::vector<float>& values) {
  std::vector<cl_half> out;
  out.reserve(values.size());
  for (float v : values) out.push_back(toHalf(v));
  return out;
}

using ref::depthWithHoles;

MomentsConfig halfConfig(MomentKind kind) {
  MomentsConfig config;
  config.kind = kind;
  config.depthNear = 2.0f, config.depthFar = 9.0f;
  config.storage = MomentStorage::Float16;
  config.evsmPositive = 40.0f, config.evsmNegative = 40.0f;  // both clamped to 5.54: e^(2c) just below 65,504
  return config;
}

constexpr MomentKind kKinds[] = {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Msm,
                                 MomentKind::Esm};
const std::pair<uint32_t, uint32_t> kSizes[] = {{67, 41}, {1, 1}, {130, 3}};

class HalfStorage : public test::ClTest {};

TEST_F(HalfStorage, MomentsEqualFp32MomentsRoundedToHalf) {
  for (const auto& [width, height] : kSizes) {
    const Buffer<float> depth(ctx(), std::span<const float>(depthWithHoles(width, height, width + height)));
    for (MomentKind kind : kKinds) {
      const MomentsConfig config = halfConfig(kind);
      const size_t count = size_t(width) * height * momentChannels(kind);
      Buffer<float> single(ctx(), count);
      Buffer<cl_half> half(ctx(), count);
      single.fill(ctx(), kPoison);
      half.fill(ctx(), kHalfPoison);
      computeMoments(ctx(), depth, width, height, config, single);
      computeMoments(ctx(), depth, width, height, config, half);
      const std::vector<cl_half> got = half.download(ctx());
      EXPECT_EQ(got, rounded(single.download(ctx()))) << width << "x" << height << " kind " << int(kind);
      for (cl_half h : got) ASSERT_TRUE(std::isfinite(fromHalf(h))) << "kind " << int(kind);
    }
  }
}

TEST_F(HalfStorage, MomentsRejectHalfWithoutTheHalfExponentBoundAndLvsm) {
  Buffer<float> depth(ctx(), 4);
  Buffer<cl_half> out(ctx(), 16);
  MomentsConfig fp32Bound = halfConfig(MomentKind::Evsm4);
  fp32Bound.storage = MomentStorage::Float32;  // would let e^(2c) overflow half
  EXPECT_THROW(computeMoments(ctx(), depth, 2, 2, fp32Bound, out), std::invalid_argument);
  MomentsConfig layered = halfConfig(MomentKind::Lvsm);
  layered.layers = {{0.0f, 1.0f}};
  EXPECT_THROW(computeMoments(ctx(), depth, 2, 2, layered, out), std::invalid_argument);
  Buffer<float> scratch(ctx(), 16);
  EXPECT_THROW(blurMoments(ctx(), depth, fp32Bound, out, scratch, 2, 2, BlurConfig{}), std::invalid_argument);
}

// Direct plans store half from the column pass; running sums (sigma 15: radius 45) blur in fp32 and pack. ESM's
// log-space blur (direct plans only) stores half from its column pass too, at the half exponent bound 8.
TEST_F(HalfStorage, BlurredMomentsEqualFp32BlurRoundedToHalf) {
  BlurConfig box;
  box.filter = BlurFilter::Box;
  box.radius = 3;
  BlurConfig wide;
  wide.sigma = 15.0f;
  BlurConfig narrow;
  narrow.sigma = 2.0f;
  for (const auto& [width, height] : kSizes) {
    const Buffer<float> depth(ctx(), std::span<const float>(depthWithHoles(width, height, 3 * width + height)));
    for (MomentKind kind : kKinds)
      for (const BlurConfig& blur : {narrow, box, wide}) {
        if (kind == MomentKind::Esm && !planBlur(blur).direct) continue;  // refused: BlurKernels.EsmBlursInLogSpace
        const MomentsConfig config = halfConfig(kind);
        const ImageShape shape{width, height, momentChannels(kind)};
        Buffer<float> single(ctx(), shape.count()), scratch(ctx(), shape.count());
        single.fill(ctx(), kPoison);
        blurMoments(ctx(), depth, config, single, scratch, width, height, blur);
        Buffer<cl_half> half(ctx(), shape.count());
        Buffer<float> halfScratch(ctx(), blurMomentsScratch(ctx(), shape, blur, MomentStorage::Float16, kind));
        half.fill(ctx(), kHalfPoison);
        halfScratch.fill(ctx(), kPoison);
        blurMoments(ctx(), depth, config, half, halfScratch, width, height, blur);
        EXPECT_EQ(half.download(ctx()), rounded(single.download(ctx())))
            << width << "x" << height << " kind " << int(kind) << " radius " << planBlur(blur).radius;
      }
  }
}

// Each stored level is the area average of the stored level above (read as half, summed in fp32), rounded to
// half: within half a half-ulp (at most 2^-11 relative, 2^-25 among subnormal halves) plus fp32 error (2e-6
// absolute on unit data, 1e-6 relative). Both schedules agree bit for bit: the batched one keeps each level in
// local memory as it reads back once stored, and that rounding (PN_ROUND) must equal vstore_half_rte on
// subnormal halves too, which the log-uniform images over [2^-26, 2^15] reach (EVSM4's squared negative warp
// goes down to e^-11 = 1.5e-5, below the smallest normal half 6.1e-5).
TEST_F(HalfStorage, MipsAverageTheStoredLevelAboveAndBothSchedulesAgree) {
  for (const auto& [width, height, channels, logUniform] : {std::tuple{97u, 61u, 2u, false},
                                                            {1u, 1u, 4u, false},
                                                            {2u, 17u, 4u, false},
                                                            {300u, 1u, 2u, false},
                                                            {256u, 256u, 4u, false},
                                                            {97u, 61u, 2u, true},
                                                            {256u, 256u, 4u, true}}) {
    const ImageShape shape{width, height, channels};
    std::vector<float> values = test::randomUnitImage(shape.count(), width + 7 * height);
    if (logUniform)
      for (float& v : values) v = std::exp2(-26.0f + 41.0f * v);
    const std::vector<cl_half> base = rounded(values);
    const PyramidLayout layout = pyramidLayout(width, height, 1);
    const Buffer<cl_half> in(ctx(), std::span<const cl_half>(base));
    Buffer<cl_half> batched(ctx(), std::max<size_t>(1, layout.texels * channels)), perLevel(ctx(), batched.size());
    batched.fill(ctx(), kHalfPoison);
    perLevel.fill(ctx(), kHalfPoison);
    computeMomentMips(ctx(), in, shape, batched);
    PyramidConfig reference;
    reference.schedule = PyramidSchedule::PerLevel;
    computeMomentMips(ctx(), in, shape, perLevel, reference);
    const std::vector<cl_half> got = batched.download(ctx());
    EXPECT_EQ(got, perLevel.download(ctx())) << width << "x" << height;

    std::vector<double> above(base.size());
    for (size_t i = 0; i < base.size(); ++i) above[i] = fromHalf(base[i]);
    ImageShape aboveShape = shape;
    for (size_t l = 0; l < layout.levels.size(); ++l) {
      const PyramidLevel& level = layout.levels[l];
      const std::vector<double> expected = ref::momentMips(above, aboveShape).front();
      ASSERT_EQ(expected.size(), size_t(level.width) * level.height * channels);
      int wrong = 0;
      for (size_t i = 0; i < expected.size(); ++i) {
        const double value = fromHalf(got[size_t(level.offset) * channels + i]);
        const double tolerance = std::ldexp(std::abs(expected[i]), -11) + std::ldexp(1.0, -25) +
                                 (logUniform ? 1e-6 * std::abs(expected[i]) : 2e-6);
        if (std::abs(value - expected[i]) > tolerance && ++wrong <= 3)
          ADD_FAILURE() << width << "x" << height << " level " << l + 1 << " element " << i << ": " << value << " vs "
                        << expected[i];
      }
      above.resize(expected.size());
      for (size_t i = 0; i < expected.size(); ++i) above[i] = fromHalf(got[size_t(level.offset) * channels + i]);
      aboveShape = {level.width, level.height, channels};
    }
  }
}

}  // namespace half_storage_test
}  // namespace penumbra
