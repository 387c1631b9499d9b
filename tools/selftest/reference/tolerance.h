// The named margins every kernel is checked with, and the one element-wise comparison: the test suite
// (tests/support/compare.h) and `penumbra selftest` (tools/selftest/) take them from here, so that a device the user
// runs the selftest on is held to exactly the margins the suite holds PoCL to. Each margin says where it comes from.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

#include "host/stages/image_shape.h"
#include "host/stages/moments.h"

namespace penumbra::ref {

// An element passes when |a - e| <= abs + rel * |e|, or both are NaN and NaNs are allowed to match; infinities must
// be equal.
struct Tolerance {
  double abs = 0.0;
  double rel = 0.0;
  bool nanMatchesNan = false;  // true: expected NaN must be NaN; false: any NaN fails
};

// The outcome of comparing one output with its reference: how many elements failed, the element whose error is the
// largest share of what its margin allows (its error and its margin), and the first few failures with their indices.
struct Comparison {
  size_t count = 0, mismatches = 0;
  double worstError = 0.0;        // |a - e| of the worst element (infinite where a NaN or infinity mismatched)
  double worstAllowed = 0.0;      // abs + rel |e| there
  double worstFiniteError = 0.0;  // the largest finite |a - e| among the failures
  std::string report;             // up to 8 failures, "\n  (x, y): a vs expected e"
  bool pass() const { return mismatches == 0; }
  // Folds another output's comparison into this one (a check of several outputs or levels).
  void merge(const Comparison& other, const std::string& label = {});
};

template <class A, class E>
Comparison compare(std::span<const A> actual, std::span<const E> expected, Tolerance tol, size_t width = 0) {
  Comparison out;
  out.count = actual.size();
  if (actual.size() != expected.size()) {
    out.mismatches = std::max<size_t>(1, std::max(actual.size(), expected.size()));
    out.worstError = std::numeric_limits<double>::infinity();
    out.report = fmt::format("\n  size {} != expected {}", actual.size(), expected.size());
    return out;
  }
  double worstShare = -1.0;
  for (size_t i = 0; i < actual.size(); ++i) {
    const double a = static_cast<double>(actual[i]), e = static_cast<double>(expected[i]);
    const double allowed = tol.abs + tol.rel * std::abs(e);
    double error;
    bool ok;
    if (std::isnan(e) || std::isnan(a)) {
      ok = tol.nanMatchesNan && std::isnan(e) && std::isnan(a);
      error = ok ? 0.0 : std::numeric_limits<double>::infinity();
    } else if (std::isinf(e) || std::isinf(a)) {
      ok = a == e;
      error = ok ? 0.0 : std::numeric_limits<double>::infinity();
    } else {
      error = std::abs(a - e);
      ok = error <= allowed;
    }
    const double share = allowed > 0.0 ? error / allowed : error > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
    if (share > worstShare) worstShare = share, out.worstError = error, out.worstAllowed = allowed;
    if (!ok) {
      if (std::isfinite(error)) out.worstFiniteError = std::max(out.worstFiniteError, error);
      if (++out.mismatches <= 8)
        out.report += width != 0 ? fmt::format("\n  ({}, {}): {} vs expected {}", i % width, i / width, a, e)
                                 : fmt::format("\n  [{}]: {} vs expected {}", i, a, e);
    }
  }
  return out;
}

inline void Comparison::merge(const Comparison& other, const std::string& label) {
  const double share = worstAllowed > 0.0 ? worstError / worstAllowed : worstError > 0.0 ? INFINITY : 0.0;
  const double otherShare = other.worstAllowed > 0.0 ? other.worstError / other.worstAllowed
                            : other.worstError > 0.0 ? INFINITY
                                                     : 0.0;
  if (count == 0 || otherShare > share) worstError = other.worstError, worstAllowed = other.worstAllowed;
  count += other.count;
  if (other.mismatches != 0 && mismatches < 8) report += (label.empty() ? "" : "\n  " + label + ":") + other.report;
  mismatches += other.mismatches;
  worstFiniteError = std::max(worstFiniteError, other.worstFiniteError);
}

// Moments (tools/selftest/reference/moments_ref.h). fp32 normalisation ((d - near) * 1/range) is within ~3 ulp of the
// double value; squares double it.
inline constexpr Tolerance kMomentsVsmTol{1e-6, 1e-6};
// exp(c x) with c = 42 amplifies the ~2e-7 error of x by c: 1e-5 relative, 2e-5 for the square.
inline constexpr Tolerance kMomentsEvsmTol{1e-30, 3e-5};
// ESM's e^(80 (d - 1)) (the default exponent): d's fp32 rounding (~3 ulp) times 80, relative.
inline constexpr Tolerance kMomentsEsmTol{1e-6, 1e-5};
// The MSM transform sums terms up to ~80 with cancellation: absolute error ~ 80 * 4 * 6e-8.
inline constexpr Tolerance kMomentsMsmTol{5e-5, 0.0};
// The published 10-digit MSM matrices are inverse to about 1e-7 (conditioning ~1e3 for b3, b4).
inline constexpr double kMsmRoundTripTol = 2e-4;
inline Tolerance momentsTolerance(MomentKind kind) {
  if (kind == MomentKind::Evsm2 || kind == MomentKind::Evsm4) return kMomentsEvsmTol;
  if (kind == MomentKind::Esm) return kMomentsEsmTol;
  return kind == MomentKind::Msm ? kMomentsMsmTol : kMomentsVsmTol;
}
// Block means (computeMomentsReduced): a mean of factor^2 texels adds at most factor^2 fp32 roundings of its partial
// sums, 64 x 6e-8 relative at 8 x 8, on top of the per-texel margin.
inline Tolerance momentsReducedTolerance(MomentKind kind) {
  Tolerance tol = momentsTolerance(kind);
  tol.rel += 4e-6;
  tol.abs = std::max(tol.abs, 1e-6);
  return tol;
}

// Blur (blur_ref.h). Direct sums of <= 2*32+1 fp32 products per pass of data in [0, 1]: <= 65 roundings of ~6e-8,
// twice.
inline constexpr Tolerance kBlurDirectTol{5e-6, 1e-6};
// Running sums add and subtract one texel per step over segments of >= 128 steps: the drift is bounded by steps * eps
// relative to the window mean (~8e-6), three boxes per axis.
inline constexpr Tolerance kBlurRunningTol{5e-5, 1e-5};
// Positive data spanning 1e20..1e30: only relative error is meaningful.
inline constexpr Tolerance kBlurHugeRangeTol{0.0, 1e-5};
// Three boxes approximate the Gaussian: for data in [0, 1] the filtered values differ by a few percent of the local
// contrast at most (Wells 1986; Kovesi 2010).
inline constexpr Tolerance kBlurBoxesVsGaussianTol{0.03, 0.0};
// The two direct layouts add each texel's taps in the same order with the same `sum += w * x`; they can differ only
// where a compiler contracts that into a fused multiply-add for one vector width and not the other: at most one
// rounding (6e-8 of the running sum, <= 1 for data in [0, 1]) per tap, 2 * 201 taps at radius 100.
inline constexpr Tolerance kBlurLayoutTol{1e-5, 1e-5};

// ESM's log-space blur (ref::logBlur): fp32 rounds each pass's D to ~6e-8 and c (d - m) to ~6e-8 relative (a D error
// of 6e-8 whatever c). Absolute, in normalised depth: a visibility error of at most c times it.
inline constexpr Tolerance kLogBlurTol{2e-6, 0.0};
// The blur's margins above are for data in [0, 1]; moments of magnitude up to M (EVSM's e^(c x) reach e^42) carry the
// absolute part scaled by M, on top of the moments' own margin.
inline Tolerance blurredMomentsTolerance(Tolerance moments, Tolerance blur, double magnitude) {
  return {moments.abs + blur.abs * std::max(1.0, magnitude), moments.rel + blur.rel, moments.nanMatchesNan};
}

// Half storage: the stages compute in fp32 and round once when they store, so a half result is within the fp32 margin
// plus half a half-ulp (2^-11 relative, 2^-25 absolute among subnormals) of the reference.
inline Tolerance halfStorageTolerance(Tolerance fp32) {
  fp32.rel += 0x1p-11;
  fp32.abs += 0x1p-25;
  return fp32;
}

// SAT (sat_ref.h). Floating-point tables: an entry is reached through at most ~2 * 32 in-tile additions plus one per
// tile along each axis, each rounding by at most eps times the running magnitude, which Sum |x - offset| bounds
// (`magnitude`). Measured worst cases are below 1/4 of this. Fixed-point tables are exact.
double satTableTolerance(const ImageShape& shape, double epsilon, double magnitude);
// The device's zero-mean offset is a float tree sum of float inputs: relative error ~ log2(n) eps.
inline constexpr double kSatMeanRelTol = 1e-5;

// Pyramids (pyramid_ref.h). Each mip level is <= 9 fp32 products of the previous one (data in [0, 1]); errors add
// over <= 8 levels. Min-max pyramids are exact.
inline constexpr Tolerance kMipTol{2e-6, 1e-6};
// The mean of a level (a double sum of fp32 texels) drifts by the per-level rounding only.
inline constexpr double kMipMeanTol = 1e-5;
// ESM's log-space mips: fp32 rounds each level's D to ~6e-8 and its taps' c (d - m) to ~6e-8 relative; errors add
// over the levels. Absolute, in normalised depth.
inline constexpr Tolerance kLogMipTol{2e-6, 0.0};

// Lloyd reduction (reduce_ref.h): fp32 sums of positive terms, serial runs of <= 64 samples then trees of depth
// <= 16; the error is bounded by (64 + 16) eps relative to the (all positive) sum. Counts are exact.
inline constexpr double kLloydSumRelTol = 80 * 6e-8;

}  // namespace penumbra::ref
