// Accuracy of a visibility image against a reference (`penumbra compare`, bench, stability tests): mean absolute,
// RMS and 95th-percentile error, the fraction of pixels off by more than 0.1, light leaking, false shadow and the
// mean signed error, over the pixels a coverage mask marks. Plain C++; the error is ours - reference.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "host/io/image.h"

namespace penumbra {

// The pixel classes the fractions count (named constants so bench and the README agree with the code).
inline constexpr double kOffThreshold = 0.1;      // |error| above this counts as "off"
inline constexpr double kLeakReference = 0.05;    // reference darker than this ...
inline constexpr double kLeakOurs = 0.5;          // ... but ours brighter than this: light leaking
inline constexpr double kShadowReference = 0.95;  // reference brighter than this ...
inline constexpr double kShadowOurs = 0.5;        // ... but ours darker than this: false shadow (acne, over-darkening)
inline constexpr double kUmbraReference = 0.02;   // reference darker than this: the umbra ...
inline constexpr double kUmbraOurs = 0.1;         // ... where ours is brighter than this: light in the umbra

struct ErrorMetrics {
  size_t pixels = 0;     // covered pixels where both values are finite: what every statistic is over
  size_t nonFinite = 0;  // covered pixels where either value is NaN or infinite (left out of the statistics)
  // All 0 when `pixels` is 0 (nothing to get wrong).
  double mae = 0;          // mean |e|
  double rmse = 0;         // sqrt(mean e^2)
  double p95 = 0;          // 95th percentile of |e|, nearest rank: the ceil(0.95 n)-th smallest
  double maxAbs = 0;       // max |e|
  double off = 0;          // fraction with |e| > kOffThreshold
  double leak = 0;         // fraction with reference < kLeakReference and ours > kLeakOurs
  double falseShadow = 0;  // fraction with reference > kShadowReference and ours < kShadowOurs
  // Of the umbra pixels only (reference < kUmbraReference; 0 when there are none), the fraction where ours >
  // kUmbraOurs: light let into the umbra, which `leak` (ours > 0.5) misses when the error is moderate.
  double umbraLight = 0;
  size_t umbraPixels = 0;  // covered pixels with reference < kUmbraReference
  double meanSigned = 0;   // mean e (> 0: ours too bright on average)
  // Mean |e| over the penumbra pixels only (reference strictly between 0 and 1; 0 when there are none): the error
  // where soft-shadow techniques differ, which the fully lit and umbra pixels every technique gets right dilute in
  // `mae`.
  double penumbraMae = 0;
  size_t penumbraPixels = 0;
};

// `coverage` may be empty (every pixel counts); else a pixel counts when coverage > 0. Throws
// std::invalid_argument when the spans differ in size.
ErrorMetrics computeErrorMetrics(std::span<const float> ours, std::span<const float> reference,
                                 std::span<const float> coverage = {});

// Per-pixel ours - reference where covered, 0 elsewhere (NaN stays NaN). Same size rules.
std::vector<float> signedError(std::span<const float> ours, std::span<const float> reference,
                               std::span<const float> coverage = {});

// Upper limits; a metric without one is not checked.
struct MetricThresholds {
  std::optional<double> mae, rmse, p95, maxAbs, off, leak, falseShadow, umbraLight, bias;  // bias: |meanSigned|
  std::optional<double> penumbraMae;
};

// One line per metric over its limit ("mae 0.031 > 0.02"); a non-finite pixel is always a failure. Empty: pass.
std::vector<std::string> exceededThresholds(const ErrorMetrics& metrics, const MetricThresholds& limits);

// The reference's receivability mask (`penumbra reference`): 1 where the point can receive direct light (the
// surface the camera sees faces the light's centre and, for a spot light, lies inside its cone), 0 where its
// visibility can never show in the shaded image.
inline constexpr const char* kLitChannel = "lit.Y";

// What two images are compared on: the channel both must have, the coverage channel and the mask channel (each
// taken from the reference, else from ours; neither has it: every pixel counts). A pixel counts when both are > 0.
struct CompareSpec {
  std::string channel = "visibility.Y";
  std::string coverage = "A";
  std::string mask = kLitChannel;  // empty: no mask
};

// The metrics of ours against reference. Throws std::runtime_error naming both images when their sizes differ
// or either lacks the channel.
ErrorMetrics compareImages(const Image& ours, const Image& reference, const CompareSpec& spec = {});

// The channel named `channel` of the reference, else of ours (empty span: neither has it, or `channel` is empty).
std::span<const float> coverageOf(const Image& ours, const Image& reference, const std::string& channel);

// The pixels compareImages() counts: coverage ∩ mask as 1/0 (empty: every pixel counts).
std::vector<float> comparedPixels(const Image& ours, const Image& reference, const CompareSpec& spec);

// Whether comparedPixels() applies a mask channel (spec.mask non-empty and present in either image).
bool hasMask(const Image& ours, const Image& reference, const CompareSpec& spec);

}  // namespace penumbra
