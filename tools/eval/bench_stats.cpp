// Medians over runs and bandwidth floors for `penumbra bench`.
#include "tools/eval/bench_stats.h"

#include <algorithm>

namespace penumbra {

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  const double lower = *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

std::optional<double> bandwidthFloorMs(uint64_t bytes, double bytesPerSecond) {
  if (bytes == 0 || !(bytesPerSecond > 0)) return std::nullopt;
  return static_cast<double>(bytes) / bytesPerSecond * 1e3;
}

RunSummary summariseRuns(const std::vector<std::vector<PassTime>>& runs) {
  RunSummary summary;
  for (const std::vector<PassTime>& run : runs)
    for (const PassTime& pass : run)
      if (std::none_of(summary.passes.begin(), summary.passes.end(),
                       [&](const PassSummary& p) { return p.name == pass.name; }))
        summary.passes.push_back({pass.name, 0.0, 0, 0});
  std::vector<double> totals;
  for (PassSummary& p : summary.passes) {
    std::vector<double> times;
    for (const std::vector<PassTime>& run : runs) {
      auto it = std::find_if(run.begin(), run.end(), [&](const PassTime& t) { return t.name == p.name; });
      times.push_back(it == run.end() ? 0.0 : it->ms);
      if (&run == &runs.back()) {
        p.calls = it == run.end() ? 0 : it->count;
        p.bytes = it == run.end() ? 0 : it->bytes;
      }
    }
    p.ms = median(std::move(times));
    summary.totalBytes += p.bytes;
  }
  for (const std::vector<PassTime>& run : runs) {
    double total = 0;
    for (const PassTime& pass : run) total += pass.ms;
    totals.push_back(total);
  }
  summary.totalMs = median(std::move(totals));
  return summary;
}

}  // namespace penumbra
