#include "tools/selftest/reference/cases.h"

#include <fmt/format.h>

#include <tuple>

namespace penumbra::ref {

const char* momentKindName(MomentKind kind) {
  static const char* const kNames[] = {"Vsm", "Evsm2", "Evsm4", "Lvsm", "Msm", "Esm"};
  return kNames[int(kind)];
}

std::string MomentsCase::name() const {
  return fmt::format("{}_{}x{}{}", momentKindName(kind), width, height, constant ? "_constant" : "");
}

std::vector<MomentsCase> momentsCases() {
  std::vector<MomentsCase> out;
  for (MomentKind kind :
       {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Lvsm, MomentKind::Msm, MomentKind::Esm})
    for (auto [w, h, constant] : {std::tuple{1u, 1u, false}, {97u, 61u, false}, {64u, 32u, false}, {13u, 7u, true}})
      out.push_back({kind, w, h, constant, w == 97});
  return out;
}

MomentsConfig momentsCaseConfig(MomentKind kind) {
  MomentsConfig c;
  c.kind = kind;
  c.depthNear = kMomentsCaseNear;
  c.depthFar = kMomentsCaseFar;
  c.evsmPositive = 100.0f;  // clamped to 42: the worst case for the fp32 range
  c.evsmNegative = 7.5f;
  c.layers = {{0.0f, 0.3f}, {0.25f, 0.6f}, {0.55f, 1.0f}};
  return c;
}

std::string MomentsReducedCase::name() const {
  return fmt::format("{}_{}x{}_by{}", momentKindName(kind), width, height, factor);
}

std::vector<MomentsReducedCase> momentsReducedCases() {
  std::vector<MomentsReducedCase> out;
  for (MomentKind kind : {MomentKind::Vsm, MomentKind::Evsm2, MomentKind::Evsm4, MomentKind::Msm, MomentKind::Esm})
    for (auto [w, h, f] : {std::tuple{64u, 32u, 2u},
                           {97u, 61u, 2u},
                           {97u, 61u, 4u},
                           {97u, 61u, 3u},
                           {1u, 1u, 4u},
                           {50u, 7u, 8u},
                           {64u, 48u, 8u},
                           {13u, 7u, 1u}})
      out.push_back({kind, w, h, f, w == 97 && f == 4 && (kind == MomentKind::Vsm || kind == MomentKind::Evsm4)});
  return out;
}

BlurConfig gaussianBlur(float sigma, float scale, BlurMethod method) {
  return {BlurFilter::Gaussian, sigma, 0, scale, method};
}
BlurConfig boxBlur(int radius, BlurMethod method) { return {BlurFilter::Box, 0.0f, radius, 1.0f, method}; }

std::vector<BlurCase> blurCases() {
  return {
      {"Gauss1p5_97x61_c1", 97, 61, 1, gaussianBlur(1.5f)},
      {"Gauss1p5_97x61_c2", 97, 61, 2, gaussianBlur(1.5f), BlurInput::Random, true},
      {"Gauss1p5_97x61_c4", 97, 61, 4, gaussianBlur(1.5f)},
      {"Gauss10_97x61_c2", 97, 61, 2, gaussianBlur(10.0f)},
      {"Gauss2_scale2_3x200_c2", 3, 200, 2, gaussianBlur(2.0f, 2.0f)},
      {"Gauss0_identity_5x4_c1", 5, 4, 1, gaussianBlur(0.0f)},
      {"Gauss14_boxes_97x61_c1", 97, 61, 1, gaussianBlur(14.0f), BlurInput::Random, true},
      {"Gauss40_boxes_300x2_c2", 300, 2, 2, gaussianBlur(40.0f)},
      {"Box3_1x1_c2", 1, 1, 2, boxBlur(3)},
      {"Box7_256x3_c1", 256, 3, 1, boxBlur(7)},
      {"Box40_running_97x61_c2", 97, 61, 2, boxBlur(40)},
      {"Box5_running_130x70_c4", 130, 70, 4, boxBlur(5, BlurMethod::RunningSums)},
      {"Box100_direct_40x9_c1", 40, 9, 1, boxBlur(100, BlurMethod::Direct)},
      {"Box33_constant_61x67_c4", 61, 67, 4, boxBlur(33), BlurInput::Constant},
      {"Gauss2_hugerange_50x37_c1", 50, 37, 1, gaussianBlur(2.0f), BlurInput::HugeRange},
  };
}

namespace {

const char* satAlgorithmName(SatAlgorithm algorithm) {
  return algorithm == SatAlgorithm::Tiled   ? "Tiled"
         : algorithm == SatAlgorithm::Lines ? "Lines"
         : algorithm == SatAlgorithm::Auto  ? "Auto"
                                            : "Hensley";
}

}  // namespace

std::vector<SatCase> satCases() {
  struct Size {
    uint32_t w, h;
  };
  const Size sizes[] = {{1, 1}, {97, 61}, {64, 64}, {33, 130}, {300, 5}};
  const std::pair<uint32_t, uint32_t> modes[] = {
      {SAT_MODE_FP32, 2}, {SAT_MODE_FIXED32, 2}, {SAT_MODE_FIXED64, 1}, {SAT_MODE_FP64, 2}};
  const char* modeNames[] = {"Fp32", "Fixed32", "Fixed64", "Fp64"};
  std::vector<SatCase> out;
  for (auto [mode, channels] : modes)
    for (SatAlgorithm algorithm : {SatAlgorithm::Tiled, SatAlgorithm::Lines, SatAlgorithm::Hensley})
      for (Size s : sizes) {
        SatCase c{fmt::format("{}_{}_{}x{}_c{}", modeNames[mode], satAlgorithmName(algorithm), s.w, s.h, channels),
                  s.w,
                  s.h,
                  channels,
                  mode,
                  algorithm};
        c.quick = s.w == 97 && algorithm != SatAlgorithm::Hensley;
        out.push_back(c);
      }
  // Adversarial inputs and the other channel counts, tiled (the production path); and the line scans' fixed-point
  // rows, which convert 16 floats at a time (a chunk of 16, 8 or 4 texels) and the rest one by one: VSSM's
  // two-channel fixed64 table, four channels, and widths around the chunk.
  out.push_back({"Fp32_Tiled_97x61_c1_raw", 97, 61, 1, SAT_MODE_FP32, SatAlgorithm::Tiled, SatInput::Random, false});
  struct Adversarial {
    uint32_t w, h, channels, mode;
    SatAlgorithm algorithm;
    SatInput input;
  };
  const char* inputNames[] = {"random", "constant", "hugerange", "nonfinite"};
  constexpr SatAlgorithm kTiled = SatAlgorithm::Tiled, kLines = SatAlgorithm::Lines;
  for (const Adversarial& a : {Adversarial{45, 70, 4, SAT_MODE_FP32, kTiled, SatInput::Constant},
                               {97, 61, 1, SAT_MODE_FP32, kTiled, SatInput::HugeRange},
                               {97, 61, 2, SAT_MODE_FP32, kTiled, SatInput::NonFinite},
                               {50, 40, 2, SAT_MODE_FP32, SatAlgorithm::Hensley, SatInput::NonFinite},
                               {97, 61, 2, SAT_MODE_FIXED32, kTiled, SatInput::HugeRange},
                               {97, 61, 2, SAT_MODE_FIXED32, kTiled, SatInput::NonFinite},
                               {70, 45, 1, SAT_MODE_FIXED64, kTiled, SatInput::NonFinite},
                               {61, 97, 2, SAT_MODE_FP64, kTiled, SatInput::HugeRange},
                               {97, 61, 2, SAT_MODE_FIXED64, kLines, SatInput::NonFinite},
                               {45, 70, 4, SAT_MODE_FIXED64, kLines, SatInput::HugeRange},
                               {17, 9, 1, SAT_MODE_FIXED32, kLines, SatInput::NonFinite},
                               {16, 3, 2, SAT_MODE_FIXED32, kLines, SatInput::HugeRange}})
    out.push_back({fmt::format("{}_{}_{}x{}_c{}_{}", modeNames[a.mode], satAlgorithmName(a.algorithm), a.w, a.h,
                               a.channels, inputNames[static_cast<int>(a.input)]),
                   a.w, a.h, a.channels, a.mode, a.algorithm, a.input});
  // One large case per mode family: fp32 (zero mean) and 32-bit fixed point.
  out.push_back({"Fp32_Tiled_2048x2048_c2", 2048, 2048, 2, SAT_MODE_FP32});
  out.push_back({"Fixed32_Tiled_2048x2048_c1", 2048, 2048, 1, SAT_MODE_FIXED32});
  return out;
}

std::string PyramidCase::name() const { return fmt::format("{}x{}_c{}", width, height, channels); }

std::vector<PyramidCase> momentMipCases() {
  return {{1, 1, 2, false},   {97, 61, 2, true},  {64, 64, 1, false}, {2, 17, 4, false},
          {300, 1, 1, false}, {1, 300, 2, false}, {45, 23, 4, false}, {1021, 3, 4, false}};
}

std::vector<PyramidCase> minMaxCases() {
  // 128x64 and 480x68: the CPU rows schedule's two-level launches (widths multiples of 32, heights of 4), the second
  // then down to odd sizes.
  return {{1, 1, 1, false},  {97, 61, 1, true},   {128, 64, 1, false}, {480, 68, 1, false},
          {3, 41, 1, false}, {1021, 3, 1, false}, {13, 9, 0, false}};
}

std::vector<PyramidCase> logMipCases() {
  return {{1, 1, 1, false},   {97, 61, 1, true},  {64, 64, 1, false},
          {300, 1, 1, false}, {1, 300, 1, false}, {1021, 3, 1, false}};
}

std::string ReduceCase::name() const { return fmt::format("n{}_k{}", count, clusters); }

std::vector<ReduceCase> reduceCases() {
  // 4099 samples: five work-groups, the last one short (quick: Oclgrind simulates every work-item).
  return {{1, 1, false},       {1000, 3, false},          {4099, 5, true},
          {100003, 16, false}, {65536 * 5 + 7, 4, false}, {0, 2, false}};
}

}  // namespace penumbra::ref
