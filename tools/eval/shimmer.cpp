// Per pixel |Δ ours| where |Δ reference| <= kStableReference, summed in double.
#include "tools/eval/shimmer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

ShimmerMetrics frameShimmer(std::span<const float> oursA, std::span<const float> oursB,
                            std::span<const float> referenceA, std::span<const float> referenceB,
                            std::span<const float> coverageA, std::span<const float> coverageB) {
  const size_t n = oursA.size();
  const auto sized = [n](std::span<const float> s, bool optional) { return s.size() == n || (optional && s.empty()); };
  if (!sized(oursB, false) || !sized(referenceA, false) || !sized(referenceB, false) || !sized(coverageA, true) ||
      !sized(coverageB, true))
    throw std::invalid_argument("frameShimmer: the frames' channels differ in size");
  ShimmerMetrics m;
  double sum = 0;
  size_t steps = 0;
  for (size_t i = 0; i < n; ++i) {
    if ((!coverageA.empty() && !(coverageA[i] > 0)) || (!coverageB.empty() && !(coverageB[i] > 0))) continue;
    const double ref = std::fabs(static_cast<double>(referenceB[i]) - referenceA[i]);
    if (!std::isfinite(ref) || ref > kStableReference) continue;
    double change = std::fabs(static_cast<double>(oursB[i]) - oursA[i]);
    if (!std::isfinite(change)) change = 1.0;
    ++m.pixels, sum += change, steps += change > kShimmerStep ? 1 : 0;
    m.maxAbs = std::max(m.maxAbs, change);
  }
  if (m.pixels > 0) m.mean = sum / static_cast<double>(m.pixels), m.fraction = static_cast<double>(steps) / m.pixels;
  return m;
}

ShimmerMetrics combineShimmer(const std::vector<ShimmerMetrics>& pairs) {
  ShimmerMetrics all;
  double sum = 0, steps = 0;
  for (const ShimmerMetrics& p : pairs) {
    all.pixels += p.pixels;
    sum += p.mean * static_cast<double>(p.pixels), steps += p.fraction * static_cast<double>(p.pixels);
    all.maxAbs = std::max(all.maxAbs, p.maxAbs);
  }
  if (all.pixels > 0) all.mean = sum / static_cast<double>(all.pixels), all.fraction = steps / all.pixels;
  return all;
}

}  // namespace penumbra
