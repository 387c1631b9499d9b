// Shared pieces of the rasterizer tests: the scenes, views, poisoned draw and comparison of
// tools/selftest/reference/raster_compare.h (which `penumbra selftest` runs too), and their GoogleTest assertion.
#pragma once

#include <gtest/gtest.h>

#include "tests/support/cl_test.h"
#include "tools/selftest/reference/raster_compare.h"

namespace penumbra::test {

// Expects no mismatches and at most `maxAmbiguous` ties.
inline ::testing::AssertionResult matchesReference(const RasterComparison& c, size_t maxAmbiguous = 0) {
  if (c.mismatches == 0 && c.ambiguous <= maxAmbiguous) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << c.mismatches << " mismatching pixels, " << c.ambiguous
                                       << " depth ties (allowed " << maxAmbiguous << "), " << c.covered << " covered"
                                       << c.report;
}

}  // namespace penumbra::test
