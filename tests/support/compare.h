// The one comparison helper for kernel outputs: absolute and relative margins and explicit NaN rules.
// An element passes when |a - e| <= abs + rel * |e|, or both are NaN and NaNs are allowed to match.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace penumbra::test {

struct Tolerance {
  double abs = 0.0;
  double rel = 0.0;
  bool nanMatchesNan = false;  // true: expected NaN must be NaN; false: any NaN fails
};

// Reports the first few mismatches with their indices (x, y for images of `width` columns).
template <class A, class E>
::testing::AssertionResult allNear(std::span<const A> actual, std::span<const E> expected, Tolerance tol,
                                   size_t width = 0) {
  if (actual.size() != expected.size())
    return ::testing::AssertionFailure() << "size " << actual.size() << " != expected " << expected.size();
  size_t failures = 0;
  std::string report;
  double worst = 0.0;
  for (size_t i = 0; i < actual.size(); ++i) {
    const double a = static_cast<double>(actual[i]), e = static_cast<double>(expected[i]);
    bool ok;
    if (std::isnan(e) || std::isnan(a))
      ok = tol.nanMatchesNan && std::isnan(e) && std::isnan(a);
    else if (std::isinf(e) || std::isinf(a))
      ok = a == e;
    else
      ok = std::abs(a - e) <= tol.abs + tol.rel * std::abs(e);
    if (!ok) {
      if (!std::isnan(a) && !std::isnan(e)) worst = std::max(worst, std::abs(a - e));
      if (++failures <= 8)
        report += width != 0 ? fmt::format("\n  ({}, {}): {} vs expected {}", i % width, i / width, a, e)
                             : fmt::format("\n  [{}]: {} vs expected {}", i, a, e);
    }
  }
  if (failures == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << failures << " of " << actual.size()
                                       << " elements differ (worst finite |diff| " << worst << ")" << report;
}

}  // namespace penumbra::test
