#include "tools/selftest/probe_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <type_traits>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "host/stages/moments.h"
#include "host/stages/sat.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/moments_ref.h"
#include "tools/selftest/reference/sat_ref.h"
#include "tools/selftest/selftest.h"

namespace penumbra::selftest {
namespace {

struct Box {
  float lox, loy, hix, hiy;
};

std::vector<Box> makeBoxes(const ImageShape& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-3.0f, float(std::max(s.width, s.height)) + 3.0f), extent(0.0f, 25.0f);
  const float w = float(s.width), h = float(s.height);
  std::vector<Box> boxes = {
      {0, 0, w, h}, {2, 3, 3, 4}, {1.5f, 2.25f, 1.5f, 9.0f}, {-9, -9, -1, -1}, {w + 1, 0, w + 5, h}};
  for (int i = 0; i < 200; ++i) {
    const float x = pos(rng), y = pos(rng);
    boxes.push_back({x, y, x + extent(rng), y + extent(rng)});
  }
  return boxes;
}

// One value against its reference within an absolute margin, as a comparison of one element.
ref::Comparison near(double actual, double expected, double margin, const std::string& what) {
  ref::Comparison c =
      ref::compare(std::span<const double>(&actual, 1), std::span<const double>(&expected, 1), {margin, 0.0});
  if (!c.pass()) c.report = fmt::format("\n  {}: {} vs expected {} (margin {})", what, actual, expected, margin);
  return c;
}

}  // namespace

template <class T>
ref::Comparison satLookup(Context& ctx, uint32_t channels) {
  if (std::is_same_v<T, double> && !ctx.info().fp64) throw NotApplicable("fp64 tables need cl_khr_fp64");
  const ImageShape shape{61, 47, channels};
  const std::vector<float> image = ref::satImage(shape, ref::SatInput::Random, 77 + channels);
  Buffer<float> in(ctx, std::span<const float>(image)), offset(ctx, 4);
  Buffer<T> table(ctx, shape.count());
  computeSat(ctx, in, shape, table, offset);
  const SatTableDesc desc = satDesc(shape, satMode<T>());
  const std::vector<Box> boxes = makeBoxes(shape, channels);
  Buffer<cl_float4> boxBuffer(ctx, boxes.size());
  boxBuffer.upload(ctx, std::span<const cl_float4>(reinterpret_cast<const cl_float4*>(boxes.data()), boxes.size()));
  Buffer<float> sums(ctx, boxes.size() * channels), means(ctx, boxes.size() * channels);
  sums.fill(ctx, ref::kPoison);
  means.fill(ctx, ref::kPoison);
  Kernel(ctx, "tools/selftest/kernels/sat_probe.cl", "sat_test_box", "sat", satBuildOptions(desc))
      .args(table, desc, offset, boxBuffer, uint32_t(boxes.size()), sums, means)
      .launch(boxes.size(), 64);
  const std::vector<float> actualSums = sums.download(ctx), actualMeans = means.download(ctx);
  const std::vector<float> off = offset.download(ctx);
  const std::array<double, 4> used{off[0], off[1], off[2], off[3]};
  const double tableTol = std::is_integral_v<T>
                              ? 0.0
                              : ref::satTableTolerance(shape, std::is_same_v<T, float> ? FLT_EPSILON : DBL_EPSILON,
                                                       ref::satMagnitude(image, used, channels));
  ref::Comparison c;
  for (size_t b = 0; b < boxes.size(); ++b) {
    const Box& box = boxes[b];
    const std::array<double, 4> exact = ref::boxIntegral(image, shape, box.lox, box.loy, box.hix, box.hiy);
    const double ax = std::clamp<double>(box.lox, 0, shape.width), bx = std::clamp<double>(box.hix, ax, shape.width);
    const double ay = std::clamp<double>(box.loy, 0, shape.height), by = std::clamp<double>(box.hiy, ay, shape.height);
    const double area = (bx - ax) * (by - ay), covered = (std::ceil(bx - ax) + 1) * (std::ceil(by - ay) + 1);
    const double quantum = std::is_integral_v<T> ? std::ldexp(0.5, -int(std::log2(desc.scale))) : 0.0;
    for (uint32_t ch = 0; ch < channels; ++ch) {
      const double tol = 4.0 * tableTol + quantum * covered + kSatLookupRelTol * (std::abs(exact[ch]) + covered);
      c.merge(near(actualSums[b * channels + ch], exact[ch], tol, fmt::format("box {} channel {} sum", b, ch)));
      const double mean = area > 0 ? exact[ch] / area : 0.0;
      c.merge(near(actualMeans[b * channels + ch], mean, area > 0 ? tol / area : 0.0,
                   fmt::format("box {} channel {} mean", b, ch)));
    }
  }
  return c;
}

template ref::Comparison satLookup<float>(Context&, uint32_t);
template ref::Comparison satLookup<uint32_t>(Context&, uint32_t);
template ref::Comparison satLookup<uint64_t>(Context&, uint32_t);
template ref::Comparison satLookup<double>(Context&, uint32_t);

ref::Comparison msmDecode(Context& ctx) {
  constexpr int kCount = 257;
  std::vector<cl_float4> encoded(kCount);
  std::vector<double> expected;
  for (int i = 0; i < kCount; ++i) {
    const double d = double(i) / (kCount - 1);
    double q[4];
    ref::msmEncode(d, q);
    encoded[i] = {{float(q[0]), float(q[1]), float(q[2]), float(q[3])}};
    for (int k = 1; k <= 4; ++k) expected.push_back(std::pow(d, k));
  }
  Buffer<cl_float4> in(ctx, std::span<const cl_float4>(encoded)), out(ctx, kCount);
  Kernel(ctx, "tools/selftest/kernels/moments_probe.cl", "moments_msm_decode_test", "moments")
      .args(in, out, uint32_t(kCount))
      .launch(kCount, 64);
  const std::vector<cl_float4> decoded = out.download(ctx);
  return ref::compare(std::span<const float>(&decoded[0].s[0], kCount * 4), std::span<const double>(expected),
                      {ref::kMsmRoundTripTol, 0.0}, 4);
}

ref::Comparison packUnorm16(Context& ctx) {
  std::vector<float> values = {0.0f,
                               1.0f,
                               -0.5f,
                               2.0f,
                               std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity(),
                               0.5f / 65535.0f,
                               1.0f / 65535.0f,
                               65534.5f / 65535.0f};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 997; ++i) values.push_back(unit(rng));
  const size_t offset = 5;
  Buffer<float> in(ctx, std::span<const float>(values));
  Buffer<cl_ushort> out(ctx, values.size() + offset);
  out.fill(ctx, 0xBEEF);
  packMomentsUnorm16(ctx, in, values.size(), out, offset);
  const std::vector<cl_ushort> codes = out.download(ctx);
  std::vector<double> got, expected;
  int exact = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    got.push_back(codes[offset + i]), expected.push_back(ref::unorm16(values[i]));
    exact += got.back() == expected.back();
  }
  ref::Comparison c = ref::compare(std::span<const double>(got), std::span<const double>(expected), {1.0, 0.0});
  c.merge(ref::compare(std::span<const double>(got.data(), 7), std::span<const double>(expected.data(), 7), {}),
          "values without ties");
  const std::vector<double> before(codes.begin(), codes.begin() + offset), untouched(offset, 0xBEEF);
  c.merge(ref::compare(std::span<const double>(before), std::span<const double>(untouched), {}), "before the offset");
  if (exact < static_cast<int>(values.size()) - 5)
    c.mismatches += 1, c.report += fmt::format("\n  {} of {} codes exact", exact, values.size());
  return c;
}

}  // namespace penumbra::selftest
