// Naive per-sample accumulation in double.
#include "tools/selftest/reference/reduce_ref.h"

#include <cmath>

namespace penumbra::ref {

std::vector<LloydRef> lloydStats(const std::vector<float>& x, const std::vector<float>& w,
                                 const std::vector<float>& boundaries) {
  std::vector<LloydRef> out(boundaries.size() + 1);
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(w[i]) || !(w[i] > 0.0f)) continue;
    size_t k = 0;
    while (k < boundaries.size() && x[i] >= boundaries[k]) ++k;
    out[k].sumW += w[i];
    out[k].sumWX += double(w[i]) * x[i];
    out[k].sumWX2 += double(w[i]) * x[i] * x[i];
    out[k].samples += 1;
  }
  return out;
}

}  // namespace penumbra::ref
