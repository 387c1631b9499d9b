// The statistics `penumbra bench` reports: the median of repeated device times, per pass across runs, and each
// pass's bandwidth floor (the least time its bytes take at the device's measured copy bandwidth). Plain C++.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "host/cl/profiler.h"

namespace penumbra {

// The middle value; the mean of the two middle ones for an even count; 0 for none. NaNs are not expected.
double median(std::vector<double> values);

// bytes / bandwidth in milliseconds; nullopt when the pass gave no byte count (0) or the bandwidth is unknown.
std::optional<double> bandwidthFloorMs(uint64_t bytes, double bytesPerSecond);

struct PassSummary {
  std::string name;    // "stage/kernel"
  double ms = 0;       // median over the runs of the pass's summed device time in that run (absent: 0)
  int calls = 0;       // launches per run (the last run's)
  uint64_t bytes = 0;  // least bytes moved per run (the last run's; 0: no hint)
};

// Per pass name, in first-seen order over all runs; plus the median over runs of each run's total.
struct RunSummary {
  std::vector<PassSummary> passes;
  double totalMs = 0;
  uint64_t totalBytes = 0;  // sum of the passes' bytes
};
RunSummary summariseRuns(const std::vector<std::vector<PassTime>>& runs);

}  // namespace penumbra
