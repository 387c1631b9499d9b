// The blur's local-memory plan: the tiles it derives from a device's local memory, and every direct configuration
// (1/2/4 channels, radii 1 .. 128, both layouts, the fused moments of EVSM4 and MSM) run on contexts whose device
// reports 16 KiB and 32 KiB with the GPU layouts forced, against the double reference and the uncapped device.
#include "host/stages/blur_local.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <random>
#include <span>
#include <vector>

#include "host/cl/buffer.h"
#include "host/stages/blur.h"
#include "kernels/shared/blur.h"
#include "tests/support/cl_test.h"
#include "tests/support/compare.h"
#include "tools/selftest/reference/blur_ref.h"

namespace penumbra {
namespace blur_local_test {
using test::Tolerance;

// Direct sums of <= 2 * 128 + 1 fp32 products of data in [0, 1] per pass: <= 257 roundings of ~6e-8, twice.
constexpr Tolerance kDirectTol{4e-5, 4e-6};
// Capped and uncapped runs add each texel's taps in the same order; only a fused multiply-add contracted in one
// kernel (tile, global taps) and not in the other may differ, by one rounding per tap (as BlurKernels.LayoutsAgree).
constexpr Tolerance kSameSumsTol{2e-5, 2e-5};
constexpr uint64_t kSmallDevices[] = {16 * 1024, 32 * 1024};
constexpr int kRadii[] = {1, 6, 17, 31, 32, 64, 128};

TEST(BlurLocalPlan, DerivesTilesFromLocalMemory) {
  const ImageShape rgba{64, 64, 4};
  // 32 KiB, radius 32, 4 channels: one column row needs 65 x 32 x 16 = 33,280 bytes, so the columns read global taps.
  EXPECT_EQ(planBlurLocal(false, 32 * 1024, rgba, 32).columnRows, 0);
  EXPECT_EQ(planBlurLocal(false, 48 * 1024, rgba, 32).columnRows, 32);  // 96 x 512 = 49,152 bytes: all of 48 KiB
  EXPECT_EQ(planBlurLocal(false, 32 * 1024, rgba, 17).columnRows, 16);  // 50 x 512 = 25,600 bytes of 32 KiB
  EXPECT_EQ(planBlurLocal(false, 64 * 1024, rgba, 1).columnRows, 32);   // 34 x 512 = 17,408 bytes: 64 rows pass 32 KiB
  EXPECT_EQ(planBlurLocal(false, 16 * 1024, rgba, 128).rowLines, 2);    // 2 x 320 x 16 = 10,240 bytes
  EXPECT_EQ(planBlurLocal(true, 16 * 1024, rgba, 128).rowLines, 1);     // 768 x 16 = 12,288 bytes
  EXPECT_EQ(planBlurLocal(false, 48 * 1024, {64, 64, 2}, 100).columnRows, 0);  // LayoutsAgree's 51,456 bytes
  EXPECT_THROW(planBlurLocal(false, 4 * 1024, rgba, 128), std::invalid_argument);
  for (uint64_t local : {16 * 1024, 32 * 1024, 48 * 1024, 64 * 1024})
    for (uint32_t channels : {1u, 2u, 4u})
      for (int radius = 0; radius <= BLUR_DIRECT_RADIUS_LIMIT; ++radius)
        for (bool runs : {false, true}) {
          const BlurLocalPlan plan = planBlurLocal(runs, local, {64, 64, channels}, radius);
          EXPECT_LE(plan.rowBytes, local) << local << " " << channels << " " << radius;
          EXPECT_LE(plan.columnBytes, local) << local << " " << channels << " " << radius;
        }
}

std::vector<float> randomImage(const ImageShape& shape, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<float> image(shape.count());
  for (float& v : image) v = unit(rng);
  return image;
}

std::vector<float> blurOn(Context& ctx, const std::vector<float>& image, const ImageShape& shape,
                          const BlurConfig& config) {
  Buffer<float> in(ctx, std::span<const float>(image)), out(ctx, shape.count()), scratch(ctx, shape.count());
  out.fill(ctx, test::kPoison);
  blur(ctx, in, out, scratch, shape, config);
  return out.download(ctx);
}

class BlurLocalMemory : public test::ClTest {};

TEST_F(BlurLocalMemory, EveryRadiusFitsSmallDevices) {
  const ImageShape shapes[] = {{37, 29, 1}, {37, 29, 2}, {37, 29, 4}};
  for (uint64_t local : kSmallDevices) {
    std::unique_ptr<Context> small = test::smallGpuContext(ctx(), local);
    for (const ImageShape& shape : shapes)
      for (int radius : kRadii)
        for (BlurLayout layout : {BlurLayout::Tiles, BlurLayout::Runs}) {
          const BlurConfig config{BlurFilter::Box, 0.0f, radius, 1.0f, BlurMethod::Direct, layout};
          const std::vector<float> image = randomImage(shape, radius + shape.channels);
          const std::vector<float> capped = blurOn(*small, image, shape, config);
          const std::vector<double> input(image.begin(), image.end());
          const std::string where = fmt::format("{} bytes, {} channels, radius {}, {}", local, shape.channels, radius,
                                                layout == BlurLayout::Tiles ? "tiles" : "runs");
          EXPECT_TRUE(test::allNear(std::span<const float>(capped),
                                    std::span<const double>(ref::convolveSeparable(input, shape, ref::boxTaps(radius))),
                                    kDirectTol, shape.width * shape.channels))
              << where;
          EXPECT_TRUE(test::allNear(std::span<const float>(capped),
                                    std::span<const float>(blurOn(ctx(), image, shape, config)), kSameSumsTol,
                                    shape.width * shape.channels))
              << where;
        }
  }
}

// The failures on a 32 KiB device: EVSM4 and MSM moments blurred at radius 17 (the fused row pass).
TEST_F(BlurLocalMemory, FusedMomentsFitSmallDevices) {
  const uint32_t width = 41, height = 23;
  std::vector<float> depth(size_t(width) * height);
  for (size_t i = 0; i < depth.size(); ++i) depth[i] = 2.0f + 7.0f * float((i * 7919) % 1000) / 1000.0f;
  const Buffer<float> depthBuffer(ctx(), std::span<const float>(depth));
  for (uint64_t local : kSmallDevices) {
    std::unique_ptr<Context> small = test::smallGpuContext(ctx(), local);
    const Buffer<float> smallDepth(*small, std::span<const float>(depth));
    for (MomentKind kind : {MomentKind::Evsm4, MomentKind::Msm})
      for (int radius : {17, 32}) {
        MomentsConfig moments;
        moments.kind = kind;
        moments.depthNear = 2.0f, moments.depthFar = 9.0f;
        const ImageShape shape{width, height, momentChannels(kind)};
        const BlurConfig config{BlurFilter::Box, 0.0f, radius, 1.0f, BlurMethod::Direct, BlurLayout::Tiles};
        Buffer<float> out(ctx(), shape.count()), scratch(ctx(), shape.count());
        Buffer<float> smallOut(*small, shape.count()), smallScratch(*small, shape.count());
        blurMoments(ctx(), depthBuffer, moments, out, scratch, width, height, config);
        blurMoments(*small, smallDepth, moments, smallOut, smallScratch, width, height, config);
        EXPECT_TRUE(test::allNear(std::span<const float>(smallOut.download(*small)),
                                  std::span<const float>(out.download(ctx())), kSameSumsTol, width * shape.channels))
            << local << " bytes, kind " << int(kind) << ", radius " << radius;
      }
  }
}

}  // namespace blur_local_test
}  // namespace penumbra
