#include "tools/selftest/blur_checks.h"

#include <fmt/format.h>

#include <cmath>
#include <span>
#include <utility>

#include "host/cl/buffer.h"
#include "tools/selftest/reference/blur_ref.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/moments_ref.h"
#include "tools/selftest/selftest.h"
#include "tools/selftest/stage_checks.h"

namespace penumbra::selftest {
namespace {

constexpr float kDepthNear = 2.0f, kDepthFar = 9.0f;  // the depths of ref::depthWithHoles reach past both
const std::pair<uint32_t, uint32_t> kSizes[] = {{67, 41}, {1, 1}, {130, 3}};

std::string configName(const BlurConfig& config) {
  const BlurPlan plan = planBlur(config);
  return fmt::format(
      "{}{}{}", config.filter == BlurFilter::Gaussian ? "gauss" : "box",
      config.filter == BlurFilter::Gaussian ? fmt::format("{:g}", config.sigma) : std::to_string(config.radius),
      plan.direct ? (config.layout == BlurLayout::Runs    ? "_runs"
                     : config.layout == BlurLayout::Tiles ? "_tiles"
                                                          : "")
                  : "_running");
}

}  // namespace

std::string EsmBlurCase::name() const {
  return fmt::format("esm_c{:g}_{}_{}x{}", exponent, configName(config), width, height);
}

std::vector<EsmBlurCase> esmBlurCases() {
  std::vector<EsmBlurCase> out;
  for (const auto& [width, height] : kSizes)
    for (float c : {0.0f, 0.5f, 20.0f, 80.0f, 81.0f, 1000.0f})
      for (const BlurConfig& config :
           {ref::gaussianBlur(2.0f), ref::boxBlur(2), ref::gaussianBlur(5.0f), ref::gaussianBlur(15.0f)}) {
        if (esmLogSpace(c) && !planBlur(config).direct) continue;  // refused (tests/blur_test.cpp)
        const bool quick = width == 67 && config.sigma == 2.0f && config.filter == BlurFilter::Gaussian &&
                           (c == 80.0f || c == 1000.0f);
        out.push_back({width, height, c, config, quick});
      }
  return out;
}

ref::Comparison esmBlur(Context& ctx, const EsmBlurCase& c) {
  const std::vector<float> depth = ref::depthWithHoles(c.width, c.height, 23 + c.width);
  const Buffer<float> depthBuffer(ctx, std::span<const float>(depth));
  MomentsConfig moments;
  moments.kind = MomentKind::Esm;
  moments.depthNear = kDepthNear, moments.depthFar = kDepthFar;
  moments.esmExponent = c.exponent;
  const ImageShape shape{c.width, c.height, 1};
  Buffer<float> out(ctx, shape.count()),
      scratch(ctx, blurMomentsScratch(ctx, shape, c.config, MomentStorage::Float32, MomentKind::Esm));
  out.fill(ctx, ref::kPoison);
  scratch.fill(ctx, ref::kPoison);
  blurMoments(ctx, depthBuffer, moments, out, scratch, c.width, c.height, c.config);
  std::vector<double> d(depth.size());
  for (size_t i = 0; i < depth.size(); ++i) d[i] = ref::normalizeDepth(depth[i], kDepthNear, kDepthFar);
  std::vector<double> expected;
  if (planBlur(c.config).direct) {
    expected = ref::logBlur(
        d, c.width, c.height,
        c.config.filter == BlurFilter::Gaussian ? ref::gaussianTaps(c.config.sigma) : ref::boxTaps(c.config.radius),
        c.exponent);
  } else {  // running sums (c in [1, 80]): the plan's boxes one after another, on e^(c (d - 1)) in double
    std::vector<double> warped;
    for (double v : d) warped.push_back(std::exp(c.exponent * (v - 1.0)));
    for (double v : ref::blurExpected(warped, shape, c.config)) expected.push_back(1.0 + std::log(v) / c.exponent);
  }
  std::vector<float> got = out.download(ctx);
  if (!esmLogSpace(c.exponent))  // the map holds e^(c (d - 1)): its depth D
    for (float& v : got) v = 1.0f + std::log(v) / c.exponent;
  return ref::compare(std::span<const float>(got), std::span<const double>(expected), ref::kLogBlurTol, c.width);
}

std::string MomentBlurCase::name() const {
  return fmt::format("{}_{}_{}x{}{}", ref::momentKindName(kind), configName(config), width, height,
                     storage == MomentStorage::Float16 ? "_half" : "");
}

std::vector<MomentBlurCase> momentBlurCases() {
  std::vector<MomentBlurCase> out;
  for (const auto& [width, height] : kSizes)
    for (MomentKind kind : {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Msm})
      for (BlurConfig config : {ref::gaussianBlur(2.0f), ref::boxBlur(3), ref::gaussianBlur(15.0f)})
        for (BlurLayout layout : {BlurLayout::Tiles, BlurLayout::Runs}) {
          if (layout == BlurLayout::Runs && !planBlur(config).direct) continue;  // one running-sum plan
          config.layout = layout;
          for (MomentStorage storage : {MomentStorage::Float32, MomentStorage::Float16}) {
            const bool quick = width == 67 && storage == MomentStorage::Float32 && layout == BlurLayout::Tiles &&
                               ((kind == MomentKind::Evsm4 && config.sigma == 2.0f) ||
                                (kind == MomentKind::Msm && config.sigma == 15.0f));
            out.push_back({width, height, kind, config, storage, quick});
          }
        }
  return out;
}

ref::Comparison momentBlur(Context& ctx, const MomentBlurCase& c) {
  const ImageShape shape{c.width, c.height, momentChannels(c.kind)};
  requireLayoutFits(ctx, shape, c.config);
  const std::vector<float> depth = ref::depthWithHoles(c.width, c.height, 17 + c.width);
  const Buffer<float> depthBuffer(ctx, std::span<const float>(depth));
  MomentsConfig moments;
  moments.kind = c.kind;
  moments.depthNear = kDepthNear, moments.depthFar = kDepthFar;
  moments.storage = c.storage;
  if (c.storage == MomentStorage::Float16) moments.evsmPositive = moments.evsmNegative = 40.0f;  // clamped to 5.54
  const std::vector<double> texels = ref::moments(depth, moments);
  const std::vector<double> expected = ref::blurExpected(texels, shape, c.config);
  double magnitude = 0.0;
  for (double v : texels) magnitude = std::max(magnitude, std::abs(v));
  ref::Tolerance tol = ref::blurredMomentsTolerance(
      ref::momentsTolerance(c.kind), planBlur(c.config).direct ? ref::kBlurDirectTol : ref::kBlurRunningTol, magnitude);
  Buffer<float> scratch(ctx, blurMomentsScratch(ctx, shape, c.config, c.storage, c.kind));
  scratch.fill(ctx, ref::kPoison);
  std::vector<float> got;
  if (c.storage == MomentStorage::Float32) {
    Buffer<float> out(ctx, shape.count());
    out.fill(ctx, ref::kPoison);
    blurMoments(ctx, depthBuffer, moments, out, scratch, c.width, c.height, c.config);
    got = out.download(ctx);
  } else {
    Buffer<cl_half> out(ctx, shape.count());
    out.fill(ctx, ref::kHalfPoison);
    blurMoments(ctx, depthBuffer, moments, out, scratch, c.width, c.height, c.config);
    got = ref::fromHalf(out.download(ctx));
    tol = ref::halfStorageTolerance(tol);
  }
  return ref::compare(std::span<const float>(got), std::span<const double>(expected), tol,
                      size_t(c.width) * shape.channels);
}

void addBlurChecks(std::vector<Check>& out) {
  for (const EsmBlurCase& c : esmBlurCases())
    out.push_back({"blur", c.name(), c.quick, [c](Context& ctx) {
                     return Measured{esmBlur(ctx, c), "normalised depth"};
                   }});
  for (const MomentBlurCase& c : momentBlurCases())
    out.push_back({"blur", "moments_" + c.name(), c.quick, [c](Context& ctx) { return Measured{momentBlur(ctx, c)}; }});
}

}  // namespace penumbra::selftest
