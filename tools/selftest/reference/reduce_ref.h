// Double-precision reference of the Lloyd reduction: per cluster sum w, sum w x, sum w x^2 and counts.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace penumbra::ref {

struct LloydRef {
  double sumW = 0, sumWX = 0, sumWX2 = 0;
  uint32_t samples = 0;
};

// Cluster of x = number of boundaries <= x; samples with non-finite x or w, or w <= 0, are skipped.
std::vector<LloydRef> lloydStats(const std::vector<float>& x, const std::vector<float>& w,
                                 const std::vector<float>& boundaries);

}  // namespace penumbra::ref
