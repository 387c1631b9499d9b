#include "tools/selftest/vssm_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <variant>

#include "host/cl/kernel.h"
#include "kernels/shared/light_view.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/reference/vssm_ref.h"
#include "tools/selftest/selftest.h"

namespace penumbra::selftest {
namespace {

// Planar occluder blocks over a tilted floor, with holes: what shadow maps hold, plus NaN.
std::vector<float> randomMap(const VssmCase& c, std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float range = c.zFar - c.zNear;
  const bool logDepth = c.zFar / c.zNear > 1e4f;  // huge ranges: depths spread over every decade
  auto depthAt = [&](float s) { return logDepth ? c.zNear * std::pow(c.zFar / c.zNear, s) : c.zNear + s * range; };
  std::vector<float> map(size_t(c.width) * c.height);
  for (uint32_t y = 0; y < c.height; ++y)
    for (uint32_t x = 0; x < c.width; ++x)
      map[y * c.width + x] = depthAt(0.8f + 0.15f * float(x + y) / (c.width + c.height));
  for (int b = 0; b < 6; ++b) {  // planar blocks
    const uint32_t x0 = uint32_t(rng() % c.width), y0 = uint32_t(rng() % c.height);
    const uint32_t x1 = std::min(c.width, x0 + 1 + uint32_t(rng() % std::max(1u, c.width / 2)));
    const uint32_t y1 = std::min(c.height, y0 + 1 + uint32_t(rng() % std::max(1u, c.height / 2)));
    const float z = depthAt(0.1f + 0.6f * unit(rng));
    for (uint32_t y = y0; y < y1; ++y)
      for (uint32_t x = x0; x < x1; ++x) map[y * c.width + x] = z;
  }
  for (float& z : map) {
    const float u = unit(rng);
    if (u < c.holes / 2)
      z = INFINITY;
    else if (u < c.holes)
      z = NAN;
    else if (u < c.holes + 0.03f)
      z = depthAt(unit(rng));  // isolated noise texels
  }
  return map;
}

// Half anywhere in front of the far plane, half on the map's own surfaces (where camera pixels are).
std::vector<ref::VssmReceiverIn> randomReceivers(const VssmCase& c, const std::vector<float>& map, std::mt19937& rng,
                                                 size_t count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<ref::VssmReceiverIn> out(count);
  const double range = c.zFar - c.zNear;
  for (size_t i = 0; i < count; ++i) {
    ref::VssmReceiverIn& r = out[i];
    r.u = -3.0 + unit(rng) * (c.width + 6.0), r.v = -3.0 + unit(rng) * (c.height + 6.0);
    r.depth = c.zNear + range * (0.3 + 0.7 * unit(rng));
    const int x = int(std::floor(r.u)), y = int(std::floor(r.v));
    const bool inside = x >= 0 && y >= 0 && x < int(c.width) && y < int(c.height);
    if (i % 2 == 1 && inside && std::isfinite(map[size_t(y) * c.width + x]))
      r.depth = map[size_t(y) * c.width + x] * (1.0 + 1e-4 * unit(rng));
    r.bias = range * 2e-3 * unit(rng), r.biasSlope = range * (c.steep && i % 3 == 2 ? 2e-2 : 1e-4) * unit(rng);
    r.seed = static_cast<uint32_t>(i);
  }
  return out;
}

ref::VssmSettings settingsFor(const VssmCase& c) {
  ref::VssmSettings s;
  s.searchScheme = c.searchScheme, s.shadeScheme = c.shadeScheme;
  s.m = 5, s.n = 6, s.levels = 3, s.leafTaps = 2;
  s.planarMaxLit = 0.9;
  s.diskStrips = c.diskStrips;
  s.stackedSpread = c.stacked, s.stackedTaps = 8;
  s.searchNarrowings = c.narrowings;
  s.satReduce = c.satReduce;
  s.firstMoment = c.firstMoment;
  s.tiltShare = c.tilt;
  s.litVariance = 2.5e-5, s.contactDepth = 0.02 * (c.zFar - c.zNear), s.maxRadius = 24, s.minVariance = 1e-6;
  return s;
}

LightViewGpu lightFor(const VssmCase& c) {
  LightViewGpu lv{};
  lv.kind = c.spot ? LIGHT_KIND_SPOT : LIGHT_KIND_DIRECTIONAL;
  lv.lightSize = c.spot ? 0.05f * (c.zFar - c.zNear) : 0.08f;
  lv.texelScale = c.spot ? 2.0f / c.width : 0.01f * (c.zFar - c.zNear);
  lv.zNear = c.zNear, lv.zFar = c.zFar;
  lv.width = static_cast<int>(c.width), lv.height = static_cast<int>(c.height);
  return lv;
}

struct KernelOut {
  std::vector<float> visibility;
  std::vector<cl_float4> debug;
};

KernelOut runKernel(Context& ctx, const VssmCase& c, const std::vector<float>& map, const ref::VssmSettings& s,
                    const std::vector<ref::VssmReceiverIn>& receivers) {
  const LightViewGpu lv = lightFor(c);
  Buffer<float> depth(ctx, std::span<const float>(map));
  Buffer<LightViewGpu> lvBuffer(ctx, std::span<const LightViewGpu>(&lv, 1), CL_MEM_READ_ONLY);
  VssmMaps maps;
  maps.build(ctx, depth, c.width, c.height, c.zNear, c.zFar,
             {c.sat, float(s.maxRadius), uint32_t(s.levels), uint32_t(s.satReduce), TexelWindow{}});
  VssmParams p{};
  p.depthNear = maps.depthNear(), p.depthInvRange = maps.depthInvRange();
  p.litVariance = float(s.litVariance), p.contactDepth = float(s.contactDepth), p.maxRadius = float(s.maxRadius);
  p.minVariance = float(s.minVariance);
  p.searchScheme = uint32_t(s.searchScheme), p.shadeScheme = uint32_t(s.shadeScheme);
  p.searchDivisions = uint32_t(s.m), p.shadeDivisions = uint32_t(s.n), p.leafTaps = uint32_t(s.leafTaps);
  p.nodeCount = maps.nodeCount(), p.pyramidLevels = maps.levelCount();
  p.planarMaxLit = float(s.planarMaxLit);
  p.diskStrips = uint32_t(s.diskStrips);
  p.stackedSpread = float(s.stackedSpread), p.stackedTaps = uint32_t(s.stackedTaps);
  p.searchNarrowings = uint32_t(s.searchNarrowings);
  p.satReduce = maps.satReduce();
  p.firstMoment = s.firstMoment ? 1u : 0u;
  p.tiltShare = float(s.tiltShare);
  p.satX = maps.window().x, p.satY = maps.window().y;
  p.satWidth = maps.window().width, p.satHeight = maps.window().height;
  std::vector<cl_float4> rx(receivers.size());
  std::vector<float> slopes(receivers.size());
  for (size_t i = 0; i < receivers.size(); ++i) {
    const ref::VssmReceiverIn& r = receivers[i];
    rx[i] = {{float(r.u), float(r.v), float(r.depth), float(r.bias)}};
    slopes[i] = float(r.biasSlope);
  }
  const uint32_t count = static_cast<uint32_t>(receivers.size());
  Buffer<cl_float4> rxBuffer(ctx, std::span<const cl_float4>(rx)), debug(ctx, count);
  Buffer<float> slopeBuffer(ctx, std::span<const float>(slopes)), visibility(ctx, count);
  visibility.fill(ctx, ref::kPoison);
  Kernel kernel(ctx, "tools/selftest/kernels/vssm_probe.cl", "vssm_visibility_receivers", "vssm", maps.buildOptions());
  std::visit(
      [&](const auto& sat) {
        kernel
            .args(rxBuffer, slopeBuffer, count, depth, lvBuffer, sat, maps.satDesc(), maps.satOffset(), maps.hsm(),
                  maps.levels(), maps.nodes(), maps.diskStrips(), p, debug, visibility)
            .launch(count, 64);
      },
      maps.sat());
  return {visibility.download(ctx), debug.download(ctx)};
}

}  // namespace

std::vector<VssmCase> vssmCases() {
  constexpr int kU = VSSM_SCHEME_UNIFORM, kA = VSSM_SCHEME_ADAPTIVE, kN = VSSM_SCHEME_NONE;
  constexpr VssmSatMode k64 = VssmSatMode::Fixed64;
  constexpr double kTol = kVssmVisTol;
  std::vector<VssmCase> out = {
      {"mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA},
      {"uniform_64x64", 64, 64, 2.0f, 12.0f, kU, kU},
      {"adaptive_64x64", 64, 64, 2.0f, 12.0f, kA, kA},
      {"none_45x45", 45, 45, 2.0f, 12.0f, kN, kN},
      {"mixed_1x1", 1, 1, 2.0f, 12.0f, kU, kA},
      {"mixed_200x3", 200, 3, 2.0f, 12.0f, kU, kA},
      {"mixed_huge_range", 53, 47, 0.01f, 1e6f, kU, kA},
      {"mixed_no_holes", 64, 48, 2.0f, 12.0f, kU, kA, k64, true, 0.0f},
      {"mixed_mostly_holes", 40, 40, 2.0f, 12.0f, kU, kA, k64, true, 0.6f},
      {"mixed_directional", 50, 50, 5.0f, 25.0f, kU, kA, k64, false},
      {"mixed_fixed32", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed32, true, 0.05f, 2e-2},
      {"mixed_fp32", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Float32, true, 0.05f, 2e-2},
      {"mixed_fp64", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Float64},
      {"disk8_mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 8},
      {"disk4_uniform_64x64", 64, 64, 2.0f, 12.0f, kU, kU, k64, true, 0.05f, kTol, 4},
      {"disk16_adaptive_64x64", 64, 64, 2.0f, 12.0f, kA, kA, k64, true, 0.05f, kTol, 16},
      {"disk8_none_45x45", 45, 45, 2.0f, 12.0f, kN, kN, k64, true, 0.05f, kTol, 8},
      {"disk8_mixed_1x1", 1, 1, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 8},
      {"disk8_directional", 50, 50, 5.0f, 25.0f, kU, kA, k64, false, 0.05f, kTol, 8},
      {"mixed_no_stacked_fallback", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 0, 0.0},
      {"mixed_full_search", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 0, 0.1, 0},
      {"disk8_full_search", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 8, 0.1, 0},
      // The SAT over blocks: 2 and 4 (vssm-sat-reduce auto's), 3 on sizes it does not divide, fixed32's bits.
      {"reduce2_disk8_mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 8, 0.1, 2, 2},
      {"reduce4_mixed_64x64", 64, 64, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 0, 0.1, 2, 4},
      {"reduce3_disk8_uniform_50x47", 50, 47, 2.0f, 12.0f, kU, kU, k64, true, 0.05f, kTol, 8, 0.1, 2, 3},
      {"reduce2_disk8_fixed32", 48, 48, 2.0f, 12.0f, kU, kA, VssmSatMode::Fixed32, true, 0.05f, 2e-2, 8, 0.1, 2, 2},
      {"reduce4_disk8_directional", 50, 50, 5.0f, 25.0f, kU, kA, k64, false, 0.05f, kTol, 8, 0.1, 2, 4},
      {"reduce2_mixed_1x1", 1, 1, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 8, 0.1, 2, 2},
      // Chebyshev's bound alone (--vssm-first-moment off, the paper's shading).
      {"chebyshev_mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 0, 0.1, 2, 1, false},
      {"chebyshev_reduce2_disk8_directional", 50, 50, 5.0f, 25.0f, kU, kA, k64, false, 0.05f, kTol, 8, 0.1, 2, 2,
       false},
      // Receivers on planes steep in the map: the tilted receivers' taps (--vssm-tilt), and without them.
      {"tilted_disk8_mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 8, 0.1, 2, 1, true, 0.05, true},
      {"tilted_reduce2_directional", 50, 50, 5.0f, 25.0f, kU, kA, k64, false, 0.05f, kTol, 0, 0.1, 2, 2, true, 0.05,
       true},
      {"untilted_disk8_mixed_61x37", 61, 37, 2.0f, 12.0f, kU, kA, k64, true, 0.05f, kTol, 8, 0.1, 2, 1, true, 0.0,
       true}};
  // Quick: the defaults' shape (adaptive shading, disks, the SAT over blocks) and the paper's uniform subdivision.
  for (VssmCase& c : out) c.quick = c.name == "mixed_61x37" || c.name == "reduce2_disk8_mixed_61x37";
  return out;
}

std::string VssmOutcome::failure(const VssmCase& c) const {
  std::string out;
  const double n = double(receivers);
  if (outOfRange != 0) out += fmt::format("; {} visibilities outside [0, 1]", outOfRange);
  if (paths > kVssmMaxPathShare * n) out += fmt::format("; {} of {} receivers took another path", paths, receivers);
  if (meanDifference > kVssmMeanVisTol)
    out += fmt::format("; mean |difference| {:.3g} > {}", meanDifference, kVssmMeanVisTol);
  if (c.searchScheme != VSSM_SCHEME_NONE && c.width * c.height > 1 && subdivided == 0)
    out += "; no receiver took the subdivision path";
  // Over a huge depth range (the map's depths spread over every decade) the casters nearest the light have cones that
  // span the map: every node can hold a blocker there.
  const bool hugeRange = c.zFar / c.zNear > 1e4f;
  const bool noBlockerTested =
      c.searchScheme != VSSM_SCHEME_NONE && c.narrowings > 0 && c.width * c.height > 1 && !hugeRange;
  if (noBlockerTested && noBlocker == 0) out += "; no receiver's search was ended by the HSM's no-blocker test";
  // Receivers on surfaces tilted to the light: their own texels fail a coarse node's test and pass their own.
  if (noBlockerTested && descents == 0) out += "; no receiver's no-blocker test descended below its first level";
  // The random maps' blocks overlap at several depths: some penumbra kernels hold stacked blockers.
  if (c.stacked > 0 && c.width * c.height > 1 && stacked == 0) out += "; no receiver took the stacked-blocker fallback";
  if (c.stacked == 0 && stacked != 0) out += fmt::format("; {} receivers took the fallback switched off", stacked);
  if (c.tilt > 0 && c.steep && tilted == 0) out += "; no steep receiver took the tilted receivers' taps";
  if (c.tilt == 0 && tilted != 0) out += fmt::format("; {} receivers took the tilted taps switched off", tilted);
  return out.empty() ? out : out.substr(2) + report;
}

VssmOutcome runVssmCase(Context& ctx, const VssmCase& c) {
  if (c.sat == VssmSatMode::Float64 && !ctx.info().fp64) throw NotApplicable("fp64 tables need cl_khr_fp64");
  std::mt19937 rng(c.width * 131 + c.height * 7 + c.searchScheme * 3 + c.shadeScheme);
  const std::vector<float> map = randomMap(c, rng);
  const std::vector<ref::VssmReceiverIn> receivers = randomReceivers(c, map, rng, 600);
  const ref::VssmSettings settings = settingsFor(c);
  const KernelOut got = runKernel(ctx, c, map, settings, receivers);
  ref::VssmLight light;
  const LightViewGpu lv = lightFor(c);
  light.spot = c.spot, light.lightSize = lv.lightSize, light.texelScale = lv.texelScale;
  light.zNear = c.zNear, light.zFar = c.zFar;
  const ref::VssmReference reference(map, c.width, c.height, light, settings);
  VssmOutcome o;
  o.receivers = receivers.size();
  double sum = 0.0;
  for (size_t i = 0; i < receivers.size(); ++i) {
    const ref::VssmResult want = reference.pixel(receivers[i]);
    const float vis = got.visibility[i];
    if (!(vis >= 0.0f && vis <= 1.0f)) {
      ++o.outOfRange;
      continue;
    }
    const double diff = std::abs(vis - want.visibility);
    sum += diff, o.worstDifference = std::max(o.worstDifference, diff);
    o.subdivided += want.path == VSSM_PATH_SUBDIVIDED;
    o.stacked += want.path == VSSM_PATH_STACKED;
    o.tilted += want.path == VSSM_PATH_TILTED;
    o.noBlocker += want.path == VSSM_PATH_NO_BLOCKER && want.visited == 0;
    if (diff > c.visTol && ++o.flips <= 5)
      o.report += fmt::format("\n  receiver {} ({:.3f}, {:.3f}, d {:.4g}): {} vs {} (paths {} / {})", i, receivers[i].u,
                              receivers[i].v, receivers[i].depth, vis, want.visibility, got.debug[i].s[3], want.path);
    o.paths += int(got.debug[i].s[3]) != want.path;
  }
  o.descents = reference.descents();
  o.meanDifference = sum / double(std::max<size_t>(1, receivers.size()));
  return o;
}

void addVssmChecks(std::vector<Check>& out) {
  for (const VssmCase& c : vssmCases())
    out.push_back({"vssm", c.name, c.quick, [c](Context& ctx) {
                     const VssmOutcome o = runVssmCase(ctx, c);
                     // The error is the mean |difference| against its margin; a failure of the suite's other criteria
                     // (visibility range, paths, the subdivision and stacked-blocker paths taken) is a mismatch.
                     Measured m;
                     m.comparison.count = o.receivers;
                     m.comparison.worstError = o.meanDifference, m.comparison.worstAllowed = kVssmMeanVisTol;
                     const std::string failure = o.failure(c);
                     if (!failure.empty()) m.comparison.mismatches = 1, m.comparison.report = "\n  " + failure;
                     m.unit = "mean |visibility difference|";
                     return m;
                   }});
}

}  // namespace penumbra::selftest
