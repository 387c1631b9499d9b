// The one comparison helper for kernel outputs, as a GoogleTest assertion: ref::compare (the tolerances and the
// comparison `penumbra selftest` uses too, tools/selftest/reference/tolerance.h) with its failures reported.
// An element passes when |a - e| <= abs + rel * |e|, or both are NaN and NaNs are allowed to match.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <span>

#include "tools/selftest/reference/tolerance.h"

namespace penumbra::test {

using ref::Tolerance;

// Reports the first few mismatches with their indices (x, y for images of `width` columns).
template <class A, class E>
::testing::AssertionResult allNear(std::span<const A> actual, std::span<const E> expected, Tolerance tol,
                                   size_t width = 0) {
  const ref::Comparison c = ref::compare(actual, expected, tol, width);
  if (c.pass()) return ::testing::AssertionSuccess();
  if (actual.size() != expected.size())
    return ::testing::AssertionFailure() << "size " << actual.size() << " != expected " << expected.size();
  return ::testing::AssertionFailure() << c.mismatches << " of " << c.count << " elements differ (worst finite |diff| "
                                       << c.worstFiniteError << ")" << c.report;
}

// A selftest comparison (tools/selftest/), as an assertion: its failures reported.
inline ::testing::AssertionResult passes(const ref::Comparison& c) {
  if (c.pass()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << c.mismatches << " of " << c.count << " elements outside the margin (worst "
                                       << c.worstError << ", allowed " << c.worstAllowed << ")" << c.report;
}

}  // namespace penumbra::test
