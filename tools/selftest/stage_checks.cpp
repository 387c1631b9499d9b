// The filtering stages' checks: moments of every kind in fp32 and half storage and their block means, the blur in
// both direct layouts and as running sums, the SAT in every precision and algorithm, the moment, log-space and
// min-max pyramids, the Lloyd reduction. Each case is one of tools/selftest/reference/cases.h's, the test suite's.
#include "tools/selftest/stage_checks.h"

#include <fmt/format.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

#include "host/cl/buffer.h"
#include "host/stages/blur.h"
#include "host/stages/moments.h"
#include "host/stages/pyramid.h"
#include "host/stages/reduce.h"
#include "host/stages/sat.h"
#include "tools/selftest/probe_checks.h"
#include "tools/selftest/reference/blur_ref.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/moments_ref.h"
#include "tools/selftest/reference/pyramid_ref.h"
#include "tools/selftest/reference/reduce_ref.h"
#include "tools/selftest/reference/sat_ref.h"
#include "tools/selftest/selftest.h"

namespace penumbra::selftest {
namespace {

using ref::kPoison;

template <class T>
std::span<const T> view(const std::vector<T>& v) {
  return std::span<const T>(v);
}

// Exact comparison of integer tables (no round trip through double, which would lose 64-bit bits).
template <class T>
ref::Comparison compareExact(const std::vector<T>& actual, const std::vector<T>& expected, size_t width) {
  ref::Comparison c;
  c.count = actual.size();
  if (actual.size() != expected.size()) {
    c.mismatches = 1, c.worstError = INFINITY;
    return c;
  }
  for (size_t i = 0; i < actual.size(); ++i) {
    if (actual[i] == expected[i]) continue;
    const double error = std::abs(double(actual[i]) - double(expected[i]));
    c.worstError = std::max(c.worstError, std::max(error, 1.0)), c.worstFiniteError = c.worstError;
    if (++c.mismatches <= 8)
      c.report += fmt::format("\n  ({}, {}): {} vs expected {}", i % width, i / width, actual[i], expected[i]);
  }
  return c;
}

}  // namespace

void requireLayoutFits(const Context& ctx, const ImageShape& shape, const BlurConfig& config) {
  if (config.layout != BlurLayout::Runs || !planBlur(config).direct) return;
  // blur.cpp's own rule: Auto takes the runs on a CPU device only where all their lines fit its local memory.
  DeviceInfo asCpu = ctx.info();
  asCpu.type = CL_DEVICE_TYPE_CPU, asCpu.layouts.clear();
  if (resolveBlurLayout(BlurLayout::Auto, asCpu, shape, planBlur(config).radius) != BlurLayout::Runs)
    throw NotApplicable(
        fmt::format("the runs layout's lines do not fit {} bytes of local memory", ctx.info().localMemBytes));
}

Measured checkMoments(Context& ctx, const ref::MomentsCase& c, MomentStorage storage) {
  MomentsConfig config = ref::momentsCaseConfig(c.kind);
  config.storage = storage;
  std::vector<float> depth =
      ref::momentsDepth(size_t(c.width) * c.height, c.width * 131 + c.height, config.depthNear, config.depthFar);
  if (c.constant) std::fill(depth.begin(), depth.end(), 5.0f);
  const Buffer<float> depthBuffer(ctx, view(depth));
  const size_t count = depth.size() * momentChannels(c.kind) * momentPlanes(config);
  const std::vector<double> expected = ref::moments(depth, config);
  if (storage == MomentStorage::Float32) {
    Buffer<float> out(ctx, count);
    out.fill(ctx, kPoison);
    computeMoments(ctx, depthBuffer, c.width, c.height, config, out);
    return {ref::compare(view(out.download(ctx)), view(expected), ref::momentsTolerance(c.kind))};
  }
  Buffer<cl_half> out(ctx, count);
  out.fill(ctx, ref::kHalfPoison);
  computeMoments(ctx, depthBuffer, c.width, c.height, config, out);
  return {ref::compare(view(ref::fromHalf(out.download(ctx))), view(expected),
                       ref::halfStorageTolerance(ref::momentsTolerance(c.kind)))};
}

Measured checkMomentsReduced(Context& ctx, const ref::MomentsReducedCase& c) {
  const MomentsConfig config = ref::momentsCaseConfig(c.kind);
  const std::vector<float> depth =
      ref::momentsDepth(size_t(c.width) * c.height, c.width * 17 + c.factor, config.depthNear, config.depthFar);
  const size_t texels = size_t(reducedExtent(c.width, c.factor)) * reducedExtent(c.height, c.factor);
  const Buffer<float> depthBuffer(ctx, view(depth));
  Buffer<float> out(ctx, texels * momentChannels(c.kind));
  out.fill(ctx, kPoison);
  computeMomentsReduced(ctx, depthBuffer, c.width, c.height, config, c.factor, out);
  const std::vector<double> expected = ref::momentBlockMeans(depth, c.width, c.height, config, c.factor);
  return {ref::compare(view(out.download(ctx)), view(expected), ref::momentsReducedTolerance(c.kind))};
}

Measured checkBlur(Context& ctx, const ref::BlurCase& c, BlurLayout layout) {
  const ImageShape shape{c.width, c.height, c.channels};
  BlurConfig config = c.config;
  config.layout = layout;
  requireLayoutFits(ctx, shape, config);
  const std::vector<double> image = ref::blurImage(shape, c.input, c.width * 7 + c.height + c.channels);
  const std::vector<float> input(image.begin(), image.end());
  Buffer<float> in(ctx, view(input)), out(ctx, shape.count()), scratch(ctx, shape.count());
  out.fill(ctx, kPoison);
  scratch.fill(ctx, kPoison);
  blur(ctx, in, out, scratch, shape, config);
  const ref::Tolerance tol = c.input == ref::BlurInput::HugeRange ? ref::kBlurHugeRangeTol
                             : planBlur(config).direct            ? ref::kBlurDirectTol
                                                                  : ref::kBlurRunningTol;
  return {ref::compare(view(out.download(ctx)), view(ref::blurExpected(image, shape, config)), tol,
                       size_t(c.width) * c.channels)};
}

namespace {

template <class T>
Measured satCase(Context& ctx, const ref::SatCase& c) {
  const ImageShape shape{c.width, c.height, c.channels};
  if (std::is_same_v<T, double> && !ctx.info().fp64) throw NotApplicable("fp64 tables need cl_khr_fp64");
  const SatTableDesc desc = satDesc(shape, satMode<T>());
  if (c.algorithm == SatAlgorithm::Tiled && !satTiledFits(ctx, desc))
    throw NotApplicable("the tiled kernels do not fit this device's local memory");
  const std::vector<float> image = ref::satImage(shape, c.input, c.width * 31 + c.height * 7 + c.channels);
  Buffer<float> in(ctx, view(image)), offset(ctx, 4);
  Buffer<T> table(ctx, shape.count());
  table.fill(ctx, T(kPoison));
  offset.fill(ctx, kPoison);
  SatConfig config;
  config.algorithm = c.algorithm;
  config.zeroMean = c.zeroMean;
  computeSat(ctx, in, shape, table, offset, config);
  const std::vector<T> actual = table.download(ctx);
  const std::vector<float> off = offset.download(ctx);
  if constexpr (std::is_integral_v<T>) {
    Measured m{compareExact(actual, ref::satFixed<T>(image, shape, desc.scale == 65536.0f ? 16 : 32),
                            size_t(c.width) * c.channels)};
    m.comparison.merge(compareExact(std::vector<float>(off.begin(), off.begin() + c.channels),
                                    std::vector<float>(c.channels, 0.0f), c.channels),
                       "offsets");
    return m;
  } else {
    const std::array<double, 4> used{off[0], off[1], off[2], off[3]};
    const double eps = std::is_same_v<T, float> ? FLT_EPSILON : DBL_EPSILON;
    const ref::Tolerance tol{ref::satTableTolerance(shape, eps, ref::satMagnitude(image, used, c.channels)), 0.0, true};
    Measured m{ref::compare(view(actual), view(ref::satDouble(image, shape, used)), tol, size_t(c.width) * c.channels)};
    if (c.zeroMean && satMode<T>() == SAT_MODE_FP32) {
      const std::array<double, 4> mean = ref::finiteMean(image, shape);
      for (uint32_t ch = 0; ch < c.channels; ++ch) {
        const ref::Tolerance meanTol{ref::kSatMeanRelTol * 1e-30, ref::kSatMeanRelTol};
        m.comparison.merge(
            ref::compare(std::span<const double>(&used[ch], 1), std::span<const double>(&mean[ch], 1), meanTol),
            fmt::format("zero-mean offset {}", ch));
      }
    }
    return m;
  }
}

}  // namespace

Measured checkSat(Context& ctx, const ref::SatCase& c) {
  switch (c.mode) {
    case SAT_MODE_FIXED32:
      return satCase<uint32_t>(ctx, c);
    case SAT_MODE_FIXED64:
      return satCase<uint64_t>(ctx, c);
    case SAT_MODE_FP64:
      return satCase<double>(ctx, c);
    default:
      return satCase<float>(ctx, c);
  }
}

Measured checkMomentMips(Context& ctx, const ref::PyramidCase& c) {
  const ImageShape shape{c.width, c.height, c.channels};
  const std::vector<float> base = ref::randomUnitImage(shape.count(), c.width * 3 + c.height);
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 1);
  Buffer<float> in(ctx, view(base)), mips(ctx, std::max<size_t>(1, layout.texels * c.channels));
  mips.fill(ctx, kPoison);
  computeMomentMips(ctx, in, shape, mips);
  const std::vector<float> actual = mips.download(ctx);
  const auto expected = ref::momentMips(std::vector<double>(base.begin(), base.end()), shape);
  Measured m;
  double baseMean = 0.0;
  for (float v : base) baseMean += v;
  baseMean /= double(base.size());
  for (size_t l = 0; l < expected.size() && l < layout.levels.size(); ++l) {
    const PyramidLevel& level = layout.levels[l];
    const std::span<const float> got(actual.data() + size_t(level.offset) * c.channels, expected[l].size());
    m.comparison.merge(ref::compare(got, view(expected[l]), ref::kMipTol, level.width * c.channels),
                       fmt::format("level {}", l + 1));
    double mean = 0.0;
    for (float v : got) mean += v;
    mean /= double(got.size());
    m.comparison.merge(
        ref::compare(std::span<const double>(&mean, 1), std::span<const double>(&baseMean, 1), {ref::kMipMeanTol, 0.0}),
        fmt::format("level {} mean", l + 1));
  }
  if (expected.size() != layout.levels.size()) m.comparison.mismatches += 1, m.comparison.report += "\n  level count";
  return m;
}

Measured checkLogMips(Context& ctx, const ref::PyramidCase& c, float exponent) {
  const ImageShape shape{c.width, c.height, 1};
  const std::vector<float> base = ref::randomUnitImage(shape.count(), c.width * 5 + c.height);
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 1);
  Buffer<float> in(ctx, view(base)), mips(ctx, std::max<size_t>(1, layout.texels));
  mips.fill(ctx, kPoison);
  computeLogMomentMips(ctx, in, shape, mips, exponent);
  const std::vector<float> actual = mips.download(ctx);
  std::vector<double> warped;
  for (float d : base) warped.push_back(exponent == 0.0f ? d : std::exp(exponent * (d - 1.0)));
  const auto levels = ref::momentMips(warped, shape);
  Measured m;
  for (size_t l = 0; l < levels.size() && l < layout.levels.size(); ++l) {
    std::vector<double> expected;
    for (double v : levels[l]) expected.push_back(exponent == 0.0f ? v : 1.0 + std::log(v) / exponent);
    const std::span<const float> got(actual.data() + layout.levels[l].offset, expected.size());
    m.comparison.merge(ref::compare(got, view(expected), ref::kLogMipTol, layout.levels[l].width),
                       fmt::format("level {}", l + 1));
  }
  return m;
}

namespace {

std::vector<float> flatten(const std::vector<std::pair<float, float>>& pairs) {
  std::vector<float> out;
  for (auto [lo, hi] : pairs) out.push_back(lo), out.push_back(hi);
  return out;
}

}  // namespace

// Min-max pyramids are exact: min and max of floats.
Measured checkMinMax(Context& ctx, const ref::PyramidCase& c) {
  const std::vector<float> base = ref::randomDepthMap(c.width, c.height, c.width + 5 * c.height, c.channels == 0);
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 0);
  Buffer<float> in(ctx, view(base));
  Buffer<cl_float2> out(ctx, layout.texels);
  out.fill(ctx, {{kPoison, kPoison}});
  computeMinMaxPyramid(ctx, in, c.width, c.height, out);
  const std::vector<cl_float2> actual = out.download(ctx);
  const auto expected = ref::minMaxPyramid(base, c.width, c.height);
  Measured m;
  for (size_t l = 0; l < expected.size() && l < layout.levels.size(); ++l) {
    const std::span<const float> got(&actual[layout.levels[l].offset].s[0], expected[l].size() * 2);
    m.comparison.merge(ref::compare(got, view(flatten(expected[l])), {}, 2 * layout.levels[l].width),
                       fmt::format("level {}", l));
  }
  return m;
}

// Levels 1.. alone (computeMinMaxLevels), background and NaN the farthest depth: the reference's pyramid of the map
// with them replaced by a finite sentinel, read back as +INFINITY; the returned top is the last level.
Measured checkMinMaxLevels(Context& ctx, const ref::PyramidCase& c) {
  const std::vector<float> base = ref::randomDepthMap(c.width, c.height, c.width + 5 * c.height, c.channels == 0);
  constexpr float kFar = 3e38f;
  std::vector<float> far = base;
  for (float& z : far) z = std::isfinite(z) ? z : kFar;
  auto expected = ref::minMaxPyramid(far, c.width, c.height);
  for (auto& level : expected)
    for (auto& [lo, hi] : level) lo = lo == kFar ? INFINITY : lo, hi = hi == kFar ? INFINITY : hi;
  const PyramidLayout layout = pyramidLayout(c.width, c.height, 1);
  Buffer<float> in(ctx, view(base));
  Buffer<cl_float2> out(ctx, std::max<size_t>(layout.texels, 1));
  out.fill(ctx, {{kPoison, kPoison}});
  const cl_float2 top = computeMinMaxLevels(ctx, in, c.width, c.height, out);
  const std::vector<cl_float2> actual = out.download(ctx);
  Measured m;
  for (size_t l = 1; l < expected.size() && l - 1 < layout.levels.size(); ++l) {
    const std::span<const float> got(&actual[layout.levels[l - 1].offset].s[0], expected[l].size() * 2);
    m.comparison.merge(ref::compare(got, view(flatten(expected[l])), {}, 2 * layout.levels[l - 1].width),
                       fmt::format("level {}", l));
  }
  const std::vector<float> topExpected = flatten({expected.back()[0]});
  m.comparison.merge(ref::compare(std::span<const float>(top.s, 2), view(topExpected), {}), "returned top");
  return m;
}

namespace {

std::vector<LloydStats> lloyd(Context& ctx, const ref::LloydInputs& in, uint32_t clusters) {
  Buffer<float> x(ctx, view(in.x)), w(ctx, view(in.w));
  Buffer<float> boundaries(ctx, std::max<size_t>(1, in.boundaries.size()));
  boundaries.upload(ctx, view(in.boundaries));
  Buffer<LloydStats> out(ctx, clusters);
  out.fill(ctx, {kPoison, kPoison, kPoison, 0xdeadbeef});
  reduceLloydStats(ctx, x, w, in.x.size(), boundaries, clusters, out);
  return out.download(ctx);
}

}  // namespace

// Counts exact, sums within the margin, and the same bits when run again (the reduction's order is fixed).
Measured checkLloyd(Context& ctx, const ref::ReduceCase& c) {
  const ref::LloydInputs in = ref::lloydInputs(c.count, c.clusters);
  const std::vector<LloydStats> actual = lloyd(ctx, in, c.clusters), again = lloyd(ctx, in, c.clusters);
  const std::vector<ref::LloydRef> expected = ref::lloydStats(in.x, in.w, in.boundaries);
  std::vector<uint32_t> counts, expectedCounts;
  std::vector<float> sums, sumsAgain;
  std::vector<double> expectedSums;
  for (size_t k = 0; k < actual.size() && k < expected.size(); ++k) {
    counts.push_back(actual[k].samples), expectedCounts.push_back(expected[k].samples);
    for (float v : {actual[k].sumW, actual[k].sumWX, actual[k].sumWX2}) sums.push_back(v);
    for (float v : {again[k].sumW, again[k].sumWX, again[k].sumWX2}) sumsAgain.push_back(v);
    for (double v : {expected[k].sumW, expected[k].sumWX, expected[k].sumWX2}) expectedSums.push_back(v);
  }
  Measured m{compareExact(counts, expectedCounts, counts.size())};
  if (actual.size() != expected.size()) m.comparison.mismatches += 1, m.comparison.report += "\n  cluster count";
  m.comparison.merge(ref::compare(view(sums), view(expectedSums), {0.0, ref::kLloydSumRelTol}), "sums");
  m.comparison.merge(
      compareExact(std::vector<uint32_t>(reinterpret_cast<const uint32_t*>(sumsAgain.data()),
                                         reinterpret_cast<const uint32_t*>(sumsAgain.data()) + sumsAgain.size()),
                   std::vector<uint32_t>(reinterpret_cast<const uint32_t*>(sums.data()),
                                         reinterpret_cast<const uint32_t*>(sums.data()) + sums.size()),
                   3),
      "second run's bits");
  return m;
}

namespace {
const char* layoutName(BlurLayout layout) { return layout == BlurLayout::Runs ? "runs" : "tiles"; }
}  // namespace

void addStageChecks(std::vector<Check>& out) {
  for (const ref::MomentsCase& c : ref::momentsCases())
    out.push_back(
        {"moments", c.name(), c.quick, [c](Context& ctx) { return checkMoments(ctx, c, MomentStorage::Float32); }});
  for (const ref::MomentsCase& c : ref::momentsCases())
    if (c.kind != MomentKind::Lvsm)  // LVSM stores 16-bit unorm or fp32, never half (moments.h)
      out.push_back({"moments", c.name() + "_half", c.quick,
                     [c](Context& ctx) { return checkMoments(ctx, c, MomentStorage::Float16); }});
  out.push_back({"moments", "msm_decode", true, [](Context& ctx) { return Measured{msmDecode(ctx)}; }});
  out.push_back({"moments", "pack_unorm16", true, [](Context& ctx) { return Measured{packUnorm16(ctx), "codes"}; }});
  for (const ref::MomentsReducedCase& c : ref::momentsReducedCases())
    out.push_back(
        {"moments", "reduced_" + c.name(), c.quick, [c](Context& ctx) { return checkMomentsReduced(ctx, c); }});
  for (const ref::BlurCase& c : ref::blurCases()) {
    if (planBlur(c.config).direct) {
      for (BlurLayout layout : {BlurLayout::Tiles, BlurLayout::Runs})
        out.push_back({"blur", c.name + "_" + layoutName(layout), c.quick,
                       [c, layout](Context& ctx) { return checkBlur(ctx, c, layout); }});
    } else {
      out.push_back({"blur", c.name, c.quick, [c](Context& ctx) { return checkBlur(ctx, c, BlurLayout::Auto); }});
    }
  }
  for (const ref::SatCase& c : ref::satCases())
    out.push_back({"sat", c.name, c.quick, [c](Context& ctx) { return checkSat(ctx, c); }});
  // Box lookups through the SAT probe (kernels/shared/sat.h), as savsm and vssm read their tables.
  out.push_back({"sat", "lookup_Fp32_c2", true, [](Context& ctx) { return Measured{satLookup<float>(ctx, 2)}; }});
  out.push_back({"sat", "lookup_Fixed32_c2", true, [](Context& ctx) { return Measured{satLookup<uint32_t>(ctx, 2)}; }});
  out.push_back({"sat", "lookup_Fixed64_c1", true, [](Context& ctx) { return Measured{satLookup<uint64_t>(ctx, 1)}; }});
  out.push_back({"sat", "lookup_Fp64_c2", false, [](Context& ctx) { return Measured{satLookup<double>(ctx, 2)}; }});
  for (const ref::PyramidCase& c : ref::momentMipCases())
    out.push_back({"pyramid", "mips_" + c.name(), c.quick, [c](Context& ctx) { return checkMomentMips(ctx, c); }});
  for (const ref::PyramidCase& c : ref::logMipCases())
    for (float exponent : ref::kLogMipExponents)
      out.push_back({"pyramid", fmt::format("log_mips_{}_c{}", c.name(), exponent), c.quick && exponent == 80.0f,
                     [c, exponent](Context& ctx) { return checkLogMips(ctx, c, exponent); }});
  for (const ref::PyramidCase& c : ref::minMaxCases()) {
    out.push_back({"pyramid", "minmax_" + c.name(), c.quick, [c](Context& ctx) { return checkMinMax(ctx, c); }});
    out.push_back(
        {"pyramid", "minmax_levels_" + c.name(), c.quick, [c](Context& ctx) { return checkMinMaxLevels(ctx, c); }});
  }
  for (const ref::ReduceCase& c : ref::reduceCases())
    out.push_back({"reduce", "lloyd_" + c.name(), c.quick, [c](Context& ctx) { return checkLloyd(ctx, c); }});
}

}  // namespace penumbra::selftest
